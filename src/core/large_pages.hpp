#pragma once
// An allocator for large arrays: on Linux, an array of 2 MiB or more is placed on 2 MiB
// boundaries and the kernel is asked to back it with huge pages (madvise MADV_HUGEPAGE,
// honoured where transparent huge pages are "madvise" or "always"). Two kinds of array gain:
//   - those read in no particular order (a ray caster's tree): a ray's walk touches a few cache
//     lines in each of many pages; with 4 KiB pages nearly every step also misses the address
//     translation cache. Embree allocates its trees the same way;
//   - those written once per frame (the pipeline's screen triangles, the frame's buffers): a
//     fresh array of 64 MiB first touched in 4 KiB pages takes 16,384 page faults, in 2 MiB
//     pages 32, which is most of what a one-shot render pays over a warm one (the frame's
//     buffers take the same allocation through hsr::FrameBufferAllocator, hsr/render.hpp).
// Elsewhere, or when the kernel declines, it is an ordinary aligned allocation: the contents
// and every result are the same either way.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace hsr::detail {

inline constexpr std::size_t kLargePage = std::size_t{2} << 20;

inline void* allocateLargePages(std::size_t bytes, std::size_t align) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (bytes >= kLargePage) {
    const std::size_t rounded = (bytes + kLargePage - 1) / kLargePage * kLargePage;
    if (void* p = std::aligned_alloc(kLargePage, rounded)) {
      madvise(p, rounded, MADV_HUGEPAGE);  // a hint: refused, the pages are ordinary ones
      return p;
    }
    throw std::bad_alloc();
  }
#endif
  const std::size_t a = align < alignof(std::max_align_t) ? alignof(std::max_align_t) : align;
  if (void* p = std::aligned_alloc(a, (bytes + a - 1) / a * a)) return p;
  throw std::bad_alloc();
}

template <class T>
struct LargePageAllocator {
  using value_type = T;
  LargePageAllocator() = default;
  template <class U>
  LargePageAllocator(const LargePageAllocator<U>&) {}
  T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
    return static_cast<T*>(allocateLargePages(n * sizeof(T), alignof(T)));
  }
  void deallocate(T* p, std::size_t) { std::free(p); }
  template <class U>
  bool operator==(const LargePageAllocator<U>&) const {
    return true;
  }
};

}  // namespace hsr::detail

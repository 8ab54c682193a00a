#pragma once
// An allocator whose value-less construct() default-initialises instead of value-initialising,
// so that resizing a vector of plain structs that are about to be overwritten costs no zero
// fill (the pipeline resizes its output of a million triangles every frame, then copies the
// chunks' triangles into it in parallel).

#include <memory>
#include <utility>

namespace hsr::detail {

template <class T, class Base = std::allocator<T>>
class DefaultInitAllocator : public Base {
 public:
  using Base::Base;
  template <class U>
  struct rebind {
    using other =
        DefaultInitAllocator<U, typename std::allocator_traits<Base>::template rebind_alloc<U>>;
  };
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    std::allocator_traits<Base>::construct(static_cast<Base&>(*this), p,
                                           std::forward<Args>(args)...);
  }
};

}  // namespace hsr::detail

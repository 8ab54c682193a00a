// A frame's buffers (hsr::FrameBuffer): on Linux a buffer of 1 MiB or more starts on a 2 MiB
// boundary, so that its first touch takes huge pages from its first byte to its last; they hold
// what any vector holds, are reused by the next render into the same frame, and a copied frame
// is the same frame.

#include <gtest/gtest.h>

#include <cstdint>

#include "core/large_pages.hpp"
#include "hsr/camera.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"

namespace hsr {
namespace {

template <class Buffer>
bool onLargePageBoundary(const Buffer& b) {
  return reinterpret_cast<std::uintptr_t>(b.data()) % detail::kLargePage == 0;
}

TEST(FrameBuffers, A1080pFrameStartsEachBufferOnA2MiBBoundaryAndReusesIt) {
  const Scene scene = makeBuiltinScene("spheres:2000");
  const Camera camera = frameScene(scene, 1920, 1080);
  Frame frame;
  render(scene, camera, {}, frame);
  const std::size_t n = std::size_t{1920} * 1080;
  ASSERT_EQ(frame.color.size(), n);
  ASSERT_EQ(frame.depth.size(), n);
  ASSERT_EQ(frame.ids.size(), n);
  ASSERT_EQ(frame.overdraw.size(), n);
#if defined(__linux__)
  EXPECT_TRUE(onLargePageBoundary(frame.color));
  EXPECT_TRUE(onLargePageBoundary(frame.depth));
  EXPECT_TRUE(onLargePageBoundary(frame.ids));
  EXPECT_TRUE(onLargePageBoundary(frame.overdraw));
#endif
  std::uint64_t drawn = 0;
  for (const PolygonId id : frame.ids) drawn += id != kNoPolygon;
  EXPECT_GT(drawn, 0u);
  // The next frame into it draws into the same memory, and draws the same.
  const Frame first = frame;
  const void* color = frame.color.data();
  const void* depth = frame.depth.data();
  render(scene, camera, {}, frame);
  EXPECT_EQ(frame.color.data(), color);
  EXPECT_EQ(frame.depth.data(), depth);
  EXPECT_EQ(frame.color, first.color);
  EXPECT_EQ(frame.depth, first.depth);
  EXPECT_EQ(frame.ids, first.ids);
  EXPECT_EQ(frame.overdraw, first.overdraw);
#if defined(__linux__)
  EXPECT_TRUE(onLargePageBoundary(first.color));  // a copy is allocated the same way
#endif
}

TEST(FrameBuffers, HoldWhatAVectorHoldsAtEverySize) {
  for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{1000},
                              detail::kLargePage / 4 - 1, detail::kLargePage / 4 + 3}) {
    FrameBuffer<std::uint32_t> b(n);  // value-initialised, as std::vector's
    for (const std::uint32_t v : b) ASSERT_EQ(v, 0u);
    for (std::size_t i = 0; i < n; ++i) b[i] = static_cast<std::uint32_t>(i * 7);
    b.push_back(99);  // grows (and moves) as a vector does
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(b[i], i * 7);
    EXPECT_EQ(b.back(), 99u);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(b.data()) % alignof(std::max_align_t), 0u);
  }
#if defined(__linux__)
  // From 1 MiB (an 800x600 frame's buffers: 1.8 MiB each) a buffer takes whole huge pages.
  for (const std::size_t n :
       {detail::kLargePage / 8, std::size_t{800} * 600, detail::kLargePage / 4 + 3}) {
    const FrameBuffer<std::uint32_t> b(n);
    EXPECT_TRUE(onLargePageBoundary(b)) << n;
  }
#endif
}

}  // namespace
}  // namespace hsr

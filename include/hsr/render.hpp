#pragma once
// render(): scene + camera + options -> Frame (colour, depth, polygon ids, overdraw, stats).
// Every visibility algorithm is reached through this one call and the registry.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "hsr/algorithms.hpp"
#include "hsr/camera.hpp"
#include "hsr/scene.hpp"
#include "hsr/stats.hpp"

namespace hsr {

enum class CullMode { None, Back, Front, FrontAndBack };  // glCullFace (None = disabled)
enum class FrontFace { Ccw, Cw };                         // glFrontFace
enum class PolygonMode { Fill, Line, Point };             // glPolygonMode(FRONT_AND_BACK, ...)
enum class DepthFunc { Never, Less, Equal, LEqual, Greater, NotEqual, GEqual, Always };
// How the pipeline decides facing: OpenGL's sign of the window-space area (default), or the
// notes' eye-space test N . (eye - P) > 0. They agree on every polygon that is not edge-on.
enum class FacingTest { WindowArea, EyePlane };

// How the BSP tree (algorithm "bsp", hsr/bsp.hpp) chooses each node's splitter among the
// polygons that reach it: "first" (the notes' "pick any"), "random" (seeded), "fewest" (the one
// that splits fewest others, among up to 512 of them), "balanced" (best of `candidates` sampled
// by 8 x splits + |front - behind|), "best-of-k" (best of `candidates` sampled by splits).
struct BspOptions {
  std::string splitter = "balanced";
  std::uint64_t seed = 1;  // for the sampled choices: the same seed builds the same tree
  int candidates = 8;      // for "balanced" and "best-of-k", 1..4096
};

struct RenderOptions {
  std::string algorithm = "zbuffer";
  CullMode cull = CullMode::None;
  FrontFace front_face = FrontFace::Ccw;
  FacingTest facing_test = FacingTest::WindowArea;
  PolygonMode polygon_mode = PolygonMode::Fill;
  bool depth_test = true;
  DepthFunc depth_func = DepthFunc::Less;
  bool depth_mask = true;
  bool frustum_cull = true;  // skip objects whose bounds lie outside the view volume
  bool outline = false;      // draw silhouette edges (front/back polygon boundary) over the fill
  bool shade = true;         // headlight Lambert; false = flat material colour
  glm::vec3 clear_color{0.94f, 0.94f, 0.92f};  // light paper, so outlines read
  float clear_depth = 1.0f;
  // polygon mode POINT: each vertex's square, in pixels, as glPointSize (1 to 64)
  float point_size = 1.0f;
  int threads = 0;  // 0 = all hardware threads (more are clamped); results are identical for any
  BspOptions bsp;   // algorithm "bsp" only
  // Algorithms that antialias ("abuffer"): sub-pixel samples per pixel, 1, 4, 8, 16, 32 or 64
  // (0: the algorithm's default, 4); any other algorithm refuses a value other than 0.
  int samples = 0;
  // "abuffer": the most its frame's fragment lists may take, in bytes; a frame that would need
  // more is refused with hsr::Error (the depth complexity it would take is in the message).
  std::uint64_t fragment_memory = std::uint64_t(2) << 30;
};

// Memory an algorithm keeps between renders into the same Frame (so that repeated frames
// allocate nothing). Opaque; a copied Frame starts without it, so copies never share it.
class FrameScratch {
 public:
  FrameScratch() = default;
  FrameScratch(const FrameScratch&) {}
  FrameScratch& operator=(const FrameScratch&) { return *this; }
  FrameScratch(FrameScratch&&) noexcept = default;
  FrameScratch& operator=(FrameScratch&&) noexcept = default;
  std::shared_ptr<void> ptr;
};

// Where a frame's buffers live: a buffer of 1 MiB or more starts on a 2 MiB boundary and the
// kernel is asked for huge pages under all of it (elsewhere, an ordinary allocation). A fresh
// 1080p frame (33 MB) is then first touched in 2 MiB pages; from std::allocator, whose large
// blocks start just past a 4 KiB page, each buffer's unaligned ends took 4 KiB faults, which
// were most of a one-shot render's clear (24 ms against 5). Elements are value-initialised as
// in any std::vector; the contents are the same either way.
void* allocateFrameBuffer(std::size_t bytes);  // throws std::bad_alloc
void freeFrameBuffer(void* p) noexcept;
template <class T>
struct FrameBufferAllocator {
  using value_type = T;
  FrameBufferAllocator() = default;
  template <class U>
  FrameBufferAllocator(const FrameBufferAllocator<U>&) {}
  T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
    return static_cast<T*>(allocateFrameBuffer(n * sizeof(T)));
  }
  void deallocate(T* p, std::size_t) noexcept { freeFrameBuffer(p); }
  template <class U>
  bool operator==(const FrameBufferAllocator<U>&) const {
    return true;
  }
};
template <class T>
using FrameBuffer = std::vector<T, FrameBufferAllocator<T>>;

// Buffers are width*height, TOP ROW FIRST (as image files and .npy). GL window pixel (x, y),
// origin bottom-left, is element (height - 1 - y) * width + x.
struct Frame {
  int width = 0, height = 0;
  FrameBuffer<std::uint32_t> color;     // RGBA8 packed, R in the low byte (bytes R,G,B,A)
  FrameBuffer<float> depth;             // window z in [0,1]; clear depth where nothing drawn
  FrameBuffer<PolygonId> ids;           // kNoPolygon where nothing drawn
  FrameBuffer<std::uint32_t> overdraw;  // fragments written per pixel
  FrameBuffer<float> coverage;          // antialiasing algorithms only (else empty): the fraction
                                        // of each pixel's samples covered by opaque polygons
  Stats stats;
  FrameScratch scratch;
};

Frame render(const Scene& scene, const Camera& camera, const RenderOptions& options = {});

// Why `info`'s algorithm cannot render with these options and camera (render() refuses with
// this line), or an empty string when it can.
std::string unsupported(const AlgorithmInfo& info, const Camera& camera,
                        const RenderOptions& options);
// The same, drawing into `frame` and reusing its buffers' memory (for repeated frames).
void render(const Scene& scene, const Camera& camera, const RenderOptions& options, Frame& frame);

// Parsing helpers shared by the CLI and the GL facade; throw hsr::Error on unknown names.
CullMode parseCullMode(std::string_view s);
FrontFace parseFrontFace(std::string_view s);
PolygonMode parsePolygonMode(std::string_view s);
DepthFunc parseDepthFunc(std::string_view s);

}  // namespace hsr

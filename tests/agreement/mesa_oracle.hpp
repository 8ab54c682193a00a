#pragma once
// Mesa's OpenGL (OSMesa, llvmpipe) as an independent oracle for the z-buffer: the same
// triangles (hsr::detail::triangulate) drawn through fixed-function GL with the same state,
// each triangle's PolygonId encoded exactly in its RGBA8 colour. Also a persistent renderer
// (MesaScene) for benchmarking llvmpipe against hsr in the same process.
//
// One OSMesa context per process, created on first use and reused (OSMesa's screen, and with
// it llvmpipe's thread count LP_NUM_THREADS, is fixed when the first context is created).
// Not thread-safe: call from one thread at a time.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "hsr/camera.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"

namespace hsr::testing {

// What Mesa drew. Buffers are width*height, TOP ROW FIRST (the layout of hsr::Frame).
struct MesaFrame {
  int width = 0, height = 0;
  std::vector<PolygonId> ids;  // kNoPolygon where nothing was drawn
  // Window depth in [0,1], read with glReadPixels(GL_DEPTH_COMPONENT, GL_FLOAT) from OSMesa's
  // 24-bit depth buffer (OSMesa's window-system buffer offers no more: it maps any request
  // of >= 24 bits to Z24), i.e. z24 / (2^24 - 1). Clear depth where nothing was drawn.
  std::vector<float> depth;
  int depth_bits = 0;  // GL_DEPTH_BITS of the buffer (24)
};

// Renders triangulate(scene) through OSMesa with the state of `options`: viewport = camera
// size, GL_PROJECTION = camera.projection(), GL_MODELVIEW = camera.view(), depth test, func,
// mask and clear depth, glCullFace / glFrontFace / GL_CULL_FACE per options.cull and
// options.front_face. Fill mode only (throws std::invalid_argument otherwise). Polygons with
// material alpha < 1 are left out: hsr blends them without writing ids or depth. Throws
// std::runtime_error when no OSMesa context can be made.
MesaFrame renderWithMesa(const Scene& scene, const Camera& camera,
                         const RenderOptions& options = {});

// Checks that the id-in-colour encoding survives Mesa exactly: draws one point per colour
// (every byte value in every channel, plus `random_count` random 32-bit words) and returns
// how many read back differently (0 expected).
std::size_t mesaColorRoundTripErrors(int random_count = 4096);

// "llvmpipe (LLVM 15.0.6, 256 bits)": GL_RENDERER of the shared context (creates it).
std::string mesaRenderer();

// A scene uploaded once into a vertex buffer object, drawn as many frames as wanted: the
// llvmpipe side of the benchmark. Flat colour per triangle (its material colour), depth
// test LESS, no culling, camera as for renderWithMesa. With `msaa_samples`, frames are drawn
// into a multisampled framebuffer object (colour RGBA8, depth 24 bits) with GL_MULTISAMPLE on,
// and resolved into the window buffer by glBlitFramebuffer: the antialiased peer of the
// A-buffer. Throws std::runtime_error when Mesa cannot make that framebuffer.
class MesaScene {
 public:
  MesaScene(const Scene& scene, const Camera& camera, const RenderOptions& options = {},
            int msaa_samples = 0);
  ~MesaScene();
  MesaScene(const MesaScene&) = delete;
  MesaScene& operator=(const MesaScene&) = delete;

  // Draws one frame: glClear(COLOR | DEPTH) + glDrawArrays + glFinish (which, in OSMesa,
  // also copies the colour buffer into the client buffer). Returns its wall time in ms.
  double renderFrameMs();
  // The last frame's colour (resolved, for MSAA), RGBA8 packed with R in the low byte, top
  // row first (hsr::Frame::color's layout).
  std::vector<std::uint32_t> colour() const;
  int msaaSamples() const { return msaa_samples_; }
  std::size_t triangleCount() const { return triangle_count_; }
  // Bytes of vertex data uploaded (the GL-side copy of the scene).
  std::size_t vertexBytes() const { return vertex_bytes_; }

 private:
  Camera camera_;
  RenderOptions options_;
  std::size_t triangle_count_ = 0;
  std::size_t vertex_bytes_ = 0;
  unsigned vbo_ = 0;
  int msaa_samples_ = 0;
  unsigned fbo_ = 0, colour_rb_ = 0, depth_rb_ = 0;
  std::vector<std::uint8_t> client_;  // vertex data when VBOs are unavailable
};

}  // namespace hsr::testing

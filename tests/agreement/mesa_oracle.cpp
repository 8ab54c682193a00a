// Mesa (OSMesa + llvmpipe) as the z-buffer's oracle: fixed-function GL, one context per
// process, each triangle's PolygonId carried exactly in its RGBA8 colour (flat shading, no
// dithering, blending or lighting: llvmpipe turns the unsigned bytes into floats b/255 and back
// to round(f*255) = b, which zbuffer_mesa_test checks for every byte value).

#include "agreement/mesa_oracle.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <string>

#include <glm/gtc/type_ptr.hpp>

#include "geometry/triangulate.hpp"

// Mesa 22's OSMesa leaks a few hundred bytes of its own (even a bare create / make current /
// destroy program does): keep LeakSanitizer builds (HSR_SANITIZE) quiet about them. Only read
// when the binary runs under LSan.
extern "C" const char* __lsan_default_suppressions() { return "leak:libOSMesa.so\n"; }

namespace hsr::testing {
namespace {

// One vertex as glVertexPointer / glColorPointer read it: interleaved, 16 bytes.
struct GlVertex {
  float x, y, z;
  std::uint8_t rgba[4];
};
static_assert(sizeof(GlVertex) == 16);

// The process's one OSMesa context and the client colour buffer it draws into.
struct MesaContext {
  OSMesaContext ctx = nullptr;
  std::vector<std::uint32_t> buffer;  // RGBA8, OSMesa's layout (bottom row first, Y_UP)
  int width = 0, height = 0;
};

// Created on first use and never destroyed (OSMesa tears its screen down at exit by itself;
// destroying the context earlier would race with objects that still use it from their
// destructors, and Mesa 22 leaks its buffers either way).
MesaContext& sharedContext() {
  static MesaContext& c = *[] {
    auto* m = new MesaContext;
    // Ask for 32 depth bits; OSMesa's window-system buffer gives Z24 for any request >= 24.
    // clang-format off
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA,
                           OSMESA_DEPTH_BITS, 32,
                           OSMESA_STENCIL_BITS, 0,
                           OSMESA_ACCUM_BITS, 0,
                           OSMESA_PROFILE, OSMESA_COMPAT_PROFILE,
                           0};
    // clang-format on
    m->ctx = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!m->ctx) m->ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
    if (!m->ctx) {
      delete m;
      throw std::runtime_error("OSMesa: cannot create a context");
    }
    return m;
  }();
  return c;
}

// Makes the shared context current on a width x height buffer (a new buffer when the size
// changes) and sets the viewport to it.
MesaContext& makeCurrent(int width, int height) {
  MesaContext& c = sharedContext();
  if (c.width != width || c.height != height || OSMesaGetCurrentContext() != c.ctx) {
    c.buffer.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0u);
    if (!OSMesaMakeCurrent(c.ctx, c.buffer.data(), GL_UNSIGNED_BYTE, width, height)) {
      throw std::runtime_error("OSMesa: cannot make the context current at " +
                               std::to_string(width) + "x" + std::to_string(height));
    }
    c.width = width;
    c.height = height;
  }
  glViewport(0, 0, width, height);
  return c;
}

GLenum glDepthFuncOf(DepthFunc f) {
  switch (f) {
    case DepthFunc::Never:
      return GL_NEVER;
    case DepthFunc::Less:
      return GL_LESS;
    case DepthFunc::Equal:
      return GL_EQUAL;
    case DepthFunc::LEqual:
      return GL_LEQUAL;
    case DepthFunc::Greater:
      return GL_GREATER;
    case DepthFunc::NotEqual:
      return GL_NOTEQUAL;
    case DepthFunc::GEqual:
      return GL_GEQUAL;
    case DepthFunc::Always:
      return GL_ALWAYS;
  }
  return GL_LESS;
}

// The fixed-function state both renderers share: flat colour straight from the vertex
// colour, no dithering/blending/lighting, the camera's matrices, depth and cull per options.
void applyState(const Camera& camera, const RenderOptions& options) {
  glDisable(GL_DITHER);
  glDisable(GL_BLEND);
  glDisable(GL_LIGHTING);
  glDisable(GL_ALPHA_TEST);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_MULTISAMPLE);
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_DEPTH_CLAMP);
  glShadeModel(GL_FLAT);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthRange(0.0, 1.0);

  // Matrices: glm is column-major, as glLoadMatrixf expects.
  const glm::mat4 projection = camera.projection();
  const glm::mat4 view = camera.view();
  glMatrixMode(GL_PROJECTION);
  glLoadMatrixf(glm::value_ptr(projection));
  glMatrixMode(GL_MODELVIEW);
  glLoadMatrixf(glm::value_ptr(view));

  // Clear both buffers (the depth mask must be on for glClear to reach depth).
  glDepthMask(GL_TRUE);
  glClearColor(1.0f, 1.0f, 1.0f, 1.0f);  // RGBA bytes FF FF FF FF = kNoPolygon
  glClearDepth(options.clear_depth);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  // Depth test.
  if (options.depth_test) {
    glEnable(GL_DEPTH_TEST);
  } else {
    glDisable(GL_DEPTH_TEST);
  }
  glDepthFunc(glDepthFuncOf(options.depth_func));
  glDepthMask(options.depth_mask ? GL_TRUE : GL_FALSE);

  // Facing and culling.
  glFrontFace(options.front_face == FrontFace::Ccw ? GL_CCW : GL_CW);
  switch (options.cull) {
    case CullMode::None:
      glDisable(GL_CULL_FACE);
      break;
    case CullMode::Back:
      glEnable(GL_CULL_FACE);
      glCullFace(GL_BACK);
      break;
    case CullMode::Front:
      glEnable(GL_CULL_FACE);
      glCullFace(GL_FRONT);
      break;
    case CullMode::FrontAndBack:
      glEnable(GL_CULL_FACE);
      glCullFace(GL_FRONT_AND_BACK);
      break;
  }
}

// Triangles as an interleaved vertex array, three vertices per triangle, all three with the
// triangle's colour (flat shading takes the provoking vertex's; all agree anyway).
// `opaque_only` leaves out polygons whose material has alpha < 1: hsr's z-buffer blends them
// over the opaque ones without writing ids or depth, so they never show in those buffers.
template <typename ColorOf>
std::vector<GlVertex> vertexArray(const Scene& scene, bool opaque_only, ColorOf&& color_of) {
  const std::vector<detail::Triangle> triangles = detail::triangulate(scene);
  std::vector<GlVertex> verts;
  verts.reserve(triangles.size() * 3);
  for (const detail::Triangle& t : triangles) {
    if (opaque_only) {
      const std::uint32_t m = scene.material(t.id);
      if (m < scene.materials.size() && scene.materials[m].alpha < 1.0f) continue;
    }
    const std::uint32_t rgba = color_of(t.id);
    for (std::uint32_t v : t.v) {
      const glm::vec3& p = scene.position(v);
      GlVertex g;
      g.x = p.x;
      g.y = p.y;
      g.z = p.z;
      for (int c = 0; c < 4; ++c) g.rgba[c] = static_cast<std::uint8_t>(rgba >> (8 * c));
      verts.push_back(g);
    }
  }
  return verts;
}

// glDrawArrays takes a GLsizei count: draw in batches of whole triangles.
void drawTriangles(std::size_t vertex_count) {
  constexpr std::size_t kBatch = 3u << 24;  // vertices per call, far below 2^31
  for (std::size_t first = 0; first < vertex_count; first += kBatch) {
    const std::size_t n = std::min(kBatch, vertex_count - first);
    glDrawArrays(GL_TRIANGLES, static_cast<GLint>(first), static_cast<GLsizei>(n));
  }
}

void checkGlError(const char* where) {
  const GLenum e = glGetError();
  if (e != GL_NO_ERROR) {
    throw std::runtime_error(std::string("OSMesa: GL error ") + std::to_string(e) + " in " + where);
  }
}

std::uint32_t packedMaterialColor(const Scene& scene, PolygonId id) {
  const std::uint32_t m = scene.material(id);
  const Material mat = m < scene.materials.size() ? scene.materials[m] : Material{};
  auto q = [](float v) {
    return static_cast<std::uint32_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f);
  };
  return q(mat.color.r) | (q(mat.color.g) << 8) | (q(mat.color.b) << 16) | (255u << 24);
}

}  // namespace

MesaFrame renderWithMesa(const Scene& scene, const Camera& camera, const RenderOptions& options) {
  if (options.polygon_mode != PolygonMode::Fill) {
    throw std::invalid_argument("renderWithMesa: only polygon mode fill is supported");
  }
  camera.validate();
  const int w = camera.width, h = camera.height;

  // The id of each triangle as its colour: RGBA bytes = id bytes, least significant first.
  const std::vector<GlVertex> verts = vertexArray(scene, true, [](PolygonId id) { return id; });

  makeCurrent(w, h);
  applyState(camera, options);

  // Draw from client-side vertex arrays.
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_COLOR_ARRAY);
  glVertexPointer(3, GL_FLOAT, sizeof(GlVertex), &verts.data()->x);
  glColorPointer(4, GL_UNSIGNED_BYTE, sizeof(GlVertex), &verts.data()->rgba[0]);
  drawTriangles(verts.size());
  glDisableClientState(GL_COLOR_ARRAY);
  glDisableClientState(GL_VERTEX_ARRAY);
  glFinish();
  checkGlError("renderWithMesa draw");

  // Read back (glReadPixels returns rows bottom first) and flip to top row first.
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  std::vector<std::uint8_t> rgba(n * 4);
  std::vector<float> z(n);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  glReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, z.data());
  checkGlError("renderWithMesa read");

  MesaFrame f;
  f.width = w;
  f.height = h;
  f.ids.resize(n);
  f.depth.resize(n);
  GLint bits = 0;
  glGetIntegerv(GL_DEPTH_BITS, &bits);
  f.depth_bits = bits;
  for (int gl_y = 0; gl_y < h; ++gl_y) {
    const std::size_t src = static_cast<std::size_t>(gl_y) * w;
    const std::size_t dst = static_cast<std::size_t>(h - 1 - gl_y) * w;
    for (int x = 0; x < w; ++x) {
      const std::uint8_t* p = &rgba[(src + x) * 4];
      f.ids[dst + x] = static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
                       (static_cast<std::uint32_t>(p[2]) << 16) |
                       (static_cast<std::uint32_t>(p[3]) << 24);
      f.depth[dst + x] = z[src + x];
    }
  }
  return f;
}

std::size_t mesaColorRoundTripErrors(int random_count) {
  // Colours: byte b in all four channels for every b, then random words (SplitMix64).
  std::vector<std::uint32_t> colors;
  for (std::uint32_t b = 0; b < 256; ++b) colors.push_back(b * 0x01010101u);
  std::uint64_t state = 0x5EED;
  for (int k = 0; k < random_count; ++k) {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    colors.push_back(static_cast<std::uint32_t>(z ^ (z >> 31)));
  }
  // One point per pixel of a 64-wide buffer, at the pixel's centre in NDC.
  const int w = 64, h = static_cast<int>((colors.size() + w - 1) / w);
  std::vector<GlVertex> verts(colors.size());
  for (std::size_t k = 0; k < colors.size(); ++k) {
    const int x = static_cast<int>(k % w), y = static_cast<int>(k / w);
    verts[k].x = (2.0f * static_cast<float>(x) + 1.0f) / static_cast<float>(w) - 1.0f;
    verts[k].y = (2.0f * static_cast<float>(y) + 1.0f) / static_cast<float>(h) - 1.0f;
    verts[k].z = 0.0f;
    for (int c = 0; c < 4; ++c) verts[k].rgba[c] = static_cast<std::uint8_t>(colors[k] >> (8 * c));
  }
  makeCurrent(w, h);
  Camera identity_camera;  // only for the common state; matrices replaced below
  identity_camera.width = w;
  identity_camera.height = h;
  RenderOptions options;
  options.depth_test = false;
  applyState(identity_camera, options);
  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  glPointSize(1.0f);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_COLOR_ARRAY);
  glVertexPointer(3, GL_FLOAT, sizeof(GlVertex), &verts.data()->x);
  glColorPointer(4, GL_UNSIGNED_BYTE, sizeof(GlVertex), &verts.data()->rgba[0]);
  glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(verts.size()));
  glDisableClientState(GL_COLOR_ARRAY);
  glDisableClientState(GL_VERTEX_ARRAY);
  glFinish();
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w) * h * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  checkGlError("mesaColorRoundTripErrors");
  std::size_t errors = 0;
  for (std::size_t k = 0; k < colors.size(); ++k) {
    const std::uint8_t* p = &rgba[k * 4];
    const std::uint32_t got =
        p[0] | (p[1] << 8) | (p[2] << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
    if (got != colors[k]) ++errors;
  }
  return errors;
}

std::string mesaRenderer() {
  makeCurrent(16, 16);
  const GLubyte* r = glGetString(GL_RENDERER);
  return r ? reinterpret_cast<const char*>(r) : "unknown";
}

MesaScene::MesaScene(const Scene& scene, const Camera& camera, const RenderOptions& options,
                     int msaa_samples)
    : camera_(camera), options_(options), msaa_samples_(msaa_samples) {
  camera_.validate();
  options_.polygon_mode = PolygonMode::Fill;
  const std::vector<GlVertex> verts =
      vertexArray(scene, false, [&](PolygonId id) { return packedMaterialColor(scene, id); });
  triangle_count_ = verts.size() / 3;
  vertex_bytes_ = verts.size() * sizeof(GlVertex);

  // Upload once into a vertex buffer object; keep a client copy if that fails.
  makeCurrent(camera_.width, camera_.height);
  glGenBuffers(1, &vbo_);
  if (vbo_ != 0) {
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertex_bytes_), verts.data(),
                 GL_STATIC_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    if (glGetError() != GL_NO_ERROR) {
      glDeleteBuffers(1, &vbo_);
      vbo_ = 0;
    }
  }
  if (vbo_ == 0) {
    client_.resize(vertex_bytes_);
    std::memcpy(client_.data(), verts.data(), vertex_bytes_);
  }
  checkGlError("MesaScene upload");
  if (msaa_samples_ > 0) {
    // A multisampled colour and depth buffer to draw into
    glGenFramebuffers(1, &fbo_);
    glGenRenderbuffers(1, &colour_rb_);
    glGenRenderbuffers(1, &depth_rb_);
    glBindRenderbuffer(GL_RENDERBUFFER, colour_rb_);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, msaa_samples_, GL_RGBA8, camera_.width,
                                     camera_.height);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_rb_);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, msaa_samples_, GL_DEPTH_COMPONENT24,
                                     camera_.width, camera_.height);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_rb_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb_);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    GLint samples = 0;
    glGetIntegerv(GL_SAMPLES, &samples);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlError("MesaScene multisampled framebuffer");
    if (status != GL_FRAMEBUFFER_COMPLETE || samples < msaa_samples_)
      throw std::runtime_error("OSMesa: no " + std::to_string(msaa_samples_) +
                               "x multisampled framebuffer (status " + std::to_string(status) +
                               ", " + std::to_string(samples) + " samples)");
  }
}

MesaScene::~MesaScene() {
  if (OSMesaGetCurrentContext() != sharedContext().ctx) return;
  if (vbo_ != 0) glDeleteBuffers(1, &vbo_);
  if (fbo_ != 0) glDeleteFramebuffers(1, &fbo_);
  if (colour_rb_ != 0) glDeleteRenderbuffers(1, &colour_rb_);
  if (depth_rb_ != 0) glDeleteRenderbuffers(1, &depth_rb_);
}

std::vector<std::uint32_t> MesaScene::colour() const {
  makeCurrent(camera_.width, camera_.height);
  const int w = camera_.width, h = camera_.height;
  std::vector<std::uint32_t> gl(static_cast<std::size_t>(w) * h), out(gl.size());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, gl.data());
  checkGlError("MesaScene colour");
  for (int y = 0; y < h; ++y)
    std::copy_n(gl.begin() + static_cast<std::ptrdiff_t>(y) * w, w,
                out.begin() + static_cast<std::ptrdiff_t>(h - 1 - y) * w);
  return out;
}

double MesaScene::renderFrameMs() {
  const auto t0 = std::chrono::steady_clock::now();
  makeCurrent(camera_.width, camera_.height);
  if (fbo_ != 0) glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  applyState(camera_, options_);  // includes glClear(COLOR | DEPTH)
  if (fbo_ != 0) glEnable(GL_MULTISAMPLE);
  // Pointers are offsets into the bound VBO, or addresses in the client copy.
  std::uintptr_t base = 0;
  if (vbo_ != 0) {
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  } else {
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    base = reinterpret_cast<std::uintptr_t>(client_.data());
  }
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_COLOR_ARRAY);
  glVertexPointer(3, GL_FLOAT, sizeof(GlVertex),
                  reinterpret_cast<const void*>(base + offsetof(GlVertex, x)));
  glColorPointer(4, GL_UNSIGNED_BYTE, sizeof(GlVertex),
                 reinterpret_cast<const void*>(base + offsetof(GlVertex, rgba)));
  drawTriangles(triangle_count_ * 3);
  glDisableClientState(GL_COLOR_ARRAY);
  glDisableClientState(GL_VERTEX_ARRAY);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  if (fbo_ != 0) {  // resolve: the samples' mean into the window buffer
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glBlitFramebuffer(0, 0, camera_.width, camera_.height, 0, 0, camera_.width, camera_.height,
                      GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDisable(GL_MULTISAMPLE);
  }
  glFinish();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace hsr::testing

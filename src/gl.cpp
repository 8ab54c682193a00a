// The GL-style facade: OpenGL state in, draws into persistent buffers through the one
// orchestrator (orchestrator.cpp), with the algorithm the state names (the z-buffer by default).

#include "hsr/gl.hpp"

#include <algorithm>
#include <cmath>

#include "core/frame.hpp"
#include "hsr/error.hpp"
#include "orchestrator.hpp"

namespace hsr::gl {

Context::Context(const Camera& camera) : camera_(camera) {
  camera_.validate();
  state_.depth_test = false;  // OpenGL's default: GL_DEPTH_TEST disabled
  state_.cull = CullMode::None;
  state_.shade = true;
  state_.clear_color = {0.0f, 0.0f, 0.0f};  // glClearColor's default
  detail::clearFrame(frame_, camera_.width, camera_.height, state_);
}

void Context::enable(Capability cap) {
  if (cap == DEPTH_TEST) state_.depth_test = true;
  if (cap == CULL_FACE) cull_enabled_ = true;
}

void Context::disable(Capability cap) {
  if (cap == DEPTH_TEST) state_.depth_test = false;
  if (cap == CULL_FACE) cull_enabled_ = false;
}

bool Context::isEnabled(Capability cap) const {
  return cap == DEPTH_TEST ? state_.depth_test : cull_enabled_;
}

void Context::clear(unsigned bits) {
  Frame cleared;
  detail::clearFrame(cleared, camera_.width, camera_.height, state_);
  if (bits & COLOR_BUFFER_BIT) {
    frame_.color = cleared.color;
    std::fill(frame_.overdraw.begin(), frame_.overdraw.end(), 0u);
  }
  // The depth buffer's partner here is the id buffer: what is nearest is what is visible.
  // glClear's depth write mask applies, as in OpenGL.
  if ((bits & DEPTH_BUFFER_BIT) && state_.depth_mask) {
    frame_.depth = cleared.depth;
    frame_.ids = cleared.ids;
  }
}

void Context::polygonMode(Mode m) {
  state_.polygon_mode = m == POINT  ? PolygonMode::Point
                        : m == LINE ? PolygonMode::Line
                                    : PolygonMode::Fill;
}

void Context::setCamera(const Camera& camera) {
  if (camera.width != camera_.width || camera.height != camera_.height)
    throw Error("setCamera: the viewport size of a context is fixed");
  camera.validate();
  camera_ = camera;
}

void Context::draw(const Scene& scene) {
  RenderOptions o = state_;
  o.cull = !cull_enabled_        ? CullMode::None
           : cull_face_ == FRONT ? CullMode::Front
           : cull_face_ == BACK  ? CullMode::Back
                                 : CullMode::FrontAndBack;
  detail::renderInto(scene, camera_, o, frame_, detail::DrawMode::kOver);
}

}  // namespace hsr::gl

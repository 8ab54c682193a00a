#pragma once
// A GL-style facade over the z-buffer, mirroring the calls the lecture notes show:
//   glEnable(GL_DEPTH_TEST); glDepthMask(GL_TRUE); glClear(COLOR | DEPTH);
//   glEnable(GL_CULL_FACE); glCullFace(GL_BACK); glFrontFace(GL_CCW); glPolygonMode(...)
// State persists between draw() calls exactly as in OpenGL; buffers persist until clear().

#include "hsr/camera.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"

namespace hsr::gl {

enum Capability { DEPTH_TEST, CULL_FACE };
enum ClearBits : unsigned { COLOR_BUFFER_BIT = 1u, DEPTH_BUFFER_BIT = 2u };
enum Face { FRONT, BACK, FRONT_AND_BACK };
enum Winding { CW, CCW };
enum Mode { POINT, LINE, FILL };

class Context {
 public:
  // The camera fixes the viewport size; the context starts in OpenGL's default state
  // (depth test and culling disabled, depth mask on, LESS, cull BACK, CCW, FILL) and with
  // cleared buffers.
  explicit Context(const Camera& camera);

  void enable(Capability cap);
  void disable(Capability cap);
  bool isEnabled(Capability cap) const;
  void depthMask(bool flag) { state_.depth_mask = flag; }
  void depthFunc(DepthFunc func) { state_.depth_func = func; }
  void clearColor(float r, float g, float b) { state_.clear_color = {r, g, b}; }
  void clearDepth(float d) { state_.clear_depth = d; }
  void clear(unsigned bits);  // COLOR_BUFFER_BIT | DEPTH_BUFFER_BIT (depth also clears ids)
  void cullFace(Face face) { cull_face_ = face; }
  void frontFace(Winding w) { state_.front_face = (w == CCW) ? FrontFace::Ccw : FrontFace::Cw; }
  void polygonMode(Mode m);
  void pointSize(float size) { state_.point_size = size; }  // glPointSize: 1 to 64, checked by draw
  void setCamera(const Camera& camera);                     // same size as the context's
  void draw(const Scene& scene);  // draws every polygon of the scene, in id order

  const Frame& frame() const { return frame_; }
  const RenderOptions& state() const { return state_; }  // the state as render() options

 private:
  Camera camera_;
  RenderOptions state_;
  bool cull_enabled_ = false;
  Face cull_face_ = BACK;
  Frame frame_;
};

}  // namespace hsr::gl

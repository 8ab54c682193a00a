// libFuzzer target: bytes -> scene -> render at up to 64x64. The bytes are read as a scene
// description: render state, a camera (raw float bit patterns: NaN, Inf, 1e38, subnormals),
// then objects of vertices (raw floats) and polygons (vertex counts and indices, some out of
// range). Every path of the pipeline and the z-buffer is reachable: clipping, culling both
// ways, LINE and POINT modes, outlines, transparency, depth functions, mask. hsr::Error is
// the expected answer to a bad scene or camera; anything else (crash, sanitizer report,
// float-cast overflow, hang) is a finding.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"

namespace {

class Bytes {
 public:
  Bytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  bool empty() const { return pos_ >= size_; }
  std::uint8_t u8() { return pos_ < size_ ? data_[pos_++] : 0; }
  std::uint32_t u32() {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= std::uint32_t(u8()) << (8 * i);
    return v;
  }
  // A float: usually a small value (so that scenes are visible), sometimes a raw bit pattern
  float f32() {
    const std::uint8_t kind = u8();
    if (kind < 192)
      return (static_cast<float>(kind) - 96.0f) / 16.0f + static_cast<float>(u8()) / 4096.0f;
    const std::uint32_t bits = u32();
    float v;
    std::memcpy(&v, &bits, 4);
    return v;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_, pos_ = 0;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes in(data, size);
  hsr::RenderOptions options;
  options.threads = 1 + (in.u8() & 1);
  const std::uint8_t state = in.u8(), state2 = in.u8();
  options.cull = static_cast<hsr::CullMode>(state & 3);
  options.front_face = static_cast<hsr::FrontFace>((state >> 2) & 1);
  options.facing_test = static_cast<hsr::FacingTest>((state >> 3) & 1);
  options.polygon_mode = static_cast<hsr::PolygonMode>(((state >> 4) & 3) % 3);
  options.depth_test = (state & 64) == 0;
  options.depth_mask = (state & 128) == 0;
  options.depth_func = static_cast<hsr::DepthFunc>(state2 & 7);
  options.outline = (state2 & 8) != 0;
  options.shade = (state2 & 16) == 0;
  options.frustum_cull = (state2 & 32) == 0;
  if (state2 & 64) options.clear_depth = in.f32();

  hsr::Camera camera;
  camera.width = 1 + in.u8() % 64;
  camera.height = 1 + in.u8() % 64;
  camera.ortho = (state2 & 128) != 0;
  camera.eye = {in.f32(), in.f32(), in.f32() + 6.0f};
  camera.target = {in.f32(), in.f32(), in.f32()};
  camera.up = {0.0f, 1.0f, 0.0f};
  if (in.u8() & 1) camera.up = {in.f32(), in.f32(), in.f32()};
  camera.fov_deg = 45.0f + in.f32() * 4.0f;
  camera.ortho_half_height = 4.0f + in.f32();
  camera.near = 0.1f + in.f32() * in.f32();
  camera.far = 20.0f + in.f32() * 8.0f;

  try {
    hsr::Scene scene;
    scene.addMaterial({});
    scene.addMaterial({{0.2f, 0.4f, 0.9f}, 0.5f});  // transparent
    std::vector<std::uint32_t> local;
    while (!in.empty() && scene.polygonCount() < 4096) {
      scene.beginObject("fuzz");
      const unsigned vertices = in.u8() % 32;
      for (unsigned v = 0; v < vertices; ++v) scene.addVertex({in.f32(), in.f32(), in.f32()});
      const unsigned polygons = in.u8() % 32;
      for (unsigned p = 0; p < polygons && !in.empty(); ++p) {
        const std::uint8_t head = in.u8();
        local.clear();
        const unsigned n = 3 + (head & 7);
        // 1 in 32 indices out of range (addPolygon must refuse them)
        for (unsigned k = 0; k < n; ++k) {
          const std::uint8_t b = in.u8();
          local.push_back(b >= 248 ? vertices + b : (vertices ? b % vertices : 0));
        }
        scene.addPolygon(local, (head >> 3) & 1);
      }
    }
    if (scene.polygonCount() == 0) return 0;
    const hsr::Frame frame = hsr::render(scene, camera, options);
    for (const char* kind : {"color", "depth", "ids", "overdraw"}) (void)hsr::picture(frame, kind);
    (void)hsr::statsJson(frame, "fuzz", options.algorithm);
  } catch (const hsr::Error&) {
  }
  return 0;
}

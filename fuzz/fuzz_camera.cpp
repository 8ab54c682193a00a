// libFuzzer target: the camera readers a user's file reaches (hsr/io.hpp): the camera JSON of
// --camera (and a manifest.json or --stats file holding one), the list of --views, and the
// pose text of --pose. A camera read is validated by the reader; it is then rendered at up to
// 32x32 on the demo scene, with its intrinsics scaled along, so that what a reader lets
// through is also drawn. hsr::Error is the expected answer to bad input; anything else is a
// finding.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"

namespace {

void draw(hsr::Camera c) {
  static const hsr::Scene demo = hsr::makeBuiltinScene("demo");
  const double sx = std::min(1.0, 32.0 / c.width), sy = std::min(1.0, 32.0 / c.height);
  c.width = std::max(1, static_cast<int>(c.width * sx));
  c.height = std::max(1, static_cast<int>(c.height * sy));
  if (c.intrinsics.given())
    c.intrinsics = {c.intrinsics.fx * sx, c.intrinsics.fy * sy, c.intrinsics.cx * sx,
                    c.intrinsics.cy * sy};
  try {
    c.validate();
    hsr::RenderOptions o;
    o.threads = 1;
    hsr::render(demo, c, o);
  } catch (const hsr::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    draw(hsr::cameraFromJson(text));
  } catch (const hsr::Error&) {
  }
  try {
    const std::vector<hsr::Camera> views = hsr::camerasFromJson(text);
    for (std::size_t k = 0; k < std::min<std::size_t>(views.size(), 4); ++k) draw(views[k]);
  } catch (const hsr::Error&) {
  }
  try {
    hsr::Camera c;
    hsr::setPose(c, hsr::poseFromText(text), hsr::PoseConvention::kOpenCV);
    draw(c);
  } catch (const hsr::Error&) {
  }
  return 0;
}

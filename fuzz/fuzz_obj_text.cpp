// libFuzzer target: bytes -> hsr::parseObjText (the web page's OBJ reader, which reads files a
// visitor drops on the page) -> the scene drawn at 32x24 by the z-buffer. hsr::Error is the
// expected answer to a bad file; anything else (crash, sanitizer report, huge allocation,
// hang) is a finding.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const hsr::Scene scene =
        hsr::parseObjText(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.obj");
    hsr::RenderOptions options;
    options.threads = 1;
    (void)hsr::render(scene, hsr::frameScene(scene, 32, 24), options);
  } catch (const hsr::Error&) {
  }
  return 0;
}

// libFuzzer target: bytes -> mesh file (the format chosen by the first byte) -> scene ->
// render at 64x64. Any crash, hang, leak or sanitizer report is a finding; a clean hsr::Error
// is the expected answer to bad input.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* kExt[] = {".obj", ".ply", ".stl", ".off", ".gltf", ".glb"};
  const std::string ext = kExt[data[0] % 6];
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                     ("hsr_fuzz_" + std::to_string(::getpid()) + ext);
  {
    std::ofstream f(path, std::ios::binary);
    f.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  try {
    const hsr::Scene scene = hsr::loadMeshFile(path);
    const hsr::Camera camera = hsr::frameScene(scene, 64, 64);
    hsr::RenderOptions options;
    options.threads = 1;
    options.outline = (data[0] & 8) != 0;
    options.cull = static_cast<hsr::CullMode>((data[0] >> 4) & 3);
    hsr::render(scene, camera, options);
  } catch (const hsr::Error&) {
  }
  std::filesystem::remove(path);
  return 0;
}

// libFuzzer target for one mesh format through our import layer: bytes -> a file with the
// format's extension (HSR_FUZZ_EXT) -> hsr::loadMeshFile (size checks, the isolated assimp
// child, preflight, conversion) -> render at 64x64 with outlines. Any crash, hang, leak or
// sanitizer report in this process is a finding; hsr::Error is the expected answer to bad
// input, and so is a crash of assimp inside the import's child process (contained, refused)
// or an import past the child's memory limit. A sanitizer or libFuzzer report from inside
// the child aborts this process (mesh_import.cpp): a finding too, with this input.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include <unistd.h>

#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"

#ifndef HSR_FUZZ_EXT
#error "define HSR_FUZZ_EXT, e.g. \".obj\""
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // One file per process, written for each input (the import reads it by name) and removed
  // after it, so that a run that ends leaves nothing in the temporary directory
  static const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("hsr_fuzz_" + std::to_string(::getpid()) + HSR_FUZZ_EXT);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  const bool written = size == 0 || std::fwrite(data, 1, size, f) == size;
  if (std::fclose(f) != 0 || !written) return 0;
  try {
    hsr::ImportLimits limits;
    limits.timeout_seconds = 5;  // under libFuzzer's -timeout=10: a hang is refused, not hung
    const hsr::Scene scene = hsr::loadMeshFile(path, limits);
    const hsr::Camera camera = hsr::frameScene(scene, 64, 64);
    hsr::RenderOptions options;
    options.threads = 1;
    options.outline = true;
    hsr::render(scene, camera, options);
  } catch (const hsr::Error&) {
  }
  std::remove(path.c_str());
  return 0;
}

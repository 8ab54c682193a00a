#pragma once
// Scene sources (mesh files through assimp, built-in scenes) and writers (PNG, NPY, JSON).

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "hsr/render.hpp"
#include "hsr/scene.hpp"

namespace hsr {

// Loads SCENE: an existing file wins; otherwise a built-in name. Throws hsr::Error with a
// one-line reason (missing file, unreadable format, empty scene, non-finite coordinates...).
Scene loadScene(std::string_view spec);
// What a mesh import may spend. assimp runs in a child process that is killed after
// timeout_seconds, and may use memory_bytes beyond what this process holds when it starts;
// past either limit the file is refused with one line. memory_bytes = 0 sizes it by the file:
// 256 bytes per byte on disk (a dense OBJ needs 140), at least 1 GiB, at most 16 GiB; for
// glTF, the files beside it (its buffers) count as its size too.
struct ImportLimits {
  int timeout_seconds = 120;
  std::uint64_t memory_bytes = 0;
};
// Mesh files: anything assimp reads. Polygons stay polygons (no triangulation), node
// transforms are applied, ids follow node order then face order. Safe on untrusted input.
Scene loadMeshFile(const std::filesystem::path& path, const ImportLimits& limits = {});

struct BuiltinScene {
  std::string_view name;     // e.g. "spheres:N"
  std::string_view summary;
};
const std::vector<BuiltinScene>& builtinScenes();
// Built-ins: demo, cyclic, penetrating, spheres:N, soup:N:SEED (N: digits with an optional
// k or M suffix). Deterministic. An N above max_triangles is refused (hsr::Error), before
// anything is built.
inline constexpr std::uint64_t kMaxBuiltinTriangles = 20'000'000;
Scene makeBuiltinScene(std::string_view spec, std::uint64_t max_triangles = kMaxBuiltinTriangles);

// Writers. Images are written top row first. All throw hsr::Error on I/O failure.
void writePng(const std::filesystem::path& path, int width, int height, int channels,
              const std::uint8_t* pixels);
void writeNpy(const std::filesystem::path& path, int width, int height, const float* data);
void writeNpy(const std::filesystem::path& path, int width, int height,
              const std::uint32_t* data);

// Pictures of a frame's buffers, RGB8 top row first.
std::vector<std::uint8_t> depthPicture(const Frame& frame);     // normalised grey, near = light
// The depth range of the drawn pixels, and a depth picture normalised over a given range
// (so that the pictures of a sequence share one scale).
struct DepthRange {
  float lo, hi;
};
DepthRange drawnDepthRange(const Frame& frame);
std::vector<std::uint8_t> depthPicture(const Frame& frame, DepthRange range);
std::vector<std::uint8_t> idPicture(const Frame& frame);        // hashed palette, bg black
std::vector<std::uint8_t> overdrawPicture(const Frame& frame);  // heatmap
std::vector<std::uint8_t> picture(const Frame& frame, std::string_view kind);  // by name

std::string statsJson(const Frame& frame, const std::string& scene, const std::string& algorithm);

}  // namespace hsr

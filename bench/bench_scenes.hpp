#pragma once
// The benchmarks' scenes, one list for every race (bench_algorithms, bench_rays, bench_lines):
// the same label names the same triangles in every table, and a scene added here is one line.
// Each race picks its scenes by label. Built-ins are deterministic; the models are Debian's
// assimp-testmodels.

#include <algorithm>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/scene.hpp"

namespace hsr::bench {

inline constexpr const char* kModels = "/usr/share/assimp/models";

struct BenchSceneSpec {
  std::string label;  // "spheres/10000", "2CylinderEngine": the benchmark names' suffix
  std::string spec;   // what loadScene reads: "spheres:10000", or a model's path
};

inline const std::vector<BenchSceneSpec>& benchSceneList() {
  static const std::vector<BenchSceneSpec> list = [] {
    std::vector<BenchSceneSpec> v;
    // spheres:N, a grid of spheres most of which hide behind the front ones; soup:N, small
    // random triangles (depth complexity without structure)
    for (const char* kind : {"spheres", "soup"})
      for (const char* n : {"1000", "10000", "100000", "1000000"})
        v.push_back({std::string(kind) + "/" + n, std::string(kind) + ":" + n});
    const auto model = [&](const char* file) {
      const std::filesystem::path path = std::filesystem::path(kModels) / file;
      v.push_back({path.stem().string(), path.string()});
    };
    model("glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb");  // a CAD assembly, 121,496
                                                                     // triangles
    model("PLY/Wuson.ply");          // a scanned figure, one closed surface
    model("STL/Spider_binary.stl");  // thin legs crossing each other
    return v;
  }();
  return list;
}

inline const BenchSceneSpec& benchScene(std::string_view label) {
  const auto& list = benchSceneList();
  const auto it = std::find_if(list.begin(), list.end(),
                               [&](const BenchSceneSpec& s) { return s.label == label; });
  if (it == list.end())
    throw Error("bench: no scene '" + std::string(label) + "' in bench/bench_scenes.hpp");
  return *it;
}

inline Scene loadBenchScene(const BenchSceneSpec& s) { return loadScene(s.spec); }

}  // namespace hsr::bench

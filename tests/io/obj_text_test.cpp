// The web page's OBJ reader (hsr::parseObjText) against assimp's (hsr::loadMeshFile) on
// Debian's OBJ test models: the same polygons with the same vertices; and its refusals, each
// naming the line.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "hsr/error.hpp"
#include "hsr/io.hpp"

namespace hsr {
namespace {

const std::filesystem::path kModels = "/usr/share/assimp/models/OBJ";

std::string readText(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Each polygon as its vertices from the lowest one on (the same cycle whoever stored it), all
// polygons sorted: what both readers must agree on whatever order they keep. Coordinates are
// compared to 1e-3 for the order and to 2^-21 relative for equality: assimp's number parser
// (fast_atof) is not correctly rounded, ours (strtof) is, so the two can differ in the last bit.
using Polygons = std::vector<std::vector<float>>;
Polygons polygonsOf(const Scene& scene) {
  auto coarse = [](float v) { return std::round(v * 1000.0f); };
  auto below = [&](const glm::vec3& a, const glm::vec3& b) {
    for (int k = 0; k < 3; ++k)
      if (coarse(a[k]) != coarse(b[k])) return coarse(a[k]) < coarse(b[k]);
    return false;
  };
  Polygons out;
  for (PolygonId p = 0; p < scene.polygonCount(); ++p) {
    std::vector<glm::vec3> v;
    for (const std::uint32_t i : scene.polygon(p)) v.push_back(scene.position(i));
    std::rotate(v.begin(), std::min_element(v.begin(), v.end(), below), v.end());
    std::vector<float> flat;
    for (const glm::vec3& q : v) flat.insert(flat.end(), {q.x, q.y, q.z});
    out.push_back(std::move(flat));
  }
  std::stable_sort(out.begin(), out.end(),
                   [&](const std::vector<float>& a, const std::vector<float>& b) {
                     if (a.size() != b.size()) return a.size() < b.size();
                     for (std::size_t k = 0; k < a.size(); ++k)
                       if (coarse(a[k]) != coarse(b[k])) return coarse(a[k]) < coarse(b[k]);
                     return false;
                   });
  return out;
}

// How many coordinates differ by more than 2^-21 of their size, and how many differ at all
std::pair<int, int> differences(const Polygons& a, const Polygons& b) {
  int far = 0, any = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    if (a[i].size() != b[i].size()) {
      ++far;
      continue;
    }
    for (std::size_t k = 0; k < a[i].size(); ++k) {
      any += a[i][k] != b[i][k];
      far += std::abs(a[i][k] - b[i][k]) > 0x1p-21f * std::max(1.0f, std::abs(a[i][k]));
    }
  }
  return {far, any};
}

TEST(ObjText, ReadsDebiansModelsAsAssimpDoes) {
  int models = 0;
  for (const char* name :
       {"box.obj", "concave_polygon.obj", "cube_usemtl.obj", "testmixed.obj", "multiple_spaces.obj",
        "box_without_lineending.obj", "spider.obj", "WusonOBJ.obj"}) {
    SCOPED_TRACE(name);
    const std::filesystem::path path = kModels / name;
    ASSERT_TRUE(std::filesystem::exists(path))
        << "assimp-testmodels is installed by scripts/install-deps.sh";
    const Scene ours = parseObjText(readText(path), name);
    const Scene theirs = loadMeshFile(path);
    EXPECT_EQ(ours.polygonCount(), theirs.polygonCount());
    EXPECT_EQ(ours.triangleCount(), theirs.triangleCount());
    const auto [far, any] = differences(polygonsOf(ours), polygonsOf(theirs));
    EXPECT_EQ(far, 0) << "coordinates that differ (" << any << " in the last bits)";
    ++models;
  }
  EXPECT_EQ(models, 8);
}

TEST(ObjText, KeepsTheFilesOrderObjectsAndMaterials) {
  const Scene s = parseObjText(
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
      "o first\nusemtl red\nf 1 2 3 4\ng second\nusemtl blue\nf 1/1 2/2 3/3\nusemtl red\nf -4//1 "
      "-2//1 -1//1\n",
      "t.obj");
  ASSERT_EQ(s.polygonCount(), 3u);
  ASSERT_EQ(s.objects.size(), 2u);
  EXPECT_EQ(s.objects[0].name, "first");
  EXPECT_EQ(s.objects[1].name, "second");
  EXPECT_EQ(s.object(0), 0u);
  EXPECT_EQ(s.object(1), 1u);
  EXPECT_EQ(s.object(2), 1u);
  EXPECT_EQ(s.material(0), s.material(2));  // "red" twice: one material
  EXPECT_NE(s.material(0), s.material(1));
  EXPECT_EQ(s.polygon(0).size(), 4u);
  EXPECT_EQ(s.position(s.polygon(2)[2]), glm::vec3(0, 1, 0));  // -1: the last vertex
}

TEST(ObjText, RefusesBadFilesNamingTheLine) {
  const std::pair<const char*, const char*> cases[] = {
      {"v 0 0 0\nv 1 0 0\nf 1 2\n", "t.obj:3: a face needs three corners or more"},
      {"v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 4\n", "t.obj:4: vertex 4 does not exist (3 so far)"},
      {"v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 0\n", "t.obj:4: '0' is not a vertex index"},
      {"v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 -4\n", "t.obj:4: vertex -4 does not exist (3 so far)"},
      {"v 0 0\n", "t.obj:1: a vertex needs three coordinates"},
      {"v 0 x 0\n", "t.obj:1: 'x' is not a number"},
      {"v 1e+2 2.e+1 3.1+e2\n",
       "t.obj:1: '3.1+e2' is not a number"},  // assimp reads 3.1 (number_formats.obj)
      {"v 0 1e39 0\n", "t.obj:1: '1e39' is not a finite coordinate"},
      {"v 0 nan 0\n", "t.obj:1: 'nan' is not a finite coordinate"},
      {"v 0 0 0\n# nothing else\n", "t.obj: no faces"},
      {"", "t.obj: no faces"},
  };
  for (const auto& [text, why] : cases) {
    SCOPED_TRACE(text);
    try {
      (void)parseObjText(text, "t.obj");
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()), why);
    }
  }
}

}  // namespace
}  // namespace hsr

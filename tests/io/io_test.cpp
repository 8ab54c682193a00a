// src/io: built-in scenes (deterministic, the promised sizes and windings), the assimp import
// (real models load, hostile ones give one clean hsr::Error) and the writers (.npy parses
// back, PNG decodes back, pictures and stats JSON say what they should).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#include "png_read.hpp"

#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/scene.hpp"
#include "test_util.hpp"

namespace {

namespace fs = std::filesystem;
using hsr::Scene;
using hsr::testing::ScratchDir;

const fs::path kModels = HSR_TEST_MODELS;

void writeFile(const fs::path& p, const std::string& bytes) {
  std::ofstream f(p, std::ios::binary);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string readFile(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// Every index in range, every polygon with >= 3 vertices, every position finite, every
// material valid, objects tiling the polygons in order.
void expectWellFormed(const Scene& s, const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_GT(s.polygonCount(), 0u);
  for (const glm::vec3& p : s.positions())
    ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
  for (hsr::PolygonId id = 0; id < s.polygonCount(); ++id) {
    ASSERT_GE(s.polygon(id).size(), 3u) << "polygon " << id;
    for (std::uint32_t v : s.polygon(id)) ASSERT_LT(v, s.vertexCount()) << "polygon " << id;
    ASSERT_LT(s.material(id), s.materials.size()) << "polygon " << id;
  }
  std::uint32_t next = 0;
  for (const hsr::Object& o : s.objects) {
    EXPECT_EQ(o.first_polygon, next) << o.name;
    next += o.polygon_count;
  }
  EXPECT_EQ(next, s.polygonCount());
}

void expectIdentical(const Scene& a, const Scene& b) {
  ASSERT_EQ(a.polygonCount(), b.polygonCount());
  ASSERT_EQ(a.vertexCount(), b.vertexCount());
  EXPECT_EQ(
      std::memcmp(a.positions().data(), b.positions().data(), a.vertexCount() * sizeof(glm::vec3)),
      0);
  for (hsr::PolygonId id = 0; id < a.polygonCount(); ++id) {
    ASSERT_TRUE(std::ranges::equal(a.polygon(id), b.polygon(id))) << "polygon " << id;
    ASSERT_EQ(a.material(id), b.material(id)) << "polygon " << id;
  }
}

// Signed volume of a closed polyhedron (divergence theorem over fan-triangulated faces):
// positive when every face is wound counter-clockwise seen from outside.
double signedVolume(const Scene& s, const hsr::Object& o) {
  double v = 0.0;
  for (std::uint32_t id = o.first_polygon; id < o.first_polygon + o.polygon_count; ++id) {
    const auto poly = s.polygon(id);
    const glm::dvec3 p0 = s.position(poly[0]);
    for (std::size_t k = 1; k + 1 < poly.size(); ++k)
      v += glm::dot(p0, glm::cross(glm::dvec3(s.position(poly[k])),
                                   glm::dvec3(s.position(poly[k + 1])))) /
           6.0;
  }
  return v;
}

const hsr::Object& objectNamed(const Scene& s, const std::string& name) {
  for (const hsr::Object& o : s.objects)
    if (o.name == name) return o;
  ADD_FAILURE() << "no object " << name;
  return s.objects.front();
}

// ---------------------------------------------------------------------------------------
// Built-in scenes

const char* const kSpecs[] = {"demo",         "cyclic",     "penetrating", "spheres:100",
                              "spheres:1000", "soup:100:1", "soup:7"};

TEST(BuiltinScenes, EveryBuiltinBuildsWellFormed) {
  for (const char* spec : kSpecs) {
    const Scene s = hsr::makeBuiltinScene(spec);
    expectWellFormed(s, spec);
    EXPECT_EQ(s.name, spec);
  }
}

TEST(BuiltinScenes, SameSpecGivesIdenticalScene) {
  for (const char* spec : kSpecs) {
    SCOPED_TRACE(spec);
    expectIdentical(hsr::makeBuiltinScene(spec), hsr::makeBuiltinScene(spec));
  }
}

TEST(BuiltinScenes, ListNamesEveryBuiltin) {
  std::set<std::string> names;
  for (const hsr::BuiltinScene& b : hsr::builtinScenes()) {
    names.insert(std::string(b.name));
    EXPECT_FALSE(b.summary.empty()) << b.name;
  }
  for (const char* n : {"demo", "cyclic", "penetrating", "spheres:N", "soup:N:SEED"})
    EXPECT_TRUE(names.count(n)) << n;
}

TEST(BuiltinScenes, SpheresHaveAboutNTriangles) {
  for (std::size_t n : {100u, 1000u, 12345u, 100000u}) {
    const Scene s = hsr::makeBuiltinScene("spheres:" + std::to_string(n));
    EXPECT_EQ(s.triangleCount(), s.polygonCount()) << "spheres are made of triangles";
    EXPECT_GE(s.triangleCount(), n * 0.9) << n;
    EXPECT_LE(s.triangleCount(), n * 1.1) << n;
    // One object per sphere, each with its own vertices, shared within the sphere
    EXPECT_GE(s.objects.size(), 2u);
    EXPECT_LT(s.vertexCount(), s.polygonCount());
  }
}

TEST(BuiltinScenes, CountSuffixesAreThousandsAndMillions) {
  EXPECT_EQ(hsr::makeBuiltinScene("spheres:2k").triangleCount(),
            hsr::makeBuiltinScene("spheres:2000").triangleCount());
  EXPECT_EQ(hsr::makeBuiltinScene("soup:3k:3").polygonCount(), 3000u);
  EXPECT_THROW(hsr::makeBuiltinScene("spheres:21M"), hsr::Error);  // over 20M
}

TEST(BuiltinScenes, SphereTrianglesFaceOutward) {
  const Scene s = hsr::makeBuiltinScene("spheres:5000");
  for (const hsr::Object& o : s.objects) {
    const glm::vec3 c = o.bounds.center();
    for (std::uint32_t id = o.first_polygon; id < o.first_polygon + o.polygon_count; ++id) {
      const auto t = s.polygon(id);
      const glm::vec3 a = s.position(t[0]), b = s.position(t[1]), d = s.position(t[2]);
      const glm::vec3 n = glm::cross(b - a, d - a);
      ASSERT_GT(glm::dot(n, (a + b + d) / 3.0f - c), 0.0f) << o.name << " polygon " << id;
    }
  }
}

TEST(BuiltinScenes, DemoSolidsAreClosedAndWoundOutward) {
  const Scene s = hsr::makeBuiltinScene("demo");
  for (const char* name : {"convex dodecahedron", "non-convex star prism", "cube behind glass"}) {
    const hsr::Object& o = objectNamed(s, name);
    // Shift to the object's centre so the volume does not depend on where it stands
    Scene local;
    local.beginObject(name);
    for (std::uint32_t v = 0; v < o.vertex_count; ++v)
      local.addVertex(s.position(o.first_vertex + v) - o.bounds.center());
    for (std::uint32_t id = o.first_polygon; id < o.first_polygon + o.polygon_count; ++id) {
      std::vector<std::uint32_t> idx;
      for (std::uint32_t v : s.polygon(id)) idx.push_back(v - o.first_vertex);
      local.addPolygon(idx, 0);
    }
    EXPECT_GT(signedVolume(local, local.objects[0]), 0.1) << name;
  }
  // Exactly one translucent material, and it is used
  int translucent = 0;
  for (hsr::PolygonId id = 0; id < s.polygonCount(); ++id)
    translucent += s.materials[s.material(id)].alpha < 1.0f;
  EXPECT_EQ(translucent, 1);
  // The dodecahedron keeps its pentagons, the star its concave 10-gons
  const hsr::Object& dodeca = objectNamed(s, "convex dodecahedron");
  EXPECT_EQ(dodeca.polygon_count, 12u);
  EXPECT_EQ(s.polygon(dodeca.first_polygon).size(), 5u);
  EXPECT_EQ(s.polygon(objectNamed(s, "non-convex star prism").first_polygon).size(), 10u);
}

// z of the plane through polygon `id` at (x, y).
float planeZ(const Scene& s, hsr::PolygonId id, glm::vec2 xy) {
  const auto q = s.polygon(id);
  const glm::vec3 a = s.position(q[0]);
  const glm::vec3 n = glm::cross(s.position(q[1]) - a, s.position(q[2]) - a);
  return a.z - (n.x * (xy.x - a.x) + n.y * (xy.y - a.y)) / n.z;
}

TEST(BuiltinScenes, CyclicSticksOverlapInACycle) {
  // Where stick i's centre line crosses stick i+1's (in x,y), stick i is nearer the viewer
  // (higher z): 0 over 1, 1 over 2, 2 over 0, so no depth order exists.
  const Scene s = hsr::makeBuiltinScene("cyclic");
  ASSERT_EQ(s.polygonCount(), 3u);
  const auto centreLine = [&](hsr::PolygonId id, glm::vec2* p, glm::vec2* d) {
    const auto q = s.polygon(id);
    const glm::vec3 a = (s.position(q[0]) + s.position(q[3])) * 0.5f;
    const glm::vec3 b = (s.position(q[1]) + s.position(q[2])) * 0.5f;
    *p = {a.x, a.y};
    *d = glm::vec2(b.x, b.y) - *p;
  };
  for (hsr::PolygonId i = 0; i < 3; ++i) {
    const hsr::PolygonId j = (i + 1) % 3;
    glm::vec2 p, d, q, e;
    centreLine(i, &p, &d);
    centreLine(j, &q, &e);
    // p + t d = q + u e
    const float det = d.x * (-e.y) - d.y * (-e.x);
    ASSERT_NE(det, 0.0f);
    const glm::vec2 r = q - p;
    const float t = (r.x * (-e.y) - r.y * (-e.x)) / det;
    const float u = (d.x * r.y - d.y * r.x) / det;
    ASSERT_TRUE(t > 0 && t < 1 && u > 0 && u < 1) << "sticks " << i << " and " << j << " cross";
    const glm::vec2 x = p + t * d;
    EXPECT_GT(planeZ(s, i, x), planeZ(s, j, x) + 0.05f) << "stick " << i << " over " << j;
  }
}

TEST(BuiltinScenes, PenetratingQuadsPierceEachOther) {
  const Scene s = hsr::makeBuiltinScene("penetrating");
  ASSERT_EQ(s.polygonCount(), 2u);
  for (hsr::PolygonId a = 0; a < 2; ++a) {
    const auto q = s.polygon(a);
    const glm::vec3 p0 = s.position(q[0]);
    const glm::vec3 n = glm::cross(s.position(q[1]) - p0, s.position(q[2]) - p0);
    int above = 0, below = 0;
    for (std::uint32_t v : s.polygon(1 - a)) {
      const float side = glm::dot(n, s.position(v) - p0);
      above += side > 0, below += side < 0;
    }
    EXPECT_GT(above, 0) << a;
    EXPECT_GT(below, 0) << a;
  }
}

TEST(BuiltinScenes, SoupDependsOnlyOnNAndSeed) {
  const Scene a = hsr::makeBuiltinScene("soup:50:1");
  const Scene b = hsr::makeBuiltinScene("soup:50:2");
  EXPECT_EQ(a.polygonCount(), 50u);
  EXPECT_NE(std::memcmp(a.positions().data(), b.positions().data(), 150 * sizeof(glm::vec3)), 0);
  expectIdentical(hsr::makeBuiltinScene("soup:50"), hsr::makeBuiltinScene("soup:50:1"));
  // Inside the promised box: centres in [-1,1]^3, corners a little around them
  for (const glm::vec3& p : a.positions())
    EXPECT_LT(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}), 1.3f);
}

TEST(BuiltinScenes, BadSpecsThrowError) {
  for (const char* spec : {"",
                           "nope",
                           "Demo",
                           "demo:1",
                           "spheres",
                           "spheres:",
                           "spheres:abc",
                           "spheres:0",
                           "spheres:-5",
                           "spheres:+5",
                           "spheres:1e6",
                           "spheres:20000001",
                           "spheres:99999999999999999999",
                           "spheres:10:3",
                           "spheres:5G",
                           "soup",
                           "soup:",
                           "soup:0:1",
                           "soup:10:x",
                           "soup:10:-1",
                           "soup:10:1:2",
                           "soup:30M:1",
                           "cyclic:"}) {
    EXPECT_THROW(hsr::makeBuiltinScene(spec), hsr::Error) << "'" << spec << "'";
  }
  try {
    hsr::makeBuiltinScene("teapot");
    FAIL();
  } catch (const hsr::Error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown scene 'teapot'"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------------------
// Mesh import

TEST(MeshImport, LoadsRealModels) {
  for (const char* f : {"OBJ/spider.obj", "PLY/Wuson.ply", "STL/Spider_binary.stl", "OFF/Cube.off",
                        "glTF2/BoxTextured-glTF/BoxTextured.gltf"}) {
    const Scene s = hsr::loadMeshFile(kModels / f);
    expectWellFormed(s, f);
  }
}

TEST(MeshImport, PolygonsStayPolygons) {
  const Scene s = hsr::loadMeshFile(kModels / "OFF/Cube.off");
  ASSERT_EQ(s.polygonCount(), 6u);
  for (hsr::PolygonId id = 0; id < 6; ++id) EXPECT_EQ(s.polygon(id).size(), 4u);
  EXPECT_EQ(s.vertexCount(), 8u);
}

// A minimal glTF: one triangle mesh placed twice under a translated root, plus a camera.
void writeTinyGltf(const fs::path& dir) {
  std::string bin;
  const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  bin.append(reinterpret_cast<const char*>(pos), sizeof pos);
  writeFile(dir / "tiny.bin", bin);
  writeFile(dir / "tiny.gltf", R"({
    "asset": {"version": "2.0"},
    "scene": 0,
    "scenes": [{"nodes": [0]}],
    "nodes": [
      {"translation": [10, 0, 0], "children": [1, 2, 3]},
      {"mesh": 0, "scale": [2, 2, 2]},
      {"mesh": 0, "translation": [0, 5, 0]},
      {"camera": 0, "translation": [0, 0, 10]}
    ],
    "cameras": [{"type": "perspective",
                 "perspective": {"yfov": 0.5, "aspectRatio": 2.0, "znear": 0.5, "zfar": 50}}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "buffers": [{"uri": "tiny.bin", "byteLength": 36}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                   "min": [0, 0, 0], "max": [1, 1, 0]}]
  })");
}

TEST(MeshImport, AppliesNodeTransformsInNodeOrder) {
  const ScratchDir scratch("hsr_io_test");
  const fs::path d = scratch.path();
  writeTinyGltf(d);
  const Scene s = hsr::loadMeshFile(d / "tiny.gltf");
  ASSERT_EQ(s.polygonCount(), 2u);
  ASSERT_EQ(s.objects.size(), 2u);
  // Polygon 0: the first child (scale 2 under translation 10); polygon 1: the second
  const auto p0 = s.polygon(0), p1 = s.polygon(1);
  EXPECT_EQ(s.position(p0[1]), glm::vec3(12, 0, 0));
  EXPECT_EQ(s.position(p0[2]), glm::vec3(10, 2, 0));
  EXPECT_EQ(s.position(p1[0]), glm::vec3(10, 5, 0));
  EXPECT_EQ(s.position(p1[2]), glm::vec3(10, 6, 0));
  // The camera: at its node's origin, looking down its -Z, vertical fov as written
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_EQ(s.cameras[0].eye, glm::vec3(10, 0, 10));
  EXPECT_EQ(s.cameras[0].target, glm::vec3(10, 0, 9));
  EXPECT_EQ(s.cameras[0].up, glm::vec3(0, 1, 0));
  EXPECT_NEAR(s.cameras[0].fov_deg, 0.5 * 180.0 / 3.14159265358979, 1e-3);
  EXPECT_FLOAT_EQ(s.cameras[0].near, 0.5f);
  EXPECT_LE(s.cameras[0].far, 50.0f);
  EXPECT_GT(s.cameras[0].far, 11.0f);  // still reaches the whole scene
  EXPECT_FALSE(s.cameras[0].ortho);
}

// Hostile or broken input: a clean hsr::Error, or (where assimp makes sense of it) a
// well-formed scene. Never a crash, a hang, or a non-finite position.
void expectErrorOrWellFormed(const fs::path& p) {
  try {
    const Scene s = hsr::loadMeshFile(p);
    expectWellFormed(s, p.string());
  } catch (const hsr::Error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    EXPECT_NE(msg.find(p.filename().string()), std::string::npos) << msg;
  }
}

TEST(MeshImport, InvalidModelsNeverCrash) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(kModels / "invalid")) files.push_back(e.path());
  ASSERT_GE(files.size(), 10u);
  for (const char* f : {"OFF/invalid.off", "glTF2/IndexOutOfRange/AllIndicesOutOfRange.gltf",
                        "glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb"})
    files.push_back(kModels / f);
  for (const fs::path& p : files) expectErrorOrWellFormed(p);
  // These two must be refused, not loaded
  EXPECT_THROW(hsr::loadMeshFile(kModels / "invalid/OutOfMemory.off"), hsr::Error);
  EXPECT_THROW(
      hsr::loadMeshFile(kModels / "glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb"),
      hsr::Error);
}

TEST(MeshImport, TruncatedBinaryStlThrows) {
  const ScratchDir scratch("hsr_io_test");
  const fs::path d = scratch.path();
  const std::string stl = readFile(kModels / "STL/Spider_binary.stl");
  ASSERT_GT(stl.size(), 5000u);
  writeFile(d / "truncated.stl", stl.substr(0, 5000));
  EXPECT_THROW(hsr::loadMeshFile(d / "truncated.stl"), hsr::Error);
  // Header says 1000 triangles, data holds 2
  std::string shortStl(80, ' ');
  const std::uint32_t n = 1000;
  shortStl.append(reinterpret_cast<const char*>(&n), 4);
  shortStl.append(100, '\0');
  writeFile(d / "short.stl", shortStl);
  EXPECT_THROW(hsr::loadMeshFile(d / "short.stl"), hsr::Error);
}

TEST(MeshImport, GarbageAndEmptyFilesThrowNamingTheFile) {
  const ScratchDir scratch("hsr_io_test");
  const fs::path d = scratch.path();
  writeFile(d / "garbage.obj", "this is not a mesh\njust some words\n");
  writeFile(d / "empty.obj", "");
  writeFile(d / "lines.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n");
  writeFile(d / "nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
  writeFile(d / "inf.obj", "v 0 0 0\nv 1 0 0\nv 1e39 1 0\nf 1 2 3\n");
  writeFile(d / "index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
  writeFile(d / "huge.off", "OFF\n353535235358 6 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  writeFile(d / "huge.ply",
            "ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\n"
            "property float x\nproperty float y\nproperty float z\nend_header\n");
  for (const char* f : {"garbage.obj", "empty.obj", "lines.obj", "nan.obj", "inf.obj", "index.obj",
                        "huge.off", "huge.ply", "missing.obj"}) {
    try {
      hsr::loadMeshFile(d / f);
      ADD_FAILURE() << f << " loaded";
    } catch (const hsr::Error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(f), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
  }
  EXPECT_THROW(hsr::loadMeshFile(d), hsr::Error);  // a directory
  try {
    hsr::loadMeshFile(d / "nan.obj");
  } catch (const hsr::Error& e) {
    EXPECT_NE(std::string(e.what()).find("not finite"), std::string::npos) << e.what();
  }
}

TEST(LoadScene, ExistingFileWinsOverBuiltin) {
  const ScratchDir scratch("hsr_io_test");
  const fs::path d = scratch.path() / "wins";
  fs::create_directories(d);
  writeFile(d / "cyclic", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  const fs::path old = fs::current_path();
  fs::current_path(d);
  Scene s;
  try {
    s = hsr::loadScene("cyclic");
  } catch (...) {
    fs::current_path(old);
    throw;
  }
  fs::current_path(old);
  EXPECT_EQ(s.polygonCount(), 1u);  // the file, not the three sticks
  EXPECT_EQ(hsr::loadScene("cyclic").polygonCount(), 3u);
  EXPECT_EQ(hsr::loadScene((kModels / "OFF/Cube.off").string()).polygonCount(), 6u);
}

TEST(LoadScene, NeitherFileNorBuiltinIsNamed) {
  try {
    hsr::loadScene("no_such_model.obj");
    FAIL();
  } catch (const hsr::Error& e) {
    EXPECT_EQ(std::string(e.what()), "no such file or built-in scene: no_such_model.obj");
  }
  EXPECT_THROW(hsr::loadScene("spheres:many"), hsr::Error);
  EXPECT_THROW(hsr::loadScene(""), hsr::Error);
}

// ---------------------------------------------------------------------------------------
// Writers

TEST(Writers, NpyParsesBack) {
  const ScratchDir scratch("hsr_io_test");
  const fs::path d = scratch.path();
  const float depth[6] = {0.0f, 0.25f, 0.5f, 0.75f, 1.0f, -2.0f};
  const std::uint32_t ids[6] = {0, 1, 2, 0xFFFFFFFFu, 7, 123456789};
  hsr::writeNpy(d / "depth.npy", 3, 2, depth);
  hsr::writeNpy(d / "ids.npy", 3, 2, ids);
  for (const auto& [file, descr, data] :
       {std::tuple{"depth.npy", "'<f4'", static_cast<const void*>(depth)},
        std::tuple{"ids.npy", "'<u4'", static_cast<const void*>(ids)}}) {
    SCOPED_TRACE(file);
    const std::string b = readFile(d / file);
    ASSERT_GE(b.size(), 10u);
    EXPECT_EQ(b.substr(0, 6), std::string("\x93NUMPY"));
    EXPECT_EQ(b[6], 1);  // version 1.0
    EXPECT_EQ(b[7], 0);
    const std::size_t header_len = static_cast<unsigned char>(b[8]) |
                                   static_cast<std::size_t>(static_cast<unsigned char>(b[9])) << 8;
    ASSERT_LE(10 + header_len, b.size());
    EXPECT_EQ((10 + header_len) % 64, 0u);  // numpy aligns the data
    const std::string header = b.substr(10, header_len);
    EXPECT_EQ(header.back(), '\n');
    EXPECT_NE(header.find(std::string("'descr': ") + descr), std::string::npos) << header;
    EXPECT_NE(header.find("'fortran_order': False"), std::string::npos) << header;
    EXPECT_NE(header.find("'shape': (2, 3)"), std::string::npos) << header;  // (height, width)
    ASSERT_EQ(b.size(), 10 + header_len + 6 * 4);
    EXPECT_EQ(std::memcmp(b.data() + 10 + header_len, data, 24), 0);  // little-endian host
  }
}

TEST(Writers, PngDecodesBack) {
  const ScratchDir scratch("hsr_io_test");
  const fs::path d = scratch.path();
  std::vector<std::uint8_t> rgb(5 * 3 * 3);
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<std::uint8_t>(i * 7);
  hsr::writePng(d / "p.png", 5, 3, 3, rgb.data());
  const auto back = hsr::testing::decodePng(d / "p.png");
  ASSERT_TRUE(back.ok()) << back.error;
  EXPECT_EQ(back.width, 5);
  EXPECT_EQ(back.height, 3);
  EXPECT_EQ(back.rgb, rgb);  // first row first
}

TEST(Writers, FailedWritesThrowNamingTheFile) {
  // The writers create missing folders, but not through a file
  const ScratchDir scratch("hsr_io_test");
  const fs::path not_a_dir = scratch.path() / "a_file";
  std::ofstream(not_a_dir) << "x";
  const fs::path bad = not_a_dir / "x.png";
  const std::uint8_t px[3] = {1, 2, 3};
  const float z = 0.5f;
  for (int which = 0; which < 2; ++which) {
    try {
      if (which == 0)
        hsr::writePng(bad, 1, 1, 3, px);
      else
        hsr::writeNpy(bad, 1, 1, &z);
      ADD_FAILURE() << which;
    } catch (const hsr::Error& e) {
      EXPECT_NE(std::string(e.what()).find("x.png"), std::string::npos) << e.what();
    }
  }
}

hsr::Frame tinyFrame() {
  hsr::Frame f;
  f.width = 4;
  f.height = 1;
  f.ids = {hsr::kNoPolygon, 0, 1, 2};
  f.depth = {1.0f, 0.2f, 0.5f, 0.8f};
  f.overdraw = {0, 1, 2, 4};
  f.color = {0xFF000000u, 0xFF0000FFu, 0xFF00FF00u, 0xFFFF0000u};  // bytes R,G,B,A
  return f;
}

TEST(Writers, DepthPictureIsLightNearDarkFarBlackBehind) {
  const std::vector<std::uint8_t> p = hsr::depthPicture(tinyFrame());
  ASSERT_EQ(p.size(), 12u);
  EXPECT_EQ(p[0], 0);      // background
  EXPECT_EQ(p[3], 255);    // nearest
  EXPECT_GT(p[6], p[9]);   // nearer is lighter
  EXPECT_GT(p[9], 0);      // farthest still visible
  EXPECT_EQ(p[9], p[10]);  // grey
}

TEST(Writers, IdPictureIsBlackOnlyWhereNothingWasDrawn) {
  const std::vector<std::uint8_t> p = hsr::idPicture(tinyFrame());
  ASSERT_EQ(p.size(), 12u);
  EXPECT_EQ(p[0] + p[1] + p[2], 0);
  std::set<std::vector<std::uint8_t>> colours;
  for (int k = 1; k < 4; ++k) {
    EXPECT_GT(std::max({p[3 * k], p[3 * k + 1], p[3 * k + 2]}), 150) << "bright";
    colours.insert({p[3 * k], p[3 * k + 1], p[3 * k + 2]});
  }
  EXPECT_EQ(colours.size(), 3u);
}

TEST(Writers, OverdrawPictureRampsFromBlackToWhite) {
  const std::vector<std::uint8_t> p = hsr::overdrawPicture(tinyFrame());
  ASSERT_EQ(p.size(), 12u);
  EXPECT_EQ(p[0] + p[1] + p[2], 0);
  EXPECT_GT(p[3] + p[4] + p[5], 0);
  EXPECT_EQ(p[9] + p[10] + p[11], 3 * 255);  // the maximum is white
}

// On a shared scale (the comparison sheet's), a count has one colour whatever the frame's own
// maximum: the frame's maximum is white only when it is the scale's
TEST(Writers, OverdrawPictureOnASharedScale) {
  const hsr::Frame f = tinyFrame();
  const std::uint32_t own = *std::max_element(f.overdraw.begin(), f.overdraw.end());
  EXPECT_EQ(hsr::overdrawPicture(f, own), hsr::overdrawPicture(f));
  EXPECT_EQ(hsr::overdrawPicture(f, 0), hsr::overdrawPicture(f));  // never below its own
  const std::vector<std::uint8_t> shared = hsr::overdrawPicture(f, 4 * own);
  EXPECT_LT(shared[9] + shared[10] + shared[11], 3 * 255);
  hsr::Frame g = f;
  g.overdraw = {0, 1, 2, 2};  // another frame, another maximum
  const std::vector<std::uint8_t> a = hsr::overdrawPicture(f, 4 * own),
                                  b = hsr::overdrawPicture(g, 4 * own);
  EXPECT_NE(hsr::overdrawPicture(f)[6], hsr::overdrawPicture(g)[6])
      << "each on its own scale differs";
  for (std::size_t k = 0; k < f.overdraw.size(); ++k)
    if (f.overdraw[k] == g.overdraw[k]) {
      EXPECT_TRUE(std::equal(&a[3 * k], &a[3 * k + 3], &b[3 * k])) << k;
    }
}

TEST(Writers, PictureByName) {
  const hsr::Frame f = tinyFrame();
  const std::vector<std::uint8_t> c = hsr::picture(f, "color");
  EXPECT_EQ(c, (std::vector<std::uint8_t>{0, 0, 0, 255, 0, 0, 0, 255, 0, 0, 0, 255}));
  EXPECT_EQ(hsr::picture(f, "depth"), hsr::depthPicture(f));
  EXPECT_EQ(hsr::picture(f, "ids"), hsr::idPicture(f));
  EXPECT_EQ(hsr::picture(f, "overdraw"), hsr::overdrawPicture(f));
  EXPECT_THROW(hsr::picture(f, "smell"), hsr::Error);
  // A frame whose buffers were not filled gives black, never a read past the end
  hsr::Frame empty;
  empty.width = 2;
  empty.height = 2;
  for (const char* k : {"color", "depth", "ids", "overdraw"})
    EXPECT_EQ(hsr::picture(empty, k), std::vector<std::uint8_t>(12, 0)) << k;
}

// The id palette keeps neighbouring ids apart: ids k and k + 1 (a mesh's neighbouring faces,
// mostly) and k + 2 differ clearly in colour, for every k of a long run.
TEST(Writers, IdPaletteKeepsNeighbouringIdsApart) {
  hsr::Frame f;
  f.width = 4096, f.height = 1;
  f.ids.resize(4096);
  for (std::uint32_t k = 0; k < 4096; ++k) f.ids[k] = 1000 + k;
  const std::vector<std::uint8_t> p = hsr::idPicture(f);
  auto distance = [&](std::size_t a, std::size_t b) {
    int d = 0;
    for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(p[3 * a + c]) - int(p[3 * b + c])));
    return d;
  };
  int closest1 = 255, closest2 = 255;
  for (std::size_t k = 0; k + 2 < 4096; ++k) {
    closest1 = std::min(closest1, distance(k, k + 1));
    closest2 = std::min(closest2, distance(k, k + 2));
  }
  EXPECT_GE(closest1, 80) << "k and k + 1";
  EXPECT_GE(closest2, 40) << "k and k + 2";
}

TEST(Writers, StatsJsonHasEveryCounter) {
  hsr::Frame f = tinyFrame();
  f.stats.polygons_in = 3;
  f.stats.fragments_tested = 42;
  f.stats.addStage("raster", 1.5);
  f.stats.addStage("bin", 0.5);
  const auto j = nlohmann::json::parse(hsr::statsJson(f, "demo", "zbuffer"));
  EXPECT_EQ(j["scene"], "demo");
  EXPECT_EQ(j["algorithm"], "zbuffer");
  EXPECT_EQ(j["width"], 4);
  EXPECT_EQ(j["height"], 1);
  EXPECT_EQ(j["polygons_in"], 3);
  EXPECT_EQ(j["fragments_tested"], 42);
  for (const char* k :
       {"triangles_in", "degenerate_dropped", "culled_frustum", "culled_backface", "clipped",
        "clipped_away", "triangles_rasterized", "fragments_written", "state_bytes"})
    EXPECT_TRUE(j.contains(k)) << k;
  ASSERT_EQ(j["stages"].size(), 2u);
  EXPECT_EQ(j["stages"][0]["name"], "raster");
  EXPECT_DOUBLE_EQ(j["stages"][0]["ms"].get<double>(), 1.5);
  EXPECT_DOUBLE_EQ(j["total_ms"].get<double>(), f.stats.totalMs());
  // A scene named by a non-UTF-8 path still gives valid JSON
  EXPECT_TRUE(nlohmann::json::parse(hsr::statsJson(f, "bad\xff.obj", "zbuffer"), nullptr, false)
                  .is_object());
}

// A binary PLY with three vertices (given as raw float bits) and one triangle, its header
// lines ended by `eol`.
std::string binaryPly(const std::string& eol, const std::uint32_t (&bits)[9], bool big_endian) {
  std::string ply = "ply" + eol + "format binary_" + (big_endian ? "big" : "little") +
                    "_endian 1.0" + eol + "element vertex 3" + eol + "property float x" + eol +
                    "property float y" + eol + "property float z" + eol + "element face 1" + eol +
                    "property list uchar int vertex_indices" + eol + "end_header" + eol;
  const auto put = [&](std::uint32_t v, int n) {
    for (int k = 0; k < n; ++k)
      ply.push_back(static_cast<char>(v >> (8 * (big_endian ? n - 1 - k : k))));
  };
  for (std::uint32_t b : bits) put(b, 4);
  put(3, 1);
  for (std::uint32_t i : {0u, 1u, 2u}) put(i, 4);
  return ply;
}

// assimp 5.2 drops a 0x0A byte right after a binary PLY's header (meant for the '\n' of a
// "\r\n") and then reads every value a byte off: found reading its PLY parser while bounding
// the header counts. 1 binary PLY in 256 with "\n" headers starts so. The import inserts the
// '\r' that makes assimp read it right; headers ended by "\r\n" or "\r" are read as written.
TEST(MeshImport, BinaryPlyWhoseDataStartsWithByte0x0ALoadsExactly) {
  const ScratchDir scratch("hsr_io_test");
  const fs::path d = scratch.path();
  // The first x is 1.0000012f: its low byte (first in little-endian order) is 0x0A
  const std::uint32_t bits[9] = {0x3F80000Au, 0, 0, 0x40000000u, 0, 0, 0, 0x40400000u, 0};
  // Big-endian: the first byte is the sign and exponent; 0x0A... is about 6.2e-33
  const std::uint32_t big_bits[9] = {0x0A80000Fu, 0, 0, 0x40000000u, 0, 0, 0, 0x40400000u, 0};
  const std::uint32_t plain_bits[9] = {0x3F800001u, 0, 0, 0x40000000u, 0, 0, 0, 0x40400000u, 0};
  struct Case {
    const char* name;
    std::string bytes;
    const std::uint32_t* bits;
  } cases[] = {{"lf_little.ply", binaryPly("\n", bits, false), bits},
               {"crlf_little.ply", binaryPly("\r\n", bits, false), bits},
               {"lf_big.ply", binaryPly("\n", big_bits, true), big_bits},
               // Header lines ended by a bare '\r' (old Mac files): the data is read where it
               // starts. (Were it to start with 0x0A it would read as "\r\n": ambiguous.)
               {"cr_little.ply", binaryPly("\r", plain_bits, false), plain_bits}};
  for (const Case& c : cases) {
    writeFile(d / c.name, c.bytes);
    const Scene s = hsr::loadMeshFile(d / c.name);
    ASSERT_EQ(s.polygonCount(), 1u) << c.name;
    const auto poly = s.polygon(0);
    ASSERT_EQ(poly.size(), 3u) << c.name;
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k) {
        float expected;
        std::memcpy(&expected, &c.bits[3 * v + k], 4);
        EXPECT_EQ(s.position(poly[v])[k], expected) << c.name << " vertex " << v << " axis " << k;
      }
  }
}

// assimp 5.2's PLY reader sizes its vertex array by the first vertex element and writes every
// later one into it (valgrind: "Invalid write of size 8 ... 0 bytes after a block of size
// 12"): found reading its parser. Such a header is refused before assimp reads it.
TEST(MeshImport, PlyWithASecondVertexElementIsRefused) {
  std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nelement vertex 40\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
      "end_header\n0 0 0\n";
  for (int i = 1; i <= 40; ++i) ply += std::to_string(i) + " 0 0\n";
  ply += "3 0 1 2\n";
  const ScratchDir scratch("hsr_io_test");
  const fs::path p = scratch.path() / "two_vertex_elements.ply";
  writeFile(p, ply);
  try {
    hsr::loadMeshFile(p);
    ADD_FAILURE() << "a PLY with two vertex elements loaded";
  } catch (const hsr::Error& e) {
    EXPECT_NE(std::string(e.what()).find("declares a second vertex element"), std::string::npos)
        << e.what();
  }
}

// ImportLimits::memory_bytes: an import that needs more is refused with one line that says
// so (the child's address space, and under ASan its heap, are limited; a failed allocation
// inside assimp ends as this refusal, never as a crash or an abort).
TEST(MeshImport, ImportOverItsMemoryLimitIsRefused) {
  // 2.8 KB that assimp subdivides into about 120 MB of meshes; a free heap this process
  // already holds is the child's to use too, so the limit is set far below the need
  const fs::path model = kModels / "AC/sample_subdiv.ac";
  hsr::ImportLimits tight;
  tight.memory_bytes = 16 << 20;
  try {
    hsr::loadMeshFile(model, tight);
    ADD_FAILURE() << "sample_subdiv.ac loaded within 16 MiB";
  } catch (const hsr::Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("sample_subdiv.ac: importing it needs more than 16 MiB"), std::string::npos)
        << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
  // The automatic limit for a file this size (1 GiB) lets it load
  EXPECT_GT(hsr::loadMeshFile(model).polygonCount(), 1000u);

  // One large allocation instead of many small ones (under ASan the two fail differently:
  // the heap watch, or the address-space limit inside the sanitizer's allocator): a binary
  // STL of 1M triangles, for which assimp allocates 36 MB of positions at once
  const ScratchDir scratch("hsr_io_test");
  const fs::path stl = scratch.path() / "million.stl";
  {
    std::string bytes(84 + 50 * 1'000'000ull, '\0');
    const std::uint32_t n = 1'000'000;
    std::memcpy(&bytes[80], &n, 4);
    for (std::uint32_t t = 0; t < n; ++t) {
      const float v[9] = {float(t), 0, 0, float(t) + 1, 0, 0, float(t), 1, 0};
      std::memcpy(&bytes[84 + 50 * t + 12], v, sizeof v);
    }
    writeFile(stl, bytes);
  }
  try {
    hsr::loadMeshFile(stl, tight);
    ADD_FAILURE() << "million.stl loaded within 16 MiB";
  } catch (const hsr::Error& e) {
    EXPECT_NE(std::string(e.what()).find("million.stl: importing it needs more than 16 MiB"),
              std::string::npos)
        << e.what();
  }
  fs::remove(stl);
}

// Found by fuzzing (fuzz/fuzz_scene.cpp): a binary PLY whose element has no count segfaults
// inside Debian's assimp 5.2 PLY reader. The import runs in a child process, so it is
// refused with one error instead of taking the program down.
TEST(MeshImport, BinaryPlyThatCrashesAssimpIsRefused) {
  const unsigned char bytes[] = {
      0x70, 0x6c, 0x79, 0x0a, 0x66, 0x6f, 0x72, 0x6d, 0x61, 0x74, 0x20, 0x62, 0x69, 0x6e, 0x61,
      0x72, 0x79, 0x5f, 0x6c, 0x69, 0x74, 0x74, 0x6c, 0x65, 0x5f, 0x65, 0x6e, 0x64, 0x69, 0x61,
      0x6e, 0x20, 0x31, 0x2e, 0x30, 0x0a, 0x63, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x3f, 0x00,
      0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x00, 0x00,
      0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x00,
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
      0x80, 0x3f, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x80, 0x3f, 0x00,
      0x00, 0x80, 0x2f, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x00,
      0x00, 0x01, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x00, 0x00, 0x02,
      0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x00, 0x03, 0x07, 0x00, 0x00, 0x00, 0x06, 0x00, 0x00,
      0x00, 0x05, 0x00, 0x00, 0x00, 0x03, 0x07, 0x00, 0x00, 0x00, 0x05, 0x00, 0x00, 0x00, 0x04,
      0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x05, 0x00, 0x00,
      0x00, 0x03, 0x00, 0x00, 0x00, 0x00, 0x05, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x03,
      0x01, 0x00, 0x00, 0x00, 0x05, 0x00, 0x00, 0x00, 0x06, 0x00, 0x00, 0x00, 0x03, 0x01, 0x00,
      0x00, 0x00, 0x06, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x03, 0x02, 0x00, 0x00, 0x00,
      0x06, 0x00, 0x00, 0x00, 0x07, 0x00, 0x00, 0x00, 0x03, 0x02, 0x00, 0x00, 0x00, 0x07, 0x00,
      0x00, 0x00, 0x03, 0x00, 0x00, 0x00, 0x03, 0x03, 0x00, 0x00, 0x00, 0x07, 0x00, 0x00, 0x00,
      0x04, 0x00, 0x00, 0x00, 0x03, 0x03, 0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00,
      0x00, 0x00,
  };
  const ScratchDir scratch("hsr_assimp_crash");
  const std::filesystem::path p = scratch / "crash.ply";
  {
    std::ofstream f(p, std::ios::binary);
    f.write(reinterpret_cast<const char*>(bytes), sizeof bytes);
  }
  try {
    hsr::loadMeshFile(p);
    ADD_FAILURE() << "the malformed PLY loaded";
  } catch (const hsr::Error& e) {
    EXPECT_NE(std::string(e.what()).find(p.filename().string()), std::string::npos) << e.what();
  }
}

}  // namespace

namespace hsr {
namespace {

// A file without materials gets hsr's one default material, whatever assimp makes up for the
// format (white for PLY and STL, grey for OBJ); named materials keep their names.
TEST(MeshImport, FilesWithoutMaterialsGetTheOneDefault) {
  for (const char* model : {"PLY/Wuson.ply", "STL/Spider_binary.stl"}) {
    const Scene s = loadScene((std::filesystem::path(HSR_TEST_MODELS) / model).string());
    ASSERT_FALSE(s.materials.empty()) << model;
    for (const Material& m : s.materials) {
      EXPECT_EQ(m.color, Material{}.color) << model;
      EXPECT_TRUE(m.name.empty()) << model;
    }
  }
  const Scene spider =
      loadScene((std::filesystem::path(HSR_TEST_MODELS) / "OBJ/spider.obj").string());
  bool named = false;
  for (const Material& m : spider.materials) named |= !m.name.empty();
  EXPECT_TRUE(named) << "spider.mtl names its materials";
}

// An import reports its progress: seconds that only grow, and one last call saying it is done
// with the whole answer received.
TEST(MeshImport, ProgressIsReportedAndEndsDone) {
  ImportLimits limits;
  std::vector<std::pair<double, bool>> calls;
  std::uint64_t last_bytes = 0;
  limits.progress = [&](double seconds, std::uint64_t bytes, bool done) {
    calls.emplace_back(seconds, done);
    last_bytes = bytes;
  };
  const Scene s =
      loadScene((std::filesystem::path(HSR_TEST_MODELS) / "PLY/Wuson.ply").string(), limits);
  ASSERT_FALSE(calls.empty());
  EXPECT_TRUE(calls.back().second);
  for (std::size_t k = 0; k + 1 < calls.size(); ++k) {
    EXPECT_FALSE(calls[k].second);
    EXPECT_LE(calls[k].first, calls[k + 1].first);
  }
  EXPECT_GT(last_bytes, 12 * s.vertexCount());  // the scene came through the pipe
  calls.clear();
  loadScene("spheres:100", limits);
  EXPECT_TRUE(calls.empty()) << "a built-in scene is no import";
}

// An STL repeats each corner in every triangle: identical positions join into shared vertices
// (0 and -0 alike), different ones stay apart, and the triangles keep their order and corners.
TEST(MeshImport, IdenticalPositionsJoinIntoSharedVertices) {
  const ScratchDir scratch("hsr_io_join");
  // A unit cube's 12 triangles, some corners written with -0
  const float c[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                         {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int tri[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                          {3, 6, 2}, {3, 7, 6}, {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};
  std::string stl(80, '\0');
  const std::uint32_t n = 12;
  stl.append(reinterpret_cast<const char*>(&n), 4);
  for (int t = 0; t < 12; ++t) {
    const float normal[3] = {0, 0, 0};
    stl.append(reinterpret_cast<const char*>(normal), 12);
    for (int k = 0; k < 3; ++k) {
      float p[3] = {c[tri[t][k]][0], c[tri[t][k]][1], c[tri[t][k]][2]};
      if (t % 2 == 1)
        for (float& v : p) v = v == 0.0f ? -0.0f : v;  // -0 in every other triangle
      stl.append(reinterpret_cast<const char*>(p), 12);
    }
    stl.append(2, '\0');
  }
  writeFile(scratch / "cube.stl", stl);
  const Scene s = loadScene((scratch / "cube.stl").string());
  ASSERT_EQ(s.polygonCount(), 12u);
  EXPECT_EQ(s.vertexCount(), 8u);
  for (PolygonId id = 0; id < 12; ++id)
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = s.position(s.polygon(id)[k]);
      EXPECT_EQ(p, glm::vec3(c[tri[id][k]][0], c[tri[id][k]][1], c[tri[id][k]][2]))
          << id << "," << k;
    }
  // A position one float step away is another vertex
  float moved = 1.0f;
  moved = std::nextafter(moved, 2.0f);
  std::memcpy(&stl[84 + 12 + 12], &moved, 4);  // triangle 0's second corner's x
  writeFile(scratch / "moved.stl", stl);
  EXPECT_EQ(loadScene((scratch / "moved.stl").string()).vertexCount(), 9u);
}

}  // namespace
}  // namespace hsr

// docs/testing.md row 16: one committed file per historical mesh-loader bug class (fuzz/seeds/),
// each loaded through hsr::loadMeshFile with its exact documented outcome. Either a refusal:
// hsr::Error, one line, naming the file and the fault (a distinctive substring is checked);
// or a documented lenient result. Valid edge cases (subnormals, relative indices, CRLF, no
// final newline, long digit strings) must load exactly: vertex positions and each polygon's
// vertex list are compared as loaded (vertices enter the scene on first use, in face order).
// Seeds that other work adds to fuzz/seeds/ (fuzzing findings) get the generic check.

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/scene.hpp"
#include "test_util.hpp"

namespace {

namespace fs = std::filesystem;
using hsr::Scene;

const fs::path kSeeds = HSR_FUZZ_SEEDS;

// The seeds, one per bug class; every one has a TEST below.
const char* const kSeedFiles[] = {
    "stl_short_83_bytes.stl",
    "stl_count_overflow.stl",
    "stl_solid_but_binary.stl",
    "stl_bom_binary.stl",
    "ply_count_exceeds_data.ply",
    "ply_binary_count_exceeds_data.ply",
    "ply_list_length_0.ply",
    "ply_list_length_huge.ply",
    "obj_face_index_0.obj",
    "obj_negative_index_beyond_start.obj",
    "obj_index_beyond_end.obj",
    "obj_missing_vt_vn.obj",
    "obj_100_digit_number.obj",
    "obj_100_digit_fraction.obj",
    "obj_no_final_newline.obj",
    "obj_crlf.obj",
    "obj_subnormal.obj",
    "obj_above_flt_max.obj",
    "obj_negative_relative_index.obj",
    "obj_nested_groups.obj",
};

// "[ figures ]" for the README's Reliability table: LoaderSeed tests run and passed.
[[maybe_unused]] ::testing::Environment* const kFigures = hsr::testing::printFiguresAtEnd([] {
  const hsr::testing::SuiteTally t = hsr::testing::tallySuite("LoaderSeed");
  if (t.run == 0) return;
  std::printf(
      "[ figures ] row 16 loader known-bug seeds: %zu seed files, %d cases run, %d passed\n",
      std::size(kSeedFiles), t.run, t.passed);
});

fs::path seed(const char* name) {
  const fs::path p = kSeeds / name;
  EXPECT_TRUE(fs::is_regular_file(p)) << p << " is missing";
  return p;
}

std::string readBytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// The load fails with one hsr::Error line that names the file and contains `fault`.
void expectRefused(const char* name, const std::string& fault) {
  const fs::path p = seed(name);
  try {
    const Scene s = hsr::loadMeshFile(p);
    ADD_FAILURE() << name << " loaded (" << s.polygonCount()
                  << " polygons); expected a refusal: " << fault;
  } catch (const hsr::Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(p.string()), std::string::npos) << "names the file: " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
    EXPECT_NE(msg.find(fault), std::string::npos) << "expected '" << fault << "' in: " << msg;
  }
}

// Loads a seed that must load; a failure is reported, and an empty scene returned.
Scene load(const char* name) {
  try {
    return hsr::loadMeshFile(seed(name));
  } catch (const hsr::Error& e) {
    ADD_FAILURE() << name << " was refused: " << e.what();
    return Scene{};
  }
}

// The scene's polygons as lists of vertex indices, and those indices' positions, exactly.
void expectPolygons(const Scene& s, const std::vector<std::vector<std::uint32_t>>& indices,
                    const std::vector<glm::vec3>& positions) {
  ASSERT_EQ(s.polygonCount(), indices.size());
  ASSERT_EQ(s.vertexCount(), positions.size());
  for (hsr::PolygonId id = 0; id < s.polygonCount(); ++id) {
    const auto poly = s.polygon(id);
    EXPECT_EQ(std::vector<std::uint32_t>(poly.begin(), poly.end()), indices[id])
        << "polygon " << id;
  }
  for (std::uint32_t v = 0; v < s.vertexCount(); ++v) {
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(std::bit_cast<std::uint32_t>(s.position(v)[k]),
                std::bit_cast<std::uint32_t>(positions[v][k]))
          << "vertex " << v << " coordinate " << k << ": " << s.position(v)[k] << " vs "
          << positions[v][k];
  }
}

TEST(LoaderSeed, SeedsAreCommittedAndSmall) {
  for (const char* name : kSeedFiles) {
    ASSERT_TRUE(fs::is_regular_file(kSeeds / name)) << name;
    EXPECT_LE(fs::file_size(kSeeds / name), 2'100'000u) << name << ": seeds stay small";
  }
}

// fuzz/seeds/ is shared with the fuzzers' findings: a seed without a named test here must
// still load into a well-formed scene or be refused with one line naming the file.
TEST(LoaderSeed, OtherSeedsLoadOrAreRefusedCleanly) {
  const std::set<std::string> named(std::begin(kSeedFiles), std::end(kSeedFiles));
  hsr::ImportLimits limits;
  limits.timeout_seconds = 30;
  for (const auto& entry : fs::directory_iterator(kSeeds)) {
    const fs::path& p = entry.path();
    // Subfolders (args/: the argument fuzzer's findings) are not meshes
    if (!entry.is_regular_file() || named.count(p.filename().string())) continue;
    SCOPED_TRACE(p.filename().string());
    try {
      const Scene s = hsr::loadMeshFile(p, limits);
      EXPECT_GT(s.polygonCount(), 0u);
      for (const glm::vec3& v : s.positions())
        EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
      for (hsr::PolygonId id = 0; id < s.polygonCount(); ++id) {
        EXPECT_GE(s.polygon(id).size(), 3u);
        for (std::uint32_t v : s.polygon(id)) EXPECT_LT(v, s.vertexCount());
      }
    } catch (const hsr::Error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
  }
}

// ---------------------------------------------------------------------------------------
// STL

// 83 bytes: the header and 3 of the count's 4 bytes. Neither binary (84 + 50 n bytes) nor
// ASCII ("solid"): refused (by hsr's check of what the file is, before assimp reads it, as
// assimp itself refused it: "Failed to determine STL storage representation").
TEST(LoaderSeed, StlShorterThan84Bytes) {
  EXPECT_EQ(fs::file_size(seed("stl_short_83_bytes.stl")), 83u);
  expectRefused("stl_short_83_bytes.stl", "not an STL file: not a binary one");
}

// n = 85899346 makes 84 + 50 n = 2^32 + 88: in 32 bits the 88-byte file "has room for
// every facet" (readers then allocate 3 GB and read far past the end). assimp checks the
// facets against the size and refuses it ("file is too small to hold all facets"); hsr's
// check, in 64 bits, refuses it first, naming the bytes the count asks for.
TEST(LoaderSeed, StlCountOverflowing32Bits) {
  const std::string bytes = readBytes(seed("stl_count_overflow.stl"));
  ASSERT_EQ(bytes.size(), 88u);
  std::uint32_t n = 0;
  std::memcpy(&n, bytes.data() + 80, 4);
  EXPECT_EQ(n, 85899346u);
  EXPECT_EQ(static_cast<std::uint32_t>(84u + 50u * n), 88u);  // the overflow the seed is for
  expectRefused("stl_count_overflow.stl",
                "its count 85899346 asks for 4294967384 bytes, the file has 88");
}

// A binary STL whose 80-byte header starts with "solid": its size matches 84 + 50 n, so it is
// read as binary (not as broken ASCII). Loads exactly: two facets, shared corners joined.
TEST(LoaderSeed, StlSolidHeaderButBinaryLoads) {
  const Scene s = load("stl_solid_but_binary.stl");
  expectPolygons(s, {{0, 1, 2}, {1, 3, 2}}, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}});
}

// A UTF-8 byte order mark before a binary STL: 3 bytes too many for binary, no "solid" for
// ASCII. Refused (not guessed at).
TEST(LoaderSeed, StlByteOrderMarkBeforeBinary) {
  EXPECT_EQ(readBytes(seed("stl_bom_binary.stl")).substr(0, 3), "\xEF\xBB\xBF");
  expectRefused("stl_bom_binary.stl", "not an STL file: not a binary one");
}

// ---------------------------------------------------------------------------------------
// PLY

// ASCII PLY declaring 5 vertices and 2 faces with 5 data lines. assimp 5.2 reads the face
// lines as vertices and repeats the last line for everything missing: it loaded 2 wrong
// faces silently. Refused before assimp (checkDeclaredCounts).
TEST(LoaderSeed, PlyAsciiCountExceedsData) {
  expectRefused("ply_count_exceeds_data.ply",
                "its header declares 7 elements but its data has only 5 lines");
}

// Binary PLY declaring 40 vertices (480 bytes) with 49 bytes of data: assimp reads past the
// end. Refused before assimp, naming where the data ends.
TEST(LoaderSeed, PlyBinaryCountExceedsData) {
  expectRefused("ply_binary_count_exceeds_data.ply",
                "its data ends inside vertex 4 (the header declares 40)");
}

// A face with a vertex list of length 0 (after a valid one): refused by assimp's validation
// (a polygon needs vertices); the message names the face.
TEST(LoaderSeed, PlyListLength0) {
  expectRefused("ply_list_length_0.ply", "aiMesh::mFaces[1].mNumIndices is 0");
}

// A face list claiming 2^32 - 1 entries: assimp would allocate tens of GB first (out of
// memory, or an ASan abort in the importer process). Refused before assimp.
TEST(LoaderSeed, PlyListLengthHuge) {
  expectRefused("ply_list_length_huge.ply",
                "face 0 has a list of 4294967295 entries but its line holds 3 values");
}

// ---------------------------------------------------------------------------------------
// OBJ

// OBJ indices count from 1: index 0 is refused.
TEST(LoaderSeed, ObjFaceIndex0) {
  expectRefused("obj_face_index_0.obj", "OBJ: Invalid face index");
}

// Relative index -4 with 3 vertices defined points before the first: refused.
TEST(LoaderSeed, ObjNegativeIndexBeyondStart) {
  expectRefused("obj_negative_index_beyond_start.obj", "OBJ: vertex index out of range");
}

// Index 4 with 3 vertices defined: refused.
TEST(LoaderSeed, ObjIndexBeyondEnd) {
  expectRefused("obj_index_beyond_end.obj", "OBJ: vertex index out of range");
}

// Faces naming texture coordinates and normals that were never defined (f 1/1/1, f 2/7):
// lenient, documented: the positions are all hsr uses, so the faces load exactly.
TEST(LoaderSeed, ObjMissingTexcoordsAndNormalsLoadPositions) {
  const Scene s = load("obj_missing_vt_vn.obj");
  expectPolygons(s, {{0, 1, 2}, {1, 3, 2}}, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}});
}

// A 100-digit coordinate: assimp 5.2 reads integer parts in 64 bits and returns 0 for the
// whole number when they overflow (it loaded x = 0 silently). Refused before assimp.
TEST(LoaderSeed, Obj100DigitNumberIsRefused) {
  expectRefused("obj_100_digit_number.obj",
                "line 2: the number 123456789012345678901234... (100 digits) is too long for the "
                "OBJ reader");
}

// Valid 100-digit numbers: a 100-digit fraction, 99 leading zeros, 100 trailing zeros. They
// load as the float nearest their value (what strtof gives).
TEST(LoaderSeed, ObjLongValidNumbersLoadExactly) {
  const Scene s = load("obj_100_digit_fraction.obj");
  const float x = std::strtof(("0." + std::string(100, '1')).c_str(), nullptr);
  EXPECT_EQ(x, 0.11111111f);
  expectPolygons(s, {{0, 1, 2}}, {{x, 0, 0}, {2, 0, 0}, {0, 1, 0}});
}

// The last line (a quad) ends without a newline: its last index is kept.
TEST(LoaderSeed, ObjNoFinalNewlineLoadsExactly) {
  const std::string bytes = readBytes(seed("obj_no_final_newline.obj"));
  ASSERT_FALSE(bytes.empty());
  EXPECT_NE(bytes.back(), '\n');
  const Scene s = load("obj_no_final_newline.obj");
  expectPolygons(s, {{0, 1, 2, 3}}, {{0, 0, 0}, {2, 0, 0}, {2, 3, 0}, {0, 3, 0}});
}

// CRLF line endings throughout (comment, o, v, vt, f): loads exactly, no '\r' in names.
TEST(LoaderSeed, ObjCrlfLoadsExactly) {
  const std::string bytes = readBytes(seed("obj_crlf.obj"));
  EXPECT_NE(bytes.find("\r\nf 4 3 5\r\n"), std::string::npos);
  const Scene s = load("obj_crlf.obj");
  expectPolygons(
      s, {{0, 1, 2, 3}, {3, 2, 4}},
      {{0.5f, 0.25f, -1}, {2.5f, 0.25f, -1}, {2.5f, 3.75f, -1}, {0.5f, 3.75f, -1}, {1.5f, 5, -2}});
  for (const hsr::Object& o : s.objects) EXPECT_EQ(o.name.find('\r'), std::string::npos) << o.name;
}

// Subnormal coordinates (below FLT_MIN, above 0) are valid: they load as subnormals of the
// right sign, never flushed to 0 nor refused, and are not joined with other vertices.
// Documented limit: assimp 5.2's reader (mantissa * powf(10, exponent)) rounds twice, so a
// subnormal may land 1 ULP (2^-149) from the correctly rounded value (strtof); the rest of
// each vertex is exact.
TEST(LoaderSeed, ObjSubnormalsLoad) {
  const Scene s = load("obj_subnormal.obj");
  ASSERT_EQ(s.polygonCount(), 2u);
  ASSERT_EQ(s.vertexCount(), 4u);
  EXPECT_EQ(std::vector<std::uint32_t>(s.polygon(0).begin(), s.polygon(0).end()),
            (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_EQ(std::vector<std::uint32_t>(s.polygon(1).begin(), s.polygon(1).end()),
            (std::vector<std::uint32_t>{0, 2, 3}));
  const char* const text[4][3] = {{"1e-40", "1.1754942e-38", "0"},
                                  {"1", "-2.5e-42", "0"},
                                  {"0", "1", "1.401298464324817e-45"},
                                  {"5e-39", "-3e-44", "1"}};
  int subnormals = 0, exact = 0;
  for (std::uint32_t v = 0; v < 4; ++v) {
    for (int k = 0; k < 3; ++k) {
      const float want = std::strtof(text[v][k], nullptr);
      const float got = s.position(v)[k];
      SCOPED_TRACE(std::string(text[v][k]));
      if (std::fpclassify(want) != FP_SUBNORMAL) {
        EXPECT_EQ(std::bit_cast<std::uint32_t>(got), std::bit_cast<std::uint32_t>(want));
        continue;
      }
      ++subnormals;
      EXPECT_EQ(std::fpclassify(got), FP_SUBNORMAL) << got;
      EXPECT_EQ(std::signbit(got), std::signbit(want));
      const std::int64_t ulps =
          std::llabs(std::int64_t(std::bit_cast<std::uint32_t>(got) & 0x7FFFFFFF) -
                     std::int64_t(std::bit_cast<std::uint32_t>(want) & 0x7FFFFFFF));
      EXPECT_LE(ulps, 1) << got << " vs " << want;
      exact += ulps == 0;
    }
  }
  EXPECT_EQ(subnormals, 6);
  std::printf("loader seeds: %d subnormal coordinates, %d correctly rounded, %d one ULP off\n",
              subnormals, exact, subnormals - exact);
}

// 3.5e38 > FLT_MAX reads as infinity: refused, naming the vertex.
TEST(LoaderSeed, ObjAboveFltMaxIsRefused) {
  expectRefused("obj_above_flt_max.obj", "vertex 0 of mesh 0 is not finite");
}

// Relative indices (f -3 -2 -1) count back from the last vertex defined so far: valid, and
// load exactly; a vertex shared by two faces is one vertex.
TEST(LoaderSeed, ObjNegativeRelativeIndexLoadsExactly) {
  const Scene s = load("obj_negative_relative_index.obj");
  expectPolygons(s, {{0, 1, 2}, {1, 3, 2}}, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}});
}

// OBJ groups cannot nest; the nearest the format allows is many of them: 500,000 group
// statements (each one a new group, 2 MB), then one face. Loads exactly, in bounded time:
// the empty groups leave no objects behind.
TEST(LoaderSeed, ObjHalfAMillionGroupsLoad) {
  hsr::ImportLimits limits;
  limits.timeout_seconds = 60;
  Scene s;
  try {
    s = hsr::loadMeshFile(seed("obj_nested_groups.obj"), limits);
  } catch (const hsr::Error& e) {
    FAIL() << e.what();
  }
  expectPolygons(s, {{0, 1, 2}}, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  EXPECT_EQ(s.objects.size(), 1u);
}

}  // namespace

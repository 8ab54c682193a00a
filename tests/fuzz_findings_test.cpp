// Fuzzing findings (scripts/fuzz.sh), each kept as a named regression test with the literal
// input the fuzzer produced. Earlier: MeshImport.BinaryPlyThatCrashesAssimpIsRefused.

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

#include <gtest/gtest.h>
#include <unistd.h>

#include "hsr/error.hpp"
#include "hsr/io.hpp"

namespace hsr {
namespace {

// Writes bytes to a temporary file with the given extension, loads it, and returns the error
// message ("" if it loaded).
std::string loadError(std::string_view bytes, const std::string& ext) {
  const std::filesystem::path p = std::filesystem::temp_directory_path() /
                                  ("hsr_finding_" + std::to_string(::getpid()) + ext);
  std::FILE* f = std::fopen(p.c_str(), "wb");
  EXPECT_NE(f, nullptr);
  if (!f) return "cannot write " + p.string();
  std::fwrite(bytes.data(), 1, bytes.size(), f);
  std::fclose(f);
  std::string message;
  try {
    loadMeshFile(p);
  } catch (const Error& e) {
    message = e.what();
  }
  std::filesystem::remove(p);
  return message;
}

// fuzz_ply, first minutes: assimp 5.2's PLY reader spins forever on a header without an
// end_header line (here a mutated "end_header" byte). Before: refused only when the import's
// 120 s deadline killed it. Now: refused at once, saying why.
TEST(FuzzFindings, PlyHeaderWithoutEndHeaderIsRefusedAtOnce) {
  static const char kInput[] =
      "ply\n"
      "format ascii 1.0          \n"
      "element vertex 8     \023\023\023\023\023\023\023\023\023\023\023\023\023\023\023\023"
      "\023\023\023\023\023\023\023\023\023\023\023\023\023\023\023     \n"
      "property float32 x         \n"
      "property float32 y         \n"
      "property float32 z         \n"
      "element face 6             \n"
      "property list uint8 int32 vertex_index \n"
      "end_heade\377r\n"
      "0 0 0\n"
      "0 0 1\n"
      "0 1 1\n"
      "0 1 0\n"
      "1 0 0\n"
      "1 0 1\n"
      "1 1 1\n"
      "1 1 0\n"
      "4 0 1 2 3\n"
      "4 7 6 5 4\n"
      "4 0 4 5 1\n"
      "4 1 5 6 2\n"
      "4 2 6 7 3\n"
      "4 3 7 4 0\n";
  const std::string message = loadError({kInput, sizeof kInput - 1}, ".ply");
  EXPECT_NE(message.find("no end_header line"), std::string::npos) << message;
  // The same by content, whatever the extension (assimp recognises PLY by its first line)
  const std::string by_content = loadError({kInput, sizeof kInput - 1}, ".bin");
  EXPECT_NE(by_content.find("no end_header line"), std::string::npos) << by_content;
  // The smallest such file
  const std::string smallest =
      loadError("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n", ".ply");
  EXPECT_NE(smallest.find("no end_header line"), std::string::npos) << smallest;
}

// fuzz_args, campaign (about 20 CPU-minutes in): the 9-byte argument "soup:739K" ran out of
// the fuzzer's 512 MB. The harness guessed a spec's size from its digits (739) and missed
// the k suffix the library reads (739,000 triangles). Now the library takes the ceiling
// itself: makeBuiltinScene(spec, max_triangles) counts with its own parser and refuses
// beyond it before building anything; the harness and the CLI cannot disagree with it.
std::string builtinError(std::string_view spec, std::uint64_t max_triangles) {
  try {
    (void)makeBuiltinScene(spec, max_triangles);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(FuzzFindings, ArgsSceneCountSuffixIsCountedByTheLibrary) {
  const std::string literal = builtinError("soup:739K", 4096);  // the fuzzer's input
  EXPECT_NE(literal.find("at most 4096"), std::string::npos) << literal;
  for (const char* spec : {"soup:5k", "soup:5K:3", "spheres:1M", "soup:4097"})
    EXPECT_NE(builtinError(spec, 4096).find("too large"), std::string::npos) << spec;
  // At the ceiling: built, with exactly that many triangles
  EXPECT_EQ(builtinError("soup:4096", 4096), "");
  EXPECT_EQ(makeBuiltinScene("soup:4k:9", 4096).triangleCount(), 4000u);
  // The default ceiling is the CLI's (20M): the suffix counts there too
  EXPECT_NE(builtinError("soup:21M", kMaxBuiltinTriangles).find("at most 20000000"),
            std::string::npos);
  EXPECT_EQ(makeBuiltinScene("soup:739K").triangleCount(), 739000u);
}

}  // namespace
}  // namespace hsr

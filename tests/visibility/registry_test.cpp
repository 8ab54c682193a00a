// The registry: one table, well formed, and the list of algorithms each property suite leaves
// out (printed at the end of the run), so that no suite skips an algorithm silently.

#include <gtest/gtest.h>

#include <cctype>
#include <set>

#include "hsr/algorithms.hpp"
#include "hsr/error.hpp"
#include "hsr/render.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

[[maybe_unused]] ::testing::Environment* const kNotApplicable = testing::printFiguresAtEnd([] {
  for (const testing::NotApplicable& n : testing::notApplicable())
    std::printf("[ not applicable ] %s: %s lacks %s\n", n.suite.c_str(), n.algorithm.c_str(),
                n.lacks.c_str());
});

TEST(Registry, EntriesAreWellFormedAndExactlyOneIsTheReference) {
  std::set<std::string_view> names;
  int references = 0;
  for (const AlgorithmInfo& a : algorithms()) {
    EXPECT_TRUE(names.insert(a.name).second) << "duplicate name " << a.name;
    EXPECT_FALSE(a.summary.empty()) << a.name;
    EXPECT_FALSE(a.source.empty()) << a.name;
    for (char c : a.name)
      EXPECT_TRUE(std::islower(static_cast<unsigned char>(c)) || c == '-') << a.name;
    references += a.reference;
    EXPECT_EQ(&findAlgorithm(a.name), &a);
  }
  EXPECT_EQ(references, 1);
  EXPECT_EQ(referenceAlgorithm().name, "zbuffer");
}

TEST(Registry, UnknownNamesAreRefusedNamingTheKnownOnes) {
  try {
    findAlgorithm("zbufer");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("zbuffer-textbook"), std::string::npos) << e.what();
  }
}

// The textbook z-buffer and the tiled one are one algorithm: they promise the same.
TEST(Registry, BothZBuffersPromiseTheSame) {
  EXPECT_EQ(findAlgorithm("zbuffer").capabilities, findAlgorithm("zbuffer-textbook").capabilities);
  EXPECT_EQ(findAlgorithm("zbuffer").input, InputKind::kScreenTriangles);
}

}  // namespace
}  // namespace hsr

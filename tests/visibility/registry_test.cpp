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

// What an algorithm lacks is refused in one line naming it, never silently ignored.
TEST(Registry, OptionsAnAlgorithmLacksAreRefused) {
  Scene s;
  s.addPolygonVertices({{0, 0, 0}, {4, 0, 0}, {0, 4, 0}}, s.addMaterial({}));
  const Camera camera = testing::pixelCamera(8, 8);
  struct Case {
    Capability needs;
    void (*set)(RenderOptions&);
  };
  const Case cases[] = {
      {kDepthFuncs, [](RenderOptions& o) { o.depth_func = DepthFunc::Greater; }},
      {kDepthFuncs, [](RenderOptions& o) { o.depth_test = false; }},
      {kDepthMask, [](RenderOptions& o) { o.depth_mask = false; }},
      {kPolygonModes, [](RenderOptions& o) { o.polygon_mode = PolygonMode::Line; }},
      {kOutline, [](RenderOptions& o) { o.outline = true; }},
  };
  int refused = 0;
  for (const AlgorithmInfo& a : algorithms()) {
    for (const Case& c : cases) {
      RenderOptions o = testing::optionsFor(std::string(a.name));
      c.set(o);
      if (a.has(c.needs)) {
        EXPECT_NO_THROW(render(s, camera, o)) << a.name;
        continue;
      }
      try {
        render(s, camera, o);
        ADD_FAILURE() << a.name << " accepted what it lacks: " << capabilityList(c.needs);
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(std::string(a.name)), std::string::npos) << e.what();
        ++refused;
      }
    }
  }
  EXPECT_GT(refused, 0);
}

}  // namespace
}  // namespace hsr

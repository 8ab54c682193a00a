// The front-ends' table of options (src/frontend.cpp) against what it describes: the algorithms
// that take an option are those render() lets take it, the defaults are RenderOptions' and the
// auto-framed camera's, text and typed values are one value. How the three front-ends use it is
// tested by tests/cli/frontends_test.cpp and its Python and web siblings.

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "hsr/algorithms.hpp"
#include "hsr/error.hpp"
#include "hsr/frontend.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"

namespace {

using hsr::FrontEnd;
using hsr::OptionRequest;

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const hsr::Error& e) {
    return e.what();
  }
  return {};
}

TEST(FrontEndTable, NamesAndSpellingsAreUnique) {
  std::set<std::string> names, flags;
  for (const hsr::OptionSpec& s : hsr::optionSpecs()) {
    EXPECT_TRUE(names.insert(std::string(s.name)).second) << s.name;
    EXPECT_TRUE(flags.insert(hsr::spelled(s.name, FrontEnd::kCli)).second) << s.name;
    EXPECT_EQ(hsr::spelled(s.name, FrontEnd::kPython), s.name);
    EXPECT_FALSE(s.help.empty()) << s.name;
    if (s.needs != 0) {
      EXPECT_FALSE(s.trial.empty()) << s.name << " needs a value to try";
    }
  }
  EXPECT_EQ(hsr::spelled("clear_depth", FrontEnd::kCli), "--clear-depth");
  EXPECT_EQ(hsr::spelled("depth_test", FrontEnd::kCli), "--no-depth-test");
  EXPECT_EQ(hsr::spelled("shade", FrontEnd::kCli), "--flat");
}

// An option that needs a capability: every algorithm without it refuses a value other than the
// default (render()'s unsupported()), every algorithm with it takes it.
TEST(FrontEndTable, WhatAnOptionNeedsIsWhatRenderChecks) {
  hsr::Camera cam;
  cam.width = 64;
  cam.height = 48;
  int checked = 0;
  for (const hsr::OptionSpec& s : hsr::optionSpecs()) {
    if (s.needs == 0) continue;
    for (const hsr::AlgorithmInfo& a : hsr::algorithms()) {
      OptionRequest r(FrontEnd::kCli);
      r.setText("algorithm", a.name);
      r.setText(s.name, s.trial);
      const std::string why = hsr::unsupported(a, cam, r.options());
      EXPECT_EQ(why.empty(), a.has(static_cast<hsr::Capability>(s.needs)))
          << s.name << " = " << s.trial << " with " << a.name << ": " << why;
      ++checked;
    }
  }
  EXPECT_GE(checked, 5 * static_cast<int>(hsr::algorithms().size()));
}

TEST(FrontEndTable, TheDefaultsAreTheLibrarys) {
  const hsr::Scene scene = hsr::makeBuiltinScene("demo");
  OptionRequest given(FrontEnd::kCli);
  for (const hsr::OptionSpec& s : hsr::optionSpecs())
    if (!s.default_text.empty() && s.kind != hsr::OptionKind::kFile)
      given.setText(s.name, s.default_text);
  const hsr::RenderOptions a = given.options(), b = OptionRequest(FrontEnd::kCli).options(),
                           c = hsr::RenderOptions{};
  for (const hsr::RenderOptions* o : {&a, &b}) {
    EXPECT_EQ(o->algorithm, c.algorithm);
    EXPECT_EQ(o->cull, c.cull);
    EXPECT_EQ(o->front_face, c.front_face);
    EXPECT_EQ(o->facing_test, c.facing_test);
    EXPECT_EQ(o->polygon_mode, c.polygon_mode);
    EXPECT_EQ(o->depth_test, c.depth_test);
    EXPECT_EQ(o->depth_func, c.depth_func);
    EXPECT_EQ(o->depth_mask, c.depth_mask);
    EXPECT_EQ(o->outline, c.outline);
    EXPECT_EQ(o->shade, c.shade);
    EXPECT_EQ(o->clear_depth, c.clear_depth);
    EXPECT_EQ(o->point_size, c.point_size);
    EXPECT_EQ(o->threads, c.threads);
    EXPECT_EQ(o->samples, c.samples);
    EXPECT_EQ(o->fragment_memory, c.fragment_memory);
    EXPECT_EQ(o->bsp.splitter, c.bsp.splitter);
    EXPECT_EQ(o->bsp.seed, c.bsp.seed);
    EXPECT_EQ(o->bsp.candidates, c.bsp.candidates);
  }
  // The camera of no options is the auto-framed one at 800x600
  const hsr::Camera framed = hsr::frameScene(scene, 800, 600);
  const hsr::Camera made = OptionRequest(FrontEnd::kWeb).camera(scene, "demo");
  EXPECT_EQ(hsr::cameraJson(made), hsr::cameraJson(framed));
  EXPECT_EQ(hsr::cameraJson(given.camera(scene, "demo")), hsr::cameraJson(framed));
}

TEST(FrontEndTable, TextAndTypedValuesAreOneValue) {
  const hsr::Scene scene = hsr::makeBuiltinScene("demo");
  OptionRequest text(FrontEnd::kCli), typed(FrontEnd::kPython);
  text.setText("size", "64x48");
  typed.set("size", std::vector<double>{64, 48});
  text.setText("eye", "3,2.5,4");
  typed.set("eye", std::vector<double>{3, 2.5, 4});
  text.setText("fov", "30");
  typed.set("fov", std::int64_t{30});
  text.setText("clear_depth", "0.5");
  typed.set("clear_depth", 0.5);
  text.setText("threads", "2");
  typed.set("threads", 2.0);  // a number with no fraction is a whole number (JSON's 2.0)
  text.setText("cull", "BACK");
  typed.set("cull", std::string("back"));
  text.setText("depth_test", "false");
  typed.set("depth_test", false);
  EXPECT_EQ(hsr::cameraJson(text.camera(scene, "demo")),
            hsr::cameraJson(typed.camera(scene, "demo")));
  const hsr::RenderOptions a = text.options(), b = typed.options();
  EXPECT_EQ(a.clear_depth, b.clear_depth);
  EXPECT_EQ(a.threads, 2);
  EXPECT_EQ(b.threads, 2);
  EXPECT_EQ(a.cull, hsr::CullMode::Back);
  EXPECT_EQ(b.cull, hsr::CullMode::Back);
  EXPECT_FALSE(a.depth_test);
  EXPECT_FALSE(b.depth_test);
}

TEST(FrontEndTable, MessagesNameTheOptionAsItsFrontEndSpellsIt) {
  for (const auto& [fe, spelled] : {std::pair{FrontEnd::kCli, "--clear-depth must be in [0, 1]"},
                                    {FrontEnd::kPython, "clear_depth must be in [0, 1]"}}) {
    OptionRequest r(fe);
    EXPECT_NE(errorOf([&] { r.set("clear_depth", 2.0); }).find(spelled), std::string::npos);
  }
  OptionRequest r(FrontEnd::kPython);
  EXPECT_EQ(errorOf([&] { r.set("front_fase", std::string("cw")); }),
            "unknown option 'front_fase'; did you mean front_face?");
  EXPECT_EQ(errorOf([&] { r.set("wibble", true); }), "unknown option 'wibble'");
  // The command line's files are its own
  EXPECT_NE(errorOf([&] { r.set("pose", std::string("pose.txt")); }).find("unknown option 'pose'"),
            std::string::npos);
  EXPECT_EQ(errorOf([&] {
              r.set("eye", std::vector<double>{1, 2});
            }),
            "eye must be X,Y,Z (got [1, 2])");
  EXPECT_EQ(errorOf([&] { r.set("samples", std::string("4")); }),
            "samples must be a whole number (got '4')");
}

}  // namespace

// hsr explain: numbered pictures of an algorithm's steps, a contact sheet and an index.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "hsr/algorithms.hpp"
#include "hsr/compare.hpp"
#include "hsr/error.hpp"
#include "hsr/explain.hpp"
#include "hsr/io.hpp"
#include "test_util.hpp"

#include "png_read.hpp"

namespace hsr {
namespace {

namespace fs = std::filesystem;

// Width and height of a PNG, or {0, 0} when it does not decode.
std::pair<int, int> pngSize(const fs::path& p) {
  const auto png = hsr::testing::decodePng(p);
  return {png.width, png.height};
}

TEST(Explain, TextbookZBufferShowsEachPolygonBeingDrawn) {
  const Scene scene = loadScene("demo");
  const Camera cam = frameScene(scene, 240, 180);
  RenderOptions o;
  o.algorithm = "zbuffer-textbook";
  const testing::ScratchDir scratch("hsr_explain");
  const fs::path dir = scratch / "textbook";
  const Explanation e = explain(scene, cam, o, dir, {.pictures_per_step = 6});
  ASSERT_GE(e.steps.size(), 4u);
  EXPECT_EQ(e.steps.front().name, "initialise");
  EXPECT_EQ(e.steps.back().name, "done");
  int polygons = 0;
  for (const ExplainedStep& s : e.steps) {
    EXPECT_EQ(s.number, &s - &e.steps[0] + 1);
    EXPECT_FALSE(s.caption.empty());
    polygons += s.name == "draw polygon";
    const auto [w, h] = pngSize(s.picture);
    EXPECT_GT(w, 2 * cam.width) << s.picture;  // colour and depth side by side
    EXPECT_GT(h, cam.height) << s.picture;     // under a caption
  }
  EXPECT_EQ(polygons, 6);  // evenly spaced, first and last polygon among them
  EXPECT_NE(e.steps[1].caption.find("Polygon 1 of"), std::string::npos) << e.steps[1].caption;
  EXPECT_GT(pngSize(e.sheet).first, 0);
  std::ifstream index(e.index);
  std::stringstream text;
  text << index.rdbuf();
  EXPECT_NE(text.str().find("01-initialise.png"), std::string::npos);
  EXPECT_NE(text.str().find("sheet.png"), std::string::npos);
  // The finished frame is the algorithm's ordinary render.
  const Frame f = render(scene, cam, o);
  EXPECT_EQ(e.frame.ids, f.ids);
  EXPECT_EQ(e.frame.color, f.color);
  fs::remove_all(dir);
}

TEST(Explain, TiledZBufferShowsItsTiles) {
  const Scene scene = loadScene("demo");
  const Camera cam = frameScene(scene, 200, 150);
  RenderOptions o;
  o.algorithm = "zbuffer";
  const testing::ScratchDir scratch("hsr_explain");
  const fs::path dir = scratch / "tiled";
  const Explanation e = explain(scene, cam, o, dir);
  ASSERT_GE(e.steps.size(), 3u);
  EXPECT_EQ(e.steps.front().name, "bin");
  EXPECT_EQ(e.steps.back().name, "done");
  int tiles = 0;
  for (const ExplainedStep& s : e.steps) tiles += s.name == "fill tile";
  EXPECT_EQ(tiles, 12);  // 4 x 3 tiles of 64 x 64
  fs::remove_all(dir);
}

// The A-buffer, explained by its textbook file: each polygon added to the lists, then the
// longest fragment list of the frame in words (each fragment's polygon, opacity, sample mask and
// depth) and magnified; the finished frame is the fast sibling's ordinary one.
TEST(Explain, ABufferShowsItsPolygonsAndOnePixelsList) {
  const Scene scene = loadScene("demo");
  const Camera cam = frameScene(scene, 200, 150);
  RenderOptions o;
  o.algorithm = "abuffer";
  const testing::ScratchDir scratch("hsr_explain");
  const fs::path dir = scratch / "abuffer";
  const Explanation e = explain(scene, cam, o, dir);
  ASSERT_GE(e.steps.size(), 4u);
  EXPECT_EQ(e.steps.front().name, "add polygon");
  EXPECT_EQ(e.steps.back().name, "done");
  int added = 0, pixel = 0, magnified = 0;
  std::string magnified_caption;
  for (const ExplainedStep& s : e.steps) {
    added += s.name == "add polygon";
    if (s.name == "one pixel's list") {
      ++pixel;
      EXPECT_NE(s.caption.find("samples"), std::string::npos) << s.caption;
      EXPECT_NE(s.caption.find("fragments"), std::string::npos) << s.caption;
    }
    if (s.name == "one pixel magnified") {
      ++magnified;
      magnified_caption = s.caption;
      EXPECT_TRUE(fs::exists(s.picture)) << s.picture;
    }
  }
  EXPECT_GT(added, 1);
  EXPECT_EQ(pixel, 1);
  EXPECT_EQ(magnified, 1);
  // The magnified pixel's samples average to the colour the frame has there
  int x = -1, y = -1;
  unsigned r = 0, g = 0, b = 0;
  ASSERT_EQ(std::sscanf(magnified_caption.c_str(), "Pixel (%d, %d)", &x, &y), 2)
      << magnified_caption;
  const std::size_t hash = magnified_caption.rfind('#');
  ASSERT_NE(hash, std::string::npos) << magnified_caption;
  ASSERT_EQ(std::sscanf(magnified_caption.c_str() + hash, "#%2x%2x%2x", &r, &g, &b), 3)
      << magnified_caption;
  ASSERT_TRUE(x >= 0 && y >= 0 && x < e.frame.width && y < e.frame.height);
  const std::uint32_t c = e.frame.color[static_cast<std::size_t>(y) * e.frame.width + x];
  EXPECT_EQ(c & 0xFFFFFFu, r | (g << 8) | (b << 16)) << magnified_caption;
  // explained by the textbook file, drawn by the fast one: the same frame
  const Frame plain = render(scene, cam, o);
  EXPECT_EQ(e.frame.color, plain.color);
  EXPECT_EQ(e.frame.ids, plain.ids);
  EXPECT_EQ(e.frame.coverage, plain.coverage);
  fs::remove_all(dir);
}

// The object-order algorithms explain themselves too: the painter's sort, swaps, splits and
// paints; the BSP tree's splitters node by node, then its paints in the traversal's order.
// Either way the finished frame is the algorithm's ordinary render.
TEST(Explain, ObjectOrderAlgorithmsShowTheirSteps) {
  const Scene scene = loadScene("demo");
  const Camera cam = frameScene(scene, 200, 150);
  const testing::ScratchDir scratch("hsr_explain");
  for (const char* algorithm : {"painter", "bsp"}) {
    SCOPED_TRACE(algorithm);
    RenderOptions o;
    o.algorithm = algorithm;
    const Explanation e = explain(scene, cam, o, scratch / algorithm);
    ASSERT_GE(e.steps.size(), 4u);
    EXPECT_EQ(e.steps.back().name, "done");
    std::map<std::string, int> count;
    for (const ExplainedStep& s : e.steps) count[s.name]++;
    EXPECT_GT(count["paint"], 0);
    if (std::string(algorithm) == "painter") {
      EXPECT_EQ(e.steps.front().name, "sort");
      EXPECT_GT(count["swap"] + count["split"], 0);
    } else {
      EXPECT_EQ(e.steps.front().name, "choose splitter");
      EXPECT_NE(e.steps.front().caption.find("Node 0"), std::string::npos)
          << e.steps.front().caption;
      EXPECT_GT(count["choose splitter"], 1);
    }
    const Frame f = render(scene, cam, o);
    EXPECT_EQ(e.frame.ids, f.ids);
    EXPECT_EQ(e.frame.color, f.color);
  }
}

// The ray caster, explained by its textbook file: the polygons cut into triangles, rows of rays
// cast, and a few rays with the triangle each kept; its pictures end on the frame render() gives
// with the fast sibling.
TEST(Explain, RayCasterShowsItsRowsAndRays) {
  const Scene scene = loadScene("spheres:3000");
  const Camera cam = frameScene(scene, 200, 150);
  const testing::ScratchDir scratch("hsr_explain_raycast");
  RenderOptions o;
  o.algorithm = "raycast";
  const Explanation e = explain(scene, cam, o, scratch / "raycast");
  std::map<std::string, int> count;
  for (const ExplainedStep& s : e.steps) count[s.name]++;
  EXPECT_EQ(e.steps.front().name, "polygons");
  EXPECT_EQ(e.steps.back().name, "done");
  EXPECT_GE(count["cast row"], 2);
  EXPECT_EQ(count["one ray"], 3);
  for (const ExplainedStep& s : e.steps) {
    if (s.name == "one ray") {
      EXPECT_NE(s.caption.find("it keeps polygon"), std::string::npos) << s.caption;
    }
  }
  const Frame f = render(scene, cam, o);
  EXPECT_EQ(e.frame.ids, f.ids);
  EXPECT_EQ(e.frame.color, f.color);
}

// The scan-line algorithm, explained by its textbook file: the edge table, then rows with their
// active edges and spans, then the frame the fast sibling draws (bands of rows on all cores).
TEST(Explain, ScanLineShowsItsRows) {
  const Scene scene = loadScene("demo");
  const Camera cam = frameScene(scene, 200, 150);
  const testing::ScratchDir scratch("hsr_explain_scanline");
  RenderOptions o;
  o.algorithm = "scanline";
  const Explanation e = explain(scene, cam, o, scratch / "scanline");
  std::map<std::string, int> count;
  for (const ExplainedStep& s : e.steps) count[s.name]++;
  ASSERT_FALSE(e.steps.empty());
  EXPECT_EQ(e.steps.front().name, "initialise");
  EXPECT_EQ(e.steps.back().name, "done");
  EXPECT_GE(count["scan row"], 2);
  const Frame f = render(scene, cam, o);
  EXPECT_EQ(e.frame.ids, f.ids);
  EXPECT_EQ(e.frame.color, f.color);
}

}  // namespace
}  // namespace hsr

namespace hsr {
namespace {

// The pictures' font draws every printable ASCII character, and every caption and step name
// that `hsr explain` writes on demo and solids, for every algorithm that explains itself, is
// drawn whole: no character left as a blank (the scan-line spans' and octree footprints'
// brackets once were).
TEST(Explain, EveryCaptionIsDrawnWithGlyphsTheFontHas) {
  for (char c = 32; c < 127; ++c) EXPECT_TRUE(labelHasGlyph(c)) << "'" << c << "'";
  const testing::ScratchDir scratch("hsr_explain_glyphs");
  std::size_t captions = 0;
  for (const char* spec : {"demo", "solids"}) {
    const Scene scene = loadScene(spec);
    const Camera cam = frameScene(scene, 160, 120);
    for (const AlgorithmInfo& a : algorithms()) {
      if (!a.has(kExplain)) continue;
      SCOPED_TRACE(std::string(a.name) + " on " + spec);
      RenderOptions o;
      o.algorithm = std::string(a.name);
      const Explanation e = explain(scene, cam, o, scratch / (std::string(a.name) + "-" + spec));
      for (const ExplainedStep& s : e.steps) {
        captions++;
        for (const char c : s.name + s.caption)
          EXPECT_TRUE(labelHasGlyph(c))
              << "step " << s.number << " (" << s.name << "): byte "
              << int(static_cast<unsigned char>(c)) << " in \"" << s.caption << "\"";
      }
    }
  }
  EXPECT_GT(captions, 50u);
}

}  // namespace
}  // namespace hsr

namespace hsr {
namespace {

// The teaching scenes show the octree's subdivision: rendered, demo and solids each fit one
// leaf (a single octant at depth 0), but explained they are cut more than one level deep, each
// octant's turn pictured, and the finished picture is still the ordinary render's.
TEST(Explain, OctreeShowsItsSubdivisionOnTheTeachingScenes) {
  const testing::ScratchDir scratch("hsr_explain_octree");
  for (const char* spec : {"demo", "solids"}) {
    SCOPED_TRACE(spec);
    const Scene scene = loadScene(spec);
    const Camera cam = frameScene(scene, 160, 120);
    RenderOptions o;
    o.algorithm = "octree";
    EXPECT_EQ(render(scene, cam, o).stats.counter("octree: depth"), 0u)
        << "the scene no longer fits one leaf";
    const Explanation e = explain(scene, cam, o, scratch / spec);
    ASSERT_FALSE(e.steps.empty());
    ASSERT_EQ(e.steps.front().name, "build");
    const std::string& caption = e.steps.front().caption;
    const std::size_t at = caption.find("depth ");
    ASSERT_NE(at, std::string::npos) << caption;
    EXPECT_GE(std::stoi(caption.substr(at + 6)), 2) << caption;
    int octants = 0;
    for (const ExplainedStep& s : e.steps) octants += s.name == "octant";
    EXPECT_GE(octants, 8) << "one picture per octant visited, at least a level's eight";
    const Frame f = render(scene, cam, o);
    EXPECT_EQ(e.frame.ids, f.ids);
    EXPECT_EQ(e.frame.color, f.color);
  }
}

// In memory: the same steps as the written explanation, each with its two buffers; the BSP
// build's steps are pictured on the plan from above, not on the frame.
TEST(Explain, InMemoryStepsAreTheWrittenOnes) {
  const Scene scene = loadScene("demo");
  const Camera cam = frameScene(scene, 160, 120);
  const testing::ScratchDir scratch("hsr_explain_memory");
  for (const char* alg : {"zbuffer-textbook", "bsp", "warnock", "abuffer"}) {
    SCOPED_TRACE(alg);
    RenderOptions o;
    o.algorithm = alg;
    const Explanation mem = explainSteps(scene, cam, o, {.pictures_per_step = 5});
    const Explanation disk = explain(scene, cam, o, scratch / alg, {.pictures_per_step = 5});
    ASSERT_EQ(mem.steps.size(), disk.steps.size());
    ASSERT_GE(mem.steps.size(), 3u);
    EXPECT_TRUE(mem.sheet.empty());
    EXPECT_EQ(mem.frame.ids, disk.frame.ids);
    for (std::size_t i = 0; i < mem.steps.size(); ++i) {
      const ExplainedStep &m = mem.steps[i], &d = disk.steps[i];
      EXPECT_EQ(m.number, d.number);
      EXPECT_EQ(m.name, d.name);
      EXPECT_EQ(m.caption, d.caption);
      EXPECT_EQ(m.outlines, d.outlines);
      EXPECT_TRUE(m.picture.empty());
      EXPECT_FALSE(d.picture.empty());
      EXPECT_TRUE(d.color.empty()) << "a written step lets its buffers go";
      ASSERT_GT(m.width, 0);
      ASSERT_GT(m.height, 0);
      const std::size_t bytes =
          static_cast<std::size_t>(m.width) * static_cast<std::size_t>(m.height) * 3;
      EXPECT_EQ(m.color.size(), bytes);
      EXPECT_EQ(m.depth.size(), bytes);
      // The written picture holds both buffers side by side.
      const testing::DecodedPng png = testing::decodePng(d.picture);
      ASSERT_TRUE(png.ok()) << png.error;
      EXPECT_GE(png.width, 2 * m.width);
      EXPECT_GE(png.height, m.height);
    }
    // The buffers tell a story: the last step is not blank, and not every step looks alike
    // (a first step may well be the cleared window).
    const auto& last = mem.steps.back().color;
    EXPECT_NE(std::count(last.begin(), last.end(), last[0]),
              static_cast<std::ptrdiff_t>(last.size()));
    EXPECT_NE(mem.steps.front().color, last);
    if (std::string(alg) == "bsp") {
      // The build's steps are seen from above: a picture that is not the frame's.
      const auto split =
          std::find_if(mem.steps.begin(), mem.steps.end(),
                       [](const ExplainedStep& s) { return s.name == "choose splitter"; });
      ASSERT_NE(split, mem.steps.end());
      EXPECT_NE(split->color, mem.steps.back().color);
      EXPECT_GE(split->outlines.size(), 3u) << "the splitter, and the eye's square and line";
    }
  }
  // What cannot explain itself says so.
  RenderOptions o;
  o.algorithm = "painter-naive";
  EXPECT_THROW(explainSteps(scene, cam, o), Error);
}

// One step at a time: the sink sees every step, in order, before the frame comes back.
TEST(Explain, StepsCanBeTakenOneAtATime) {
  const Scene scene = loadScene("demo");
  const Camera cam = frameScene(scene, 120, 90);
  RenderOptions o;
  o.algorithm = "painter";
  std::vector<std::string> names;
  const Frame f = forEachExplainedStep(scene, cam, o, [&](ExplainedStep&& s) {
    EXPECT_EQ(s.number, static_cast<int>(names.size()) + 1);
    names.push_back(s.name);
  });
  const Explanation whole = explainSteps(scene, cam, o);
  ASSERT_EQ(names.size(), whole.steps.size());
  for (std::size_t i = 0; i < names.size(); ++i) EXPECT_EQ(names[i], whole.steps[i].name);
  EXPECT_EQ(f.ids, render(scene, cam, o).ids);
}

}  // namespace
}  // namespace hsr

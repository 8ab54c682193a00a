// hsr explain: numbered pictures of an algorithm's steps, a contact sheet and an index.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "hsr/explain.hpp"
#include "hsr/io.hpp"
#include "test_util.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wshadow"
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

namespace hsr {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("hsr_explain_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

// Width and height of a PNG, or {0, 0} when it does not decode.
std::pair<int, int> pngSize(const fs::path& p) {
  int w = 0, h = 0, n = 0;
  unsigned char* data = stbi_load(p.string().c_str(), &w, &h, &n, 3);
  if (!data) return {0, 0};
  stbi_image_free(data);
  return {w, h};
}

TEST(Explain, TextbookZBufferShowsEachPolygonBeingDrawn) {
  const Scene scene = loadScene("demo");
  const Camera cam = frameScene(scene, 240, 180);
  RenderOptions o;
  o.algorithm = "zbuffer-textbook";
  const fs::path dir = freshDir("textbook");
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
  const fs::path dir = freshDir("tiled");
  const Explanation e = explain(scene, cam, o, dir);
  ASSERT_GE(e.steps.size(), 3u);
  EXPECT_EQ(e.steps.front().name, "bin");
  EXPECT_EQ(e.steps.back().name, "done");
  int tiles = 0;
  for (const ExplainedStep& s : e.steps) tiles += s.name == "fill tile";
  EXPECT_EQ(tiles, 12);  // 4 x 3 tiles of 64 x 64
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hsr

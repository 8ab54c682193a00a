// Every output of a render pinned to exact figures that each test derives on its own, from
// the documented rule and the scene's geometry, never from the code under test: the
// orientation of every buffer, raw file and picture (library and CLI); transparency's blend
// and order; the coverage of concave polygons; silhouette outlines on a closed solid;
// overdraw; LINE mode on clipped polygons. Each test says which bug it exists to catch: each
// of those bugs once survived the whole suite.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <optional>
#include <ostream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"
#include "test_util.hpp"

#include "png_read.hpp"

namespace hsr {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;

// ---------------------------------------------------------------------------------------------
// Reading outputs back, independently of the writers: .npy by its published format, PNG
// through stb_image.

std::string readBytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// A NumPy .npy file, version 1.0: "\x93NUMPY", 1, 0, the header's length (little-endian
// uint16), the header (a Python dict literal), then the array in C order, row 0 first.
struct Npy {
  std::string descr;
  int rows = 0, cols = 0;
  std::string data;
};

Npy readNpy(const fs::path& p) {
  const std::string b = readBytes(p);
  Npy n;
  EXPECT_GE(b.size(), 10u) << p;
  if (b.size() < 10) return n;
  EXPECT_EQ(b.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8)) << p;
  const std::size_t len = static_cast<unsigned char>(b[8]) |
                          static_cast<std::size_t>(static_cast<unsigned char>(b[9])) << 8;
  EXPECT_LE(10 + len, b.size()) << p;
  if (10 + len > b.size()) return n;
  const std::string header = b.substr(10, len);
  EXPECT_NE(header.find("'fortran_order': False"), std::string::npos) << header;
  const std::size_t d = header.find("'descr': '");
  EXPECT_NE(d, std::string::npos) << header;
  if (d != std::string::npos) n.descr = header.substr(d + 10, header.find('\'', d + 10) - d - 10);
  const std::size_t s = header.find("'shape': (");
  EXPECT_NE(s, std::string::npos) << header;
  if (s != std::string::npos) {
    EXPECT_EQ(std::sscanf(header.c_str() + s + 10, "%d, %d", &n.rows, &n.cols), 2) << header;
  }
  n.data = b.substr(10 + len);
  return n;
}

// Element k of a '<u4' or '<f4' array, assembled from its little-endian bytes.
std::uint32_t npyWord(const Npy& n, std::size_t k) {
  const auto byte = [&](int i) {
    return static_cast<std::uint32_t>(static_cast<unsigned char>(n.data[4 * k + i]));
  };
  return byte(0) | byte(1) << 8 | byte(2) << 16 | byte(3) << 24;
}

struct Rgb {
  int r = 0, g = 0, b = 0;
  bool operator==(const Rgb&) const = default;
};
std::ostream& operator<<(std::ostream& o, const Rgb& c) {
  return o << "(" << c.r << ", " << c.g << ", " << c.b << ")";
}

struct Png {
  int width = 0, height = 0;
  std::vector<Rgb> pixels;  // row 0 = the top row of the picture, as PNG stores it
};

Png readPng(const fs::path& p) {
  Png png;
  const auto decoded = hsr::testing::decodePng(p);
  EXPECT_TRUE(decoded.ok()) << p << ": " << decoded.error;
  png.width = decoded.width;
  png.height = decoded.height;
  for (std::size_t k = 0; k + 2 < decoded.rgb.size(); k += 3)
    png.pixels.push_back({decoded.rgb[k], decoded.rgb[k + 1], decoded.rgb[k + 2]});
  return png;
}

Rgb frameRgb(const Frame& f, std::size_t k) {
  return {testing::channel(f, k, 0), testing::channel(f, k, 1), testing::channel(f, k, 2)};
}

// A colour in [0, 1] as the byte it is documented to become: the nearest of 0..255.
int toByte(float c) { return static_cast<int>(std::lround(static_cast<double>(c) * 255.0)); }
Rgb toRgb(const glm::vec3& c) { return {toByte(c.r), toByte(c.g), toByte(c.b)}; }

// An axis-aligned rectangle (world x in [x0, x1], y in [y0, y1]) at depth z, counter-clockwise
// seen from +z.
PolygonId addRect(Scene& s, float x0, float y0, float x1, float y1, float z, std::uint32_t m) {
  return s.addPolygonVertices({{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}}, m);
}

// Under testing::pixelCamera(w, h) world (x, y) is GL window (x, y): the pixel of buffer
// element (row, col) is sampled at world (col + 0.5, h - row - 0.5).
struct Centre {
  double x, y;
};
Centre centreOf(int row, int col, int height) { return {col + 0.5, height - row - 0.5}; }

// ---------------------------------------------------------------------------------------------
// 1. Orientation. Catches: any buffer, raw file or picture written bottom row first (or
// mirrored). The scene is one right triangle in the top-left corner of a 24x16 window and
// nothing else, so every flip moves it to an empty corner.

constexpr int kCornerW = 24, kCornerH = 16;

// The triangle (1, 15) (7.25, 15) (1, 8.75) in GL window coordinates (y up): a pixel centre
// (x, y) is inside when x > 1, y < 15 and (x - 1) + (15 - y) < 6.25. Centres sit at
// half-integers, so none lies on an edge. 21 pixels: rows 1..6 from the top, columns 1..6.
bool inCorner(int row, int col) {
  const Centre c = centreOf(row, col, kCornerH);
  return c.x > 1.0 && c.y < 15.0 && (c.x - 1.0) + (15.0 - c.y) < 6.25;
}

int cornerPixelCount() {
  int n = 0;
  for (int row = 0; row < kCornerH; ++row)
    for (int col = 0; col < kCornerW; ++col) n += inCorner(row, col);
  return n;
}

const glm::vec3 kCornerRed{1.0f, 0.0f, 0.0f};

Scene cornerScene() {
  Scene s;
  const std::uint32_t m = s.addMaterial({kCornerRed, 1.0f});
  s.addPolygonVertices({{1.0f, 15.0f, 0.0f}, {7.25f, 15.0f, 0.0f}, {1.0f, 8.75f, 0.0f}}, m);
  return s;
}

RenderOptions flatOptions(const std::string& algorithm) {
  RenderOptions o = testing::optionsFor(algorithm);
  o.shade = false;  // the material's own colour, so that the colour picture can be predicted
  return o;
}

// The pixel camera puts z = 0 at window depth (10 - 1) / 19 (eye at z = 10, near 1, far 20,
// orthographic: depth is linear in z).
constexpr double kCornerDepth = 9.0 / 19.0;

// Checks the three raw buffers, given element by element, against the corner triangle.
void expectCornerBuffers(const std::function<PolygonId(std::size_t)>& id,
                         const std::function<float(std::size_t)>& depth,
                         const std::function<std::uint32_t(std::size_t)>& overdraw,
                         double expected_depth, const std::string& what) {
  int wrong_ids = 0, wrong_depths = 0, wrong_overdraw = 0;
  for (int row = 0; row < kCornerH; ++row) {
    for (int col = 0; col < kCornerW; ++col) {
      const std::size_t k = static_cast<std::size_t>(row) * kCornerW + col;
      const bool in = inCorner(row, col);
      const bool id_ok = id(k) == (in ? 0u : kNoPolygon);
      const bool depth_ok = in ? std::abs(depth(k) - expected_depth) <= 1e-6 : depth(k) == 1.0f;
      const bool overdraw_ok = overdraw(k) == (in ? 1u : 0u);
      if (!id_ok && wrong_ids++ == 0)
        ADD_FAILURE() << what << ": ids at row " << row << " col " << col << " is " << id(k)
                      << ", expected " << (in ? "0" : "none");
      if (!depth_ok && wrong_depths++ == 0)
        ADD_FAILURE() << what << ": depth at row " << row << " col " << col << " is " << depth(k);
      if (!overdraw_ok && wrong_overdraw++ == 0)
        ADD_FAILURE() << what << ": overdraw at row " << row << " col " << col << " is "
                      << overdraw(k);
    }
  }
  EXPECT_EQ(wrong_ids, 0) << what << ": pixels with the wrong id (of " << cornerPixelCount()
                          << " covered)";
  EXPECT_EQ(wrong_depths, 0) << what << ": pixels with the wrong depth";
  EXPECT_EQ(wrong_overdraw, 0) << what << ": pixels with the wrong overdraw";
}

// The raw files of a frame of the corner scene: shape (16, 24), the documented dtypes, and
// every element where the triangle puts it.
void expectCornerRawFiles(const fs::path& dir, double expected_depth, const std::string& what) {
  const Npy ids = readNpy(dir / "ids.npy");
  const Npy depth = readNpy(dir / "depth.npy");
  const Npy overdraw = readNpy(dir / "overdraw.npy");
  const std::size_t n = static_cast<std::size_t>(kCornerW) * kCornerH;
  for (const auto& [name, npy, descr] :
       {std::tuple{"ids.npy", &ids, "<u4"}, std::tuple{"depth.npy", &depth, "<f4"},
        std::tuple{"overdraw.npy", &overdraw, "<u4"}}) {
    EXPECT_EQ(npy->descr, descr) << what << " " << name;
    EXPECT_EQ(npy->rows, kCornerH) << what << " " << name << ": shape is (height, width)";
    EXPECT_EQ(npy->cols, kCornerW) << what << " " << name;
    ASSERT_EQ(npy->data.size(), 4 * n) << what << " " << name;
  }
  expectCornerBuffers([&](std::size_t k) { return npyWord(ids, k); },
                      [&](std::size_t k) { return std::bit_cast<float>(npyWord(depth, k)); },
                      [&](std::size_t k) { return npyWord(overdraw, k); }, expected_depth, what);
}

// A picture of a frame of the corner scene: `inside` at the triangle's pixels (or, where
// the colour is not predicted, one colour other than `outside`), `outside` elsewhere.
void expectCornerPicture(const Png& png, const std::optional<Rgb>& inside, const Rgb& outside,
                         const std::string& what) {
  ASSERT_EQ(png.width, kCornerW) << what;
  ASSERT_EQ(png.height, kCornerH) << what;
  const Rgb first_in = png.pixels[1 * kCornerW + 1];  // row 1, col 1: inside
  EXPECT_NE(first_in, outside) << what << ": row 1 col 1 shows nothing";
  int wrong = 0;
  for (int row = 0; row < kCornerH; ++row) {
    for (int col = 0; col < kCornerW; ++col) {
      const Rgb got = png.pixels[static_cast<std::size_t>(row) * kCornerW + col];
      const Rgb want = inCorner(row, col) ? inside.value_or(first_in) : outside;
      if (got != want && wrong++ == 0)
        ADD_FAILURE() << what << ": row " << row << " col " << col << " is " << got << ", expected "
                      << want;
    }
  }
  EXPECT_EQ(wrong, 0) << what << ": pixels that differ (of " << cornerPixelCount()
                      << " covered, top-left)";
}

// Colours of the pictures at the triangle, from their documented definitions: the material
// colour; the nearest depth of the frame as the lightest grey (255); the others (a hashed
// palette, a heat ramp) only as one colour that is not the background. Background: the clear
// colour, or black.
void expectCornerPictures(const fs::path& dir, const std::string& stem, const std::string& what) {
  const Rgb clear = toRgb(RenderOptions{}.clear_color);
  const Rgb black{0, 0, 0};
  expectCornerPicture(readPng(dir / (stem + "color.png")), toRgb(kCornerRed), clear,
                      what + " color");
  expectCornerPicture(readPng(dir / (stem + "depth.png")), Rgb{255, 255, 255}, black,
                      what + " depth");
  expectCornerPicture(readPng(dir / (stem + "ids.png")), std::nullopt, black, what + " ids");
  expectCornerPicture(readPng(dir / (stem + "overdraw.png")), std::nullopt, black,
                      what + " overdraw");
}

class PinningOrientation : public testing::EveryAlgorithm {};

TEST_P(PinningOrientation, FrameBuffersAreTopRowFirst) {
  const Frame f =
      render(cornerScene(), testing::pixelCamera(kCornerW, kCornerH), flatOptions(GetParam()));
  ASSERT_EQ(f.ids.size(), static_cast<std::size_t>(kCornerW) * kCornerH);
  expectCornerBuffers([&](std::size_t k) { return f.ids[k]; },
                      [&](std::size_t k) { return f.depth[k]; },
                      [&](std::size_t k) { return f.overdraw[k]; }, kCornerDepth, "frame");
  const Rgb clear = toRgb(RenderOptions{}.clear_color);
  int wrong = 0;
  for (int row = 0; row < kCornerH; ++row)
    for (int col = 0; col < kCornerW; ++col) {
      const std::size_t k = static_cast<std::size_t>(row) * kCornerW + col;
      wrong += frameRgb(f, k) != (inCorner(row, col) ? toRgb(kCornerRed) : clear);
    }
  EXPECT_EQ(wrong, 0) << "colour buffer pixels that differ";
}
HSR_INSTANTIATE_FOR_EVERY_ALGORITHM(PinningOrientation);

// writeRawFrame and writePng(picture(...)), as a program using the library writes them.
TEST(PinningOrientationFiles, LibraryRawFilesAndPicturesAreTopRowFirst) {
  const Frame f =
      render(cornerScene(), testing::pixelCamera(kCornerW, kCornerH), flatOptions("zbuffer"));
  const ScratchDir dir("hsr_pinning");
  writeRawFrame(dir / "raw", f, "corner", "zbuffer");
  expectCornerRawFiles(dir / "raw", kCornerDepth, "writeRawFrame");
  for (const char* kind : {"color", "depth", "ids", "overdraw"})
    writePng(dir / ("lib-" + std::string(kind) + ".png"), f.width, f.height, 3,
             picture(f, kind).data());
  expectCornerPictures(dir.path(), "lib-", "writePng(picture)");
}

// The CLI: the same triangle in an OBJ file, seen through a perspective camera that puts it at
// the same window pixels (eye (0, 0, 5), fov 90: at z = 0 the 24x16 window spans x in
// [-7.5, 7.5] and y in [-5, 5], 1.6 pixels per unit, so window (X, Y) is world
// ((X - 12) / 1.6, (Y - 8) / 1.6)), and every output it writes.
TEST(PinningOrientationFiles, CliRawFilesAndPicturesAreTopRowFirst) {
  const ScratchDir dir("hsr_pinning");
  {
    std::ofstream obj(dir / "corner.obj");
    obj << "v -6.875 4.375 0\nv -2.96875 4.375 0\nv -6.875 0.46875 0\nf 1 2 3\n";
  }
  const std::string cmd = "timeout 60 " + std::string(HSR_CLI_PATH) + " render " +
                          (dir / "corner.obj").string() +
                          " --size 24x16 --eye 0,0,5 --target 0,0,0 --up 0,1,0 --fov 90"
                          " --near 1 --far 10 --flat -q --output color,depth,ids,overdraw -o " +
                          (dir / "cli.png").string() + " --raw " + (dir / "raw").string() + " >" +
                          (dir / "out.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd << "\n" << readBytes(dir / "out.txt");
  // z = 0 is 5 units in front of the eye: NDC z = (f + n) / (f - n) - 2 f n / ((f - n) 5) =
  // 7/9, window depth (7/9 + 1) / 2 = 8/9.
  expectCornerRawFiles(dir / "raw", 8.0 / 9.0, "hsr render --raw");
  // The OBJ has no material: its colour is the loader's default, not predicted here.
  const Rgb clear = toRgb(RenderOptions{}.clear_color);
  expectCornerPicture(readPng(dir / "cli-color.png"), std::nullopt, clear, "hsr render color");
  const Rgb black{0, 0, 0};
  expectCornerPicture(readPng(dir / "cli-depth.png"), Rgb{255, 255, 255}, black,
                      "hsr render depth");
  expectCornerPicture(readPng(dir / "cli-ids.png"), std::nullopt, black, "hsr render ids");
  expectCornerPicture(readPng(dir / "cli-overdraw.png"), std::nullopt, black,
                      "hsr render overdraw");
}

// ---------------------------------------------------------------------------------------------
// 2. Transparency. Catches: transparent polygons blended in reverse submission order, and the
// blend's weights swapped. The documented rule (raster/fragment.hpp, docs/algorithms.md):
// opaque polygons first; then each transparent polygon, in submission order (in depth order,
// farthest first, for an algorithm that paints back to front), depth-tested, blends over what
// is there as src * a + dst * (1 - a) per channel (a = its alpha byte / 255),
// rounded to the nearest byte, leaving depth and id alone.

struct Layer {
  float x0, y0, x1, y1, z;
  glm::vec3 color;
  float alpha;
  bool covers(const Centre& c) const { return c.x > x0 && c.x < x1 && c.y > y0 && c.y < y1; }
};

Rgb over(const Rgb& src, int a, const Rgb& dst) {
  auto mix = [&](int s, int d) {
    return static_cast<int>(std::lround((s * a + d * (255.0 - a)) / 255.0));
  };
  return {mix(src.r, dst.r), mix(src.g, dst.g), mix(src.b, dst.b)};
}

class PinningTransparency : public testing::EveryAlgorithm {};

TEST_P(PinningTransparency, LayersBlendInSubmissionOrderWithTheirOwnAlpha) {
  constexpr int kW = 32, kH = 16;
  // An opaque floor over the lower half, and two transparent layers overlapping each other
  // and it; alpha 0.6 and 0.25 (bytes 153 and 64), so that swapping the weights, or the
  // order, changes every channel that differs.
  const Layer ground{0, 0, 32, 8, -5, {0.2f, 0.4f, 1.0f}, 1.0f};
  const Layer a{4, 3, 20, 13, 0, {1.0f, 0.6f, 0.0f}, 0.6f};
  const Layer b{12, 5, 28, 15, 2, {0.0f, 0.2f, 0.8f}, 0.25f};
  const std::vector<std::vector<const Layer*>> orders = {{&a, &ground, &b}, {&b, &a, &ground}};
  for (const std::vector<const Layer*>& order : orders) {
    Scene s;
    for (const Layer* l : order)
      addRect(s, l->x0, l->y0, l->x1, l->y1, l->z, s.addMaterial({l->color, l->alpha}));
    const std::string what = order[0] == &a ? "A, floor, B" : "B, A, floor";
    SCOPED_TRACE(what);
    const Frame f = render(s, testing::pixelCamera(kW, kH), flatOptions(GetParam()));
    // The z-buffer blends in submission order; an algorithm that paints back to front blends
    // in depth order, farthest first (a at z = 0 before b at z = 2), whatever the scene lists.
    std::vector<const Layer*> blendOrder = order;
    if (findAlgorithm(GetParam()).has(kBackToFront))
      std::stable_sort(blendOrder.begin(), blendOrder.end(),
                       [](const Layer* x, const Layer* y) { return x->z < y->z; });
    int wrong = 0, blended_twice = 0;
    for (int row = 0; row < kH; ++row) {
      for (int col = 0; col < kW; ++col) {
        const Centre c = centreOf(row, col, kH);
        const std::size_t k = static_cast<std::size_t>(row) * kW + col;
        // Opaque first, then the transparent layers in the order the scene lists them (each
        // nearer than the floor, so the depth test passes).
        Rgb want = toRgb(RenderOptions{}.clear_color);
        PolygonId want_id = kNoPolygon;
        if (ground.covers(c)) {
          want = toRgb(ground.color);
          for (std::size_t i = 0; i < order.size(); ++i)
            if (order[i] == &ground) want_id = static_cast<PolygonId>(i);
        }
        std::uint32_t layers = ground.covers(c);
        for (const Layer* l : blendOrder) {
          if (l == &ground || !l->covers(c)) continue;
          want = over(toRgb(l->color), toByte(l->alpha), want);
          ++layers;
        }
        blended_twice += a.covers(c) && b.covers(c);
        const Rgb got = frameRgb(f, k);
        const bool ok = got == want && f.ids[k] == want_id && f.overdraw[k] == layers;
        if (!ok && wrong++ < 3)
          ADD_FAILURE() << "row " << row << " col " << col << ": colour " << got << " id "
                        << f.ids[k] << " overdraw " << f.overdraw[k] << ", expected " << want
                        << " id " << want_id << " overdraw " << layers;
      }
    }
    EXPECT_EQ(wrong, 0) << "pixels that differ from the blend computed here";
    EXPECT_EQ(blended_twice, 64);  // the 8x8 pixels where both layers overlap
  }
}
HSR_INSTANTIATE_FOR_ALGORITHMS_WITH(PinningTransparency, kTransparency);

// ---------------------------------------------------------------------------------------------
// 3. Concave polygons. Catches: every polygon triangulated as a fan from its first vertex
// (right for convex polygons only). Each polygon is ONE polygon of the scene, starting at a
// vertex from which a fan leaves the polygon; its pixels must be exactly the pixel centres
// inside it, by an even-odd crossing test computed here. Vertices lie on a 1/8 grid, so every
// coordinate here and in the renderer's 1/256 snapping is exact.

using Outline2 = std::vector<Centre>;

// Even-odd rule: a ray from p towards +x crosses the boundary an odd number of times.
bool insidePolygon(const Outline2& poly, const Centre& p) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Centre& a = poly[i];
    const Centre& b = poly[j];
    if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y)) in = !in;
  }
  return in;
}

// Whether p lies exactly on an edge (the fill rule, not the geometry, would decide it).
bool onBoundary(const Outline2& poly, const Centre& p) {
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Centre& a = poly[i];
    const Centre& b = poly[j];
    const double cross = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
    if (cross == 0.0 && p.x >= std::min(a.x, b.x) && p.x <= std::max(a.x, b.x) &&
        p.y >= std::min(a.y, b.y) && p.y <= std::max(a.y, b.y))
      return true;
  }
  return false;
}

// A five-pointed star (outer radius 15, inner 6, about (16, 16)), from its top point,
// counter-clockwise, each vertex rounded to 1/8.
Outline2 star() {
  Outline2 s;
  for (int i = 0; i < 10; ++i) {
    const double angle = 1.5707963267948966 + i * 3.141592653589793 / 5.0;
    const double r = i % 2 ? 6.0 : 15.0;
    s.push_back({std::round((16.0 + r * std::cos(angle)) * 8.0) / 8.0,
                 std::round((16.0 + r * std::sin(angle)) * 8.0) / 8.0});
  }
  return s;
}

class PinningConcave : public testing::EveryAlgorithm {};

TEST_P(PinningConcave, CoverageIsExactlyThePixelCentresInside) {
  constexpr int kSize = 32;
  struct Shape {
    const char* name;
    Outline2 outline;
    int pixels;  // how many centres lie inside, by the crossing test below
  };
  // The L starts at the top of its inner corner's column, (10, 30): the fan from there
  // (10,30)-(2,2)-(30,2) covers the notch above the lower arm, which is not in the L.
  const Shape shapes[] = {
      {"L", {{10, 30}, {2, 30}, {2, 2}, {30, 2}, {30, 10}, {10, 10}}, 8 * 28 + 20 * 8},
      {"star", star(), 270},
  };
  for (const Shape& shape : shapes) {
    SCOPED_TRACE(shape.name);
    Scene s;
    std::vector<glm::vec3> v;
    for (const Centre& p : shape.outline)
      v.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y), 0.0f);
    s.addPolygonVertices(v, s.addMaterial({}));
    ASSERT_EQ(s.polygonCount(), 1u);
    const Frame f = render(s, testing::pixelCamera(kSize, kSize), testing::optionsFor(GetParam()));
    int inside = 0, wrong = 0;
    for (int row = 0; row < kSize; ++row) {
      for (int col = 0; col < kSize; ++col) {
        const Centre c = centreOf(row, col, kSize);
        ASSERT_FALSE(onBoundary(shape.outline, c)) << "pick vertices off the pixel centres";
        const bool in = insidePolygon(shape.outline, c);
        inside += in;
        const std::size_t k = static_cast<std::size_t>(row) * kSize + col;
        // Inside: drawn exactly once (the triangles tile the polygon); outside: nothing.
        const bool ok = f.ids[k] == (in ? 0u : kNoPolygon) && f.overdraw[k] == (in ? 1u : 0u);
        if (!ok && wrong++ < 3)
          ADD_FAILURE() << "row " << row << " col " << col << ": id " << f.ids[k] << " overdraw "
                        << f.overdraw[k] << ", centre " << (in ? "inside" : "outside");
      }
    }
    EXPECT_EQ(inside, shape.pixels);
    EXPECT_EQ(wrong, 0) << "pixels whose coverage differs from the polygon's (" << inside
                        << " inside)";
  }
}
HSR_INSTANTIATE_FOR_ALGORITHMS_WITH(PinningConcave, kExactSharedCoverage);

// ---------------------------------------------------------------------------------------------
// 4. Silhouettes. Catches: the outline dropping the edges between a front-facing and a
// back-facing polygon (keeping only the borders of open surfaces). A closed cube has no
// border edge, so its whole outline is silhouette.
//
// The cube [-1.2, 1.2]^3 seen from (0, 0, 5) along -z (fov 90, 64x64): the front face is the
// only front-facing one (the four sides face away from an eye straight in front of them, and
// project inside it), so the silhouette is the front face's square. At distance 3.8 it spans
// NDC +-1.2/3.8, window 32 +- 32 * 1.2 / 3.8 = 32 +- 10.105, pixel-centre coordinates 21.395
// to 41.605. The pen (2x2, rows/columns p - 1 and p around the nearest centre p of each DDA
// step, steps < 1 pixel apart) covers a square ring two pixels thick: columns and rows 20..42
// minus 22..40, 23^2 - 19^2 = 168 pixels, all black (outside the square nothing is drawn;
// inside, the front face is the visible polygon of the edge).

Scene cube(float h) {
  Scene s;
  const std::uint32_t m = s.addMaterial({});
  for (int axis = 0; axis < 3; ++axis) {
    for (const float side : {-h, h}) {
      // The face's corners counter-clockwise seen from outside.
      glm::vec3 p[4];
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      const float su[4] = {-h, h, h, -h}, sw[4] = {-h, -h, h, h};
      for (int i = 0; i < 4; ++i) {
        p[i][axis] = side;
        p[i][u] = su[i];
        p[i][w] = side > 0 ? sw[i] : -sw[i];
      }
      s.addPolygonVertices({p[0], p[1], p[2], p[3]}, m);
    }
  }
  return s;
}

class PinningOutline : public testing::EveryAlgorithm {};

TEST_P(PinningOutline, ClosedCubeOutlinesItsSilhouette) {
  Camera cam;
  cam.width = cam.height = 64;
  cam.eye = {0.0f, 0.0f, 5.0f};
  cam.target = {0.0f, 0.0f, 0.0f};
  cam.fov_deg = 90.0f;
  cam.near = 1.0f;
  cam.far = 10.0f;
  RenderOptions o = testing::optionsFor(GetParam());
  o.outline = true;
  const Frame f = render(cube(1.2f), cam, o);
  const Rgb black{0, 0, 0};
  int black_pixels = 0, wrong = 0;
  for (int row = 0; row < 64; ++row) {
    for (int col = 0; col < 64; ++col) {
      const bool ring = row >= 20 && row <= 42 && col >= 20 && col <= 42 &&
                        !(row >= 22 && row <= 40 && col >= 22 && col <= 40);
      const bool is_black = frameRgb(f, static_cast<std::size_t>(row) * 64 + col) == black;
      black_pixels += is_black;
      if (is_black != ring && wrong++ < 3)
        ADD_FAILURE() << "row " << row << " col " << col << (ring ? " is not" : " is") << " black";
    }
  }
  EXPECT_EQ(black_pixels, 168) << "silhouette pixels";
  EXPECT_EQ(wrong, 0);
  // The corners of the square: each on two silhouette edges.
  for (const auto& [row, col] :
       {std::pair{21, 21}, std::pair{21, 42}, std::pair{42, 21}, std::pair{42, 42}})
    EXPECT_EQ(frameRgb(f, static_cast<std::size_t>(row) * 64 + col), black) << row << "," << col;
}
HSR_INSTANTIATE_FOR_ALGORITHMS_WITH(PinningOutline, kOutline);

// ---------------------------------------------------------------------------------------------
// 5. Overdraw. Catches: overdraw counting fragments before the depth test (it counts the
// fragments written: those that passed). Three rectangles at known depths drawn in three
// orders; at each pixel, a rectangle's fragment passes LESS when it is nearer than every
// rectangle drawn there before it (the clear depth being the farthest).

class PinningOverdraw : public testing::EveryAlgorithm {};

TEST_P(PinningOverdraw, CountsOnlyFragmentsThatPassTheDepthTest) {
  constexpr int kW = 32, kH = 16;
  // World z: larger is nearer the pixel camera's eye (at z = 10).
  const Layer far_rect{2, 2, 20, 12, -2, {}, 1.0f};
  const Layer mid_rect{8, 4, 28, 14, 1, {}, 1.0f};
  const Layer near_rect{4, 6, 14, 10, 3, {}, 1.0f};
  const struct {
    const char* name;
    std::vector<const Layer*> order;
    int max_overdraw;  // where all three overlap
  } cases[] = {
      {"far to near", {&far_rect, &mid_rect, &near_rect}, 3},
      {"near to far", {&near_rect, &mid_rect, &far_rect}, 1},
      {"mid, near, far", {&mid_rect, &near_rect, &far_rect}, 2},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    Scene s;
    const std::uint32_t m = s.addMaterial({});
    for (const Layer* l : c.order) addRect(s, l->x0, l->y0, l->x1, l->y1, l->z, m);
    const Frame f = render(s, testing::pixelCamera(kW, kH), testing::optionsFor(GetParam()));
    std::uint64_t tested = 0, written = 0;
    std::uint32_t max_seen = 0;
    int wrong = 0;
    for (int row = 0; row < kH; ++row) {
      for (int col = 0; col < kW; ++col) {
        const Centre p = centreOf(row, col, kH);
        std::uint32_t passed = 0;
        PolygonId visible = kNoPolygon;
        float nearest = -1e30f;
        for (std::size_t i = 0; i < c.order.size(); ++i) {
          if (!c.order[i]->covers(p)) continue;
          ++tested;
          if (c.order[i]->z > nearest) {
            nearest = c.order[i]->z;
            visible = static_cast<PolygonId>(i);
            ++passed;
          }
        }
        written += passed;
        const std::size_t k = static_cast<std::size_t>(row) * kW + col;
        max_seen = std::max(max_seen, f.overdraw[k]);
        if ((f.overdraw[k] != passed || f.ids[k] != visible) && wrong++ < 3)
          ADD_FAILURE() << "row " << row << " col " << col << ": overdraw " << f.overdraw[k]
                        << " id " << f.ids[k] << ", expected " << passed << " id " << visible;
      }
    }
    EXPECT_EQ(wrong, 0) << "pixels whose overdraw or id differ";
    EXPECT_EQ(max_seen, static_cast<std::uint32_t>(c.max_overdraw));
    EXPECT_EQ(f.stats.fragments_tested, tested);
    EXPECT_EQ(f.stats.fragments_written, written);
  }
}
// Overdraw as fragments that passed a depth test: the algorithms with one (a painter has none
// and counts every fragment it paints; tests/visibility/painter_test.cpp pins that).
HSR_INSTANTIATE_FOR_ALGORITHMS_WITH(PinningOverdraw, kExactSharedCoverage | kDepthFuncs);

// ---------------------------------------------------------------------------------------------
// 6. LINE mode. Catches: LINE mode drawing the edges that clipping makes (GL draws only the
// polygon's own edges: the clipper's new edges carry edge flag false).
//
// A rectangle tilted in depth (x from 8.25 to 56.25; from y = 2.25, z = -14 to y = 62.25,
// z = 14) through the pixel camera (64x64; near plane at z = 9, far plane at z = -10) is cut
// by both: it is visible for y in [2.25 + 4 * 60/28, 2.25 + 23 * 60/28] = [10.82, 51.54]. Of
// its own edges only the two long sides remain, pixel-centre columns 7.75 and 55.75 (pixels
// 8 and 56) between pixel-centre rows 63.5 - 51.54 = 11.96 and 63.5 - 10.82 = 52.68: one
// pixel per row, rows 12..53. The near and far cuts are horizontal and must not be drawn.
// LEQUAL, so that the fragments on the far plane (window depth 1, the clear depth) are drawn:
// under LESS the far cut would be invisible whether drawn or not.

class PinningLineMode : public testing::EveryAlgorithm {};

TEST_P(PinningLineMode, EdgesMadeByNearAndFarClippingAreNotDrawn) {
  constexpr int kSize = 64;
  Scene s;
  s.addPolygonVertices({{8.25f, 2.25f, -14.0f},
                        {56.25f, 2.25f, -14.0f},
                        {56.25f, 62.25f, 14.0f},
                        {8.25f, 62.25f, 14.0f}},
                       s.addMaterial({}));
  RenderOptions o = testing::optionsFor(GetParam());
  o.polygon_mode = PolygonMode::Line;
  o.depth_func = DepthFunc::LEqual;
  const Frame f = render(s, testing::pixelCamera(kSize, kSize), o);
  int drawn = 0, wrong = 0;
  for (int row = 0; row < kSize; ++row) {
    for (int col = 0; col < kSize; ++col) {
      const std::size_t k = static_cast<std::size_t>(row) * kSize + col;
      const bool want = (col == 8 || col == 56) && row >= 12 && row <= 53;
      const bool got = f.ids[k] != kNoPolygon;
      drawn += got;
      if (got != want && wrong++ < 3)
        ADD_FAILURE() << "row " << row << " col " << col << (got ? " drawn" : " not drawn");
    }
  }
  EXPECT_EQ(drawn, 2 * 42) << "pixels drawn (the two sides, 42 rows each)";
  EXPECT_EQ(wrong, 0);
}
HSR_INSTANTIATE_FOR_ALGORITHMS_WITH(PinningLineMode, kPolygonModes);

}  // namespace
}  // namespace hsr

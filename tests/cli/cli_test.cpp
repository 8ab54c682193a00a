// The `hsr` command on bad input: one clear line on stderr, exit code 2, never a crash or a
// hang; and on good input, the files it promises.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <set>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <sys/wait.h>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "hsr/compare.hpp"
#include "hsr/io.hpp"
#include "cli/cli_run.hpp"
#include "png_read.hpp"
#include "test_util.hpp"

namespace {

namespace fs = std::filesystem;
using hsr::testing::ScratchDir;

using hsr::testing::CliRun;
using hsr::testing::expectCleanError;
using hsr::testing::runCli;
int lines(const std::string& s) { return hsr::testing::lineCount(s); }

TEST(Cli, BadCameraAndSizeGiveOneLineAndExit2) {
  const ScratchDir scratch("hsr_cli_test");
  const std::string out = "-o " + (scratch.path() / "x.png").string();
  expectCleanError("render demo --near 0 " + out, "near");
  expectCleanError("render demo --near -1 " + out, "near");
  expectCleanError("render demo --near 5 --far 2 " + out, "far");
  expectCleanError("render demo --size 0x10 " + out, "size");
  expectCleanError("render demo --size 100000x100000 " + out, "GiB");
  expectCleanError("render demo --size banana " + out, "size");
  expectCleanError("render demo --eye nan,0,0 " + out, "finite");
  expectCleanError("render demo --eye 1,2 " + out, "--eye");
  expectCleanError("render demo --eye 0,0,0 --target 0,0,0 " + out, "same point");
  expectCleanError("render demo --fov 0 " + out, "fov");
  expectCleanError("render demo --fov inf " + out);
  expectCleanError("render demo --cull sideways " + out, "cull");
  expectCleanError("render demo --algorithm magic " + out, "algorithm");
  expectCleanError("render demo --output color,smell " + out, "output");
  expectCleanError("render demo --threads -3 " + out, "threads");
  expectCleanError("render demo --no-such-flag " + out);
}

TEST(Cli, BadFilesGiveOneLineAndExit2) {
  const ScratchDir scratch("hsr_cli_test");
  const fs::path d = scratch.path();
  const std::string out = "-o " + (d / "x.png").string();
  expectCleanError("render " + (d / "does_not_exist.obj").string() + " " + out, "does_not_exist");
  {
    std::ofstream f(d / "text.obj");
    f << "this is not a mesh\njust some words\n";
  }
  expectCleanError("render " + (d / "text.obj").string() + " " + out, "text.obj");
  { std::ofstream f(d / "empty.obj"); }
  expectCleanError("render " + (d / "empty.obj").string() + " " + out, "empty.obj");
  {
    std::ofstream f(d / "nan.obj");
    f << "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n";
  }
  expectCleanError("render " + (d / "nan.obj").string() + " " + out, "nan.obj");
  // A truncated binary STL: header says 1000 triangles, data holds 2.
  {
    std::ofstream f(d / "short.stl", std::ios::binary);
    std::string header(80, ' ');
    f.write(header.data(), 80);
    const std::uint32_t n = 1000;
    f.write(reinterpret_cast<const char*>(&n), 4);
    std::string tri(100, '\0');
    f.write(tri.data(), tri.size());
  }
  expectCleanError("render " + (d / "short.stl").string() + " " + out, "short.stl");
  // assimp's own regression files: each is refused with one line, or (malformed2.obj, whose
  // only fault is a missing material) loads with the default material. Never a crash.
  int refused = 0;
  for (const auto& e : fs::directory_iterator(fs::path(HSR_TEST_MODELS) / "invalid")) {
    const CliRun r = runCli("render " + e.path().string() + " " + out);
    const bool lenient = e.path().filename() == "malformed2.obj";
    EXPECT_EQ(r.code, lenient ? 0 : 2) << e.path() << "\nstderr: " << r.err;
    if (!lenient) {
      EXPECT_EQ(lines(r.err), 1) << e.path() << "\nstderr: " << r.err;
    }
    refused += r.code == 2;
  }
  EXPECT_GE(refused, 14);
}

TEST(Cli, RendersDemoWithEveryOutput) {
  const ScratchDir scratch("hsr_cli_test");
  const fs::path d = scratch.path() / "demo";
  const CliRun r = runCli("render demo --size 160x120 --output color,depth,ids,overdraw -o " +
                          (d / "demo.png").string() + " --raw " + (d / "raw").string() +
                          " --stats " + (d / "stats.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* f : {"demo-color.png", "demo-depth.png", "demo-ids.png", "demo-overdraw.png",
                        "raw/depth.npy", "raw/ids.npy", "raw/overdraw.npy", "stats.json"})
    EXPECT_TRUE(fs::exists(d / f)) << f;
  // ids.npy: 128-byte-aligned header + 160*120 uint32.
  EXPECT_GE(fs::file_size(d / "raw/ids.npy"), 160u * 120u * 4u);
  EXPECT_NE(r.out.find("fragments tested"), std::string::npos) << r.out;
}

// The A-buffer: its sample counts and fragment memory refused with one line, and its
// coverage.npy beside the other raw buffers (not written by the z-buffer).
TEST(Cli, ABufferSamplesMemoryAndCoverage) {
  const ScratchDir scratch("hsr_cli_test");
  const std::string out = "-o " + (scratch.path() / "x.png").string();
  expectCleanError("render demo --algorithm abuffer --samples 3 " + out, "samples");
  expectCleanError("render demo --algorithm abuffer --samples 128 " + out, "samples");
  expectCleanError("render demo --samples 4 " + out,
                   "samples");  // the z-buffer has one, at the centre
  expectCleanError("render demo --algorithm abuffer --fragment-memory 0 " + out, "fragment-memory");
  expectCleanError(
      "render spheres:20000 --size 400x300 --algorithm abuffer --fragment-memory 0.5 " + out,
      "fragment memory");
  const fs::path raw = scratch.path() / "raw";
  const CliRun r = runCli("render demo --size 160x120 --algorithm abuffer --samples 16 " + out +
                          " --raw " + raw.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_GE(fs::file_size(raw / "coverage.npy"), 160u * 120u * 4u);
  std::ifstream manifest(raw / "manifest.json");
  const std::string text((std::istreambuf_iterator<char>(manifest)),
                         std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("coverage.npy"), std::string::npos) << text;
  // The z-buffer's raw output into the same directory has no coverage buffer
  ASSERT_EQ(runCli("render demo --size 160x120 " + out + " --raw " + raw.string()).code, 0);
  EXPECT_FALSE(fs::exists(raw / "coverage.npy"));
}

// hsr bsp: build once, print, render one view with the camera flags of hsr render (the same
// picture hsr render --algorithm bsp draws), render an orbit, refuse what it cannot do.
TEST(Cli, BspBuildInfoRenderAndOrbit) {
  const ScratchDir scratch("hsr_cli_test");
  const fs::path d = scratch.path();
  const std::string tree = (d / "demo.bsp").string();
  CliRun r = runCli("bsp build demo --bsp-splitter fewest -o " + tree);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("splits"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("memory"), std::string::npos) << r.out;
  r = runCli("bsp info " + tree + " --dot " + (d / "demo.dot").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("fewest"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("root node 0"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(d / "demo.dot"));
  const std::string view = " --size 160x120 --eye 3,4,9 --target 0,0,0 --cull back";
  r = runCli("bsp render " + tree + view + " -q -o " + (d / "tree.png").string() + " --raw " +
             (d / "tree").string());
  ASSERT_EQ(r.code, 0) << r.err;
  r = runCli("render demo --algorithm bsp --bsp-splitter fewest" + view + " -q -o " +
             (d / "fresh.png").string() + " --raw " + (d / "fresh").string());
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* f : {"ids.npy", "depth.npy"}) {
    std::ifstream a(d / "tree" / f, std::ios::binary), b(d / "fresh" / f, std::ios::binary);
    const std::string x((std::istreambuf_iterator<char>(a)), {}),
        y((std::istreambuf_iterator<char>(b)), {});
    EXPECT_FALSE(x.empty());
    EXPECT_TRUE(x == y) << f << " differs between the saved tree and a fresh build";
  }
  r = runCli("bsp render " + tree + " --size 80x60 --orbit 5 -o " + (d / "orbit").string());
  ASSERT_EQ(r.code, 0) << r.err;
  for (int k = 0; k < 5; ++k)
    EXPECT_TRUE(fs::exists(d / "orbit" / ("view-000" + std::to_string(k) + ".png")));
  expectCleanError("bsp render " + tree + " --bsp-splitter first", "applies when a tree is built");
  expectCleanError("bsp render " + (d / "fresh.png").string(), "not an hsr BSP file");
  expectCleanError("bsp info " + (d / "missing.bsp").string(), "no such file");
  expectCleanError("bsp build demo --bsp-splitter greedy -o " + (d / "x.bsp").string(), "greedy");
  expectCleanError("render demo --algorithm bsp --bsp-candidates 0", "candidates");
}

// --raw's depth.npy in scene units on request, and the camera used in the manifest, the stats
// and the summary (tests/io/camera_data_test.cpp checks the values).
TEST(Cli, RawDepthInSceneUnitsAndTheCameraUsed) {
  const ScratchDir d("hsr_cli_depth");
  const std::string png = (d / "s.png").string(), raw = (d / "raw").string(),
                    stats = (d / "s.json").string();
  const CliRun r = runCli("render solids --size 160x120 -o " + png + " --raw " + raw +
                          " --depth linear --stats " + stats);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("fx "), std::string::npos) << r.out;
  auto slurp = [](const fs::path& p) {
    std::ifstream in(p);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  const std::string manifest = slurp(fs::path(raw) / "manifest.json");
  EXPECT_NE(manifest.find("depth along the view axis"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("\"intrinsics\""), std::string::npos) << manifest;
  EXPECT_NE(slurp(stats).find("\"cx\""), std::string::npos);
  EXPECT_NE(slurp(stats).find("\"first_polygon\""), std::string::npos);
  EXPECT_NE(manifest.find("\"objects.npy\""), std::string::npos) << manifest;
  // depth.npy: little-endian float32 after the header; inf where nothing was drawn, finite
  // (scene units, beyond the near plane) elsewhere
  const std::string npy = slurp(fs::path(raw) / "depth.npy");
  ASSERT_GT(npy.size(), 10u);
  const std::size_t header =
      10 + (static_cast<unsigned char>(npy[8]) | static_cast<unsigned char>(npy[9]) << 8);
  ASSERT_EQ(npy.size(), header + 160u * 120u * 4u);
  int inf = 0, finite = 0;
  for (std::size_t i = header; i < npy.size(); i += 4) {
    float v;
    std::memcpy(&v, npy.data() + i, 4);
    if (std::isinf(v))
      ++inf;
    else if (std::isfinite(v) && v > 0.0f)
      ++finite;
  }
  EXPECT_GT(inf, 0);
  EXPECT_GT(finite, 0);
  EXPECT_EQ(inf + finite, 160 * 120);
  // objects.npy: the object of the polygon each pixel shows; solids has six objects
  const std::string obj = slurp(fs::path(raw) / "objects.npy");
  ASSERT_EQ(obj.size(), header + 160u * 120u * 4u);
  std::set<std::uint32_t> seen;
  for (std::size_t i = header; i < obj.size(); i += 4) {
    std::uint32_t v;
    std::memcpy(&v, obj.data() + i, 4);
    seen.insert(v);
  }
  EXPECT_TRUE(seen.count(0xFFFFFFFFu));
  EXPECT_GE(seen.size(), 3u);
  for (const std::uint32_t v : seen) EXPECT_TRUE(v < 6 || v == 0xFFFFFFFFu) << v;
  // --output none: the raw buffers alone, no picture
  const std::string raw3 = (d / "raw3").string();
  const CliRun n = runCli("render solids --size 64x48 --output none --raw " + raw3);
  ASSERT_EQ(n.code, 0) << n.err;
  EXPECT_TRUE(fs::exists(fs::path(raw3) / "ids.npy"));
  EXPECT_EQ(n.out.find(".png"), std::string::npos) << n.out;  // the summary's "wrote" lines
  expectCleanError("render solids --output none,color -q", "none");
  expectCleanError("render solids --depth meters --raw " + (d / "raw2").string(), "depth");
  expectCleanError("render solids --depth linear -o " + png, "--raw");
}

// The view fed back in: --camera reproduces a run from its --stats or manifest.json; a
// calibrated camera (--intrinsics, --pose) in OpenCV's and OpenGL's conventions; and the
// conflicts and malformed files refused with one line.
TEST(Cli, CamerasInReproduceTheView) {
  const ScratchDir d("hsr_cli_camera_in");
  auto slurp = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  auto spit = [](const fs::path& p, const std::string& text) { std::ofstream(p) << text; };
  const std::string a = (d / "a.png").string(), b = (d / "b.png").string(),
                    stats = (d / "s.json").string();
  ASSERT_EQ(
      runCli("render solids --size 160x120 --eye 3,4,9 --fov 30 -q -o " + a + " --stats " + stats)
          .code,
      0);
  const CliRun again = runCli("render solids --camera " + stats + " -q -o " + b);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_EQ(slurp(a), slurp(b)) << "the same view from the camera it wrote";
  // A manifest.json holds the same camera; --size on a camera without intrinsics is allowed
  const std::string raw = (d / "raw").string();
  ASSERT_EQ(runCli("render solids --camera " + stats + " -q --output none --raw " + raw).code, 0);
  const CliRun from_manifest =
      runCli("render solids --camera " + (fs::path(raw) / "manifest.json").string() +
             " --size 80x60 -q -o " + b);
  ASSERT_EQ(from_manifest.code, 0) << from_manifest.err;
  // Intrinsics and a pose: the eye at (0, 0, 9) looking at the origin, as OpenCV and as OpenGL
  // write it (OpenCV's y and z axes are OpenGL's turned), give the same picture
  const fs::path cv = d / "pose_cv.txt", gl = d / "pose_gl.txt";
  spit(cv, "1 0 0 0\n0 -1 0 0\n0 0 -1 9\n0 0 0 1\n");
  spit(gl, "[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 9], [0, 0, 0, 1]]");
  const std::string c1 = (d / "c1.png").string(), c2 = (d / "c2.png").string(),
                    c3 = (d / "c3.png").string();
  const CliRun r1 = runCli("render solids --size 160x120 --intrinsics 150,140,70.5,66 --pose " +
                           cv.string() + " -o " + c1 + " --stats " + stats);
  ASSERT_EQ(r1.code, 0) << r1.err;
  EXPECT_NE(r1.out.find("fx 150.000 fy 140.000 cx 70.5 cy 66"), std::string::npos) << r1.out;
  // The field of view reported is the one the intrinsics give, never the unused default 45
  const double deg = 180.0 / 3.14159265358979323846;
  const double fov_x = (std::atan(71.0 / 150) + std::atan((160 - 0.5 - 70.5) / 150)) * deg;
  const double fov_y = (std::atan(66.5 / 140) + std::atan((120 - 0.5 - 66) / 140)) * deg;
  EXPECT_EQ(r1.out.find("fov 45"), std::string::npos) << r1.out;
  EXPECT_NE(r1.out.find(fmt::format("fov {:.4g} x {:.4g} deg (from the intrinsics)", fov_x, fov_y)),
            std::string::npos)
      << r1.out;
  {
    const nlohmann::json camera = nlohmann::json::parse(slurp(stats))["camera"];
    EXPECT_FALSE(camera.contains("fov_deg")) << camera.dump();
    EXPECT_NEAR(camera["fov_x_deg"].get<double>(), fov_x, 1e-9);
    EXPECT_NEAR(camera["fov_y_deg"].get<double>(), fov_y, 1e-9);
  }
  const CliRun r2 = runCli("render solids --size 160x120 --intrinsics 150,140,70.5,66 --pose " +
                           gl.string() + " --pose-convention opengl -q -o " + c2);
  ASSERT_EQ(r2.code, 0) << r2.err;
  EXPECT_EQ(slurp(c1), slurp(c2));
  EXPECT_NE(slurp(stats).find("\"projection_from\": \"intrinsics\""), std::string::npos);
  ASSERT_EQ(runCli("render solids --camera " + stats + " -q -o " + c3).code, 0);
  EXPECT_EQ(slurp(c1), slurp(c3)) << "a calibrated camera read back";
  expectCleanError("render solids --camera " + stats + " --size 320x240",
                   "intrinsics are for 160x120");
  expectCleanError("render solids --camera " + stats + " --eye 1,2,3", "--eye and --camera");
  expectCleanError("render solids --intrinsics 150,140,70 -q", "fx,fy,cx,cy");
  expectCleanError("render solids --intrinsics 150,140,70,60 --fov 30 -q",
                   "--fov and --intrinsics");
  expectCleanError("render solids --intrinsics 0,140,70,60 -q", "focal lengths");
  expectCleanError("render solids --intrinsics 150,140,70,60 --ortho -q", "pinhole");
  spit(d / "scaled.txt", "2 0 0 0\n0 -1 0 0\n0 0 -1 9\n0 0 0 1\n");
  expectCleanError("render solids --pose " + (d / "scaled.txt").string() + " -q", "not a rotation");
  spit(d / "short.txt", "1 0 0 0 0 1");
  expectCleanError("render solids --pose " + (d / "short.txt").string() + " -q", "6 numbers");
  expectCleanError("render solids --pose " + (d / "none.txt").string() + " -q", "no such file");
  expectCleanError("render solids --pose " + cv.string() + " --pose-convention colmap -q",
                   "must be one of opencv|opengl");
  spit(d / "bad.json", "{\"eye\": [0, 0, 5]}");
  expectCleanError("render solids --camera " + (d / "bad.json").string() + " -q",
                   "\"width\" is missing");
  expectCleanError("render solids --camera-index two -q", "--camera-index");
  expectCleanError("render solids --camera-index 2 -q", "has 0 cameras");
}

// Many views from one import: --orbit N and --views FILE (a list of cameras as --stats writes
// them) give numbered outputs, each view the picture a single run of that camera gives.
TEST(Cli, ManyViewsFromOneImport) {
  const ScratchDir d("hsr_cli_views");
  auto slurp = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  const std::string out = (d / "o.png").string(), raw = (d / "raw").string(),
                    stats = (d / "s.json").string();
  const CliRun orbit = runCli("render solids --size 96x72 --algorithm bsp --orbit 3 -o " + out +
                              " --raw " + raw + " --stats " + stats);
  ASSERT_EQ(orbit.code, 0) << orbit.err;
  EXPECT_NE(orbit.out.find("3 views"), std::string::npos) << orbit.out;
  for (const char* n : {"o-0000.png", "o-0001.png", "o-0002.png"})
    EXPECT_TRUE(fs::exists(d / n)) << n;
  EXPECT_FALSE(fs::exists(d / "o-0003.png"));
  for (const char* n : {"0000", "0001", "0002"})
    EXPECT_TRUE(fs::exists(fs::path(raw) / n / "ids.npy")) << n;
  // The stats hold every view's camera: fed back as --views, the same pictures
  const nlohmann::json s = nlohmann::json::parse(slurp(stats));
  ASSERT_EQ(s.at("views").size(), 3u);
  nlohmann::json list = nlohmann::json::array();
  for (const auto& v : s.at("views")) list.push_back(v.at("camera"));
  std::ofstream(d / "views.json") << list.dump();
  const std::string again = (d / "v.png").string();
  const CliRun views =
      runCli("render solids --views " + (d / "views.json").string() + " -q -o " + again);
  ASSERT_EQ(views.code, 0) << views.err;
  for (const char* k : {"0000", "0001", "0002"})
    EXPECT_EQ(slurp(d / ("o-" + std::string(k) + ".png")),
              slurp(d / ("v-" + std::string(k) + ".png")))
        << k;
  // View 1 of the orbit is the picture its camera gives alone (the algorithm's tree reused)
  std::ofstream(d / "one.json") << list.at(1).dump();
  const std::string one = (d / "one.png").string();
  ASSERT_EQ(runCli("render solids --algorithm bsp --camera " + (d / "one.json").string() +
                   " -q -o " + one)
                .code,
            0);
  EXPECT_EQ(slurp(one), slurp(d / "o-0001.png"));
  expectCleanError("render solids --views " + (d / "views.json").string() + " --eye 1,2,3",
                   "--eye and --views");
  expectCleanError("render solids --views " + (d / "views.json").string() + " --orbit 2",
                   "give one");
  expectCleanError("render solids --orbit 0", "--orbit must be");
  std::ofstream(d / "empty.json") << "[]";
  expectCleanError("render solids --views " + (d / "empty.json").string(), "empty");
}

// A --views file written by hand: eye and target are enough (the size from --size, up +y,
// perspective at 45 degrees, near and far fitted around the scene as auto-framing fits them),
// and a view with several wrong fields is refused with every one named, and the view.
TEST(Cli, ViewsWrittenByHandNeedOnlyEyeAndTarget) {
  const ScratchDir d("hsr_cli_views_by_hand");
  auto slurp = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  std::ofstream(d / "views.json") << R"([{"eye": [3, 2, 4], "target": [0, 0, 0]},
                                         {"eye": [-3, 1, 4], "target": [0, 0.5, 0], "fov_deg": 30}])";
  const std::string out = (d / "v.png").string(), stats = (d / "s.json").string();
  const CliRun r = runCli("render solids --views " + (d / "views.json").string() +
                          " --size 64x48 -q -o " + out + " --stats " + stats);
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json s = nlohmann::json::parse(slurp(stats));
  ASSERT_EQ(s.at("views").size(), 2u);
  for (const auto& v : s.at("views")) {
    const auto& c = v.at("camera");
    EXPECT_EQ(c.at("width"), 64);
    EXPECT_EQ(c.at("height"), 48);
    EXPECT_EQ(c.at("projection_kind"), "perspective");
    EXPECT_EQ(c.at("up"), nlohmann::json({0.0, 1.0, 0.0}));
    EXPECT_GT(c.at("near").get<double>(), 0.0);
    EXPECT_GT(c.at("far").get<double>(), c.at("near").get<double>());
    EXPECT_GT(v.at("fragments_written").get<long>(), 0)
        << "the fitted planes clipped the scene away";
  }
  EXPECT_EQ(s.at("views")[0].at("camera").at("fov_deg"), 45.0);
  EXPECT_EQ(s.at("views")[1].at("camera").at("fov_deg"), 30.0);
  // The same camera given whole renders the same picture: the defaults are the ones stated
  nlohmann::json whole = s.at("views")[0].at("camera");
  std::ofstream(d / "whole.json") << nlohmann::json::array({whole}).dump();
  const std::string again = (d / "w.png").string();
  ASSERT_EQ(runCli("render solids --views " + (d / "whole.json").string() + " -q -o " + again).code,
            0);
  EXPECT_EQ(slurp(d / "v-0000.png"), slurp(d / "w-0000.png"));
  // Every wrong field named in one message, with the view it belongs to
  std::ofstream(d / "bad.json") << R"([{"eye": [3, 2, 4], "target": [0, 0, 0]},
                                       {"eye": [1, 2], "target": "origin", "near": "close", "width": 0.5}])";
  const CliRun bad = runCli("render solids --views " + (d / "bad.json").string() + " -q -o " + out);
  EXPECT_EQ(bad.code, 2);
  for (const char* field : {"view 1", "\"eye\"", "\"target\"", "\"near\"", "\"width\""})
    EXPECT_NE(bad.err.find(field), std::string::npos) << field << " not named in: " << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
  // A view with neither eye nor pose says what a view needs
  std::ofstream(d / "none.json") << R"([{"fov_deg": 40}])";
  expectCleanError("render solids --views " + (d / "none.json").string(), "\"eye\" and \"target\"");
}

// A single picture other than colour, with no name given, says what it is in its name.
TEST(Cli, ASingleNonColourPictureHasItsKindInItsName) {
  const ScratchDir d("hsr_cli_single_kind");
  const CliRun r = runCli("render demo --size 32x24 --output depth", d.path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(d / "out" / "demo-depth.png")) << r.out;
  EXPECT_FALSE(fs::exists(d / "out" / "demo.png"));
}

// What a new user ran into, each fixed: no verb needed, --version, a flag never taken as an
// option's value, near-miss flags named, pictures only as PNG, the size limit said plainly,
// --stats to stdout, --clear-depth for --depth-func greater, and why nothing was drawn.
TEST(Cli, NewUserPapercuts) {
  const ScratchDir d("hsr_cli_papercuts");
  const std::string png = (d / "a.png").string();
  const CliRun verbless = runCli("demo --size 32x24 -q -o " + png);
  EXPECT_EQ(verbless.code, 0) << verbless.err;
  EXPECT_TRUE(fs::exists(png));
  const CliRun version = runCli("--version");
  EXPECT_EQ(version.code, 0);
  EXPECT_EQ(version.out.rfind("hsr ", 0), 0u) << version.out;
  expectCleanError("render demo --stats --quiet", "--quiet is a flag");
  EXPECT_FALSE(fs::exists("--quiet"));
  expectCleanError("render demo --raw -q", "-q is a flag");
  expectCleanError("render demo --sizee 10x10", "did you mean --size?");
  expectCleanError("render demo --eye 1,2,3 --cul back", "did you mean --cull?");
  expectCleanError("render demo -o " + (d / "a.jpg").string(), "hsr writes PNG pictures");
  EXPECT_FALSE(fs::exists(d / "a.jpg"));
  // hsr svg writes what the names say, or refuses before drawing: SVG text in a .pdf or .png,
  // a PDF in a .svg were written as asked
  for (const char* name : {"model.pdf", "x.png", "x.SVG.txt"}) {
    SCOPED_TRACE(name);
    expectCleanError("svg demo -o " + (d / name).string(),
                     "hsr writes an SVG drawing there; name the file .svg");
    EXPECT_FALSE(fs::exists(d / name));
  }
  expectCleanError(
      "svg demo -o " + (d / "ok.svg").string() + " --pdf " + (d / "x.svg").string(),
      "--pdf " + (d / "x.svg").string() + ": hsr writes a PDF drawing there; name the file .pdf");
  EXPECT_FALSE(fs::exists(d / "ok.svg"));
  EXPECT_FALSE(fs::exists(d / "x.svg"));
  // Upper-case extensions are the same format
  const CliRun upper_case = runCli("svg demo --size 64x48 -q -o " + (d / "UP.SVG").string() +
                                   " --pdf " + (d / "UP.PDF").string());
  EXPECT_EQ(upper_case.code, 0) << upper_case.err;
  EXPECT_TRUE(fs::exists(d / "UP.SVG") && fs::exists(d / "UP.PDF"));
  expectCleanError("render demo --size 20000x10", "over the limit of 16384 pixels per side");
  // A verb mistyped is not taken for a scene's name; a vector's coordinates without commas, a
  // camera looking along its up vector, get the hint that fixes them
  expectCleanError("rendr demo",
                   "rendr: no such verb, file or built-in scene; did you mean render?");
  expectCleanError("explian demo", "did you mean explain?");
  expectCleanError("render demo --eye 1 2 3 -o " + png,
                   "--eye takes x,y,z joined by commas, such as --eye 1,2,3");
  expectCleanError("render demo --eye 0,5,0 --target 0,0,0 -o " + png,
                   "parallel to the view direction: give another up vector (--up), such as 1,0,0");
  // An option given twice is named with the count, in words and not the parser's
  const CliRun twice = runCli("render demo --size 10x10 --size 20x20 -o " + png);
  EXPECT_EQ(twice.code, 2);
  EXPECT_NE(twice.err.find("--size is given 2 times; give it once"), std::string::npos)
      << twice.err;
  EXPECT_EQ(twice.err.find("At Most"), std::string::npos) << twice.err;
  // --cull both: the warning says both faces go, and does not suggest the winding
  const CliRun both = runCli("render demo --size 32x24 --cull both -o " + png);
  EXPECT_NE(both.err.find("--cull both removes every polygon, front and back faces alike"),
            std::string::npos)
      << both.err;
  EXPECT_EQ(both.err.find("--front-face"), std::string::npos) << both.err;
  // --eye with a negative value is still a value
  EXPECT_EQ(runCli("render demo --size 32x24 -q -o " + png + " --eye -3,2,5").code, 0);
  // --stats -: the JSON alone on stdout
  const CliRun stats = runCli("render demo --size 32x24 --output none --stats -");
  ASSERT_EQ(stats.code, 0) << stats.err;
  const nlohmann::json j = nlohmann::json::parse(stats.out, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << stats.out;
  EXPECT_EQ(j.at("width"), 32);
  // --depth-func greater draws nothing against the clear depth 1, and everything against 0
  const CliRun greater = runCli("render demo --size 32x24 --depth-func greater -o " + png);
  EXPECT_EQ(greater.code, 0);
  EXPECT_NE(greater.err.find("nothing was drawn: no fragment passed the depth test"),
            std::string::npos)
      << greater.err;
  const CliRun cleared =
      runCli("render demo --size 32x24 --depth-func greater --clear-depth 0 -o " + png);
  EXPECT_EQ(cleared.code, 0);
  EXPECT_EQ(cleared.err.find("nothing was drawn"), std::string::npos) << cleared.err;
  expectCleanError("render demo --clear-depth 2", "--clear-depth must be in [0, 1]");
  EXPECT_EQ(
      runCli("render demo --size 32x24 -q --polygon-mode point --point-size 3 -o " + png).code, 0);
  expectCleanError("render demo --polygon-mode point --point-size 100",
                   "--point-size must be in [1, 64] pixels");
  const CliRun away =
      runCli("render demo --size 32x24 --eye 0,0,-1000 --target 0,0,-2000 -q -o " + png);
  EXPECT_NE(away.err.find("outside the view"), std::string::npos) << away.err;
  // Names in any case, as OpenGL's: the same picture
  auto slurp = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  const std::string lower = (d / "lower.png").string(), upper = (d / "upper.png").string();
  ASSERT_EQ(runCli("render demo --size 32x24 -q --algorithm scanline --cull back --output ids -o " +
                   lower)
                .code,
            0);
  const CliRun mixed = runCli(
      "render demo --size 32x24 -q --algorithm ScanLine --cull BACK --output IDS -o " + upper);
  ASSERT_EQ(mixed.code, 0) << mixed.err;
  EXPECT_EQ(slurp(lower), slurp(upper));
}

TEST(Cli, SvgDrawsLayersOnAPageAndRefusesBadOptions) {
  const ScratchDir d("hsr_cli_svg");
  const std::string out = (d / "solids.svg").string(), stats = (d / "s.json").string();
  const CliRun r = runCli("svg solids --size 200x150 --hidden dashed --page A4-landscape -o " +
                          out + " --stats " + stats);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("strokes"), std::string::npos) << r.out;
  std::ifstream in(out);
  const std::string svg((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(svg.find("width=\"297mm\""), std::string::npos);
  EXPECT_NE(svg.find("<g id=\"hidden\" class=\"hidden\""), std::string::npos);
  EXPECT_TRUE(fs::exists(stats));
  expectCleanError("svg solids --hidden dotted -o " + out, "--hidden");
  expectCleanError("svg solids --page B7 -o " + out, "B7");
  expectCleanError("svg solids --crease-angle -3 -o " + out, "crease angle");
  expectCleanError("svg solids --algorithm zbuffer -o " + out, "--algorithm");
  expectCleanError("svg solids --polygon-mode line -o " + out, "polygon mode");
  expectCleanError("svg solids --margin 200 --page A4 -o " + out, "--margin");
  expectCleanError("svg solids --dash '2;rm' -o " + out, "--dash");
  expectCleanError("svg solids --style sketch -o " + out, "--style");
  expectCleanError("svg solids --lines outline,hatching -o " + out, "--lines");
  expectCleanError("svg solids --engine warnock -o " + out, "--engine");
  const CliRun s =
      runCli("svg solids --size 200x150 --lines outline --engine roberts -q -o " + out);
  EXPECT_EQ(s.code, 0) << s.err;
  expectCleanError("svg solids --fallback raster -o " + out, "--time-limit");
  expectCleanError("svg solids --time-limit 0.000000001 -o " + out, "time limit");
  const CliRun t =
      runCli("svg solids --size 200x150 --time-limit 0.000000001 --fallback raster -o " + out);
  EXPECT_EQ(t.code, 0) << t.err;
  EXPECT_NE(t.out.find("NOT exact"), std::string::npos) << t.out;
  expectCleanError("svg solids --style filled --hidden dashed -o " + out, "--hidden");
  // Filled, with a PDF beside
  const std::string pdf = (d / "solids.pdf").string();
  const CliRun f =
      runCli("svg solids --size 200x150 --style filled -q -o " + out + " --pdf " + pdf);
  ASSERT_EQ(f.code, 0) << f.err;
  std::ifstream fin(out);
  const std::string fsvg((std::istreambuf_iterator<char>(fin)), std::istreambuf_iterator<char>());
  EXPECT_NE(fsvg.find("<g id=\"visible-set\""), std::string::npos);
  EXPECT_GT(fs::file_size(pdf), 100u);
}

TEST(Cli, NoArgumentRendersTheDemo) {
  const ScratchDir scratch("hsr_cli_test");
  const fs::path d = scratch.path() / "noarg";
  fs::create_directories(d);
  const std::string cmd = "cd " + d.string() + " && timeout 60 " + HSR_CLI_PATH + " >/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  EXPECT_TRUE(fs::exists(d / "out" / "demo.png"));
}

TEST(Cli, ScenesListsBuiltinsAndAlgorithms) {
  const CliRun r = runCli("scenes");
  EXPECT_EQ(r.code, 0);
  for (const char* s : {"demo", "cyclic", "penetrating", "spheres:N", "soup:N:SEED", "zbuffer",
                        "zbuffer-textbook", "the reference", "exact-coverage",
                        "its textbook sibling: scanline-textbook, the same frame bit for bit; "
                        "`hsr explain` walks it",
                        "the notes' loop of abuffer: the same frame, bit for bit"})
    EXPECT_NE(r.out.find(s), std::string::npos) << s;
}

TEST(Cli, CompareWritesTableAndSheet) {
  const ScratchDir scratch("hsr_cli_test");
  const fs::path sheet = scratch.path() / "sheet.png";
  const CliRun r = runCli("compare cyclic --size 120x90 --sheet " + sheet.string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("zbuffer"), std::string::npos);
  EXPECT_NE(r.out.find("100.0000%"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(sheet));
  // At a real size the sheet is a grid that fits a screen's width (it was one row, 9,704 px
  // wide at 800x600), every cell whole: the same picture count as algorithms run
  const fs::path big = scratch.path() / "big.png";
  const CliRun b = runCli("compare demo --size 800x600 --sheet " + big.string());
  ASSERT_EQ(b.code, 0) << b.err;
  const auto png = hsr::testing::decodePng(big);
  EXPECT_LE(png.width, hsr::kMaxSheetWidth);
  EXPECT_GE(png.width, 4 * 800) << "as many cells a row as fit";
  // one per algorithm run
  const int ran = static_cast<int>(std::count(b.out.begin(), b.out.end(), '%'));
  const int rows = (ran + png.width / 808 - 1) / (png.width / 808);
  EXPECT_EQ(png.height, rows * (3 * (24 + 600) + 2 * 8) + (rows + 1) * 8 + 48)
      << ran << " algorithms";
}

// An orbit of views: each algorithm keeps its frame (and the octree its tree) from view to
// view; ids are compared on every view, so the exact algorithms stay at 100%.
TEST(Cli, CompareOrbitsTheTargetWithViews) {
  const CliRun r = runCli("compare demo --size 120x90 --views 4");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("4 views on an orbit"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("next views ms"), std::string::npos) << r.out;
  for (const char* exact : {"zbuffer-textbook", "scanline", "warnock"}) {
    const std::size_t at = r.out.find(std::string("  ") + exact + " ");
    ASSERT_NE(at, std::string::npos) << exact;
    const std::string line = r.out.substr(at, r.out.find('\n', at) - at);
    EXPECT_NE(line.find("100.0000%"), std::string::npos) << line;
  }
  expectCleanError("compare demo --views 0", "--views");
  expectCleanError("compare demo --views 100000", "--views");
  // The library: three views each, the bit-exact algorithms equal on all of them.
  const hsr::Scene scene = hsr::makeBuiltinScene("spheres:2000");
  const std::vector<hsr::ComparisonRow> rows =
      hsr::compareAlgorithms(scene, hsr::frameScene(scene, 80, 60), {}, 3);
  for (const hsr::ComparisonRow& row : rows) {
    if (!row.not_run.empty()) continue;
    EXPECT_EQ(row.views, 3) << row.algorithm;
    EXPECT_GT(row.view_ms, 0.0) << row.algorithm;
    if (row.algorithm == "zbuffer-textbook" || row.algorithm == "scanline" ||
        row.algorithm == "warnock") {
      EXPECT_EQ(row.differing_pixels, 0u) << row.algorithm;
    }
  }
}

TEST(Cli, ExplainWritesNumberedPicturesASheetAndAnIndex) {
  const ScratchDir scratch("hsr_cli_test");
  const fs::path dir = scratch.path() / "explain";
  const CliRun r = runCli("explain zbuffer demo --size 160x120 -o " + dir.string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("fill tile"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir / "01-bin.png"));
  EXPECT_TRUE(fs::exists(dir / "sheet.png"));
  EXPECT_TRUE(fs::exists(dir / "steps.md"));
  const CliRun t =
      runCli("explain zbuffer-textbook cyclic --size 120x90 -q -o " + (dir / "t").string());
  EXPECT_EQ(t.code, 0) << t.err;
  EXPECT_TRUE(fs::exists(dir / "t" / "02-draw-polygon.png"));
  expectCleanError("explain no-such-algorithm demo -o " + (dir / "x").string(), "zbuffer-textbook");
}

TEST(Cli, CameraInsideModelStillRenders) {
  // Inside a closed cube the z-buffer shows the inside faces; near-plane clipping handles the
  // polygons around the eye. It renders, with a warning line.
  const ScratchDir scratch("hsr_cli_test");
  const fs::path d = scratch.path();
  {
    std::ofstream f(d / "cube.obj");
    f << "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n"
         "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  }
  const CliRun r = runCli("render " + (d / "cube.obj").string() +
                          " --eye 0,0,0.2 --target 0,0,-1 --near 0.01 --far 10 --size 64x64 -o " +
                          (d / "inside.png").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("inside"), std::string::npos) << r.err;
}

// hsr doom: the three sub-verbs write what they promise; a bad WAD is one line and exit 2.
TEST(CliDoom, BuildMapViewAndExplain) {
  const ScratchDir d("hsr_cli_doom");
  const std::string wad = std::string(HSR_DOOM_WADS) + "/freedoom2.wad";
  const std::string out = (d / "ours.wad").string();
  CliRun r = runCli("doom build " + wad + " --map MAP02 --check -o " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("MAP02"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("every tree holds"), std::string::npos) << r.out;
  // The written WAD builds again from its own nodes' map, and its nodes check.
  r = runCli("doom map " + out + " --map MAP02 --shipped --svg " + (d / "map02.svg").string());
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream svg(d / "map02.svg");
  const std::string text((std::istreambuf_iterator<char>(svg)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("<svg"), std::string::npos);
  EXPECT_NE(text.find("subsector 0"), std::string::npos);
  EXPECT_NE(text.find("node depth 0"), std::string::npos);
  r = runCli("doom view " + wad + " --map MAP02 --size 160x100 -o " + (d / "view.png").string() +
             " --raw " + (d / "raw").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("0 differ away from an edge"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(d / "view.png"));
  EXPECT_TRUE(fs::exists(d / "raw" / "ids.npy"));
  r = runCli("explain bsp2d " + wad + " --map MAP02 --size 160x100 -q -o " +
             (d / "explain").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(d / "explain" / "sheet.png"));
  EXPECT_TRUE(fs::exists(d / "explain" / "steps.md"));
  // Any verb reads a map as a scene
  r = runCli("render " + wad + ":MAP02 --size 160x100 -q -o " + (d / "render.png").string());
  EXPECT_EQ(r.code, 0) << r.err;
}

TEST(CliDoom, BadInputIsOneLine) {
  const ScratchDir d("hsr_cli_doom_bad");
  {
    std::ofstream bad(d / "bad.wad", std::ios::binary);
    bad << "PWAD" << std::string("\xff\xff\xff\x7f\x0c\0\0\0", 8);
  }
  expectCleanError("doom build " + (d / "bad.wad").string(), "past the end");
  expectCleanError("doom build " + (d / "missing.wad").string(), "no such file");
  const std::string wad = std::string(HSR_DOOM_WADS) + "/freedoom2.wad";
  expectCleanError("doom build " + wad + " --map MAP77", "no map MAP77");
  expectCleanError("doom view " + wad + " --map MAP01 --from 1,2 -o " + (d / "v.png").string(),
                   "--from");
  expectCleanError(
      "doom map " + wad + " --map MAP01 --split-cost -3 --svg " + (d / "m.svg").string(), "split");
  expectCleanError("explain bsp2d " + wad + " -o " + (d / "e").string(), "--map");
  expectCleanError("explain zbuffer demo --map MAP01 -o " + (d / "e2").string(), "--map");
}

}  // namespace

namespace {

// The depth picture's legend says what its numbers are: window z by default, and under
// --depth linear or distance the ends in scene units, so the three pictures differ, and only
// inside the legend's box (the bottom-right corner; the picture itself is window z's ramp).
TEST(Cli, DepthLegendIsInTheUnitsOfDepth) {
  const hsr::testing::ScratchDir d("hsr_cli_depth_legend");
  std::vector<hsr::testing::DecodedPng> pictures;
  for (const char* kind : {"window", "linear", "distance"}) {
    const std::string png = (d / (std::string(kind) + ".png")).string();
    const CliRun r = runCli("render demo --size 400x300 -q --output depth -o " + png + " --raw " +
                            (d / kind).string() + " --depth " + kind);
    ASSERT_EQ(r.code, 0) << r.err;
    pictures.push_back(hsr::testing::decodePng(png));
    ASSERT_TRUE(pictures.back().ok()) << pictures.back().error;
  }
  const int w = pictures[0].width, h = pictures[0].height;
  for (int k = 1; k < 3; ++k) {
    int outside = 0, inside = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) {
          const std::size_t i = 3 * (static_cast<std::size_t>(y) * w + x) + c;
          if (pictures[0].rgb[i] == pictures[k].rgb[i]) continue;
          (x >= w - 170 && y >= h - 50 ? inside : outside)++;
        }
    EXPECT_EQ(outside, 0) << k;
    EXPECT_GT(inside, 20) << k;  // other words in the legend
  }
}

}  // namespace

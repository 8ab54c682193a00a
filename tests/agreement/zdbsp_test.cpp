// Against ZDBSP (Debian's zdbsp, a node builder no one here wrote): its trees for every map of
// both Freedoom WADs pass our checker, and down its tree and down ours every random point
// inside a map lands in the same sector. Our total splits are fewer than its fewest-splits
// setting's (-p 4096 -s 64); bench/bench_doom.cpp races the build times.

#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <string>

#include "hsr/doom.hpp"
#include "test_util.hpp"

namespace {

namespace doom = hsr::doom;

doom::Wad zdbspNodes(const std::string& wad, const std::string& flags,
                     const std::filesystem::path& out) {
  const std::string cmd = std::string(HSR_ZDBSP_PATH) + " " + flags + " -t -o '" + out.string() +
                          "' '" + wad + "' >/dev/null";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  return doom::readWad(out);
}

TEST(ZdbspAgreement, SameSectorsAndFewerSplitsOnEveryMap) {
  const hsr::testing::ScratchDir dir("hsr_zdbsp");
  for (const char* file : {"freedoom1.wad", "freedoom2.wad"}) {
    SCOPED_TRACE(file);
    const std::string path = std::string(HSR_DOOM_WADS) + "/" + file;
    const doom::Wad ours = doom::readWad(path);
    const doom::Wad fewest = zdbspNodes(path, "-p 4096 -s 64", dir / "fewest.wad");
    const doom::Wad defaults = zdbspNodes(path, "", dir / "defaults.wad");
    std::uint64_t our_splits = 0, fewest_splits = 0, default_splits = 0;
    for (const std::string& name : ours.maps()) {
      SCOPED_TRACE(name);
      const doom::Map map = doom::readMap(ours, name);
      doom::BuildStats s;
      const doom::Nodes nodes = doom::buildNodes(map, {}, &s);
      our_splits += s.splits;
      for (const doom::Wad* peer : {&fewest, &defaults}) {
        const doom::Map theirs = doom::readMap(*peer, name);
        ASSERT_TRUE(theirs.shipped.has_value());
        // Our checker on ZDBSP's tree: its structure, convex subsectors and every linedef side
        // covered once hold. What it also reports there, and only there, is ZDBSP's rounding: segs
        // that rounding shrank to no length, and offsets off by two units.
        for (const std::string& p : doom::checkNodes(theirs, *theirs.shipped)) {
          const bool rounding = p.find("has no length") != std::string::npos ||
                                p.find("offset") != std::string::npos ||
                                p.find(" more") != std::string::npos;
          EXPECT_TRUE(rounding) << "in ZDBSP's tree: " << p;
        }
        (peer == &fewest ? fewest_splits : default_splits) +=
            doom::nodeStats(theirs, *theirs.shipped).splits;
        // ZDBSP keeps the map's linedefs, sidedefs and sectors (it may drop unused sidedefs,
        // so the sectors are compared by number).
        ASSERT_EQ(theirs.linedefs.size(), map.linedefs.size());
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        double left = 1e9, right = -1e9, bottom = 1e9, top = -1e9;
        for (const doom::Vertex& v : map.vertices)
          left = std::min(left, double(v.x)), right = std::max(right, double(v.x)),
          bottom = std::min(bottom, double(v.y)), top = std::max(top, double(v.y));
        int compared = 0, differ = 0;
        for (int k = 0; k < 300; ++k) {
          const double x = left + u(rng) * (right - left), y = bottom + u(rng) * (top - bottom);
          if (!doom::sectorByLinedefs(map, x, y)) continue;
          // Points within two units of a line are left out: each builder rounds its split points.
          bool near = false;
          for (const doom::Linedef& l : map.linedefs) {
            const doom::Vertex p = map.vertices[l.v1], q = map.vertices[l.v2];
            const double dx = q.x - p.x, dy = q.y - p.y, len2 = dx * dx + dy * dy;
            const double t =
                len2 > 0 ? std::clamp(((x - p.x) * dx + (y - p.y) * dy) / len2, 0.0, 1.0) : 0.0;
            near = near || std::hypot(x - (p.x + t * dx), y - (p.y + t * dy)) < 2.0;
          }
          if (near) continue;
          ++compared;
          differ += doom::sectorByTree(map, nodes, x, y) !=
                    doom::sectorByTree(theirs, *theirs.shipped, x, y);
        }
        EXPECT_EQ(differ, 0) << "of " << compared;
      }
    }
    std::printf("%s: splits ours %llu, ZDBSP fewest-splits %llu, ZDBSP defaults %llu\n", file,
                static_cast<unsigned long long>(our_splits),
                static_cast<unsigned long long>(fewest_splits),
                static_cast<unsigned long long>(default_splits));
    EXPECT_LT(our_splits, fewest_splits);
  }
}

}  // namespace

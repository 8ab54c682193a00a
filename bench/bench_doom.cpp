// hsr's Doom node builder raced against ZDBSP (Debian's zdbsp) on every map of both Freedoom
// WADs, in the same run, and set beside the nodes the WADs ship with.
//
// Speed is whole-process time on the whole WAD, the way a mapper runs either tool: read the WAD,
// build every map's nodes, write the WAD (`hsr doom build WAD -o OUT -q` against `zdbsp -o OUT
// WAD`), the median of `runs` runs (hsr_bench_doom RUNS; 5 by default), and the ratio ours /
// theirs (< 1: hsr is faster). ZDBSP at its defaults also rebuilds the blockmap and the reject
// table, which hsr leaves as they are; it is timed a third way with those off (-b -E: an empty
// blockmap, the reject table untouched) to show what its nodes alone cost. Quality per map and
// in total: splits (segs less linedef sides), nodes and the deepest subsector, for hsr (the
// default split cost), ZDBSP at its defaults, ZDBSP at its fewest-splits setting (-p 4096
// -s 64: every seg a candidate, a split worth 64 segs of imbalance) and the shipped nodes.
//
// Bars (issue 21): fewer total splits than ZDBSP's fewest-splits setting on both WADs, in no
// more than 2x ZDBSP's default build time.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "hsr/doom.hpp"

namespace {

namespace doom = hsr::doom;
namespace fs = std::filesystem;

double secondsOf(const std::string& command) {
  const auto start = std::chrono::steady_clock::now();
  if (std::system(command.c_str()) != 0) {
    std::fprintf(stderr, "bench_doom: failed: %s\n", command.c_str());
    std::exit(1);
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

struct Figures {
  std::uint64_t splits = 0, nodes = 0, depth = 0;
};

// Each map's figures for the nodes a WAD holds.
std::map<std::string, Figures> figuresOf(const doom::Wad& wad) {
  std::map<std::string, Figures> out;
  for (const std::string& name : wad.maps()) {
    const doom::Map map = doom::readMap(wad, name);
    if (!map.shipped) continue;
    const doom::BuildStats s = doom::nodeStats(map, *map.shipped);
    out[name] = {s.splits, s.nodes, s.depth};
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  const fs::path dir = fs::temp_directory_path() / ("hsr_bench_doom_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string hsr = HSR_CLI_PATH, zdbsp = HSR_ZDBSP_PATH;
  std::printf(
      "Doom node builders, whole WAD, whole process, median of %d runs (2-core figures in "
      "README)\n\n",
      runs);
  bool bars = true;
  for (const char* file : {"freedoom2.wad", "freedoom1.wad"}) {
    const std::string wad = std::string(HSR_DOOM_WADS) + "/" + file;
    const std::string ours_out = (dir / "ours.wad").string(), z_out = (dir / "z.wad").string(),
                      zf_out = (dir / "zfewest.wad").string(),
                      zn_out = (dir / "znodes.wad").string();
    std::vector<double> t_ours, t_z, t_zf, t_zn;
    for (int r = 0; r < runs; ++r) {  // interleaved, so that a noisy moment hits all of them
      t_ours.push_back(secondsOf(hsr + " doom build -q '" + wad + "' -o '" + ours_out + "'"));
      t_z.push_back(secondsOf(zdbsp + " -t -o '" + z_out + "' '" + wad + "' > /dev/null"));
      t_zf.push_back(
          secondsOf(zdbsp + " -t -p 4096 -s 64 -o '" + zf_out + "' '" + wad + "' > /dev/null"));
      t_zn.push_back(secondsOf(zdbsp + " -t -b -E -o '" + zn_out + "' '" + wad + "' > /dev/null"));
    }
    const auto ours = figuresOf(doom::readWad(ours_out)), z = figuresOf(doom::readWad(z_out)),
               zf = figuresOf(doom::readWad(zf_out)), shipped = figuresOf(doom::readWad(wad));
    std::printf("%s: splits / nodes / deepest subsector, per map\n", file);
    std::printf("%-6s %20s %20s %20s %20s\n", "map", "hsr", "ZDBSP defaults", "ZDBSP fewest",
                "shipped");
    Figures tot[4];
    for (const auto& [name, f] : ours) {
      const Figures* all[4] = {&f, &z.at(name), &zf.at(name),
                               shipped.count(name) ? &shipped.at(name) : nullptr};
      std::printf("%-6s", name.c_str());
      for (int i = 0; i < 4; ++i) {
        if (!all[i]) {
          std::printf(" %20s", "-");
          continue;
        }
        std::printf(" %7llu %6llu %5llu", static_cast<unsigned long long>(all[i]->splits),
                    static_cast<unsigned long long>(all[i]->nodes),
                    static_cast<unsigned long long>(all[i]->depth));
        tot[i].splits += all[i]->splits, tot[i].nodes += all[i]->nodes;
        tot[i].depth = std::max(tot[i].depth, all[i]->depth);
      }
      std::printf("\n");
    }
    std::printf("%-6s", "total");
    for (const Figures& f : tot)
      std::printf(" %7llu %6llu %5llu", static_cast<unsigned long long>(f.splits),
                  static_cast<unsigned long long>(f.nodes),
                  static_cast<unsigned long long>(f.depth));
    const double mo = median(t_ours), mz = median(t_z), mzf = median(t_zf), mzn = median(t_zn);
    std::printf(
        "\n%s: time %.3f s (hsr), %.3f s (ZDBSP defaults), %.3f s (fewest-splits), %.3f s (ZDBSP "
        "nodes only, -b -E)\n",
        file, mo, mz, mzf, mzn);
    std::printf(
        "%s: splits hsr / ZDBSP fewest %.3f (%llu / %llu), hsr / shipped %.3f; time hsr / ZDBSP "
        "defaults %.2fx, "
        "/ fewest %.2fx, / nodes only %.2fx\n\n",
        file, double(tot[0].splits) / double(tot[2].splits),
        static_cast<unsigned long long>(tot[0].splits),
        static_cast<unsigned long long>(tot[2].splits),
        double(tot[0].splits) / double(tot[3].splits), mo / mz, mo / mzf, mo / mzn);
    bars = bars && tot[0].splits < tot[2].splits && mo <= 2 * mz;
  }
  fs::remove_all(dir);
  std::printf(
      "bars (fewer splits than ZDBSP's fewest-splits setting, within 2x its default time): %s\n",
      bars ? "met" : "NOT met");
  return 0;
}

// hsr's hidden-line drawings raced against Open CASCADE's polygonal hidden-line removal
// (HLRBRep_PolyAlgo, Debian's libocct-modeling-algorithms-dev) in the same run, on the same
// triangles seen by the same camera (800x600, the camera framing the scene):
//   - full drawings: OCCT with a planar face per triangle and creases above 45 degrees, hsr
//     with its outlines, creases above 45 degrees and intersection lines; both with the hidden
//     parts;
//   - silhouettes only: OCCT's mesh as one face (its outline alone), hsr's outlines alone
//     (`--lines outline`); both with the hidden parts.
// Scenes (bench_scenes.hpp): spheres:1000/10000/100000, Wuson and Spider_binary; hsr also
// at spheres:1000000, where OCCT's full drawing is not run (its time grows as n^1.9 from 10k to
// 100k: 20 s at 100k) and its silhouettes run once (3 minutes).
//
// Times: hsr's hidden-line computation (the pipeline, then which parts of the lines are
// visible: LineDrawing::visibility_ms) against OCCT's HLR step alone (Load, Projector, Update
// and the extraction of the compounds: building the OCCT shape is not counted); then hsr's
// whole drawing in memory (strokes and the SVG text too). Medians of 5 repetitions (3 for the
// largest). Threads: HSR_BENCH_THREADS (default 1, as OCCT runs on one).
// The table prints the ratios (OCCT time / hsr time: > 1 means hsr is faster), the segments and
// visible length of both, and how much of each one's visible lines lies within a pixel of the
// other's (the drawings compared), then the growth of hsr's time with n.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "agreement/occt_peer.hpp"
#include "cross/near_lines.hpp"
#include "bench_scenes.hpp"
#include "hsr/camera.hpp"
#include "hsr/io.hpp"
#include "hsr/line_drawing.hpp"
#include "median_collector.hpp"

namespace {

constexpr int kWidth = 800, kHeight = 600;
constexpr double kCreaseDeg = 45;
int g_threads = 1;

using Segment = hsr::testing::Segment2;

struct Drawn {
  std::vector<Segment> visible;
  std::size_t hidden = 0;
  double length = 0;
};

Drawn ofStrokes(const hsr::LineDrawing& d) {
  Drawn out;
  for (const hsr::LineStroke& s : d.visible)
    for (std::size_t i = 0; i + 1 < s.points.size(); ++i) {
      out.visible.emplace_back(s.points[i], s.points[i + 1]);
      out.length += glm::length(s.points[i + 1] - s.points[i]);
    }
  for (const hsr::LineStroke& s : d.hidden) out.hidden += s.points.size() - 1;
  return out;
}

Drawn ofOcct(const hsr::testing::OcctLines& l) {
  Drawn out;
  for (const hsr::testing::OcctSegment& s : l.visible) {
    out.visible.emplace_back(s.a, s.b);
    out.length += glm::length(s.b - s.a);
  }
  out.hidden = l.hidden.size();
  return out;
}

struct Race {
  std::string label;
  std::function<hsr::Scene()> make;
  bool huge = false;  // 10^6 triangles: OCCT's full drawing not run, its silhouettes once
  std::unique_ptr<hsr::Scene> scene;
  hsr::Camera camera;
  hsr::testing::OcctMesh mesh;
  std::size_t triangles = 0;
  // The last run's drawings, for the table: [silhouettes only]
  Drawn ours[2], theirs[2];
  double occt_build_ms[2] = {0, 0};

  void ensure() {
    if (scene) return;
    scene = std::make_unique<hsr::Scene>(make());
    camera = hsr::frameScene(*scene, kWidth, kHeight);
    mesh = hsr::testing::occtMeshOf(*scene);
    triangles = mesh.triangles.size();
  }
};

std::vector<std::unique_ptr<Race>>& races() {
  static std::vector<std::unique_ptr<Race>> v = [] {
    std::vector<std::unique_ptr<Race>> r;
    for (const char* label : {"spheres/1000", "spheres/10000", "spheres/100000", "spheres/1000000",
                              "Wuson", "Spider_binary"}) {
      auto race = std::make_unique<Race>();
      race->label = label;
      const hsr::bench::BenchSceneSpec& spec = hsr::bench::benchScene(label);
      race->make = [&spec] { return hsr::bench::loadBenchScene(spec); };
      race->huge = race->label == "spheres/1000000";
      r.push_back(std::move(race));
    }
    return r;
  }();
  return v;
}

hsr::LineDrawingOptions optionsFor(bool silhouettes) {
  hsr::LineDrawingOptions o;
  o.crease_angle_deg = kCreaseDeg;
  o.hidden = true;
  o.creases = o.intersections = !silhouettes;
  return o;
}

// hsr's hidden-line computation (whole = false) or its whole drawing as SVG text.
void runHsr(benchmark::State& state, Race* race, bool silhouettes, bool whole) {
  race->ensure();
  hsr::RenderOptions ro;
  ro.threads = g_threads;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const hsr::LineDrawing d =
        hsr::lineDrawing(*race->scene, race->camera, ro, optionsFor(silhouettes));
    if (whole) {
      const std::string svg = hsr::lineDrawingSvg(d);
      benchmark::DoNotOptimize(svg.data());
      state.SetIterationTime(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    } else {
      state.SetIterationTime(d.visibility_ms / 1000.0);
      race->ours[silhouettes] = ofStrokes(d);
    }
  }
}

void runOcct(benchmark::State& state, Race* race, bool silhouettes) {
  race->ensure();
  for (auto _ : state) {
    const hsr::testing::OcctLines l =
        hsr::testing::occtHiddenLines(race->mesh, race->camera,
                                      silhouettes ? hsr::testing::OcctMode::kSingleFace
                                                  : hsr::testing::OcctMode::kFacePerTriangle,
                                      kCreaseDeg);
    state.SetIterationTime(l.hlr_ms / 1000.0);
    race->theirs[silhouettes] = ofOcct(l);
    race->occt_build_ms[silhouettes] = l.build_ms;
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (const char* t = std::getenv("HSR_BENCH_THREADS")) g_threads = std::max(1, std::atoi(t));
  for (const auto& r : races()) {
    Race* race = r.get();
    const bool big = race->label == "spheres/100000" || race->label == "spheres/1000000";
    auto configure = [&](benchmark::internal::Benchmark* bm, int repetitions = 0) {
      bm->Unit(benchmark::kMillisecond)
          ->UseManualTime()
          ->Iterations(1)
          ->Repetitions(repetitions > 0 ? repetitions
                        : big           ? 3
                                        : 5)
          ->ReportAggregatesOnly(true);
    };
    for (const bool silhouettes : {false, true}) {
      const std::string what = silhouettes ? "silhouettes" : "full";
      configure(benchmark::RegisterBenchmark(("BM_hsr_" + what + "/" + race->label).c_str(), runHsr,
                                             race, silhouettes, false));
      configure(benchmark::RegisterBenchmark(("BM_hsr_svg_" + what + "/" + race->label).c_str(),
                                             runHsr, race, silhouettes, true));
      if (silhouettes || !race->huge)
        configure(benchmark::RegisterBenchmark(("BM_occt_" + what + "/" + race->label).c_str(),
                                               runOcct, race, silhouettes),
                  race->huge ? 1 : 0);
    }
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  std::printf(
      "hsr's line drawings vs Open CASCADE's HLRBRep_PolyAlgo at %dx%d, crease angle %g, "
      "hidden parts included, hsr on %d thread(s)\n",
      kWidth, kHeight, kCreaseDeg, g_threads);
  MedianCollector reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);

  for (const bool silhouettes : {false, true}) {
    const std::string what = silhouettes ? "silhouettes" : "full";
    std::printf("\n%s (OCCT time / hsr time: > 1 means hsr is faster)\n",
                silhouettes ? "silhouettes only: OCCT's mesh as one face, hsr --lines outline"
                            : "full drawings: outlines and creases above 45 degrees (hsr: and "
                              "intersection lines)");
    std::printf("%-16s %9s %10s %10s %10s %8s %10s  %-26s %-26s %s\n", "scene", "triangles",
                "hsr ms", "hsr svg ms", "OCCT ms", "ratio", "OCCT shape", "segments vis/hid hsr",
                "OCCT", "visible px hsr / OCCT, within 1 px of the other's");
    for (const auto& r : races()) {
      const std::string& l = r->label;
      const double ours = reporter.time("BM_hsr_" + what + "/" + l);
      const double svg = reporter.time("BM_hsr_svg_" + what + "/" + l);
      const double theirs = reporter.time("BM_occt_" + what + "/" + l);
      if (ours < 0) continue;
      const Drawn &a = r->ours[silhouettes], &b = r->theirs[silhouettes];
      const bool peer = theirs > 0;
      std::printf(
          "%-16s %9zu %10.2f %10.2f %10s %8s %10s  %-26s %-26s ", l.c_str(), r->triangles, ours,
          svg, peer ? std::to_string(theirs).substr(0, 9).c_str() : "not run",
          peer ? (std::to_string(theirs / ours).substr(0, 6) + "x").c_str() : "-",
          peer ? std::to_string(r->occt_build_ms[silhouettes]).substr(0, 8).c_str() : "-",
          (std::to_string(a.visible.size()) + "/" + std::to_string(a.hidden)).c_str(),
          peer ? (std::to_string(b.visible.size()) + "/" + std::to_string(b.hidden)).c_str() : "-");
      if (peer)
        std::printf("%.0f / %.0f; %.2f%% / %.2f%%\n", a.length, b.length,
                    100 * hsr::testing::nearLength(a.visible, b.visible).share(),
                    100 * hsr::testing::nearLength(b.visible, a.visible).share());
      else
        std::printf("%.0f\n", a.length);
    }
    // Growth: hsr's time against the triangles, spheres 10^4 -> 10^5 -> 10^6
    const double t4 = reporter.time("BM_hsr_" + what + "/spheres/10000");
    const double t5 = reporter.time("BM_hsr_" + what + "/spheres/100000");
    const double t6 = reporter.time("BM_hsr_" + what + "/spheres/1000000");
    if (t4 > 0 && t5 > 0 && t6 > 0)
      std::printf(
          "growth of hsr's time: n^%.2f from 10^4 to 10^5 triangles, n^%.2f from 10^5 to "
          "10^6\n",
          std::log10(t5 / t4), std::log10(t6 / t5));
  }
  std::printf(
      "\n(bars: faster than OCCT on every case, at least 10x from 10,000 triangles up, "
      "time growing no faster than n^1.2, spheres/100000 under 1 s; silhouettes no "
      "slower than OCCT's)\n");
  benchmark::Shutdown();
  return 0;
}

// hsr's rays raced against Embree's in the same run (Debian's libembree-dev): the hierarchy's
// build against rtcCommitScene (Embree's default quality and its high quality), and rays per
// second against rtcIntersect1 (default and robust mode: watertight, as hsr is), 8-wide packets
// (rtcIntersect8) and rtcIntersect1M streams,
// for 1920x1080 primary rays (the camera framing the scene) and 10^6 incoherent rays (random
// origins inside the bounds, random directions); then the whole ray-cast frame against the
// z-buffer's. Scenes (bench_scenes.hpp): spheres:10000/100000/1000000, 2CylinderEngine and Wuson.
//
// Threads: HSR_BENCH_THREADS (default 2): hsr's batch runs in a oneTBB arena of that many
// threads; Embree's device gets threads=N, and its per-ray calls are spread over the same
// arena (Embree's calls trace on the calling thread). Medians of 5 repetitions; the table at
// the end prints each as a ratio (Embree time / hsr time: > 1 means hsr is faster).

#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "agreement/embree_peer.hpp"
#include "core/random.hpp"
#include "bench_scenes.hpp"
#include "hsr/camera.hpp"
#include "hsr/io.hpp"
#include "hsr/ray_scene.hpp"
#include "hsr/render.hpp"
#include "median_collector.hpp"

namespace {

constexpr int kWidth = 1920, kHeight = 1080;
constexpr std::size_t kIncoherentRays = 1000000;
int g_threads = 2;

struct RayBatch {
  std::vector<glm::vec3> org, dir;
  float tmin = 0, tmax = INFINITY;
};

struct Race {
  std::string label;
  std::function<hsr::Scene()> make;
  std::unique_ptr<hsr::Scene> scene;
  std::unique_ptr<hsr::RayScene> ours;
  std::unique_ptr<hsr::testing::EmbreeScene> embree;
  // RTC_SCENE_FLAG_ROBUST: watertight, as hsr is
  std::unique_ptr<hsr::testing::EmbreeScene> embree_robust;
  hsr::Camera camera;
  RayBatch primary, incoherent;
  double our_bvh_ms = 0;  // the hierarchy alone, of the last build

  void ensure() {
    if (scene) return;
    scene = std::make_unique<hsr::Scene>(make());
    ours = std::make_unique<hsr::RayScene>(*scene);
    embree = std::make_unique<hsr::testing::EmbreeScene>(*ours, g_threads);
    embree_robust = std::make_unique<hsr::testing::EmbreeScene>(*ours, g_threads, /*robust=*/true);
    camera = hsr::frameScene(*scene, kWidth, kHeight);
    const hsr::CameraRays c = hsr::cameraRays(camera);
    primary = {c.origins, c.directions, c.tmin, c.tmax};
    const hsr::Bounds b = scene->bounds();
    hsr::detail::SplitMix64 rng(1);
    auto u = [&] { return static_cast<float>(rng.next() >> 40) / static_cast<float>(1u << 24); };
    incoherent.org.resize(kIncoherentRays);
    incoherent.dir.resize(kIncoherentRays);
    for (std::size_t i = 0; i < kIncoherentRays; ++i) {
      incoherent.org[i] = b.lo + (b.hi - b.lo) * glm::vec3(u(), u(), u());
      incoherent.dir[i] = glm::vec3(u() - 0.5f, u() - 0.5f, u() - 0.5f);
    }
  }
};

std::vector<std::unique_ptr<Race>>& races() {
  static std::vector<std::unique_ptr<Race>> v = [] {
    std::vector<std::unique_ptr<Race>> r;
    for (const char* label :
         {"spheres/10000", "spheres/100000", "spheres/1000000", "2CylinderEngine", "Wuson"}) {
      auto race = std::make_unique<Race>();
      race->label = label;
      const hsr::bench::BenchSceneSpec& spec = hsr::bench::benchScene(label);
      race->make = [&spec] { return hsr::bench::loadBenchScene(spec); };
      r.push_back(std::move(race));
    }
    return r;
  }();
  return v;
}

tbb::task_arena& arena() {
  static tbb::task_arena a(g_threads);
  return a;
}

// Runs f(begin, end) over [0, n) in chunks on the arena's threads.
template <class F>
void parallelRays(std::size_t n, F&& f) {
  arena().execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024),
                      [&](const tbb::blocked_range<std::size_t>& r) { f(r.begin(), r.end()); });
  });
}

enum class Way { kHsr, kEmbree1, kEmbree1Robust, kEmbree8, kEmbree1M };

void runRays(benchmark::State& state, Race* race, bool primary, Way way) {
  race->ensure();
  const RayBatch& b = primary ? race->primary : race->incoherent;
  std::vector<hsr::testing::EmbreeHit> out(b.org.size());
  std::vector<hsr::RayHit> ours(way == Way::kHsr ? b.org.size()
                                                 : 0);  // both answer into arrays made beforehand
  for (auto _ : state) {
    if (way == Way::kHsr) {
      arena().execute([&] { race->ours->intersect(b.org, b.dir, ours, b.tmax, b.tmin); });
    } else {
      parallelRays(b.org.size(), [&](std::size_t begin, std::size_t end) {
        if (way == Way::kEmbree1) {
          for (std::size_t i = begin; i < end; ++i)
            out[i] = race->embree->intersect1(b.org[i], b.dir[i], b.tmin, b.tmax);
        } else if (way == Way::kEmbree1Robust) {
          for (std::size_t i = begin; i < end; ++i)
            out[i] = race->embree_robust->intersect1(b.org[i], b.dir[i], b.tmin, b.tmax);
        } else if (way == Way::kEmbree8) {
          for (std::size_t i = begin; i < end; i += 8)
            race->embree->intersect8(&b.org[i], &b.dir[i],
                                     static_cast<int>(std::min<std::size_t>(8, end - i)), b.tmin,
                                     b.tmax, &out[i]);
        } else {
          race->embree->intersect1M(&b.org[begin], &b.dir[begin], static_cast<int>(end - begin),
                                    b.tmin, b.tmax, &out[begin]);
        }
      });
    }
  }
  // The hits of the last repetition counted outside the timed loop (reading 2 million answers
  // back is not the queries' work)
  std::uint64_t hits = 0;
  for (const hsr::RayHit& x : ours) hits += x.hit();
  for (const auto& x : out) hits += way == Way::kHsr ? 0 : x.hit();
  state.counters["Mrays/s"] = benchmark::Counter(static_cast<double>(b.org.size()) / 1e6,
                                                 benchmark::Counter::kIsIterationInvariantRate);
  state.counters["hits"] = static_cast<double>(hits);
}

void runBuild(benchmark::State& state, Race* race, int which) {
  race->ensure();
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    if (which == 0) {
      arena().execute([&] {
        const hsr::RayScene r(*race->scene);
        race->our_bvh_ms = r.stats().build_ms;
      });
    } else {
      const hsr::testing::EmbreeScene e(
          *race->ours, g_threads, false,
          which == 1 ? hsr::testing::EmbreeQuality::kMedium : hsr::testing::EmbreeQuality::kHigh);
      state.SetIterationTime(e.buildMs() / 1000.0);
      continue;
    }
    state.SetIterationTime(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
}

void runFrame(benchmark::State& state, Race* race, const char* algorithm) {
  race->ensure();
  hsr::RenderOptions o;
  o.algorithm = algorithm;
  o.threads = g_threads;
  hsr::Frame frame;
  hsr::render(*race->scene, race->camera, o, frame);  // the ray caster's hierarchy built, kept
  for (auto _ : state) hsr::render(*race->scene, race->camera, o, frame);
}

// The bar's ratio once more, measured in pairs: hsr's batch and Embree's rtcIntersect1 over the
// same primary rays of spheres:1M one right after the other, nine times; the median of the nine
// ratios and their range. On a machine whose speed drifts (a shared one), a pair sees the same
// conditions on both sides, where medians taken minutes apart may not.
void pairedBar() {
  for (const auto& r : races()) {
    if (r->label != "spheres/1000000") continue;
    Race& race = *r;
    race.ensure();
    const RayBatch& b = race.primary;
    std::vector<hsr::RayHit> ours(b.org.size());
    std::vector<hsr::testing::EmbreeHit> out(b.org.size());
    auto ms = [](auto&& f) {
      const auto t0 = std::chrono::steady_clock::now();
      f();
      return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
          .count();
    };
    auto embree = [&] {
      parallelRays(b.org.size(), [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
          out[i] = race.embree->intersect1(b.org[i], b.dir[i], b.tmin, b.tmax);
      });
    };
    auto hsr_rays = [&] {
      arena().execute([&] { race.ours->intersect(b.org, b.dir, ours, b.tmax, b.tmin); });
    };
    embree(), hsr_rays();  // warm both
    std::vector<double> ratios;
    for (int round = 0; round < 9; ++round) {
      const double e = ms(embree), o = ms(hsr_rays);
      ratios.push_back(e / o);
    }
    std::sort(ratios.begin(), ratios.end());
    std::printf(
        "\npaired, threads=%d: spheres/1000000 primary rays, rtcIntersect1 time / hsr time in 9 "
        "pairs: median %.3f (range %.3f-%.3f)\n",
        g_threads, ratios[4], ratios.front(), ratios.back());
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (const char* t = std::getenv("HSR_BENCH_THREADS")) g_threads = std::max(1, std::atoi(t));
  for (const auto& r : races()) {
    Race* race = r.get();
    const bool huge = race->label == "spheres/1000000";
    auto configure = [&](benchmark::internal::Benchmark* bm) {
      bm->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);
      if (huge)
        bm->Iterations(2);
      else
        bm->MinTime(0.2);
      return bm;
    };
    for (const char* kind : {"build_hsr", "build_embree", "build_embree_high"}) {
      const int which = std::string(kind) == "build_hsr"      ? 0
                        : std::string(kind) == "build_embree" ? 1
                                                              : 2;
      benchmark::RegisterBenchmark(("BM_" + std::string(kind) + "/" + race->label).c_str(),
                                   runBuild, race, which)
          ->Unit(benchmark::kMillisecond)
          ->UseManualTime()
          ->Iterations(1)
          ->Repetitions(huge ? 3 : 5)
          ->ReportAggregatesOnly(true);
    }
    for (const bool primary : {true, false}) {
      const std::string rays = primary ? "primary" : "incoherent";
      const std::pair<const char*, Way> ways[] = {{"hsr", Way::kHsr},
                                                  {"embree1", Way::kEmbree1},
                                                  {"embree1robust", Way::kEmbree1Robust},
                                                  {"embree8", Way::kEmbree8},
                                                  {"embree1M", Way::kEmbree1M}};
      for (const auto& [name, way] : ways)
        configure(benchmark::RegisterBenchmark(
            ("BM_" + rays + "_" + name + "/" + race->label).c_str(), runRays, race, primary, way));
    }
    for (const char* algorithm : {"raycast", "zbuffer"})
      configure(benchmark::RegisterBenchmark(
          ("BM_frame_" + std::string(algorithm) + "/" + race->label).c_str(), runFrame, race,
          algorithm));
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  std::printf("hsr's rays vs Embree %s at %dx%d primary and %zu incoherent rays, %d thread(s)\n",
              hsr::testing::EmbreeScene::version().c_str(), kWidth, kHeight, kIncoherentRays,
              g_threads);
  MedianCollector reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);

  auto ratio = [&](const std::string& peer, const std::string& ours) {
    const double p = reporter.time(peer), o = reporter.time(ours);
    return p > 0 && o > 0 ? p / o : 0.0;
  };
  std::printf("\nrays vs Embree, threads=%d (Embree time / hsr time: > 1 means hsr is faster)\n",
              g_threads);
  std::printf("%-18s %-10s %9s %9s %9s %9s %9s %11s  %s\n", "scene", "rays", "hsr Mr/s", "x 1",
              "x 1 wt", "x 8", "x 1M", "frame ms", "frame: raycast / zbuffer time");
  for (const auto& r : races()) {
    const std::string& l = r->label;
    for (const std::string rays : {"primary", "incoherent"}) {
      const double ours = reporter.time("BM_" + rays + "_hsr/" + l);
      const std::size_t n = rays == "primary" ? std::size_t(kWidth) * kHeight : kIncoherentRays;
      const double frame = reporter.time("BM_frame_raycast/" + l),
                   z = reporter.time("BM_frame_zbuffer/" + l);
      std::printf(
          "%-18s %-10s %9.2f %9.2f %9.2f %9.2f %9.2f %11.1f  %s\n", l.c_str(), rays.c_str(),
          ours > 0 ? n / (ours * 1e3) : 0.0,
          ratio("BM_" + rays + "_embree1/" + l, "BM_" + rays + "_hsr/" + l),
          ratio("BM_" + rays + "_embree1robust/" + l, "BM_" + rays + "_hsr/" + l),
          ratio("BM_" + rays + "_embree8/" + l, "BM_" + rays + "_hsr/" + l),
          ratio("BM_" + rays + "_embree1M/" + l, "BM_" + rays + "_hsr/" + l),
          rays == "primary" ? frame : 0.0,
          rays == "primary" && frame > 0 && z > 0 ? (std::to_string(frame / z) + "x").c_str() : "");
    }
  }
  std::printf("\nbuild, threads=%d: %-18s %10s %12s %10s %12s %10s\n", g_threads, "scene", "hsr ms",
              "embree ms", "hsr/embree", "embree hq ms", "hsr/hq");
  for (const auto& r : races()) {
    const std::string& l = r->label;
    const double ours = reporter.time("BM_build_hsr/" + l),
                 e = reporter.time("BM_build_embree/" + l),
                 hq = reporter.time("BM_build_embree_high/" + l);
    std::printf(
        "build, threads=%d: %-18s %10.1f %12.1f %10.2f %12.1f %10.2f   (of hsr's: the BVH %.1f ms, "
        "the rest triangulation and copies)\n",
        g_threads, l.c_str(), ours, e, e > 0 ? ours / e : 0.0, hq, hq > 0 ? ours / hq : 0.0,
        r->our_bvh_ms);
  }
  std::printf(
      "(bars: primary rays at least 1.0x Embree's rtcIntersect1 on spheres/1000000; build within "
      "2x Embree's default)\n");
  std::printf(
      "(x 1 wt: against rtcIntersect1 in Embree's robust mode, watertight as hsr's test is)\n");
  if (!std::getenv("HSR_BENCH_NO_PAIRS")) pairedBar();
  benchmark::Shutdown();
  return 0;
}

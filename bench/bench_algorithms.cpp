// Every algorithm of the registry, frames/s and triangles/s at 1920x1080, against Mesa's
// llvmpipe (through OSMesa) in the same process: spheres:N and soup:N (small random triangles)
// for N = 10000/100000/1000000, a real model (2CylinderEngine) and a fill-rate scene of ten
// full-screen quads drawn back to front (every fragment passes); the scenes are bench_scenes.hpp's,
// shared with the ray and line races. One benchmark
// per algorithm and scene, BM_<algorithm>/<scene>/<n>, with the frame's stats as counters;
// BM_llvmpipe/<scene>/<n> is the peer. An algorithm joins by its registry line alone; one
// with a size limit (AlgorithmInfo::max_pixels) below 1920x1080 is listed as not run. Scenes,
// cameras and llvmpipe's vertex buffers are built once, outside the timed loops.
//
// Threads: HSR_BENCH_THREADS (default 2) is passed to hsr as RenderOptions::threads and to
// llvmpipe as LP_NUM_THREADS, which llvmpipe reads once per process when its screen is made,
// so it is set before the first OSMesa call. After the runs, a table of speed ratios
// (llvmpipe time / algorithm time, median of repetitions: > 1 means hsr is faster) and memory.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "agreement/mesa_oracle.hpp"
#include "median_collector.hpp"
#include "bench_scenes.hpp"
#include "hsr/camera.hpp"
#include "hsr/io.hpp"
#include "hsr/bsp.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"
#include "core/random.hpp"
#include "pipeline/stages.hpp"

namespace {

constexpr int kWidth = 1920, kHeight = 1080;
int g_threads = 2;

// One benchmark scene: built on first use and kept for the whole run.
struct BenchScene {
  std::string label;  // "spheres/10000"
  std::function<hsr::Scene()> make;
  bool fill_rate = false;
  std::unique_ptr<hsr::Scene> scene;
  hsr::Camera camera;
  std::unique_ptr<hsr::testing::MesaScene> mesa;
  std::unique_ptr<hsr::testing::MesaScene> mesa_msaa;  // 4x multisampled, resolved by a blit
  std::size_t triangles = 0;
  std::map<std::string, std::uint64_t> state_bytes;  // per algorithm: memory of one frame
  std::map<std::string, hsr::Stats> stats;           // per algorithm: one frame's stats
};

// One registered benchmark: an algorithm of the registry on one scene.
struct AlgorithmRun {
  std::string algorithm;
  BenchScene* scene;
  int samples = 0;  // RenderOptions::samples (the A-buffer's sample counts)
};

// Ten quads far larger than the view, stacked along z, listed back to front.
hsr::Scene fillRateScene() {
  hsr::Scene s;
  s.name = "fillrate";
  for (int k = 0; k < 10; ++k) {
    s.beginObject("quad" + std::to_string(k));
    const std::uint32_t m = s.addMaterial({{0.1f * k, 0.5f, 1.0f - 0.1f * k}, 1.0f});
    const float z = -1.0f + 0.1f * static_cast<float>(k);  // later quads are nearer
    s.addPolygonVertices({{-4, -4, z}, {4, -4, z}, {4, 4, z}, {-4, 4, z}}, m);
  }
  return s;
}

// `layers` see-through (alpha 0.5) quads far larger than the view, stacked along z, listed back
// to front: every pixel's depth complexity is `layers`, and nothing hides anything.
hsr::Scene glassLayersScene(int layers) {
  hsr::Scene s;
  s.name = "glass";
  for (int k = 0; k < layers; ++k) {
    s.beginObject("glass" + std::to_string(k));
    const float t = static_cast<float>(k) / static_cast<float>(std::max(layers - 1, 1));
    const std::uint32_t m = s.addMaterial({{t, 0.5f, 1.0f - t}, 0.5f});
    const float z = -1.0f + 1.5f * t;  // later quads are nearer
    s.addPolygonVertices({{-4, -4, z}, {4, -4, z}, {4, 4, z}, {-4, 4, z}}, m);
  }
  return s;
}

hsr::Camera fillRateCamera() {
  hsr::Camera c;
  c.width = kWidth;
  c.height = kHeight;
  c.ortho = true;
  c.ortho_half_height = 1.0f;  // x spans +-1.78: inside the quads' +-4
  c.eye = {0.0f, 0.0f, 5.0f};
  c.target = {0.0f, 0.0f, 0.0f};
  c.near = 1.0f;
  c.far = 10.0f;
  return c;
}

std::vector<BenchScene>& benchScenes() {
  static std::vector<BenchScene> scenes = [] {
    std::vector<BenchScene> v;
    for (const char* label : {"spheres/10000", "spheres/100000", "spheres/1000000", "soup/10000",
                              "soup/100000", "soup/1000000", "2CylinderEngine"}) {
      BenchScene b;
      b.label = label;
      const hsr::bench::BenchSceneSpec& spec = hsr::bench::benchScene(label);
      b.make = [&spec] { return hsr::bench::loadBenchScene(spec); };
      v.push_back(std::move(b));
    }
    BenchScene f;
    f.label = "fillrate/10";
    f.make = fillRateScene;
    f.fill_rate = true;
    v.push_back(std::move(f));
    return v;
  }();
  return scenes;
}

void ensureScene(BenchScene& b) {
  if (b.scene) return;
  b.scene = std::make_unique<hsr::Scene>(b.make());
  b.camera = b.fill_rate ? fillRateCamera() : hsr::frameScene(*b.scene, kWidth, kHeight);
  b.triangles = b.scene->triangleCount();
}

void setCounters(benchmark::State& state, const BenchScene& b) {
  const double frames = static_cast<double>(state.iterations());
  state.counters["fps"] = benchmark::Counter(frames, benchmark::Counter::kIsRate);
  state.counters["triangles/s"] =
      benchmark::Counter(frames * static_cast<double>(b.triangles), benchmark::Counter::kIsRate);
  state.counters["triangles"] = static_cast<double>(b.triangles);
}

void runAlgorithm(benchmark::State& state, AlgorithmRun* run) {
  BenchScene* b = run->scene;
  ensureScene(*b);
  hsr::RenderOptions options;
  options.algorithm = run->algorithm;
  options.threads = g_threads;
  options.samples = run->samples;
  hsr::Frame frame;
  hsr::render(*b->scene, b->camera, options, frame);  // warm: allocate the frame's buffers
  for (auto _ : state) {
    hsr::render(*b->scene, b->camera, options, frame);
    benchmark::DoNotOptimize(frame.ids.data());
    benchmark::ClobberMemory();
  }
  const std::string key =
      run->samples ? run->algorithm + "@" + std::to_string(run->samples) : run->algorithm;
  b->state_bytes[key] = frame.stats.state_bytes;
  b->stats[key] = frame.stats;
  setCounters(state, *b);
  // The frame's stats: every count of the one table and the algorithm's own counters.
  for (const hsr::Stats::Field& f : hsr::Stats::fields())
    if (frame.stats.*f.value != 0)
      state.counters[std::string(f.name)] = static_cast<double>(frame.stats.*f.value);
  for (const hsr::Counter& c : frame.stats.counters)
    state.counters[c.name] = static_cast<double>(c.value);
}

void runLlvmpipe(benchmark::State& state, BenchScene* b) {
  ensureScene(*b);
  if (!b->mesa) {
    b->mesa = std::make_unique<hsr::testing::MesaScene>(*b->scene, b->camera);
    b->mesa->renderFrameMs();  // warm: JIT-compiles llvmpipe's shaders
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(b->mesa->renderFrameMs());
  }
  setCounters(state, *b);
}

// llvmpipe drawing into a 4x multisampled framebuffer, resolved with a blit: the A-buffer's peer.
void runLlvmpipeMsaa(benchmark::State& state, BenchScene* b) {
  ensureScene(*b);
  if (!b->mesa_msaa) {
    b->mesa_msaa =
        std::make_unique<hsr::testing::MesaScene>(*b->scene, b->camera, hsr::RenderOptions{}, 4);
    b->mesa_msaa->renderFrameMs();  // warm
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(b->mesa_msaa->renderFrameMs());
  }
  setCounters(state, *b);
}

// The A-buffer (4 samples) against llvmpipe's 4x MSAA on the same scene and thread count: time
// ratio, the resolved pictures' mean absolute difference (both flat colour on white), depth
// complexity (fragments per pixel) and memory; then time and memory against the sample count.
void printABufferTable(const MedianCollector& reporter) {
  std::printf(
      "\nA-buffer (4 samples) vs llvmpipe 4x MSAA, threads=%d\n%-16s %10s %12s %7s %12s %10s %9s "
      "%10s\n",
      g_threads, "scene", "abuffer ms", "msaa4 ms", "ratio", "no-AA ms", "frags/px", "state B/px",
      "picture MAD");
  for (BenchScene& b : benchScenes()) {
    const double ours = reporter.time("BM_abuffer/" + b.label);
    const double msaa = reporter.time("BM_llvmpipe_msaa4/" + b.label);
    const auto st = b.stats.find("abuffer");
    if (ours <= 0 || msaa <= 0 || st == b.stats.end() || !b.mesa_msaa) continue;
    // The two resolved pictures, flat colour on white as llvmpipe draws them
    hsr::RenderOptions o;
    o.algorithm = "abuffer";
    o.threads = g_threads;
    o.shade = false;
    o.clear_color = {1.0f, 1.0f, 1.0f};
    const hsr::Frame f = hsr::render(*b.scene, b.camera, o);
    b.mesa_msaa->renderFrameMs();
    const std::vector<std::uint32_t> mesa = b.mesa_msaa->colour();
    double diff = 0;
    for (std::size_t k = 0; k < mesa.size(); ++k)
      for (int c = 0; c < 3; ++c)
        diff += std::abs(static_cast<int>((f.color[k] >> (8 * c)) & 0xFF) -
                         static_cast<int>((mesa[k] >> (8 * c)) & 0xFF));
    const double px = double(kWidth) * kHeight;
    std::printf("%-16s %10.2f %12.2f %7.2f %12.2f %10.2f %9.1f %10.3f\n", b.label.c_str(), ours,
                msaa, msaa / ours, reporter.time("BM_llvmpipe/" + b.label),
                static_cast<double>(st->second.fragments_written) / px,
                static_cast<double>(st->second.state_bytes) / px, diff / (3.0 * px));
  }
  std::printf(
      "(ratio = llvmpipe 4x MSAA time / A-buffer time: >= 1 means as fast; MAD: mean |difference| "
      "per "
      "channel, 0-255)\n");
  // Time and memory against depth complexity: see-through layers, none hiding another, so every
  // pixel lists them all
  std::printf(
      "A-buffer (4 samples) against depth complexity: full-screen see-through layers, %dx%d, "
      "threads=%d\n"
      "%8s %10s %12s %10s %10s\n",
      kWidth, kHeight, g_threads, "layers", "ms", "frags/px", "MiB", "B/px");
  for (const int layers : {1, 2, 4, 8, 16, 32}) {
    const hsr::Scene scene = glassLayersScene(layers);
    hsr::RenderOptions o;
    o.algorithm = "abuffer";
    o.threads = g_threads;
    hsr::Frame f;
    hsr::render(scene, fillRateCamera(), o, f);  // warm
    std::vector<double> ms;
    for (int r = 0; r < 5; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      hsr::render(scene, fillRateCamera(), o, f);
      ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(ms.begin(), ms.end());
    const double px = double(kWidth) * kHeight;
    std::printf("%8d %10.2f %12.2f %10.1f %10.1f\n", layers, ms[ms.size() / 2],
                static_cast<double>(f.stats.fragments_written) / px,
                static_cast<double>(f.stats.state_bytes) / 1048576.0,
                static_cast<double>(f.stats.state_bytes) / px);
  }
  std::printf(
      "(median of 5 frames; state: frame buffers, fragment lists and the scene's screen "
      "triangles)\n");
  for (BenchScene& b : benchScenes()) {
    bool any = false;
    for (const int n : {1, 4, 8, 16, 32, 64}) {
      const std::string name =
          n == 4 ? "BM_abuffer/" + b.label : "BM_abuffer@" + std::to_string(n) + "/" + b.label;
      const double t = reporter.time(name);
      const auto st =
          b.stats.find(n == 4 ? std::string("abuffer") : "abuffer@" + std::to_string(n));
      if (t <= 0 || st == b.stats.end()) continue;
      if (!any) std::printf("A-buffer on %s against the sample count:\n", b.label.c_str());
      any = true;
      std::printf("  %2d samples %10.2f ms %9.1f MiB\n", n, t,
                  static_cast<double>(st->second.state_bytes) / 1048576.0);
    }
  }
}

// The BSP tree built once (timed: the build alone, not the copy of the scene it keeps) and
// rendered from the built tree (timed per frame, as the z-buffer is).
struct BspRun {
  BenchScene* scene = nullptr;
  std::unique_ptr<hsr::Bsp> bsp;
};

void runBspBuild(benchmark::State& state, BspRun* run) {
  ensureScene(*run->scene);
  for (auto _ : state) {
    hsr::Bsp bsp = hsr::buildBsp(*run->scene->scene);
    state.SetIterationTime(bsp.stats().build_ms / 1000.0);
    if (!run->bsp) run->bsp = std::make_unique<hsr::Bsp>(std::move(bsp));
  }
  const hsr::BspStats& st = run->bsp->stats();
  state.counters["splits"] = static_cast<double>(st.splits);
  state.counters["depth"] = static_cast<double>(st.depth);
  state.counters["nodes"] = static_cast<double>(st.nodes);
  state.counters["MiB"] = static_cast<double>(st.bytes) / 1048576.0;
}

void runBspRender(benchmark::State& state, BspRun* run) {
  ensureScene(*run->scene);
  if (!run->bsp) run->bsp = std::make_unique<hsr::Bsp>(hsr::buildBsp(*run->scene->scene));
  hsr::RenderOptions options;
  options.threads = g_threads;
  hsr::Frame frame;
  hsr::render(*run->bsp, run->scene->camera, options, frame);  // warm: allocate the frame's buffers
  for (auto _ : state) {
    hsr::render(*run->bsp, run->scene->camera, options, frame);
    benchmark::DoNotOptimize(frame.ids.data());
  }
  setCounters(state, *run->scene);
}

// per scene: the octree's build, from the fresh frame's stats
std::map<std::string, double> g_build_ms;

// A frame into a new Frame each time: for the octree, the tree is built for it (in the
// registry's loop the frame, and with it the tree, is kept from view to view).
void runFreshFrame(benchmark::State& state, AlgorithmRun* run) {
  BenchScene* b = run->scene;
  ensureScene(*b);
  hsr::RenderOptions options;
  options.algorithm = run->algorithm;
  options.threads = g_threads;
  for (auto _ : state) {
    hsr::Frame frame;
    hsr::render(*b->scene, b->camera, options, frame);
    benchmark::DoNotOptimize(frame.ids.data());
    for (const hsr::StageTime& st : frame.stats.stages)
      if (st.name == run->algorithm + " build") g_build_ms[b->label] = st.ms;
  }
  setCounters(state, *b);
}

// The object-order algorithms against the z-buffer on the same scene and thread count: time
// as a multiple of the z-buffer's, pair tests per polygon and splits (the algorithm's own
// counters), and the growth exponent of the time from 10k to 1M polygons (t ~ n^k).
void printObjectOrderTable(const MedianCollector& reporter) {
  std::printf("\nobject order vs zbuffer, threads=%d\n%-14s %-16s %10s %10s %9s %12s %10s %8s\n",
              g_threads, "algorithm", "scene", "ms", "zbuffer ms", "x zbuffer", "tests/poly",
              "splits", "n^k");
  for (const hsr::AlgorithmInfo& a : hsr::algorithms()) {
    if (a.precision != hsr::Precision::kObject || a.demonstration) continue;
    const std::string prefix(a.name);
    for (const char* kind : {"spheres", "soup"}) {
      double t_first = -1, n_first = 0;
      for (const BenchScene& b : benchScenes()) {
        if (!b.label.starts_with(std::string(kind) + "/")) continue;
        const double ours = reporter.time("BM_" + prefix + "/" + b.label);
        const double z = reporter.time("BM_zbuffer/" + b.label);
        const auto st = b.stats.find(prefix);
        if (ours <= 0 || st == b.stats.end()) continue;
        const double polygons =
            static_cast<double>(std::max<std::uint64_t>(st->second.polygons_in, 1));
        std::uint64_t tests = 0, splits = 0;
        for (const hsr::Counter& c : st->second.counters) {
          if (c.name.ends_with(": overlap candidates")) tests += c.value;
          if (c.name.ends_with(": splits")) splits += c.value;
        }
        char growth[16] = "-";
        if (t_first > 0)
          std::snprintf(growth, sizeof growth, "%.2f",
                        std::log(ours / t_first) / std::log(polygons / n_first));
        else
          t_first = ours, n_first = polygons;
        std::printf("%-14s %-16s %10.2f %10.2f %9.2f %12.1f %10llu %8s\n", prefix.c_str(),
                    b.label.c_str(), ours, z, z > 0 ? ours / z : 0.0,
                    static_cast<double>(tests) / polygons, static_cast<unsigned long long>(splits),
                    growth);
      }
    }
  }
  std::printf(
      "(x zbuffer = algorithm time / zbuffer time; n^k: growth of time from the 10k scene)\n");
}

// The image-order algorithms against the z-buffer on the same scene and thread count: speed
// (z-buffer time / algorithm time), the algorithm's state against the z-buffer's, and the
// counters the issue's bars are about. Bars: scan-line at least 0.5x the z-buffer's speed
// with at most 5% of its state; Warnock on spheres/100000 within 10x its time; the octree's
// frame (tree built) at least 0.5x its speed on spheres/1000000, skipping most hidden leaves.
void printImageOrderTable(const MedianCollector& reporter) {
  std::printf("\nimage order vs zbuffer, threads=%d\n%-16s %-16s %9s %10s %7s %9s %8s  %s\n",
              g_threads, "algorithm", "scene", "ms", "zbuffer ms", "speed", "state MiB", "% state",
              "work");
  for (const char* name : {"zbuffer-textbook", "scanline", "warnock", "octree"}) {
    for (const BenchScene& b : benchScenes()) {
      const double ours = reporter.time("BM_" + std::string(name) + "/" + b.label);
      const double z = reporter.time("BM_zbuffer/" + b.label);
      const auto st = b.stats.find(name);
      const auto zst = b.stats.find("zbuffer");
      if (ours <= 0 || z <= 0 || st == b.stats.end() || zst == b.stats.end()) continue;
      const hsr::Stats& s = st->second;
      std::string work;
      if (std::string(name) == "scanline") {
        work = "spans " + std::to_string(s.counter("scanline: spans")) + ", several " +
               std::to_string(s.counter("scanline: spans inside several")) + " (previous row " +
               std::to_string(s.counter("scanline: previous row's order reused")) + ", ends " +
               std::to_string(s.counter("scanline: decided at the span's ends")) +
               ", pixel by pixel " +
               std::to_string(s.counter("scanline: compared pixel by pixel")) + ")";
      } else if (std::string(name) == "warnock") {
        std::uint64_t areas = 0;
        for (const hsr::Counter& c : s.counters)
          if (c.name.starts_with("warnock: areas at level")) areas += c.value;
        work = "areas " + std::to_string(areas) + ", stops: nothing " +
               std::to_string(s.counter("warnock: stop, nothing there")) + ", one polygon " +
               std::to_string(s.counter("warnock: stop, one polygon")) + ", surrounder " +
               std::to_string(s.counter("warnock: stop, surrounder in front")) + ", pixel " +
               std::to_string(s.counter("warnock: stop, pixel"));
      } else if (std::string(name) == "octree") {
        const std::uint64_t skipped = s.counter("octree: leaves under covered octants");
        const std::uint64_t hidden = s.counter("octree: leaves drawn, hidden");
        char share[32];
        std::snprintf(share, sizeof share, "%.1f%%",
                      skipped + hidden ? 100.0 * skipped / (skipped + hidden) : 0.0);
        work = "leaves " + std::to_string(s.counter("octree: leaves")) + ", hidden skipped " +
               std::to_string(skipped) + " / drawn " + std::to_string(hidden) + " (" + share +
               " of hidden skipped)";
      }
      std::printf("%-16s %-16s %9.2f %10.2f %7.2f %9.2f %7.1f%%  %s\n", name, b.label.c_str(), ours,
                  z, z / ours, static_cast<double>(s.state_bytes) / 1048576.0,
                  100.0 * static_cast<double>(s.state_bytes) /
                      static_cast<double>(std::max<std::uint64_t>(zst->second.state_bytes, 1)),
                  work.c_str());
    }
  }
  for (const BenchScene& b : benchScenes()) {
    const double fresh = reporter.time("BM_octree_fresh/" + b.label);
    const double kept = reporter.time("BM_octree/" + b.label);
    const auto build = g_build_ms.find(b.label);
    if (fresh > 0 && kept > 0 && build != g_build_ms.end())
      std::printf(
          "octree %-16s a first frame (new buffers, tree built) %.1f ms, of it the build %.1f ms; "
          "a next view %.1f ms\n",
          b.label.c_str(), fresh, build->second, kept);
  }
  std::printf(
      "(speed = zbuffer time / algorithm time: >= 1 means as fast; %% state = the algorithm's "
      "state "
      "memory as a share of the z-buffer's)\n");
}

// The BSP tree built once and rendered from it: build time, splits, depth, memory; a frame
// from the built tree against the z-buffer's frame; growth exponents from the 10k scene.
void printBspTable(const MedianCollector& reporter,
                   const std::vector<std::unique_ptr<BspRun>>& runs) {
  std::printf(
      "\nBSP tree built once, rendered from it, threads=%d\n%-16s %10s %10s %8s %6s %8s %10s %10s "
      "%9s %7s %7s\n",
      g_threads, "scene", "build ms", "splits", "splits/n", "depth", "MiB", "render ms",
      "zbuffer ms", "x zbuffer", "build k", "frame k");
  for (const char* kind : {"spheres", "soup"}) {
    double build_first = -1, render_first = -1, n_first = 0;
    for (const std::unique_ptr<BspRun>& r : runs) {
      const BenchScene& b = *r->scene;
      if (!b.label.starts_with(std::string(kind) + "/") || !r->bsp) continue;
      const double build = reporter.time("BM_bsp_build/" + b.label);
      const double frame = reporter.time("BM_bsp_from_tree/" + b.label);
      const double z = reporter.time("BM_zbuffer/" + b.label);
      const hsr::BspStats& st = r->bsp->stats();
      const double n = static_cast<double>(std::max<std::uint64_t>(st.input_polygons, 1));
      char build_k[16] = "-", frame_k[16] = "-";
      if (build_first > 0 && build > 0 && frame > 0) {
        std::snprintf(build_k, sizeof build_k, "%.2f",
                      std::log(build / build_first) / std::log(n / n_first));
        std::snprintf(frame_k, sizeof frame_k, "%.2f",
                      std::log(frame / render_first) / std::log(n / n_first));
      } else if (build > 0 && frame > 0) {
        build_first = build, render_first = frame, n_first = n;
      }
      std::printf("%-16s %10.1f %10llu %8.3f %6llu %8.1f %10.2f %10.2f %9.2f %7s %7s\n",
                  b.label.c_str(), build, static_cast<unsigned long long>(st.splits),
                  static_cast<double>(st.splits) / n, static_cast<unsigned long long>(st.depth),
                  static_cast<double>(st.bytes) / 1048576.0, frame, z,
                  z > 0 && frame > 0 ? frame / z : 0.0, build_k, frame_k);
    }
  }
  std::printf(
      "(render ms: a frame from the built tree, the pipeline's window polygons included; k: growth "
      "exponent from the 10k scene)\n");
}

}  // namespace

// The z-buffer's bars (issue 46: 3.0x llvmpipe on every scene, at 1 and 2 threads; spheres:1M
// at 1 thread at least 25 million triangles a second), measured in back-to-back pairs (a hsr
// frame, then an llvmpipe frame, nine times; the median of the nine ratios and their range).
// This machine's speed drifts over minutes, so a pair's two frames see the same machine where
// the repetitions above may not. Mtri/s per core: the scene's triangles (after triangulating
// its polygons) over the median frame time, divided by the thread count; MiB: the z-buffer's
// memory for the frame (its buffers, bins and screen triangles). HSR_BENCH_NO_PAIRS skips it.
void printPairedZBufferTable() {
  constexpr int kPairs = 9;
  constexpr double kBar = 3.0;
  std::printf(
      "\nz-buffer vs llvmpipe in %d back-to-back pairs, %d thread(s) (bar: %.1fx on every scene; "
      "spheres/1000000 at 1 thread: 25 Mtri/s)\n",
      kPairs, g_threads, kBar);
  std::printf("threads=%d  %-22s %10s %12s %8s %16s %6s %11s %13s %9s\n", g_threads, "scene",
              "zbuffer ms", "llvmpipe ms", "ratio", "ratio range", "bar", "Mtri/s/core",
              "llvmpipe Mtri", "MiB");
  for (BenchScene& b : benchScenes()) {
    ensureScene(b);
    if (!b.mesa) {
      b.mesa = std::make_unique<hsr::testing::MesaScene>(*b.scene, b.camera);
      b.mesa->renderFrameMs();
    }
    hsr::RenderOptions options;
    options.threads = g_threads;
    hsr::Frame frame;
    hsr::render(*b.scene, b.camera, options, frame);  // warm
    std::vector<double> ours, mesa, ratio;
    for (int k = 0; k < kPairs; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      hsr::render(*b.scene, b.camera, options, frame);
      ours.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      mesa.push_back(b.mesa->renderFrameMs());
      ratio.push_back(mesa.back() / ours.back());
    }
    const auto median = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      return v[v.size() / 2];
    };
    const double r = median(ratio);
    char range[32];
    std::snprintf(range, sizeof range, "%.2f-%.2f", *std::min_element(ratio.begin(), ratio.end()),
                  *std::max_element(ratio.begin(), ratio.end()));
    // Million triangles a second per core, from a frame time in ms
    const double triangles = static_cast<double>(frame.stats.triangles_in);
    const auto mtri = [&](double ms) { return triangles / (ms * 1e3) / g_threads; };
    std::printf("threads=%d  %-22s %10.2f %12.2f %8.2f %16s %6s %11.1f %13.1f %9.1f\n", g_threads,
                b.label.c_str(), median(ours), median(mesa), r, range, r >= kBar ? "met" : "not",
                mtri(median(ours)), mtri(median(mesa)),
                static_cast<double>(frame.stats.state_bytes) / 1048576.0);
  }
}

// The fast path's triangles finished lane-wise (pipeline/shade.cpp: depth plane and Lambert
// cosine of four triangles), per level: 0 the scalar lanes (windowPlane and lambertOf, one
// triangle at a time), 1 SSE2, 2 AVX2; items are triangles.
#if defined(__x86_64__) && !defined(HSR_NO_SIMD)
void BM_shade_lanes(benchmark::State& state) {
  using hsr::detail::ShadeLanes;
  std::vector<ShadeLanes> in(1024);
  hsr::detail::SplitMix64 rng(7);
  for (ShadeLanes& l : in)
    for (int i = 0; i < ShadeLanes::kLanes; ++i) {
      double* fields[] = {l.ax, l.ay, l.bx, l.by, l.cx, l.cy};
      for (double* f : fields) f[i] = rng.uniform(0.0f, 1000.0f);
      l.az[i] = rng.uniform(), l.bz[i] = rng.uniform(), l.cz[i] = rng.uniform();
      l.nx[i] = rng.uniform() - 0.5, l.ny[i] = rng.uniform() - 0.5, l.nz[i] = rng.uniform() - 0.5;
      l.len2[i] = l.nx[i] * l.nx[i] + l.ny[i] * l.ny[i] + l.nz[i] * l.nz[i];
    }
  const glm::dvec3 light(0.0, 0.0, -1.0);
  auto fn = &hsr::detail::shadeLanesScalar;
  if (state.range(0) == 1) fn = &hsr::detail::shadeLanesSse2;
  if (state.range(0) == 2) {
    if (!hsr::detail::shadeLanesAvx2Available()) {
      state.SkipWithError("no AVX2 on this processor");
      return;
    }
    fn = &hsr::detail::shadeLanesAvx2;
  }
  hsr::detail::ShadedLanes out;
  for (auto _ : state)
    for (const ShadeLanes& l : in) {
      fn(l, light, out);
      benchmark::DoNotOptimize(out);
    }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(in.size()) *
                          ShadeLanes::kLanes);
}
BENCHMARK(BM_shade_lanes)->Arg(0)->Arg(1)->Arg(2);
#endif

int main(int argc, char** argv) {
  // Thread count for both renderers; llvmpipe reads LP_NUM_THREADS once, at its first context.
  if (const char* t = std::getenv("HSR_BENCH_THREADS")) g_threads = std::max(1, std::atoi(t));
  setenv("LP_NUM_THREADS", std::to_string(g_threads).c_str(), 1);

  static std::vector<std::unique_ptr<AlgorithmRun>> runs;
  static std::vector<std::unique_ptr<BspRun>> bsp_runs;
  std::vector<std::string> not_run;
  for (BenchScene& b : benchScenes()) {
    const bool huge = b.label.ends_with("/1000000");
    auto configure = [&](benchmark::internal::Benchmark* bm) {
      bm->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);
      if (huge) {
        bm->Iterations(3);  // a frame of 1M triangles takes long enough on its own
      } else {
        bm->MinTime(0.3);
      }
    };
    for (const hsr::AlgorithmInfo& a : hsr::algorithms()) {
      if (a.max_pixels != 0 && static_cast<std::uint64_t>(kWidth) * kHeight > a.max_pixels) {
        not_run.push_back(std::string(a.name) + " on " + b.label + " (limited to " +
                          std::to_string(a.max_pixels) + " pixels)");
        continue;
      }
      runs.push_back(std::make_unique<AlgorithmRun>(AlgorithmRun{std::string(a.name), &b}));
      benchmark::internal::Benchmark* bm = benchmark::RegisterBenchmark(
          ("BM_" + std::string(a.name) + "/" + b.label).c_str(), runAlgorithm, runs.back().get());
      configure(bm);
      // A BSP tree of a million polygons is built for every frame here: once is plenty (the
      // built tree's frames are BM_bsp_from_tree).
      if (huge && a.name == "bsp") bm->Iterations(1)->Repetitions(1);
    }
    configure(benchmark::RegisterBenchmark(("BM_llvmpipe/" + b.label).c_str(), runLlvmpipe, &b));
    // The A-buffer's peer, on the scenes its issue names; its sample counts on one scene
    if (b.label == "spheres/100000" || b.label == "spheres/1000000" || b.fill_rate)
      configure(benchmark::RegisterBenchmark(("BM_llvmpipe_msaa4/" + b.label).c_str(),
                                             runLlvmpipeMsaa, &b));
    if (b.label == "spheres/100000")
      for (const int n : {1, 8, 16, 32, 64}) {
        runs.push_back(std::make_unique<AlgorithmRun>(AlgorithmRun{"abuffer", &b, n}));
        configure(benchmark::RegisterBenchmark(
            ("BM_abuffer@" + std::to_string(n) + "/" + b.label).c_str(), runAlgorithm,
            runs.back().get()));
      }
    if (b.fill_rate) continue;
    runs.push_back(std::make_unique<AlgorithmRun>(AlgorithmRun{"octree", &b}));
    benchmark::RegisterBenchmark(("BM_octree_fresh/" + b.label).c_str(), runFreshFrame,
                                 runs.back().get())
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->Iterations(1)
        ->Repetitions(3)
        ->ReportAggregatesOnly(true);
    bsp_runs.push_back(std::make_unique<BspRun>(BspRun{&b, nullptr}));
    benchmark::RegisterBenchmark(("BM_bsp_build/" + b.label).c_str(), runBspBuild,
                                 bsp_runs.back().get())
        ->Unit(benchmark::kMillisecond)
        ->UseManualTime()
        ->Iterations(1)
        ->Repetitions(huge ? 1 : 3)
        ->ReportAggregatesOnly(true);
    configure(benchmark::RegisterBenchmark(("BM_bsp_from_tree/" + b.label).c_str(), runBspRender,
                                           bsp_runs.back().get()));
  }

  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  std::printf("hsr's algorithms vs %s at %dx%d, %d thread(s) each\n",
              hsr::testing::mesaRenderer().c_str(), kWidth, kHeight, g_threads);
  MedianCollector reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);

  // Speed ratios and memory, per algorithm and scene.
  std::printf("\nthreads=%d  %-18s %-16s %12s %12s %10s %14s %14s\n", g_threads, "algorithm",
              "scene", "ms", "llvmpipe ms", "ratio", "state B/px", "scene B/tri");
  for (const hsr::AlgorithmInfo& a : hsr::algorithms()) {
    for (const BenchScene& b : benchScenes()) {
      const double ours = reporter.time("BM_" + std::string(a.name) + "/" + b.label);
      const double mesa = reporter.time("BM_llvmpipe/" + b.label);
      if (ours < 0) continue;
      const double px = double(kWidth) * kHeight;
      const double scene_bytes = b.scene ? static_cast<double>(b.scene->memoryBytes()) : 0.0;
      const auto state = b.state_bytes.find(std::string(a.name));
      char ratio[32] = "-";
      if (ours > 0 && mesa > 0) std::snprintf(ratio, sizeof ratio, "%.2f", mesa / ours);
      std::printf("threads=%d  %-18s %-16s %12.3f %12.3f %10s %14.2f %14.1f\n", g_threads,
                  std::string(a.name).c_str(), b.label.c_str(), ours, mesa, ratio,
                  state == b.state_bytes.end() ? 0.0 : static_cast<double>(state->second) / px,
                  b.triangles ? scene_bytes / static_cast<double>(b.triangles) : 0.0);
    }
  }
  for (const std::string& n : not_run) std::printf("not run: %s\n", n.c_str());
  printObjectOrderTable(reporter);
  printImageOrderTable(reporter);
  printBspTable(reporter, bsp_runs);
  printABufferTable(reporter);
  std::printf(
      "(ratio = llvmpipe time / algorithm time, median of repetitions: > 1 means hsr is faster)\n");
  if (!std::getenv("HSR_BENCH_NO_PAIRS")) printPairedZBufferTable();
  benchmark::Shutdown();
  return 0;
}

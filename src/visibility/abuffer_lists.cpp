// What the two A-buffers share (abuffer_lists.hpp).

#include "visibility/abuffer_lists.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <utility>

#include <glm/vec2.hpp>

#include "raster/depth.hpp"
#include "raster/fragment.hpp"

namespace hsr::detail {

std::string fragmentBudgetMessage(std::uint64_t limit) {
  return "abuffer: the frame needs more than " + std::to_string(limit) + " fragments (" +
         std::to_string(limit * sizeof(Fragment) >> 20) +
         " MiB of fragment memory at 24 bytes each); raise the fragment memory limit "
         "(--fragment-memory MIB) or draw fewer overlapping polygons";
}

SampleResult resolveSample(const ScreenTriangles& tris, const SamplePattern& pattern,
                           const std::vector<const Fragment*>& list, int x, int y, int s,
                           std::uint32_t background) {
  auto opaque = [&](const Fragment* f) { return !tris[f->polygon].transparent(); };
  auto colour = [&](const Fragment* f) { return tris[f->polygon].rgba; };
  auto depthAt = [&](const Fragment* f) {
    return sampleDepth(tris[f->polygon].depth, x, y, pattern.x[s], pattern.y[s]);
  };
  const std::uint64_t bit = std::uint64_t(1) << s;
  // The nearest opaque fragment covering the sample hides everything behind it
  const Fragment* nearest = nullptr;
  float nearest_z = 0;
  for (const Fragment* f : list) {
    if (!(f->mask & bit) || !opaque(f)) continue;
    const float z = depthAt(f);
    if (!nearest || inFront(z, *f, nearest_z, *nearest)) nearest = f, nearest_z = z;
  }
  std::uint32_t c = nearest ? colour(nearest) : background;
  // The see-through ones nearer than it, laid over it farthest first (of equals, the one drawn
  // first goes under, as the z-buffer blends them)
  thread_local std::vector<std::pair<float, const Fragment*>> in_front;
  in_front.clear();
  for (const Fragment* f : list) {
    if (!(f->mask & bit) || opaque(f)) continue;
    const float z = depthAt(f);
    if (!nearest || z < nearest_z) in_front.push_back({z, f});
  }
  std::sort(in_front.begin(), in_front.end(), [](const auto& a, const auto& b) {
    return a.first > b.first || (a.first == b.first && a.second->polygon < b.second->polygon);
  });
  for (const auto& [z, f] : in_front) c = blendOver(colour(f), c);
  return {c, nearest ? nearest_z : NAN, nearest ? tris[nearest->polygon].id : kNoPolygon};
}

// The sample counts are powers of two, so it divides by shifting.
std::uint32_t meanOfSamples(const std::uint32_t sum[3], int count) {
  const int shift = std::countr_zero(static_cast<unsigned>(count));
  std::uint32_t out = 0xFF000000u;
  for (int ch = 0; ch < 3; ++ch)
    out |= ((sum[ch] + static_cast<std::uint32_t>(count) / 2) >> shift) << (8 * ch);
  return out;
}

const Fragment* nearestAtCentre(const ScreenTriangles& tris,
                                const std::vector<const Fragment*>& list, int x, int y,
                                float* depth) {
  const Fragment* at_centre = nullptr;
  float centre_z = 0;
  for (const Fragment* f : list) {
    if (tris[f->polygon].transparent() || !f->centre) continue;
    const float z = fragmentDepth(tris[f->polygon].depth, x, y);
    if (!at_centre || inFront(z, *f, centre_z, *at_centre)) at_centre = f, centre_z = z;
  }
  *depth = centre_z;
  return at_centre;
}

std::string describeList(const ScreenTriangles& tris, const SamplePattern& pattern,
                         const std::vector<const Fragment*>& fragments, int x, int y,
                         const Fragment* held) {
  std::vector<std::pair<float, const Fragment*>> list;
  for (const Fragment* f : fragments)
    list.push_back({fragmentDepth(tris[f->polygon].depth, x, y), f});
  std::sort(list.begin(), list.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::string s = "Pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") holds " +
                  std::to_string(list.size()) +
                  " fragments, one per polygon that reaches it, nearest first:";
  for (const auto& [z, f] : list) {
    const ScreenTriangle& t = tris[f->polygon];
    std::string bits;
    for (int i = 0; i < pattern.count; ++i) bits += (f->mask >> i) & 1 ? '1' : '0';
    char depth[32];
    std::snprintf(depth, sizeof depth, "%.6f", static_cast<double>(z));
    s += " polygon " + std::to_string(t.id) + " (" +
         (t.transparent() ? "alpha " + std::to_string(t.rgba >> 24) + "/255"
                          : std::string("opaque")) +
         "), samples " + bits + (f->centre ? " and the centre" : "") + ", depth " + depth +
         " at the centre" +
         (f == held ? " (covering the pixel in front of all that came before it, so held by the "
                      "pixel itself, not listed)"
                    : "") +
         ";";
  }
  s += " Resolve: each sample takes the nearest opaque fragment covering it (or the background) "
       "with the see-through ones in front of it laid over it, farthest first; the pixel is the "
       "mean of its " +
       std::to_string(pattern.count) +
       " samples, its id and depth the nearest opaque fragment at the centre.";
  return s;
}

std::uint32_t closeUp(const ScreenTriangles& tris, const std::vector<std::uint32_t>& polygon_of,
                      const SamplePattern& p, const std::vector<const Fragment*>& list, int x,
                      int y, std::uint32_t background, TracePixel& out) {
  out = {x, y, {}, {}};
  std::uint32_t sum[3] = {0, 0, 0};
  for (int s = 0; s < p.count; ++s) {
    const SampleResult r = resolveSample(tris, p, list, x, y, s, background);
    out.samples.push_back(
        {{p.x[s] / static_cast<double>(kSubpixelOne), p.y[s] / static_cast<double>(kSubpixelOne)},
         r.colour,
         r.depth,
         r.id});
    for (int ch = 0; ch < 3; ++ch) sum[ch] += (r.colour >> (8 * ch)) & 0xFFu;
  }
  const auto window = [](std::int32_t wx, std::int32_t wy) {
    return glm::dvec2(wx / static_cast<double>(kSubpixelOne),
                      wy / static_cast<double>(kSubpixelOne));
  };
  for (const Fragment* f : list)
    for (std::uint32_t i = f->polygon; i < tris.size() && polygon_of[i] == f->polygon; ++i) {
      const ScreenTriangle& t = tris[i];
      for (int e = 0; e < 3; ++e)
        out.edges.push_back({window(t.x[e], t.y[e]), window(t.x[(e + 1) % 3], t.y[(e + 1) % 3])});
    }
  return meanOfSamples(sum, p.count);
}

}  // namespace hsr::detail

// Coplanar overlap (z-fighting), docs/testing.md row 6, for every algorithm: pairs and stacks of 2
// to 5 coplanar polygons, submitted in every permutation (5! = 120 orders for a stack of 5). The
// documented rule (docs/algorithms.md): the depth test compares each polygon's own float depth;
// where those are bit-equal (a tie), with LESS the first submitted polygon stays and with LEQUAL
// the last submitted one does. The expected picture is exact, not estimated: each polygon is first
// rendered alone to get its coverage and depth, then the depth test is replayed on those in
// submission order, and every pixel must show its winner. Identical polygons, in any vertex order,
// and polygons facing an orthographic camera must tie exactly (0 pixels where their own depths
// differ): never a mix of the rule and rounding noise. Different polygons in one tilted plane are
// coplanar only up to float rounding (their vertices are rounded to float, then projected): their
// depths differ by a few ULP, and the nearer float depth wins, as in GL; those pixels are counted
// and reported, not hidden. Every LESS picture is rendered twice at 1 thread and twice at 2
// threads, every LEQUAL one once at each: all buffers must be bit-identical.
//
// Families, from the easy case to the hard one:
//   - identical triangles / quads (same vertices, same order) in a tilted plane, perspective;
//   - different overlapping triangles in a plane facing an orthographic camera (the window
//     depth is then the same constant for all of them);
//   - different overlapping triangles and quads in one tilted plane, perspective;
//   - one triangle given with each of its 6 vertex orders (same three points), perspective.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "cross/figures.hpp"
#include "hsr/render.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

constexpr int kSize = 128;
constexpr double kPi = 3.14159265358979323846;

struct Family {
  std::string name;
  Camera camera;
  std::vector<std::vector<glm::vec3>> polygons;  // stacks are the first k of these
  bool exact_ties = true;  // the polygons' own depths are bit-equal wherever they overlap
};

struct Tally {
  std::uint64_t stacks = 0, permutations = 0, renders = 0;
  std::uint64_t multi = 0;  // pixel-checks where 2 or more polygons cover the centre
  std::uint64_t all = 0;    // ... where all of the stack covers it
  std::uint64_t off_less = 0, off_lequal = 0;  // pixels not showing the rule's winner
  std::uint64_t all_off = 0;  // of the LESS ones, pixels covered by the whole stack
  std::uint64_t pictures_off = 0, pictures = 0;  // pictures with any off-rule pixel
  std::uint64_t nondeterministic = 0;            // renders differing from the first of their set
  float max_spread = 0.0f;     // at off-rule pixels: largest depth difference between the
                               // covering polygons, each rendered alone (0 = an exact tie)
  std::uint64_t rounding = 0;  // pixels under 2+ polygons whose own depths are not all equal
  std::string example_less, example_lequal;
};

Scene sceneOf(const std::vector<const std::vector<glm::vec3>*>& polys) {
  Scene s;
  const std::uint32_t m = s.addMaterial({{0.7f, 0.6f, 0.5f}, 1.0f});
  for (const auto* p : polys) s.addPolygonVertices(std::span<const glm::vec3>(*p), m);
  return s;
}

bool sameBuffers(const Frame& a, const Frame& b) {
  // Depth by bit pattern (== would equate -0 and +0 and fail on NaN).
  return a.ids == b.ids && a.color == b.color && a.overdraw == b.overdraw &&
         a.depth.size() == b.depth.size() &&
         std::memcmp(a.depth.data(), b.depth.data(), a.depth.size() * sizeof(float)) == 0;
}

// Every stack size and permutation of one family, for one algorithm.
// The thread counts of a LESS picture's renders, LEQUAL's being {1, 2}. In the sanitizer leg's tier
// one render per thread count (every comparison across thread counts is still made; the repeat at
// the same count is Release's).
#ifdef HSR_SANITIZER_BUILD
const std::vector<int> kLessThreads = {1, 2};
#else
const std::vector<int> kLessThreads = {1, 1, 2, 2};
#endif

void checkFamily(const Family& fam, const AlgorithmInfo& algo, Tally& t) {
  const std::size_t n = fam.polygons.size();
  RenderOptions base;
  base.algorithm = std::string(algo.name);
  base.cull = CullMode::None;
  // Each polygon alone: its own coverage, independent of what else is drawn.
  std::vector<std::vector<std::uint8_t>> cover(n);
  std::vector<FrameBuffer<float>> solo_depth(n);
  for (std::size_t j = 0; j < n; ++j) {
    const Frame f = render(sceneOf({&fam.polygons[j]}), fam.camera, base);
    solo_depth[j] = f.depth;
    cover[j].resize(f.ids.size());
    std::size_t covered = 0;
    for (std::size_t k = 0; k < f.ids.size(); ++k) covered += cover[j][k] = f.ids[k] == 0;
    ASSERT_GT(covered, 500u) << fam.name << ": polygon " << j << " is too small to test";
  }
  for (std::size_t size = 2; size <= std::min<std::size_t>(5, n); ++size) {
    t.stacks++;
    std::vector<std::size_t> perm(size);
    std::iota(perm.begin(), perm.end(), 0);
    do {
      t.permutations++;
      std::vector<const std::vector<glm::vec3>*> polys;
      std::string order;
      for (std::size_t i : perm) {
        polys.push_back(&fam.polygons[i]);
        order += std::to_string(i);
      }
      const Scene scene = sceneOf(polys);
      for (DepthFunc func : {DepthFunc::Less, DepthFunc::LEqual}) {
        const bool less = func == DepthFunc::Less;
        if (!less && !algo.has(kDepthFuncs)) continue;  // LEQUAL only where it can be asked
        RenderOptions o = base;
        o.depth_func = func;
        const std::vector<int> threads = less ? kLessThreads : std::vector<int>{1, 2};
        Frame first;
        for (std::size_t r = 0; r < threads.size(); ++r) {
          o.threads = threads[r];
          Frame f = render(scene, fam.camera, o);
          t.renders++;
          if (r == 0) {
            first = std::move(f);
          } else if (!sameBuffers(first, f)) {
            t.nondeterministic++;
          }
        }
        // The rule at every pixel: the first (LESS) / last (LEQUAL) submitted cover wins.
        t.pictures++;
        std::uint64_t off = 0;
        for (std::size_t k = 0; k < first.ids.size(); ++k) {
          PolygonId expected = kNoPolygon;
          std::size_t covering = 0;
          float z_lo = 1.0f, z_hi = 0.0f;
          for (std::size_t i = 0; i < size; ++i) {
            if (!cover[perm[i]][k]) continue;
            covering++;
            const float z = solo_depth[perm[i]][k];
            // The depth test on the polygons' own depths, in submission order: a nearer depth
            // replaces (LESS), or a nearer or equal one (LEQUAL). Where the depths are equal,
            // this is the tie rule itself: first submitted (LESS), last submitted (LEQUAL).
            if (expected == kNoPolygon || (less ? z < z_lo : z <= z_lo))
              expected = static_cast<PolygonId>(i);
            z_lo = std::min(z_lo, z);
            z_hi = std::max(z_hi, z);
          }
          if (less) {  // count each pixel once, on the LESS pass
            t.multi += covering >= 2;
            t.all += covering == size;
            t.rounding += covering >= 2 && z_lo != z_hi;
          }
          if (first.ids[k] == expected) continue;
          off++;
          (less ? t.off_less : t.off_lequal)++;
          if (less) t.all_off += covering == size;
          if (covering >= 2) t.max_spread = std::max(t.max_spread, z_hi - z_lo);
          std::string& example = less ? t.example_less : t.example_lequal;
          if (example.empty()) {
            const int x = static_cast<int>(k % kSize),
                      y_up = kSize - 1 - static_cast<int>(k / kSize);
            std::string depths = "; depth of each submission drawn alone:";
            for (std::size_t i = 0; i < size; ++i) {
              if (!cover[perm[i]][k]) continue;
              char buf[48];
              std::snprintf(buf, sizeof buf, " #%zu %.9g", i, double(solo_depth[perm[i]][k]));
              depths += buf;
            }
            example = "stack of " + std::to_string(size) + " submitted in order " + order +
                      " (family indices), depth func " + (less ? "LESS" : "LEQUAL") + ": pixel (" +
                      std::to_string(x) + ", " + std::to_string(y_up) + ") [y up], covered by " +
                      std::to_string(covering) + ", expected submission #" +
                      std::to_string(static_cast<int>(expected)) + ", got #" +
                      std::to_string(static_cast<int>(first.ids[k])) + depths;
          }
        }
        t.pictures_off += off > 0;
      }
    } while (std::next_permutation(perm.begin(), perm.end()));
  }
}

std::string spreadText(float v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g", double(v));
  return buf;
}

// One algorithm that promises the z-buffer's tie rule (kTieRule): with LESS, and with LEQUAL
// where it has the depth functions.
void checkFamilyFor(const Family& fam, const AlgorithmInfo& algo) {
  {
    SCOPED_TRACE("algorithm " + std::string(algo.name) + ", family: " + fam.name);
    Tally t;
    checkFamily(fam, algo, t);
    EXPECT_EQ(t.nondeterministic, 0u) << "renders of one picture differ between runs or threads";
    EXPECT_GT(t.all, 0u) << "no pixel is covered by a whole stack: the family proves nothing";
    if (fam.exact_ties) {
      EXPECT_EQ(t.rounding, 0u) << "overlapping polygons whose depths should tie do not";
    }
    EXPECT_EQ(t.off_less, 0u) << "LESS: not the first submitted; first case: " << t.example_less;
    EXPECT_EQ(t.off_lequal, 0u) << "LEQUAL: not the last submitted; first case: "
                                << t.example_lequal;
    testing::printFigures(
        "row 6 " + std::string(algo.name) + " (" + fam.name + "): " + testing::grouped(t.stacks) +
        " stack sizes, " + testing::grouped(t.permutations) + " orders, " +
        testing::grouped(t.renders) + " renders, " + testing::grouped(t.multi) +
        " pixels under 2+ polygons (" + testing::grouped(t.all) + " under the whole stack); " +
        "off the tie rule: " + testing::grouped(t.off_less) + " with LESS, " +
        testing::grouped(t.off_lequal) + " with LEQUAL (" + testing::grouped(t.pictures_off) +
        " of " + testing::grouped(t.pictures) + " pictures; with LESS " +
        testing::grouped(t.all_off) + " under the whole stack; depth spread there up to " +
        spreadText(t.max_spread) + "); " + testing::grouped(t.rounding) +
        " pixels where the polygons' own float depths differ " + "(decided by depth, as GL), " +
        testing::grouped(t.nondeterministic) + " non-identical reruns");
  }
}

// One test per algorithm and family (Coplanar.Family/ALGORITHM), so that CTest runs them side by
// side.
class Coplanar : public testing::EveryAlgorithm {};

// A perspective camera looking at the origin slightly from above and to the side.
Camera perspectiveCamera() {
  Camera c;
  c.width = kSize;
  c.height = kSize;
  c.eye = {0.7f, 0.9f, 4.0f};
  c.target = {0.0f, 0.0f, 0.0f};
  c.fov_deg = 45.0f;
  c.near = 1.0f;
  c.far = 10.0f;
  return c;
}

// Points on circles in the plane through `origin` spanned by u, v: polygon i has `sides`
// vertices on a circle of radius r_i around a centre offset by up to `spread`.
std::vector<std::vector<glm::vec3>> polygonsInPlane(testing::Rng& rng, glm::vec3 origin,
                                                    glm::vec3 u, glm::vec3 v, int count,
                                                    float radius, float spread, bool mix_quads) {
  std::vector<std::vector<glm::vec3>> out;
  for (int i = 0; i < count; ++i) {
    const int sides = mix_quads && i % 2 == 1 ? 4 : 3;
    const glm::vec3 c =
        origin + rng.uniform(-spread, spread) * u + rng.uniform(-spread, spread) * v;
    const float r = radius * rng.uniform(0.85f, 1.0f);
    const double start = rng.uniform() * 2 * kPi;
    std::vector<glm::vec3> p;
    for (int k = 0; k < sides; ++k) {
      const double a = start + (k + rng.uniform(-0.15f, 0.15f)) * (2 * kPi / sides);
      p.push_back(c + r * static_cast<float>(std::cos(a)) * u +
                  r * static_cast<float>(std::sin(a)) * v);
    }
    out.push_back(p);
  }
  return out;
}

// The tilted plane of the perspective families: through the origin, normal (0.3, 0.5, 1).
void tiltedPlane(glm::vec3* u, glm::vec3* v) {
  const glm::vec3 n = glm::normalize(glm::vec3(0.3f, 0.5f, 1.0f));
  *u = glm::normalize(glm::cross(glm::vec3(0, 1, 0), n));
  *v = glm::cross(n, *u);
}

TEST_P(Coplanar, IdenticalTrianglesFirstSubmittedWins) {
  testing::Rng rng(601);
  glm::vec3 u, v;
  tiltedPlane(&u, &v);
  const auto one = polygonsInPlane(rng, {0, 0, 0}, u, v, 1, 1.2f, 0.0f, false);
  checkFamilyFor({"identical triangles, tilted, perspective", perspectiveCamera(),
                  std::vector<std::vector<glm::vec3>>(5, one[0])},
                 findAlgorithm(GetParam()));
}

TEST_P(Coplanar, IdenticalQuadsFirstSubmittedWins) {
  testing::Rng rng(602);
  glm::vec3 u, v;
  tiltedPlane(&u, &v);
  const auto quads = polygonsInPlane(rng, {0, 0, 0}, u, v, 2, 1.2f, 0.0f, true);
  checkFamilyFor({"identical quads, tilted, perspective", perspectiveCamera(),
                  std::vector<std::vector<glm::vec3>>(5, quads[1])},
                 findAlgorithm(GetParam()));
}

TEST_P(Coplanar, OverlappingFacingTheCameraFirstSubmittedWins) {
  // World plane z = 0.25 under the orthographic pixel camera: constant window depth.
  testing::Rng rng(603);
  const glm::vec3 origin(kSize * 0.5f + 0.37f, kSize * 0.5f - 0.21f, 0.25f);
  checkFamilyFor(
      {"overlapping triangles and quads facing an ortho camera", testing::pixelCamera(kSize, kSize),
       polygonsInPlane(rng, origin, {1, 0, 0}, {0, 1, 0}, 5, 50.0f, 8.0f, true)},
      findAlgorithm(GetParam()));
}

TEST_P(Coplanar, OverlappingTiltedNearerFloatDepthWinsTiesFirstSubmitted) {
  testing::Rng rng(604);
  glm::vec3 u, v;
  tiltedPlane(&u, &v);
  checkFamilyFor({"overlapping triangles and quads, tilted, perspective", perspectiveCamera(),
                  polygonsInPlane(rng, {0, 0, 0}, u, v, 5, 1.2f, 0.2f, true), /*exact_ties=*/false},
                 findAlgorithm(GetParam()));
}

TEST_P(Coplanar, SameTriangleInAnyVertexOrderFirstSubmittedWins) {
  testing::Rng rng(605);
  glm::vec3 u, v;
  tiltedPlane(&u, &v);
  const std::vector<glm::vec3> t = polygonsInPlane(rng, {0, 0, 0}, u, v, 1, 1.2f, 0.0f, false)[0];
  // The 6 orders of the same three points (3 rotations, then the 3 reversed); stacks take
  // the first 2..5 of them.
  const std::vector<std::vector<glm::vec3>> orders = {{t[0], t[1], t[2]}, {t[1], t[2], t[0]},
                                                      {t[2], t[0], t[1]}, {t[0], t[2], t[1]},
                                                      {t[2], t[1], t[0]}, {t[1], t[0], t[2]}};
  checkFamilyFor(
      {"one triangle in different vertex orders, tilted, perspective", perspectiveCamera(), orders},
      findAlgorithm(GetParam()));
}

HSR_INSTANTIATE_FOR_ALGORITHMS_WITH(Coplanar, kTieRule);

}  // namespace
}  // namespace hsr

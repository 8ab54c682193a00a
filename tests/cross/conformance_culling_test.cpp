// Conformance, docs/testing.md rows 7 and 8.
//  - Row 7, the back-face culling matrix: {CCW, CW front} x {cull none, back, front, both} x
//    {perspective, ortho} x {normal, mirrored (x -> -x, det < 0)} on a mesh with random and
//    inconsistent winding; each triangle must be culled exactly when the rule says, by both
//    facing tests (GL's window area and the notes' eye plane).
//  - Row 8, the near plane and behind the eye: 1, 2 or 3 vertices at w <= 0; a vertex 30000
//    units beyond each of the 26 clip directions, then 2 and 3 of them; huge quads through and
//    past the eye. No crash, no NaN, depth in [0,1]; fully behind draws 0 pixels; partly
//    behind matches an analytic (double) clip on every pixel > 1 px from the clipped outline.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <set>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "hsr/render.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

using testing::Rng;

using Tri = std::array<glm::vec3, 3>;

std::string str(const glm::vec3& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", p.x, p.y, p.z);
  return buf;
}
std::string str(const Tri& t) { return str(t[0]) + " " + str(t[1]) + " " + str(t[2]); }

// Window position (GL: y up, pixels, origin bottom-left) of a world point, in double, with the
// camera's own matrices. Returns false when the point is not in front of the eye.
bool projectToWindow(const Camera& cam, const glm::vec3& p, glm::dvec2* out) {
  const glm::dmat4 m = glm::dmat4(cam.projection()) * glm::dmat4(cam.view());
  const glm::dvec4 c = m * glm::dvec4(glm::dvec3(p), 1.0);
  if (!(c.w > 0.0)) return false;
  *out = {(c.x / c.w * 0.5 + 0.5) * cam.width, (c.y / c.w * 0.5 + 0.5) * cam.height};
  return true;
}

// =============================================================================================
// Row 7: the culling matrix.

struct CullMesh {
  std::vector<Tri> tris;  // as submitted (random vertex order per triangle)
};

// A height field of n x n quads over [-1.6, 1.6]^2 around z = 0 (heights in [-0.15, 0.15]),
// every quad split along a random diagonal, every triangle given a random vertex order (so
// the winding is inconsistent across the mesh). Seen from +z, it never folds over itself.
CullMesh makeCullMesh(std::uint64_t seed, int n) {
  Rng rng(seed);
  std::vector<glm::vec3> grid((n + 1) * (n + 1));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      grid[j * (n + 1) + i] = {-1.6f + 3.2f * i / n, -1.6f + 3.2f * j / n,
                               rng.uniform(-0.15f, 0.15f)};
  CullMesh m;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const glm::vec3 a = grid[j * (n + 1) + i], b = grid[j * (n + 1) + i + 1];
      const glm::vec3 c = grid[(j + 1) * (n + 1) + i + 1], d = grid[(j + 1) * (n + 1) + i];
      Tri t0, t1;
      if (rng.next() & 1) {
        t0 = {a, b, c};
        t1 = {a, c, d};
      } else {
        t0 = {a, b, d};
        t1 = {b, c, d};
      }
      for (Tri* t : {&t0, &t1}) {
        if (rng.next() & 1) std::swap((*t)[1], (*t)[2]);   // reverse the winding
        const int rot = static_cast<int>(rng.next() % 3);  // and rotate the start vertex
        std::rotate(t->begin(), t->begin() + rot, t->end());
        m.tris.push_back(*t);
      }
    }
  }
  return m;
}

Camera cullCamera(bool ortho) {
  Camera c;
  c.width = 256;
  c.height = 256;
  c.eye = {0.0f, 0.0f, 5.0f};
  c.target = {0.0f, 0.0f, 0.0f};
  c.up = {0.0f, 1.0f, 0.0f};
  c.fov_deg = 45.0f;
  c.ortho = ortho;
  c.ortho_half_height = 2.0f;
  c.near = 0.5f;
  c.far = 20.0f;
  return c;
}

// Doubled signed area in GL's y-up window space (> 0: counter-clockwise on screen).
double windowArea(const Camera& cam, const Tri& t) {
  glm::dvec2 w[3];
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(projectToWindow(cam, t[k], &w[k]));
  return (w[1].x - w[0].x) * (w[2].y - w[0].y) - (w[1].y - w[0].y) * (w[2].x - w[0].x);
}

bool ruleCulls(CullMode mode, bool front) {
  switch (mode) {
    case CullMode::None:
      return false;
    case CullMode::Back:
      return !front;
    case CullMode::Front:
      return front;
    case CullMode::FrontAndBack:
      return true;
  }
  return false;
}

class ConformanceCulling : public testing::EveryAlgorithm {};

TEST_P(ConformanceCulling, Matrix32WithBothFacingTests) {
  const std::uint64_t seed = 0xC0111u;
  const int n = 12;  // 288 triangles, each about 100-200 pixels
  const CullMesh mesh = makeCullMesh(seed, n);
  const CullMode modes[4] = {CullMode::None, CullMode::Back, CullMode::Front,
                             CullMode::FrontAndBack};
  const char* mode_names[4] = {"none", "back", "front", "both"};
  int combinations = 0;
  std::uint64_t triangle_checks = 0;
  for (int ortho = 0; ortho < 2; ++ortho) {
    const Camera cam = cullCamera(ortho != 0);
    // Screen orientation of each triangle as submitted (unmirrored), in double.
    std::vector<int> ccw(mesh.tris.size());
    int n_ccw = 0;
    for (std::size_t i = 0; i < mesh.tris.size(); ++i) {
      const double a = windowArea(cam, mesh.tris[i]);
      ASSERT_GT(std::abs(a), 20.0) << "test setup: triangle " << i << " is nearly edge-on";
      ccw[i] = a > 0.0;
      n_ccw += ccw[i];
    }
    ASSERT_GT(n_ccw, 50) << "the mesh must mix windings";
    ASSERT_LT(n_ccw, static_cast<int>(mesh.tris.size()) - 50) << "the mesh must mix windings";
    for (int mirrored = 0; mirrored < 2; ++mirrored) {
      Scene scene;
      scene.addMaterial({});
      std::vector<Tri> submitted = mesh.tris;
      for (Tri& t : submitted)
        for (glm::vec3& p : t) p.x = mirrored ? -p.x : p.x;
      for (const Tri& t : submitted) scene.addPolygonVertices({t[0], t[1], t[2]}, 0);
      for (std::size_t i = 0; i < submitted.size(); ++i) {
        // A mirrored transform flips the facing (pbrt: reverseOrientation ^ swapsHandedness);
        // check this file's own geometry agrees before using it as the expectation.
        const bool ccw_here = (windowArea(cam, submitted[i]) > 0.0);
        ASSERT_EQ(ccw_here, mirrored ? !ccw[i] : static_cast<bool>(ccw[i])) << "triangle " << i;
      }
      for (int ff = 0; ff < 2; ++ff) {
        for (int cm = 0; cm < 4; ++cm) {
          combinations++;
          std::set<PolygonId> expected;
          for (std::size_t i = 0; i < submitted.size(); ++i) {
            const bool screen_ccw = mirrored ? !ccw[i] : static_cast<bool>(ccw[i]);
            const bool front = (ff == 0) ? screen_ccw : !screen_ccw;
            if (!ruleCulls(modes[cm], front)) expected.insert(static_cast<PolygonId>(i));
          }
          for (int ft = 0; ft < 2; ++ft) {
            RenderOptions o = options();
            o.cull = modes[cm];
            o.front_face = ff == 0 ? FrontFace::Ccw : FrontFace::Cw;
            o.facing_test = ft == 0 ? FacingTest::WindowArea : FacingTest::EyePlane;
            o.threads = 2;
            const Frame f = render(scene, cam, o);
            std::set<PolygonId> present;
            for (PolygonId id : f.ids)
              if (id != kNoPolygon) present.insert(id);
            const std::string ctx = std::string(ortho ? "ortho" : "perspective") +
                                    (mirrored ? ", mirrored" : ", normal") + ", front " +
                                    (ff == 0 ? "ccw" : "cw") + ", cull " + mode_names[cm] +
                                    ", facing " + (ft == 0 ? "window" : "eye") + ", seed " +
                                    std::to_string(seed);
            int reported = 0;
            for (std::size_t i = 0; i < submitted.size(); ++i) {
              const PolygonId id = static_cast<PolygonId>(i);
              const bool want = expected.count(id) != 0, got = present.count(id) != 0;
              triangle_checks++;
              if (want != got && reported++ < 5)
                ADD_FAILURE() << ctx << ": triangle " << i << " " << str(submitted[i])
                              << (want ? " should be drawn but is missing"
                                       : " should be culled but is drawn");
            }
            EXPECT_EQ(present, expected) << ctx;
            EXPECT_EQ(f.stats.culled_backface, submitted.size() - expected.size()) << ctx;
          }
        }
      }
    }
  }
  std::printf(
      "[conformance culling] %d combinations x 2 facing tests, %zu triangles each, "
      "%llu triangle checks\n",
      combinations, mesh.tris.size(), (unsigned long long)triangle_checks);
  EXPECT_EQ(combinations, 32);
}

// =============================================================================================
// Row 8: near plane and behind the eye.

// Camera at the origin looking down -z: world coordinates are eye coordinates.
Camera nearCamera() {
  Camera c;
  c.width = 128;
  c.height = 128;
  c.eye = {0.0f, 0.0f, 0.0f};
  c.target = {0.0f, 0.0f, -1.0f};
  c.up = {0.0f, 1.0f, 0.0f};
  c.fov_deg = 60.0f;
  c.near = 0.1f;
  c.far = 100.0f;
  return c;
}

struct NearResult {
  std::uint64_t drawn = 0;       // pixels with an id
  std::uint64_t bad_depth = 0;   // NaN or outside [0,1]
  std::uint64_t overdraw = 0;    // pixels written more than once
  std::uint64_t compared = 0;    // unambiguous pixels
  std::uint64_t mismatched = 0;  // unambiguous pixels that disagree with the analytic clip
  std::string first;             // first mismatch
};

// Renders one scene (depth test off, so Frame::overdraw counts every fragment; an algorithm
// with no depth test, a painter, counts every fragment it paints anyway) and checks the
// invariants every case must keep.
Frame renderNear(const std::string& algorithm, const Scene& scene, NearResult& r) {
  RenderOptions o = testing::optionsFor(algorithm);
  if (findAlgorithm(algorithm).has(kDepthFuncs)) o.depth_test = false;
  o.threads = 2;
  Frame f = render(scene, nearCamera(), o);
  for (std::size_t k = 0; k < f.ids.size(); ++k) {
    const float z = f.depth[k];
    if (!(z >= 0.0f && z <= 1.0f)) r.bad_depth++;
    if (f.ids[k] != kNoPolygon) r.drawn++;
    if (f.overdraw[k] > 1) r.overdraw++;
  }
  return f;
}

// The analytic clip, in double: the eye-space polygon cut by the near and far planes, then
// projected to GL window space (y up).
std::vector<glm::dvec2> analyticClip(const std::vector<glm::vec3>& poly_world, const Camera& cam) {
  const glm::dmat4 view = glm::dmat4(cam.view());
  std::vector<glm::dvec3> poly;
  for (const glm::vec3& p : poly_world)
    poly.push_back(glm::dvec3(view * glm::dvec4(glm::dvec3(p), 1.0)));
  auto cut = [&](double plane_z, bool keep_below) {  // keep z <= plane_z (or >=)
    std::vector<glm::dvec3> out;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const glm::dvec3 a = poly[i], b = poly[(i + 1) % poly.size()];
      const double da = keep_below ? plane_z - a.z : a.z - plane_z;
      const double db = keep_below ? plane_z - b.z : b.z - plane_z;
      if (da >= 0.0) out.push_back(a);
      if ((da >= 0.0) != (db >= 0.0)) out.push_back(a + (da / (da - db)) * (b - a));
    }
    poly = out;
  };
  cut(-static_cast<double>(cam.near), true);
  cut(-static_cast<double>(cam.far), false);
  const double f = 1.0 / std::tan(glm::radians(static_cast<double>(cam.fov_deg)) * 0.5);
  const double aspect = static_cast<double>(cam.width) / cam.height;
  std::vector<glm::dvec2> win;
  for (const glm::dvec3& p : poly) {
    const double xn = f / aspect * p.x / -p.z, yn = f * p.y / -p.z;
    win.push_back({(xn * 0.5 + 0.5) * cam.width, (yn * 0.5 + 0.5) * cam.height});
  }
  return win;
}

// +1 surely inside, -1 surely outside, 0 within `margin` px of the outline (not judged).
int classifyConvex(const std::vector<glm::dvec2>& poly, glm::dvec2 p, double margin) {
  if (poly.size() < 3) return -1;
  double area2 = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
    area2 += a.x * b.y - b.x * a.y;
  }
  double dist = 1e300;  // distance to the outline
  bool inside = true;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
    const glm::dvec2 e = b - a, ap = p - a;
    const double len2 = glm::dot(e, e);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(ap, e) / len2, 0.0, 1.0) : 0.0;
    dist = std::min(dist, glm::length(ap - t * e));
    const double cross = e.x * ap.y - e.y * ap.x;
    if ((area2 > 0.0 && cross < 0.0) || (area2 < 0.0 && cross > 0.0)) inside = false;
  }
  // A polygon whose area is under pi cannot hold a disc of radius 1: nothing in it is > 1 px
  // from its outline (this also covers polygons that project to a line).
  if (std::abs(area2) * 0.5 < 3.14159265358979 * margin * margin) inside = false;
  if (dist <= margin) return 0;
  return inside ? 1 : -1;
}

void compareWithAnalytic(const Frame& f, const std::vector<glm::vec3>& poly, NearResult& r,
                         const std::string& ctx) {
  const Camera cam = nearCamera();
  const std::vector<glm::dvec2> clipped = analyticClip(poly, cam);
  for (int row = 0; row < f.height; ++row) {
    for (int col = 0; col < f.width; ++col) {
      const int where = classifyConvex(clipped, {col + 0.5, f.height - row - 0.5}, 1.0);
      if (where == 0) continue;
      r.compared++;
      const bool drawn = f.ids[static_cast<std::size_t>(row) * f.width + col] != kNoPolygon;
      if (drawn != (where > 0)) {
        r.mismatched++;
        if (r.first.empty())
          r.first =
              ctx + ": pixel col " + std::to_string(col) + " row " + std::to_string(row) +
              (drawn ? " drawn, outside the analytic clip" : " missing, inside the analytic clip");
      }
    }
  }
}

// Triangles with 1, 2 or 3 vertices at w <= 0 (behind the eye or on its plane, some exactly at
// w = 0) and the rest in front with w in [0.2, 16].
class ConformanceNearPlane : public testing::EveryAlgorithm {};

TEST_P(ConformanceNearPlane, BehindTheEye) {
  const std::uint64_t seed = 0xBE41Du;
  Rng rng(seed);
  // Half of them in the sanitizer leg's tier (testing::legCases)
  const int per_k = testing::legCases(300 * testing::countScale(), 2);
  const double tan_half = std::tan(glm::radians(30.0));
  NearResult r;
  std::uint64_t cases = 0, fully_behind_drawn = 0, partly_drawn_cases = 0;
  std::string first_ghost;
  for (int behind = 1; behind <= 3; ++behind) {
    for (int c = 0; c < per_k; ++c) {
      Tri t;
      for (int v = 0; v < 3; ++v) {
        if (v < behind) {
          // w = -z_eye <= 0: one case in 8 exactly on the eye plane.
          const float z = (rng.next() % 8 == 0) ? 0.0f : rng.uniform(0.0f, 6.0f);
          t[v] = {rng.uniform(-4.0f, 4.0f), rng.uniform(-4.0f, 4.0f), z};
        } else {
          const float w = rng.uniform(0.2f, 16.0f);
          const float s = static_cast<float>(tan_half) * w * 1.3f;
          t[v] = {rng.uniform(-s, s), rng.uniform(-s, s), -w};
        }
      }
      if (rng.next() & 1) std::swap(t[1], t[2]);
      const int rot = static_cast<int>(rng.next() % 3);
      std::rotate(t.begin(), t.begin() + rot, t.end());
      Scene scene;
      scene.addMaterial({});
      scene.addPolygonVertices({t[0], t[1], t[2]}, 0);
      const std::uint64_t drawn_before = r.drawn;
      const Frame f = renderNear(GetParam(), scene, r);
      cases++;
      const std::string ctx = "seed " + std::to_string(seed) + ", " + std::to_string(behind) +
                              " behind, triangle " + str(t);
      if (behind == 3) {
        if (r.drawn != drawn_before) {
          fully_behind_drawn++;
          if (first_ghost.empty()) first_ghost = ctx;
        }
      } else {
        if (r.drawn != drawn_before) partly_drawn_cases++;
        compareWithAnalytic(f, {t[0], t[1], t[2]}, r, ctx);
      }
    }
  }
  std::printf(
      "[conformance near] behind the eye (seed %llu): %llu triangles, %llu partly-behind "
      "ones drawing pixels, %llu unambiguous pixels compared, %llu mismatched, %llu "
      "overdrawn, %llu bad depths, %llu fully-behind ones drawing\n",
      (unsigned long long)seed, (unsigned long long)cases, (unsigned long long)partly_drawn_cases,
      (unsigned long long)r.compared, (unsigned long long)r.mismatched,
      (unsigned long long)r.overdraw, (unsigned long long)r.bad_depth,
      (unsigned long long)fully_behind_drawn);
  EXPECT_EQ(fully_behind_drawn, 0u) << "first: " << first_ghost;
  EXPECT_EQ(r.mismatched, 0u) << "first: " << r.first;
  EXPECT_EQ(r.overdraw, 0u);
  EXPECT_EQ(r.bad_depth, 0u);
  EXPECT_GT(partly_drawn_cases, static_cast<std::uint64_t>(per_k));  // the test draws something
}

// Huge quads: a floor under the eye reaching behind it and past the far plane, and a plane
// through the eye itself (which projects to a line: nothing > 1 px from it may be drawn).
TEST_P(ConformanceNearPlane, HugeQuadsPastAndThroughTheEye) {
  struct Case {
    const char* name;
    std::vector<glm::vec3> quad;
  };
  const Case cases[] = {
      {"floor y=-1 from z=+1000 to z=-1000",
       {{-1000.0f, -1.0f, 1000.0f},
        {1000.0f, -1.0f, 1000.0f},
        {1000.0f, -1.0f, -1000.0f},
        {-1000.0f, -1.0f, -1000.0f}}},
      {"wall x=0.5 from z=+1000 to z=-1000",
       {{0.5f, -1000.0f, 1000.0f},
        {0.5f, -1000.0f, -1000.0f},
        {0.5f, 1000.0f, -1000.0f},
        {0.5f, 1000.0f, 1000.0f}}},
      {"plane y=0 through the eye",
       {{-1000.0f, 0.0f, 1000.0f},
        {1000.0f, 0.0f, 1000.0f},
        {1000.0f, 0.0f, -1000.0f},
        {-1000.0f, 0.0f, -1000.0f}}},
      {"plane y=z/2 through the eye",
       {{-1000.0f, 500.0f, 1000.0f},
        {1000.0f, 500.0f, 1000.0f},
        {1000.0f, -500.0f, -1000.0f},
        {-1000.0f, -500.0f, -1000.0f}}},
  };
  NearResult r;
  for (const Case& c : cases) {
    for (int reversed = 0; reversed < 2; ++reversed) {
      std::vector<glm::vec3> q = c.quad;
      if (reversed) std::reverse(q.begin(), q.end());
      Scene scene;
      scene.addMaterial({});
      scene.addPolygonVertices(std::span<const glm::vec3>(q), 0);
      NearResult one;
      const Frame f = renderNear(GetParam(), scene, one);
      compareWithAnalytic(f, q, one, c.name);
      std::printf(
          "[conformance near] %s%s: %llu pixels drawn, %llu unambiguous compared, "
          "%llu mismatched, %llu overdrawn\n",
          c.name, reversed ? " (reversed)" : "", (unsigned long long)one.drawn,
          (unsigned long long)one.compared, (unsigned long long)one.mismatched,
          (unsigned long long)one.overdraw);
      EXPECT_EQ(one.mismatched, 0u) << one.first;
      EXPECT_EQ(one.overdraw, 0u) << c.name;
      EXPECT_EQ(one.bad_depth, 0u) << c.name;
    }
  }
}

// One, two and three vertices 30000 units beyond each of the 26 clip directions (x beyond
// left/right, y beyond bottom/top, z beyond far or behind the eye), the other vertices in
// front with w in [0.2, 16]. No crash, no NaN, depth in [0,1], fans written exactly once; and
// a triangle whose three vertices lie behind the eye, or beyond one same side plane, draws 0.
TEST_P(ConformanceNearPlane, Far30000Beyond26Directions) {
  const std::uint64_t seed = 0x30000u;
  Rng rng(seed);
  std::vector<glm::vec3> dirs;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (dx || dy || dz) dirs.push_back(glm::vec3(float(dx), float(dy), float(dz)));
  ASSERT_EQ(dirs.size(), 26u);
  const Camera cam = nearCamera();
  const double tan_half = std::tan(glm::radians(30.0));
  auto inside = [&] {
    const float w = rng.uniform(0.2f, 16.0f);
    const float s = static_cast<float>(tan_half) * w * 0.9f;
    return glm::vec3(rng.uniform(-s, s), rng.uniform(-s, s), -w);
  };
  auto outside = [&](const glm::vec3& d) {
    // Clip direction d: +x right, +y top, +z beyond far (eye z more negative), -z behind.
    return glm::vec3(30000.0f * d.x, 30000.0f * d.y, -5.0f - 30000.0f * d.z);
  };
  NearResult r;
  std::uint64_t cases[4] = {0, 0, 0, 0}, must_be_empty = 0, empty_but_drawn = 0;
  std::string first_bad;
  const glm::dmat4 mvp = glm::dmat4(cam.projection()) * glm::dmat4(cam.view());
  auto run = [&](int out_count, const Tri& t) {
    Scene scene;
    scene.addMaterial({});
    scene.addPolygonVertices({t[0], t[1], t[2]}, 0);
    const std::uint64_t drawn_before = r.drawn, bad_before = r.bad_depth, over_before = r.overdraw;
    renderNear(GetParam(), scene, r);
    cases[out_count]++;
    const std::string ctx = "seed " + std::to_string(seed) + ", " + std::to_string(out_count) +
                            " out, triangle " + str(t);
    if ((r.bad_depth != bad_before || r.overdraw != over_before) && first_bad.empty())
      first_bad = ctx;
    // Entirely behind the eye, or entirely beyond one of the 6 planes (in double, with room).
    bool empty = true;
    for (const glm::vec3& p : t) empty = empty && p.z > 0.0f;
    for (int plane = 0; plane < 6 && !empty; ++plane) {
      bool all_out = true;
      for (const glm::vec3& p : t) {
        const glm::dvec4 c = mvp * glm::dvec4(glm::dvec3(p), 1.0);
        const double v = plane < 3 ? c[plane] : -c[plane - 3];  // +x,+y,+z, then -x,-y,-z
        all_out = all_out && v - c.w > 1e-3 * (std::abs(v) + std::abs(c.w));
      }
      empty = all_out;
    }
    if (empty) {
      must_be_empty++;
      if (r.drawn != drawn_before) {
        empty_but_drawn++;
        if (first_bad.empty()) first_bad = ctx + " (must draw nothing)";
      }
    }
  };
  // One out: each direction at each vertex slot.
  for (const glm::vec3& d : dirs)
    for (int slot = 0; slot < 3; ++slot) {
      Tri t{inside(), inside(), inside()};
      t[slot] = outside(d);
      run(1, t);
    }
  // Two out: every ordered pair of directions.
  for (const glm::vec3& d1 : dirs)
    for (const glm::vec3& d2 : dirs) {
      Tri t{outside(d1), outside(d2), inside()};
      std::rotate(t.begin(), t.begin() + static_cast<int>(rng.next() % 3), t.end());
      run(2, t);
    }
  // Three out: all 26^3 triples at intensity >= 3, a fixed random sample of 2000 otherwise (250
  // in the sanitizer leg's tier, testing::legCases).
  if (testing::testIntensity() >= 3) {
    for (const glm::vec3& d1 : dirs)
      for (const glm::vec3& d2 : dirs)
        for (const glm::vec3& d3 : dirs) run(3, Tri{outside(d1), outside(d2), outside(d3)});
  } else {
    const int samples = testing::legCases(2000, 8);
    for (int i = 0; i < samples; ++i)
      run(3, Tri{outside(dirs[rng.next() % 26]), outside(dirs[rng.next() % 26]),
                 outside(dirs[rng.next() % 26])});
  }
  std::printf(
      "[conformance near] 30000 beyond 26 directions (seed %llu): %llu/%llu/%llu "
      "triangles with 1/2/3 out, %llu pixels drawn, %llu bad depths, %llu overdrawn, "
      "%llu must draw nothing, %llu of them drew\n",
      (unsigned long long)seed, (unsigned long long)cases[1], (unsigned long long)cases[2],
      (unsigned long long)cases[3], (unsigned long long)r.drawn, (unsigned long long)r.bad_depth,
      (unsigned long long)r.overdraw, (unsigned long long)must_be_empty,
      (unsigned long long)empty_but_drawn);
  EXPECT_EQ(r.bad_depth, 0u) << first_bad;
  EXPECT_EQ(r.overdraw, 0u) << first_bad;
  EXPECT_EQ(empty_but_drawn, 0u) << first_bad;
  EXPECT_GT(must_be_empty, 0u);
  EXPECT_GT(r.drawn, 0u);
}

HSR_INSTANTIATE_FOR_EVERY_ALGORITHM(ConformanceCulling);
HSR_INSTANTIATE_FOR_EVERY_ALGORITHM(ConformanceNearPlane);

}  // namespace
}  // namespace hsr

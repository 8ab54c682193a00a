#pragma once
// The random scenes of docs/testing.md row 4 (reused by rows 5 and 17): 50-500 triangles in the
// cube [-1.6, 1.6]^3 seen by a perspective camera from 4.2-5.5 units away, so that every
// vertex lies in front of the eye and between near and far (no clipping but the viewport's).
// Besides random triangles of every size (slivers included), each scene holds
//   - 2-5 interpenetrating pairs: two triangles through one point in different planes;
//   - one 3-polygon cyclic overlap: three planar quads ("sticks", as the built-in "cyclic"),
//     each over the next, facing the camera within about 35 degrees;
//   - one coplanar overlapping pair (same plane, partly overlapping), facing the camera;
//   - one exact duplicate (same vertices, same order) of an earlier triangle, drawn later;
//   - 1-3 convex planar polygons with 4-6 vertices.
// Everything derives from the seed (SplitMix64 only), so a seed names a scene everywhere.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "hsr/camera.hpp"
#include "hsr/scene.hpp"
#include "test_util.hpp"

namespace hsr::testing {

namespace detail_scenes {

constexpr double kPi = 3.14159265358979323846;

inline glm::vec3 randomUnit(Rng& rng) {
  for (;;) {
    const glm::vec3 v(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    const float l2 = glm::dot(v, v);
    if (l2 > 0.01f && l2 <= 1.0f) return v / std::sqrt(l2);
  }
}

inline glm::vec3 randomInCube(Rng& rng, float h) {
  return {rng.uniform(-h, h), rng.uniform(-h, h), rng.uniform(-h, h)};
}

// Two unit vectors spanning the plane with normal n.
inline void planeBasis(const glm::vec3& n, glm::vec3* u, glm::vec3* v) {
  const glm::vec3 a = std::abs(n.x) < 0.6f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  *u = glm::normalize(glm::cross(n, a));
  *v = glm::cross(n, *u);
}

// A normal that faces `eye` from `c` within about 35 degrees.
inline glm::vec3 facing(Rng& rng, const glm::vec3& c, const glm::vec3& eye) {
  return glm::normalize(glm::normalize(eye - c) + 0.6f * rng.uniform() * randomUnit(rng));
}

// A triangle around c in the plane (u, v): three points on a circle of radius r, spread
// around it, so c lies inside.
inline std::array<glm::vec3, 3> triangleAround(Rng& rng, const glm::vec3& c, const glm::vec3& u,
                                               const glm::vec3& v, float r) {
  std::array<glm::vec3, 3> t;
  const double start = rng.uniform() * 2 * kPi;
  for (int k = 0; k < 3; ++k) {
    const double a = start + k * (2 * kPi / 3) + rng.uniform(-0.4f, 0.4f);
    const float rk = r * rng.uniform(0.7f, 1.3f);
    t[k] = c + rk * static_cast<float>(std::cos(a)) * u + rk * static_cast<float>(std::sin(a)) * v;
  }
  return t;
}

}  // namespace detail_scenes

// The camera of row-4 scene `seed`: perspective, 256x256 unless asked otherwise.
inline Camera agreementCamera(std::uint64_t seed, int width = 256, int height = 256) {
  using namespace detail_scenes;
  Rng rng(seed * 0x9E3779B97F4A7C15ull + 0x5CA1AB1Eull);
  Camera c;
  c.width = width;
  c.height = height;
  glm::vec3 dir;
  do {
    dir = randomUnit(rng);
  } while (std::abs(dir.y) > 0.9f);  // keep up = +y usable
  const float distance = rng.uniform(4.2f, 5.5f);
  c.eye = dir * distance;
  c.target = randomInCube(rng, 0.2f);
  c.up = {0.0f, 1.0f, 0.0f};
  c.fov_deg = rng.uniform(40.0f, 55.0f);
  c.ortho = false;
  // Scene points lie within 2.8 of the origin: nearest eye depth > 4.2 - 0.35 - 2.8 > 1,
  // farthest < 5.5 + 0.35 + 2.8 < distance + 3.5.
  c.near = 0.5f;
  c.far = distance + 3.5f;
  return c;
}

inline Scene agreementScene(std::uint64_t seed) {
  using namespace detail_scenes;
  Rng rng(seed * 0xD1B54A32D192ED03ull + 0x0123456789ABCDEFull);
  const glm::vec3 eye = agreementCamera(seed).eye;
  Scene s;
  s.name = "agreement:" + std::to_string(seed);
  for (int m = 0; m < 8; ++m)
    s.addMaterial(
        {{rng.uniform(0.2f, 1.0f), rng.uniform(0.2f, 1.0f), rng.uniform(0.2f, 1.0f)}, 1.0f});
  auto material = [&] { return static_cast<std::uint32_t>(rng.next() % 8); };

  // 50-500 triangles in all (the features below add up to about 30 beyond the target).
  const int target_triangles = 50 + static_cast<int>(rng.next() % 421);
  int triangles = 0;
  int polygons_in_object = 0;
  std::vector<std::array<glm::vec3, 3>> plain;  // random triangles, for the duplicate

  auto beginObjectIfFull = [&] {
    if (polygons_in_object == 0 || polygons_in_object >= 48) {
      s.beginObject("part " + std::to_string(s.objects.size()));
      polygons_in_object = 0;
    }
  };
  auto addTriangle = [&](const std::array<glm::vec3, 3>& t) {
    beginObjectIfFull();
    s.addPolygonVertices({t[0], t[1], t[2]}, material());
    polygons_in_object++;
    triangles++;
  };
  auto addPolygon = [&](const std::vector<glm::vec3>& p) {
    beginObjectIfFull();
    s.addPolygonVertices(std::span<const glm::vec3>(p), material());
    polygons_in_object++;
    triangles += static_cast<int>(p.size()) - 2;
  };

  // Features, each due at a random point of the submission order.
  enum Feature { kPenetrating, kCyclic, kCoplanar, kConvex };
  struct Due {
    int at;
    Feature what;
  };
  std::vector<Due> due;
  const int pairs = 2 + static_cast<int>(rng.next() % 4);
  for (int i = 0; i < pairs; ++i) due.push_back({int(rng.next() % 40), kPenetrating});
  due.push_back({int(rng.next() % 40), kCyclic});
  due.push_back({int(rng.next() % 40), kCoplanar});
  const int convex = 1 + static_cast<int>(rng.next() % 3);
  for (int i = 0; i < convex; ++i) due.push_back({int(rng.next() % 40), kConvex});
  std::stable_sort(due.begin(), due.end(), [](const Due& a, const Due& b) { return a.at < b.at; });
  std::size_t next_due = 0;

  auto emitFeature = [&](Feature what) {
    switch (what) {
      case kPenetrating: {
        // Two triangles through c in different planes: they cross along a line through c.
        const glm::vec3 c = randomInCube(rng, 0.8f);
        const float r = rng.uniform(0.2f, 0.6f);
        for (int k = 0; k < 2; ++k) {
          glm::vec3 u, v;
          planeBasis(facing(rng, c, eye), &u, &v);
          addTriangle(triangleAround(rng, c, u, v, r));
        }
        break;
      }
      case kCyclic: {
        // The built-in "cyclic" sticks, scaled, turned to face the camera: at each corner the
        // stick that ends there lies over the one that starts there. No depth order exists.
        const glm::vec3 c = randomInCube(rng, 0.7f);
        const float scale = rng.uniform(0.3f, 0.6f);
        const glm::vec3 n = facing(rng, c, eye);
        glm::vec3 u, v;
        planeBasis(n, &u, &v);
        constexpr float kCircumradius = 0.95f, kOverhang = 0.55f, kHalfWidth = 0.14f, kRise = 0.16f;
        const double turn = rng.uniform() * 2 * kPi;
        auto local = [&](double x, double y, double z) {
          return c + scale * (static_cast<float>(x) * u + static_cast<float>(y) * v +
                              static_cast<float>(z) * n);
        };
        for (int i = 0; i < 3; ++i) {
          const double a0 = turn + i * (2 * kPi / 3), a1 = turn + (i + 1) * (2 * kPi / 3);
          const double ax = kCircumradius * std::cos(a0), ay = kCircumradius * std::sin(a0);
          const double bx = kCircumradius * std::cos(a1), by = kCircumradius * std::sin(a1);
          const double len = std::hypot(bx - ax, by - ay);
          const double dx = (bx - ax) / len, dy = (by - ay) / len;
          const double lx = -dy, ly = dx;  // left of the stick, in its plane
          const double sx = ax - dx * kOverhang, sy = ay - dy * kOverhang;
          const double ex = bx + dx * kOverhang, ey = by + dy * kOverhang;
          addPolygon({local(sx - lx * kHalfWidth, sy - ly * kHalfWidth, -kRise),
                      local(ex - lx * kHalfWidth, ey - ly * kHalfWidth, kRise),
                      local(ex + lx * kHalfWidth, ey + ly * kHalfWidth, kRise),
                      local(sx + lx * kHalfWidth, sy + ly * kHalfWidth, -kRise)});
        }
        break;
      }
      case kCoplanar: {
        // Two triangles in one plane, the second shifted within it: they partly overlap.
        const glm::vec3 c = randomInCube(rng, 0.9f);
        glm::vec3 u, v;
        planeBasis(facing(rng, c, eye), &u, &v);
        // Small: a float z-buffer z-fights on the overlap (its pixels are depth ties, so
        // ambiguous), and all of it must fit in row 4's 0.5 % cap (328 px at 256x256).
        const float r = rng.uniform(0.06f, 0.14f);
        const std::array<glm::vec3, 3> a = triangleAround(rng, c, u, v, r);
        const double angle = rng.uniform() * 2 * kPi;
        const float shift = r * rng.uniform(0.3f, 0.8f);
        const glm::vec3 d = shift * (static_cast<float>(std::cos(angle)) * u +
                                     static_cast<float>(std::sin(angle)) * v);
        addTriangle(a);
        addTriangle(triangleAround(rng, c + d, u, v, r));
        break;
      }
      case kConvex: {
        // A convex polygon: 4-6 points on a circle in a random plane, in angular order.
        const glm::vec3 c = randomInCube(rng, 0.9f);
        glm::vec3 u, v;
        planeBasis(randomUnit(rng), &u, &v);
        const float r = rng.uniform(0.1f, 0.4f);
        const int n = 4 + static_cast<int>(rng.next() % 3);
        std::vector<glm::vec3> p;
        const double start = rng.uniform() * 2 * kPi;
        for (int k = 0; k < n; ++k) {
          const double a = start + (k + 0.2 + 0.6 * rng.uniform()) * (2 * kPi / n);
          p.push_back(c + r * static_cast<float>(std::cos(a)) * u +
                      r * static_cast<float>(std::sin(a)) * v);
        }
        addPolygon(p);
        break;
      }
    }
  };

  // (addTriangle and emitFeature count the triangles: the loop's end is tested in its body, where
  // a reader and clang's loop analysis both see that it moves)
  for (int i = 0;; ++i) {
    if (triangles >= target_triangles - 1) break;
    while (next_due < due.size() && due[next_due].at <= i) emitFeature(due[next_due++].what);
    // A random triangle of any size (log-uniform, 0.04-0.6 units; about 3-40 px), slivers and
    // near edge-on ones included.
    const glm::vec3 c = randomInCube(rng, 1.0f);
    const float size = 0.04f * std::pow(15.0f, rng.uniform());
    std::array<glm::vec3, 3> t;
    for (glm::vec3& p : t) p = c + size * randomInCube(rng, 1.0f);
    addTriangle(t);
    plain.push_back(t);
  }
  while (next_due < due.size()) emitFeature(due[next_due++].what);
  // An exact duplicate of an earlier triangle, drawn last: a coplanar tie with identical
  // vertices (the tie rule's clean case).
  addTriangle(plain[rng.next() % plain.size()]);
  return s;
}

// A box turned about y by `turn` radians: six quads, counter-clockwise seen from outside.
inline void addBox(Scene& s, glm::vec3 c, glm::vec3 h, float turn, std::uint32_t material) {
  const float cs = std::cos(turn), sn = std::sin(turn);
  std::uint32_t v[8];
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 p(i & 1 ? h.x : -h.x, i & 2 ? h.y : -h.y, i & 4 ? h.z : -h.z);
    v[i] = s.addVertex(c + glm::vec3(p.x * cs + p.z * sn, p.y, -p.x * sn + p.z * cs));
  }
  s.addPolygon({v[0], v[4], v[6], v[2]}, material);  // -x
  s.addPolygon({v[1], v[3], v[7], v[5]}, material);  // +x
  s.addPolygon({v[0], v[1], v[5], v[4]}, material);  // -y
  s.addPolygon({v[2], v[6], v[7], v[3]}, material);  // +y
  s.addPolygon({v[0], v[2], v[3], v[1]}, material);  // -z
  s.addPolygon({v[4], v[5], v[7], v[6]}, material);  // +z
}

// Seeded boxes, some passing through others (junction lines).
inline Scene randomBoxes(std::uint64_t seed) {
  Rng rng(seed * 0x9E3779B97F4A7C15ull + 7);
  Scene s;
  for (int k = 0; k < 8; ++k) {
    s.addMaterial(
        {{rng.uniform(0.2f, 1.0f), rng.uniform(0.2f, 1.0f), rng.uniform(0.2f, 1.0f)}, 1.0f});
    s.beginObject("box " + std::to_string(k));
    addBox(s, {rng.uniform(-1.5f, 1.5f), rng.uniform(-1.0f, 1.0f), rng.uniform(-1.5f, 1.5f)},
           {rng.uniform(0.2f, 0.7f), rng.uniform(0.2f, 0.7f), rng.uniform(0.2f, 0.7f)},
           rng.uniform(0.0f, 3.0f), static_cast<std::uint32_t>(k));
  }
  return s;
}

}  // namespace hsr::testing

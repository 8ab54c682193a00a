// Built-in scenes: the lecture notes' classic cases (penetrating polygons, cyclic overlap,
// convex and non-convex solids, a transparent pane) and two scalable test scenes (a grid of
// UV spheres, a soup of random triangles). Fully deterministic: the only randomness is
// SplitMix64 and the only trigonometry is computed once per scene, so the same spec gives
// bit-identical positions and indices on every platform with the same libm.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/scene.hpp"
#include "core/color.hpp"
#include "core/random.hpp"

namespace hsr {
namespace {

constexpr double kPi = 3.14159265358979323846;
// The largest N accepted by spheres:N and soup:N:SEED (about 1.5 GiB of scene at the top).

// HSV (all in [0,1]) to linear RGB, for evenly spread bright colours.
glm::vec3 hsv(float h, float s, float v) { return detail::hsvToRgb(h, s, v); }

// ---------------------------------------------------------------------------------------
// Spec parsing

std::vector<std::string_view> splitSpec(std::string_view spec) {
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t colon = spec.find(':', start);
    parts.push_back(spec.substr(start, colon == std::string_view::npos ? colon : colon - start));
    if (colon == std::string_view::npos) break;
    start = colon + 1;
  }
  return parts;
}

// A count: decimal digits with an optional k (x1000) or M (x1000000) suffix, e.g. 250k, 1M.
std::uint64_t parseCount(std::string_view text, std::string_view spec, std::string_view what,
                         std::uint64_t max) {
  const auto bad = [&](const std::string& why) {
    return Error("scene '" + std::string(spec) + "': " + std::string(what) + " " + why);
  };
  std::uint64_t scale = 1;
  if (!text.empty() && (text.back() == 'k' || text.back() == 'K')) scale = 1000;
  if (!text.empty() && text.back() == 'M') scale = 1000000;
  if (scale != 1) text.remove_suffix(1);
  if (text.empty()) throw bad("is missing");
  std::uint64_t n = 0;
  for (char c : text) {
    if (c < '0' || c > '9') throw bad("'" + std::string(text) + "' is not a whole number");
    n = n * 10 + static_cast<std::uint64_t>(c - '0');
    if (n * scale > max) throw bad("is too large (at most " + std::to_string(max) + ")");
  }
  return n * scale;
}

std::uint64_t parseSeed(std::string_view text, std::string_view spec) {
  if (text.empty() || text.size() > 19)
    throw Error("scene '" + std::string(spec) + "': SEED must be a whole number of 1..19 digits");
  std::uint64_t n = 0;
  for (char c : text) {
    if (c < '0' || c > '9')
      throw Error("scene '" + std::string(spec) + "': SEED '" + std::string(text) +
                  "' is not a whole number");
    n = n * 10 + static_cast<std::uint64_t>(c - '0');
  }
  return n;
}

// ---------------------------------------------------------------------------------------
// Shapes

// A convex polyhedron given by its vertices and one outward normal per face: a face is the
// vertices that lie furthest along its normal, ordered counter-clockwise seen from outside.
void addConvexPolyhedron(Scene& scene, const std::vector<glm::vec3>& vertices,
                         const std::vector<glm::vec3>& face_normals, glm::vec3 offset,
                         std::uint32_t material) {
  std::vector<std::uint32_t> local(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i)
    local[i] = scene.addVertex(vertices[i] + offset);
  for (const glm::vec3& n : face_normals) {
    // Collect the face: the vertices at the maximal distance along n
    float best = -1e30f;
    for (const glm::vec3& v : vertices) best = std::max(best, glm::dot(v, n));
    std::vector<std::uint32_t> face;
    for (std::uint32_t i = 0; i < vertices.size(); ++i)
      if (glm::dot(vertices[i], n) > best - 1e-4f * std::abs(best)) face.push_back(i);
    // Order it counter-clockwise around n: angles in a basis (a, b) with a x b = n
    glm::vec3 c(0.0f);
    for (std::uint32_t i : face) c += vertices[i];
    c /= static_cast<float>(face.size());
    const glm::vec3 a = glm::normalize(vertices[face[0]] - c);
    const glm::vec3 b = glm::cross(glm::normalize(n), a);
    std::vector<std::pair<float, std::uint32_t>> by_angle;
    for (std::uint32_t i : face) {
      const glm::vec3 d = vertices[i] - c;
      by_angle.emplace_back(std::atan2(glm::dot(d, b), glm::dot(d, a)), local[i]);
    }
    std::sort(by_angle.begin(), by_angle.end());
    std::vector<std::uint32_t> ordered;
    for (const auto& [angle, v] : by_angle) ordered.push_back(v);
    scene.addPolygon(ordered, material);
  }
}

void addCube(Scene& scene, float half, glm::vec3 offset, std::uint32_t material) {
  std::vector<glm::vec3> v;
  for (int i = 0; i < 8; ++i)
    v.emplace_back(i & 1 ? half : -half, i & 2 ? half : -half, i & 4 ? half : -half);
  addConvexPolyhedron(scene, v,
                      {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}, offset,
                      material);
}

// A regular dodecahedron of circumradius `radius`: 12 pentagons (polygons stay polygons).
void addDodecahedron(Scene& scene, float radius, glm::vec3 offset, std::uint32_t material) {
  const float phi = 1.6180339887f, iphi = 1.0f / phi;
  std::vector<glm::vec3> v;
  for (int i = 0; i < 8; ++i) v.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
  for (int i = 0; i < 4; ++i) {
    const float s1 = i & 1 ? 1.0f : -1.0f, s2 = i & 2 ? 1.0f : -1.0f;
    v.emplace_back(0.0f, s1 * iphi, s2 * phi);
    v.emplace_back(s1 * iphi, s2 * phi, 0.0f);
    v.emplace_back(s1 * phi, 0.0f, s2 * iphi);
  }
  const float scale = radius / std::sqrt(3.0f);
  for (glm::vec3& p : v) p *= scale;
  // Face normals: the vertices of the dual icosahedron
  std::vector<glm::vec3> normals;
  for (int i = 0; i < 4; ++i) {
    const float s1 = i & 1 ? 1.0f : -1.0f, s2 = i & 2 ? 1.0f : -1.0f;
    normals.emplace_back(0.0f, s1 * phi, s2);
    normals.emplace_back(s1 * phi, s2, 0.0f);
    normals.emplace_back(s1, 0.0f, s2 * phi);
  }
  addConvexPolyhedron(scene, v, normals, offset, material);
}

// A five-pointed star extruded along z: two concave 10-gons and ten side quads, all wound
// counter-clockwise seen from outside.
void addStarPrism(Scene& scene, float outer, float inner, float half_depth, glm::vec3 offset,
                  std::uint32_t material) {
  constexpr int kCorners = 10;
  std::array<std::uint32_t, kCorners> front{}, back{};
  for (int k = 0; k < kCorners; ++k) {
    const double angle = kPi / 2 + k * (2 * kPi / kCorners);  // counter-clockwise from +y
    const float r = k % 2 == 0 ? outer : inner;
    const glm::vec3 p(static_cast<float>(r * std::cos(angle)),
                      static_cast<float>(r * std::sin(angle)), 0.0f);
    front[k] = scene.addVertex(p + glm::vec3(0, 0, half_depth) + offset);
    back[k] = scene.addVertex(p - glm::vec3(0, 0, half_depth) + offset);
  }
  scene.addPolygon(front, material);  // faces +z
  std::array<std::uint32_t, kCorners> back_reversed{};
  for (int k = 0; k < kCorners; ++k) back_reversed[k] = back[kCorners - 1 - k];
  scene.addPolygon(back_reversed, material);  // faces -z
  for (int k = 0; k < kCorners; ++k) {
    const int n = (k + 1) % kCorners;
    scene.addPolygon({back[k], back[n], front[n], front[k]}, material);  // outward normal
  }
}

// ---------------------------------------------------------------------------------------
// The notes' cases

// Two quads that cross along a vertical line at 64 degrees: each is in front of the other on
// one side of the line. The pair is turned to face the three-quarter camera of frameBounds, so
// that both quads show the same width.
void addPenetrating(Scene& scene, glm::vec3 o, std::uint32_t mat_a, std::uint32_t mat_b) {
  scene.beginObject("penetrating quads");
  constexpr double kFacing = 35.0, kHalfCrossing = 32.0;  // degrees about +y from +z
  const auto quad = [&](double yaw_deg, float y_lo, float y_hi, std::uint32_t mat) {
    // A unit-half-width quad whose normal points at azimuth yaw (from +z towards +x)
    const double yaw = yaw_deg * kPi / 180.0;
    const glm::vec3 h(static_cast<float>(std::cos(yaw)), 0.0f, static_cast<float>(-std::sin(yaw)));
    scene.addPolygonVertices({o - h + glm::vec3(0, y_lo, 0), o + h + glm::vec3(0, y_lo, 0),
                              o + h + glm::vec3(0, y_hi, 0), o - h + glm::vec3(0, y_hi, 0)},
                             mat);
  };
  quad(kFacing - kHalfCrossing, -0.85f, 0.65f, mat_a);
  quad(kFacing + kHalfCrossing, -0.65f, 0.85f, mat_b);
}

// The three sticks: long thin quads along the edges of a triangle, each rising along its
// length, so that at every corner the stick that ends there lies over the one that starts
// there: 0 over 1, 1 over 2, 2 over 0. No depth order exists; one stick must be split.
void addCyclic(Scene& scene, glm::vec3 o, const std::array<std::uint32_t, 3>& materials) {
  scene.beginObject("cyclic sticks");
  constexpr float kCircumradius = 0.95f, kOverhang = 0.55f, kHalfWidth = 0.14f, kRise = 0.16f;
  std::array<glm::vec3, 3> corner;
  for (int i = 0; i < 3; ++i) {
    const double angle = kPi / 2 + i * (2 * kPi / 3);
    corner[i] = glm::vec3(static_cast<float>(kCircumradius * std::cos(angle)),
                          static_cast<float>(kCircumradius * std::sin(angle)), 0.0f);
  }
  for (int i = 0; i < 3; ++i) {
    const glm::vec3 a = corner[i], b = corner[(i + 1) % 3];
    const glm::vec3 d = glm::normalize(b - a);
    const glm::vec3 left(-d.y, d.x, 0.0f);
    // Extend past both corners so that neighbours cross, and rise from -kRise to +kRise
    const glm::vec3 s = a - d * kOverhang - glm::vec3(0, 0, kRise);
    const glm::vec3 e = b + d * kOverhang + glm::vec3(0, 0, kRise);
    scene.addPolygonVertices({o + s - left * kHalfWidth, o + e - left * kHalfWidth,
                              o + e + left * kHalfWidth, o + s + left * kHalfWidth},
                             materials[i]);
  }
}

// A glass pane (alpha 0.5) in front of the left half of an opaque cube.
void addTransparent(Scene& scene, glm::vec3 o, std::uint32_t cube_mat, std::uint32_t glass_mat) {
  scene.beginObject("cube behind glass");
  addCube(scene, 0.6f, o, cube_mat);
  scene.beginObject("glass pane");
  scene.addPolygonVertices({o + glm::vec3(-1.0f, -0.8f, 1.0f), o + glm::vec3(0.15f, -0.8f, 1.0f),
                            o + glm::vec3(0.15f, 0.75f, 1.0f), o + glm::vec3(-1.0f, 0.75f, 1.0f)},
                           glass_mat);
}

Scene makeDemo() {
  Scene scene;
  const std::uint32_t red = scene.addMaterial({{0.95f, 0.30f, 0.25f}, 1.0f});
  const std::uint32_t blue = scene.addMaterial({{0.25f, 0.55f, 0.95f}, 1.0f});
  const std::uint32_t gold = scene.addMaterial({{0.98f, 0.80f, 0.20f}, 1.0f});
  const std::uint32_t green = scene.addMaterial({{0.30f, 0.85f, 0.35f}, 1.0f});
  const std::uint32_t violet = scene.addMaterial({{0.70f, 0.40f, 0.95f}, 1.0f});
  const std::uint32_t teal = scene.addMaterial({{0.20f, 0.80f, 0.78f}, 1.0f});
  const std::uint32_t pink = scene.addMaterial({{0.95f, 0.35f, 0.70f}, 1.0f});
  const std::uint32_t orange = scene.addMaterial({{1.00f, 0.58f, 0.18f}, 1.0f});
  const std::uint32_t glass = scene.addMaterial({{0.60f, 0.88f, 1.00f}, 0.5f});
  // Two rows read left to right: penetrating, cyclic, convex; then non-convex, transparent.
  // Spacing leaves a gap between neighbours from the three-quarter view of frameBounds.
  constexpr float kColumn = 2.45f, kRow = 2.5f;
  addPenetrating(scene, {-kColumn, kRow * 0.5f, 0.0f}, red, blue);
  addCyclic(scene, {0.0f, kRow * 0.5f, 0.0f}, {gold, green, violet});
  scene.beginObject("convex dodecahedron");
  addDodecahedron(scene, 1.0f, {kColumn, kRow * 0.5f, 0.0f}, teal);
  scene.beginObject("non-convex star prism");
  addStarPrism(scene, 1.1f, 0.48f, 0.3f, {-kColumn * 0.5f, -kRow * 0.5f, 0.0f}, pink);
  addTransparent(scene, {kColumn * 0.5f, -kRow * 0.5f, -0.3f}, orange, glass);
  return scene;
}

// Six convex polyhedra (Roberts' case): spread along the three-quarter view of frameBounds
// so that they overlap on the picture, apart enough in depth that none touches another (their
// centres are further apart than the sum of their circumradii). Each is an object.
Scene makeSolids() {
  Scene scene;
  const glm::vec3 forward = glm::normalize(glm::vec3(0.55f, 0.45f, 1.0f));  // towards the eye
  const glm::vec3 right = glm::normalize(glm::cross(glm::vec3(0.0f, 1.0f, 0.0f), forward));
  const glm::vec3 up = glm::cross(forward, right);
  const auto at = [&](float a, float b, float c) { return a * right + b * up + c * forward; };
  const std::uint32_t slate = scene.addMaterial({{0.45f, 0.55f, 0.75f}, 1.0f});
  const std::uint32_t teal = scene.addMaterial({{0.20f, 0.80f, 0.78f}, 1.0f});
  const std::uint32_t gold = scene.addMaterial({{0.98f, 0.80f, 0.20f}, 1.0f});
  const std::uint32_t red = scene.addMaterial({{0.95f, 0.30f, 0.25f}, 1.0f});
  const std::uint32_t violet = scene.addMaterial({{0.70f, 0.40f, 0.95f}, 1.0f});
  const std::uint32_t green = scene.addMaterial({{0.30f, 0.85f, 0.35f}, 1.0f});
  scene.beginObject("cube");
  addCube(scene, 0.7f, at(0.0f, 0.0f, -2.4f), slate);
  scene.beginObject("dodecahedron");
  addDodecahedron(scene, 0.9f, at(0.9f, 0.5f, -0.2f), teal);
  scene.beginObject("octahedron");
  {
    const float r = 0.85f;
    std::vector<glm::vec3> v{{r, 0, 0}, {-r, 0, 0}, {0, r, 0}, {0, -r, 0}, {0, 0, r}, {0, 0, -r}};
    std::vector<glm::vec3> n;
    for (int i = 0; i < 8; ++i) n.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
    addConvexPolyhedron(scene, v, n, at(-0.8f, -0.3f, 0.0f), gold);
  }
  scene.beginObject("tetrahedron");
  {
    const float k = 0.7f / std::sqrt(3.0f);
    std::vector<glm::vec3> v{{k, k, k}, {k, -k, -k}, {-k, k, -k}, {-k, -k, k}};
    std::vector<glm::vec3> n;
    for (const glm::vec3& q : v) n.push_back(-q);
    addConvexPolyhedron(scene, v, n, at(0.1f, -0.5f, 1.4f), red);
  }
  scene.beginObject("hexagonal prism");
  {
    std::vector<glm::vec3> v, n{{0, 1, 0}, {0, -1, 0}};
    for (int k = 0; k < 6; ++k) {
      const double a = k * kPi / 3, m = a + kPi / 6;
      for (float y : {0.8f, -0.8f})
        v.emplace_back(static_cast<float>(0.5 * std::cos(a)), y,
                       static_cast<float>(0.5 * std::sin(a)));
      n.emplace_back(static_cast<float>(std::cos(m)), 0.0f, static_cast<float>(std::sin(m)));
    }
    addConvexPolyhedron(scene, v, n, at(-1.6f, 1.0f, -1.2f), violet);
  }
  scene.beginObject("small cube");
  addCube(scene, 0.35f, at(1.3f, -0.9f, 0.9f), green);
  return scene;
}

Scene makeCyclic() {
  Scene scene;
  const std::uint32_t gold = scene.addMaterial({{0.98f, 0.80f, 0.20f}, 1.0f});
  const std::uint32_t green = scene.addMaterial({{0.30f, 0.85f, 0.35f}, 1.0f});
  const std::uint32_t violet = scene.addMaterial({{0.70f, 0.40f, 0.95f}, 1.0f});
  addCyclic(scene, {0.0f, 0.0f, 0.0f}, {gold, green, violet});
  return scene;
}

Scene makePenetrating() {
  Scene scene;
  const std::uint32_t red = scene.addMaterial({{0.95f, 0.30f, 0.25f}, 1.0f});
  const std::uint32_t blue = scene.addMaterial({{0.25f, 0.55f, 0.95f}, 1.0f});
  addPenetrating(scene, {0.0f, 0.0f, 0.0f}, red, blue);
  return scene;
}

// ---------------------------------------------------------------------------------------
// spheres:N

// A UV sphere with `stacks` bands from pole to pole and `slices` segments around: the caps
// are triangle fans and each band in between is `slices` quads split into two triangles,
// 2 * slices * (stacks - 1) triangles in all.
struct SphereShape {
  int stacks = 2, slices = 3;
  std::uint64_t triangles() const { return 2ull * slices * (stacks - 1); }
};

// Pick a sphere whose triangle count times `spheres` is closest to `target` (within 2% when
// possible), preferring round spheres (slices = 2 * stacks).
SphereShape chooseSphere(std::uint64_t target, std::uint64_t spheres) {
  const double per = static_cast<double>(target) / static_cast<double>(spheres);
  SphereShape best;
  double best_score = 1e300;
  for (int stacks = 2; stacks <= 4096; ++stacks) {
    const double want = per / (2.0 * (stacks - 1));
    if (want < 2.5 && stacks > 2) break;
    for (int slices = std::max(3, static_cast<int>(want));
         slices <= std::max(3, static_cast<int>(want) + 1); ++slices) {
      const SphereShape s{stacks, slices};
      const double total = static_cast<double>(s.triangles() * spheres);
      const double error =
          std::abs(total - static_cast<double>(target)) / static_cast<double>(target);
      const double roundness = std::abs(std::log(slices / (2.0 * stacks)));
      // Anything within 2% is as good as exact; then the roundest wins
      const double score = std::max(error, 0.02) * 100.0 + roundness;
      if (score < best_score) best_score = score, best = s;
    }
  }
  return best;
}

Scene makeSpheres(std::uint64_t n) {
  // Layout: a g x g grid of spheres in x/y, two layers, the back one set behind the front
  // one along the three-quarter view direction of frameBounds, and a little aside so that it
  // peeks out. Most rays from that camera cross two spheres: a depth complexity of about 4.
  constexpr double kTrianglesPerSphere = 1500.0;  // enough spheres for frustum culling to bite
  const int layers = n < 48 ? 1 : 2;              // below 48 triangles: a single sphere
  const int grid = std::max(1, static_cast<int>(std::sqrt(n / (layers * kTrianglesPerSphere))));
  const std::uint64_t spheres = static_cast<std::uint64_t>(layers) * grid * grid;
  const SphereShape shape = chooseSphere(n, spheres);

  // The unit sphere, computed once and shared by every sphere (y is the polar axis)
  std::vector<glm::vec3> unit;
  unit.reserve(2 + static_cast<std::size_t>(shape.stacks - 1) * shape.slices);
  unit.emplace_back(0.0f, 1.0f, 0.0f);
  for (int i = 1; i < shape.stacks; ++i) {
    const double theta = kPi * i / shape.stacks;
    for (int j = 0; j < shape.slices; ++j) {
      const double phi = 2 * kPi * j / shape.slices;
      unit.emplace_back(static_cast<float>(std::sin(theta) * std::cos(phi)),
                        static_cast<float>(std::cos(theta)),
                        static_cast<float>(-std::sin(theta) * std::sin(phi)));
    }
  }
  unit.emplace_back(0.0f, -1.0f, 0.0f);
  // Ring i (1..stacks-1), slice j -> local vertex index
  const auto ring = [&](int i, int j) {
    return static_cast<std::uint32_t>(1 + (i - 1) * shape.slices + j % shape.slices);
  };
  const std::uint32_t south = static_cast<std::uint32_t>(unit.size() - 1);

  Scene scene;
  scene.materials.reserve(spheres);
  scene.objects.reserve(spheres);
  constexpr float kRadius = 1.0f, kSpacing = 2.05f;  // nearly touching in a layer
  const float half = (grid - 1) * kSpacing * 0.5f;
  const glm::vec3 behind =
      -2.4f * glm::normalize(glm::vec3(0.55f, 0.45f, 1.0f)) + glm::vec3(0.25f, -0.25f, 0.0f);
  for (std::uint64_t s = 0; s < spheres; ++s) {
    const int layer = static_cast<int>(s / (grid * grid));
    const int cell = static_cast<int>(s % (grid * grid));
    const int row = cell / grid, col = cell % grid;
    const glm::vec3 center = glm::vec3(col * kSpacing - half, row * kSpacing - half, 0.0f) +
                             static_cast<float>(layer) * behind;
    // Golden-ratio hues: neighbours always differ
    const std::uint32_t mat = scene.addMaterial(
        {hsv(static_cast<float>(std::fmod(s * 0.6180339887498949, 1.0)), 0.65f, 0.95f), 1.0f});
    scene.beginObject("sphere " + std::to_string(s));
    for (const glm::vec3& u : unit) scene.addVertex(center + u * kRadius);
    for (int j = 0; j < shape.slices; ++j) {
      // Counter-clockwise seen from outside: phi grows clockwise seen from +y (z = -sin phi)
      scene.addPolygon({0u, ring(1, j), ring(1, j + 1)}, mat);
      for (int i = 1; i + 1 < shape.stacks; ++i) {
        scene.addPolygon({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)}, mat);
        scene.addPolygon({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)}, mat);
      }
      scene.addPolygon({ring(shape.stacks - 1, j), south, ring(shape.stacks - 1, j + 1)}, mat);
    }
  }
  return scene;
}

// ---------------------------------------------------------------------------------------
// soup:N:SEED

Scene makeSoup(std::uint64_t n, std::uint64_t seed) {
  // Triangle centres uniform in [-1,1]^3, corners within a cube around the centre: edges
  // about 0.3 long for up to 1000 triangles, shrinking as 1/sqrt(N) beyond that so that the
  // depth complexity (about N times the projected area) stays that of 1000 triangles.
  const float size = 0.45f * static_cast<float>(std::min(1.0, std::sqrt(1000.0 / n)));
  detail::SplitMix64 rng(seed);
  Scene scene;
  // A palette of random colours rather than one material per triangle (20M materials would
  // cost more than the triangles)
  constexpr int kPalette = 64;
  // (Random numbers are drawn one statement at a time: the order in which a call's
  // arguments are evaluated differs between compilers.)
  const auto point = [&rng](float lo, float hi) {
    const float x = rng.uniform(lo, hi);
    const float y = rng.uniform(lo, hi);
    const float z = rng.uniform(lo, hi);
    return glm::vec3(x, y, z);
  };
  for (int i = 0; i < kPalette; ++i) {
    const glm::vec3 h = point(0.0f, 1.0f);
    scene.addMaterial({hsv(h.x, 0.45f + 0.45f * h.y, 0.7f + 0.3f * h.z), 1.0f});
  }
  scene.beginObject("soup");
  for (std::uint64_t t = 0; t < n; ++t) {
    const glm::vec3 c = point(-1.0f, 1.0f);
    std::array<std::uint32_t, 3> v{};
    for (std::uint32_t& k : v) k = scene.addVertex(c + size * point(-0.5f, 0.5f));
    scene.addPolygon(v, static_cast<std::uint32_t>(rng.next() % kPalette));
  }
  return scene;
}

}  // namespace

const std::vector<BuiltinScene>& builtinScenes() {
  static const std::vector<BuiltinScene> kScenes = {
      {"demo", "the notes' cases side by side: penetrating, cyclic, convex, non-convex, glass"},
      {"solids", "six convex polyhedra overlapping in the view, apart in depth: Roberts' case"},
      {"cyclic", "three sticks overlapping in a cycle: no depth order exists"},
      {"penetrating", "two quads crossing each other: each is in front on one side"},
      {"spheres:N", "a grid of UV spheres, about N triangles, depth complexity about 4"},
      {"soup:N:SEED", "N random triangles in a box (SEED optional, default 1)"},
  };
  return kScenes;
}

Scene makeBuiltinScene(std::string_view spec, std::uint64_t max_triangles) {
  const std::vector<std::string_view> parts = splitSpec(spec);
  const std::string_view name = parts[0];
  const std::uint64_t max_n = std::min(max_triangles, kMaxBuiltinTriangles);
  const auto takesNoParameters = [&] {
    if (parts.size() != 1)
      throw Error("scene '" + std::string(name) + "' takes no parameters (got '" +
                  std::string(spec) + "')");
  };
  Scene scene;
  if (name == "demo") {
    takesNoParameters();
    scene = makeDemo();
  } else if (name == "solids") {
    takesNoParameters();
    scene = makeSolids();
  } else if (name == "cyclic") {
    takesNoParameters();
    scene = makeCyclic();
  } else if (name == "penetrating") {
    takesNoParameters();
    scene = makePenetrating();
  } else if (name == "spheres") {
    if (parts.size() != 2)
      throw Error("scene '" + std::string(spec) + "': expected spheres:N, e.g. spheres:100000");
    const std::uint64_t n = parseCount(parts[1], spec, "N", max_n);
    if (n == 0) throw Error("scene '" + std::string(spec) + "': N must be at least 1");
    scene = makeSpheres(n);
  } else if (name == "soup") {
    if (parts.size() != 2 && parts.size() != 3)
      throw Error("scene '" + std::string(spec) + "': expected soup:N:SEED, e.g. soup:1000:7");
    const std::uint64_t n = parseCount(parts[1], spec, "N", max_n);
    if (n == 0) throw Error("scene '" + std::string(spec) + "': N must be at least 1");
    const std::uint64_t seed = parts.size() == 3 ? parseSeed(parts[2], spec) : 1;
    scene = makeSoup(n, seed);
  } else {
    throw Error("unknown scene '" + std::string(spec) + "' (see `hsr scenes`)");
  }
  scene.name = std::string(spec);
  return scene;
}

}  // namespace hsr

#pragma once
// Watertight ray/triangle intersection: Woop, Benthin & Wald, "Watertight Ray/Triangle
// Intersection", JCGT 2(1), 2013 (the test pbrt-v3 and v4 use). The ray is made the z axis of
// a sheared frame, so the three edge functions of the triangle's projection are evaluated at
// the same point (the origin) from the same projected vertices by every triangle that shares
// an edge: the two triangles beside an edge see one edge function with opposite signs.
// Guarantee: no ray passes between two triangles that share an edge (no cracks); a ray through
// a shared edge or vertex hits every triangle that has it (the caller breaks the tie: hsr keeps
// the lowest triangle number). Where float edge functions come out 0 they are recomputed in
// double, as the paper says. Built with -ffp-contract=off, so the bits are the same everywhere.

#include <cmath>
#include <cstdint>
#include <utility>

#include <glm/vec3.hpp>

namespace hsr::detail {

// A ray prepared for the test: the dimension where its direction is largest becomes z (kz),
// the other two x and y (swapped when that component is negative, so the winding is kept),
// and the shear that makes the direction the z axis.
struct ShearedRay {
  glm::vec3 org{0.0f}, dir{0.0f};
  int kx = 0, ky = 1, kz = 2;
  float sx = 0, sy = 0, sz = 1;
};

// Made in place, a field at a time (a caller keeping it in a larger structure would otherwise
// copy a whole just written word by word: a store-forwarding stall on every ray).
inline void shearRayInto(const glm::vec3& org, const glm::vec3& dir, ShearedRay& r) {
  r.org = org;
  r.dir = dir;
  const float ax = std::abs(dir.x), ay = std::abs(dir.y), az = std::abs(dir.z);
  const int kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
  int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
  if (dir[kz] < 0.0f) std::swap(kx, ky);  // keep the winding
  r.kx = kx, r.ky = ky, r.kz = kz;
  r.sx = dir[kx] / dir[kz];
  r.sy = dir[ky] / dir[kz];
  r.sz = 1.0f / dir[kz];
}

inline ShearedRay shearRay(const glm::vec3& org, const glm::vec3& dir) {
  ShearedRay r;
  shearRayInto(org, dir, r);
  return r;
}

// Which sides of a triangle a ray may hit. A triangle is "counter-clockwise" seen from the ray's
// origin when its vertices a, b, c turn counter-clockwise looking down the ray: its normal by
// the right-hand rule points back at the origin (N . d < 0), and the determinant is positive.
enum class HitSides : std::uint8_t { kBoth, kCounterClockwiseOnly, kClockwiseOnly };

struct TriangleHit {
  float t = 0;         // along the ray: org + t dir
  float u = 0, v = 0;  // barycentrics of b and c (a's is 1 - u - v), as Embree reports them
  bool counter_clockwise = false;  // seen from the ray's origin
};

// The paper's test from its edge functions on: U, V, W (the scaled barycentric coordinates,
// float) and the vertices' sheared-and-scaled heights az, bz, cz. The part of the test after
// the edge functions, shared by the one-triangle test below and the leaf test that computes
// the edge functions of four triangles at once (geometry/bvh.cpp).
inline bool finishTriangleHit(float U, float V, float W, float az, float bz, float cz, float tmin,
                              float tmax, HitSides sides, TriangleHit* hit) {
  // Outside an edge: mixed signs
  if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return false;
  const float det = U + V + W;
  if (det == 0.0f || std::isnan(det)) return false;  // edge-on, or the ray's plane degenerate
  const bool ccw = det > 0.0f;
  if ((sides == HitSides::kCounterClockwiseOnly && !ccw) ||
      (sides == HitSides::kClockwiseOnly && ccw))
    return false;
  // The scaled hit distance, then the distance: in double, where the three products are exact,
  // so t carries the edge functions' rounding alone (only hits get here)
  const double T = double(U) * az + double(V) * bz + double(W) * cz;
  const float t = static_cast<float>(T / (double(U) + double(V) + double(W)));
  if (!(t > tmin && t < tmax)) return false;
  hit->t = t;
  hit->u = V / det;
  hit->v = W / det;
  hit->counter_clockwise = ccw;
  return true;
}

// The edge functions in double, where float cannot tell their signs (one came out 0).
inline void edgeFunctionsInDouble(float ax, float ay, float bx, float by, float cx, float cy,
                                  float* U, float* V, float* W) {
  *U = static_cast<float>(double(cx) * double(by) - double(cy) * double(bx));
  *V = static_cast<float>(double(ax) * double(cy) - double(ay) * double(cx));
  *W = static_cast<float>(double(bx) * double(ay) - double(by) * double(ax));
}

// The paper's test, for a hit with tmin < t < tmax on the allowed sides.
inline bool intersectTriangle(const ShearedRay& r, const glm::vec3& a, const glm::vec3& b,
                              const glm::vec3& c, float tmin, float tmax, HitSides sides,
                              TriangleHit* hit) {
  // Vertices relative to the origin
  const glm::vec3 A = a - r.org, B = b - r.org, C = c - r.org;
  // Shear and scale: the ray becomes the +z axis through the origin
  const float ax = A[r.kx] - r.sx * A[r.kz], ay = A[r.ky] - r.sy * A[r.kz];
  const float bx = B[r.kx] - r.sx * B[r.kz], by = B[r.ky] - r.sy * B[r.kz];
  const float cx = C[r.kx] - r.sx * C[r.kz], cy = C[r.ky] - r.sy * C[r.kz];
  // The scaled barycentric coordinates: edge functions at the origin
  float U = cx * by - cy * bx;
  float V = ax * cy - ay * cx;
  float W = bx * ay - by * ax;
  // Fall back to double where float cannot tell the sign
  if (U == 0.0f || V == 0.0f || W == 0.0f)
    edgeFunctionsInDouble(ax, ay, bx, by, cx, cy, &U, &V, &W);
  return finishTriangleHit(U, V, W, r.sz * A[r.kz], r.sz * B[r.kz], r.sz * C[r.kz], tmin, tmax,
                           sides, hit);
}

}  // namespace hsr::detail

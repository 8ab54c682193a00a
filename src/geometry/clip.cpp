// Sutherland-Hodgman clipping (1974), homogeneous as Blinn & Newell (1978) and Mesa's
// draw_pipe_clip do it, and in 2D.

#include "geometry/clip.hpp"

#include <algorithm>
#include <cmath>

#include <glm/vec4.hpp>

namespace hsr::detail {

// Ordinary edges use Mesa's float arithmetic, so clipped vertices stay bit-identical to
// llvmpipe's. An edge with an endpoint more than 2^12 viewports away (|x|, |y| or |z| beyond
// 4096 |w|) is computed in double instead: in float, w - x loses w entirely once |x| >> |w|,
// and a triangle spanning 1e10 units clipped up to 32 pixels off (the test
// Degenerate.HugeCoordinatesClipCorrectly).
glm::vec4 clipIntersection(const glm::vec4& near_p, const glm::vec4& far_p, float dnear, float dfar,
                           int k, const ClipSetup& cs) {
  constexpr float kFarAway = 4096.0f;
  const auto huge = [&](const glm::vec4& p) {
    const float m = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    return !(m <= kFarAway * std::abs(p.w));
  };
  if (!huge(near_p) && !huge(far_p)) {
    const float t = dnear / (dnear - dfar);
    return near_p + t * (far_p - near_p);
  }
  const glm::dvec4 a(near_p), b(far_p);
  const auto dist = [&](const glm::dvec4& v) {
    const double gx = cs.gx, gy = cs.gy;
    switch (k) {
      case 0:
        return gx * v.w - v.x;
      case 1:
        return gx * v.w + v.x;
      case 2:
        return gy * v.w - v.y;
      case 3:
        return gy * v.w + v.y;
      case 4:
        return v.z + v.w;
      default:
        return v.w - v.z;
    }
  };
  const double da = dist(a), db = dist(b);
  const double t = da / (da - db);
  glm::dvec4 v = a + t * (b - a);
  // Exactly on the plane (the interpolation may miss it by a rounding step)
  switch (k) {
    case 0:
      v.x = cs.gx * v.w;
      break;
    case 1:
      v.x = -cs.gx * v.w;
      break;
    case 2:
      v.y = cs.gy * v.w;
      break;
    case 3:
      v.y = -cs.gy * v.w;
      break;
    case 4:
      v.z = -v.w;
      break;
    default:
      v.z = v.w;
      break;
  }
  return glm::vec4(v);
}

void clipPolygon(ClipPolygon& poly, unsigned planes, const ClipSetup& cs, ClipPolygon& tmp) {
  for (int k = 0; k < kClipPlanes && !poly.empty(); ++k) {
    if (!(planes & kPlaneBit[k])) continue;
    tmp.clear();
    const std::size_t n = poly.size();
    for (std::size_t i = 0; i < n; ++i) {
      const ClipVertex& a = poly[i];
      const ClipVertex& b = poly[(i + 1) % n];
      const float da = planeDistance(a.p, k, cs), db = planeDistance(b.p, k, cs);
      const bool ina = da >= 0.0f, inb = db >= 0.0f;
      if (ina) tmp.push_back(a);
      if (ina != inb) {
        // Interpolate from the endpoint nearer the plane (the inside one on a tie), as Mesa's
        // clipper does: independent of edge direction, and bit-identical to llvmpipe.
        const bool from_a = std::abs(da) < std::abs(db) || (std::abs(da) == std::abs(db) && ina);
        const ClipVertex& near_v = from_a ? a : b;
        const ClipVertex& far_v = from_a ? b : a;
        ClipVertex v{clipIntersection(near_v.p, far_v.p, from_a ? da : db, from_a ? db : da, k, cs),
                     false, false};
        // Entering the inside keeps the original edge's flag; the new edge along the plane
        // (from the exit point to the next entry) is not an original edge.
        v.edge = ina ? false : a.edge;
        if (ina) tmp.back().edge = a.edge;
        tmp.push_back(v);
      }
    }
    poly.swap(tmp);
  }
}

void clipToHalfPlane(std::vector<glm::dvec2>& poly, double a, double b, double c) {
  std::vector<glm::dvec2> out;
  const std::size_t n = poly.size();
  out.reserve(n + 1);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec2& p = poly[i];
    const glm::dvec2& q = poly[(i + 1) % n];
    const double dp = a * p.x + b * p.y + c, dq = a * q.x + b * q.y + c;
    if (dp >= 0.0) out.push_back(p);
    if ((dp >= 0.0) != (dq >= 0.0)) {
      // From the inside endpoint, so the shared edge of two polygons meets the line at one point.
      out.push_back(dp >= 0.0 ? p + (dp / (dp - dq)) * (q - p) : q + (dq / (dq - dp)) * (p - q));
    }
  }
  poly.swap(out);
}

}  // namespace hsr::detail

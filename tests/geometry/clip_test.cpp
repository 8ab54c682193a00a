// Homogeneous clipping (src/geometry/clip.cpp) where an edge's endpoint lies far beyond |w| (more
// than 4096 |w| in x, y or z): there the crossing is computed in double, since in float w - x
// loses w once |x| >> |w|. Held here against the crossing computed exactly from the same float
// endpoints (in long double, whose 64-bit mantissa holds every product of two floats): for
// each of the six planes, the clipped vertex lies on the plane exactly and on the edge within a
// few float ulps; and a whole scene whose far-away vertex makes the near-plane crossing take that
// path renders as the same scene with the vertex pulled in along its edges (the ordinary path).

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "cross/figures.hpp"
#include "geometry/clip.hpp"
#include "hsr/render.hpp"
#include "test_util.hpp"

namespace hsr {
namespace {

using detail::ClipSetup;

long double distanceExact(const glm::vec4& v, int k) {
  const long double x = v.x, y = v.y, z = v.z, w = v.w;
  switch (k) {
    case 0:
      return w - x;
    case 1:
      return w + x;
    case 2:
      return w - y;
    case 3:
      return w + y;
    case 4:
      return z + w;
    default:
      return w - z;
  }
}

TEST(Clip, FarAwayEndpointsCrossEveryPlaneExactlyOnIt) {
  testing::Rng rng(52);
  const ClipSetup cs;
  int checked = 0, worst_ulps = 0;
  for (int k = 0; k < detail::kClipPlanes; ++k) {
    for (int i = 0; i < 2000; ++i) {
      // Inside: a point of the view volume; outside: beyond plane k, by 10^4 to 10^9 times |w|
      // in the coordinate plane k bounds (for the near plane, z beyond -w with x, y inside)
      const float w_in = rng.uniform(0.5f, 50.0f);
      glm::vec4 in(rng.uniform(-0.9f, 0.9f) * w_in, rng.uniform(-0.9f, 0.9f) * w_in,
                   rng.uniform(-0.9f, 0.9f) * w_in, w_in);
      const float w_out = rng.uniform(0.01f, 2.0f) * (rng.uniform() < 0.5f ? 1.0f : -1.0f);
      const float far = std::abs(w_out) * std::pow(10.0f, rng.uniform(4.0f, 9.0f));
      glm::vec4 out(rng.uniform(-0.5f, 0.5f) * std::abs(w_out),
                    rng.uniform(-0.5f, 0.5f) * std::abs(w_out),
                    rng.uniform(-0.5f, 0.5f) * std::abs(w_out), w_out);
      const int axis = k / 2 < 2 ? k / 2 : 2;
      const float sign = k < 4 ? (k % 2 == 0 ? 1.0f : -1.0f) : (k == 4 ? -1.0f : 1.0f);
      out[axis] = sign * far;
      const float d_in = detail::planeDistance(in, k, cs),
                  d_out = detail::planeDistance(out, k, cs);
      ASSERT_GT(d_in, 0.0f);
      ASSERT_LT(d_out, 0.0f);
      ASSERT_GT(std::abs(out[axis]), 4096.0f * std::abs(out.w)) << "not the far-away path";
      const glm::vec4 v = detail::clipIntersection(in, out, d_in, d_out, k, cs);
      // On the plane, exactly
      EXPECT_EQ(detail::planeDistance(v, k, cs), 0.0f) << "plane " << k << ", case " << i;
      // On the edge: the exact crossing of the segment from the same float endpoints
      const long double a = distanceExact(in, k), b = distanceExact(out, k), t = a / (a - b);
      for (int c = 0; c < 4; ++c) {
        const long double want =
            static_cast<long double>(in[c]) + t * (static_cast<long double>(out[c]) - in[c]);
        const long double scale =
            std::max<long double>(std::abs(want), std::abs(static_cast<long double>(v.w)));
        const long double ulp = std::ldexp(1.0L, std::ilogb(static_cast<double>(scale)) - 23);
        const long double off = std::abs(static_cast<long double>(v[c]) - want) / ulp;
        worst_ulps = std::max(worst_ulps, static_cast<int>(std::ceil(off)));
        EXPECT_LE(off, 4.0L) << "plane " << k << " component " << c << ": " << double(v[c])
                             << " for " << double(want);
      }
      ++checked;
    }
  }
  testing::printFigures(
      "clipping far-away edges: " + testing::grouped(checked) +
      " crossings (6 planes, endpoints 1e4 to 1e9 |w| away), each exactly on its plane, "
      "at most " +
      std::to_string(worst_ulps) + " float ulps from the exact crossing");
}

// A whole scene on the far-away path: a floor triangle with a corner a million units to the
// right, just in front of the eye plane (|x| some 10^9 times |w|), so that its edges cross the
// right plane in double. The same floor with that corner cut off outside the view (a quad whose
// two new corners lie on the same edges, twice as far right as the right plane: the ordinary
// float path) must render the same pixels and depths. (The near plane's own far-away path
// cannot be reached by a polygon that is not seen edge-on: after x and y are clipped, a vertex
// beyond 4096 |w| in z lies within 2 near / 4096 of the eye, and so does the polygon's plane.
// The test above holds it.)
TEST(Clip, FarAwayVertexRendersAsTheOrdinaryPath) {
  Camera c;
  c.eye = {0, 0, 0}, c.target = {0, 0, -1}, c.up = {0, 1, 0};
  c.width = 256, c.height = 192, c.fov_deg = 60, c.near = 0.1f, c.far = 100.0f;
  const glm::vec3 a(-2.0f, -1.0f, -4.0f), b(1.0f, -1.0f, -9.0f), e(1.0e6f, -1.0f, -1e-3f);
  const glm::dmat4 clip_from_world = glm::dmat4(c.projection()) * glm::dmat4(c.view());
  const auto clip = [&](glm::vec3 p) { return clip_from_world * glm::dvec4(glm::dvec3(p), 1.0); };
  ASSERT_GT(std::abs(clip(e).x), 4096.0 * std::abs(clip(e).w))
      << "the corner does not take the far-away path";
  // The point of the edge from `from` to e where x = 2 w (outside the right plane, not far away)
  const auto cut = [&](glm::vec3 from) {
    const double d0 = clip(from).x - 2 * clip(from).w, d1 = clip(e).x - 2 * clip(e).w;
    const double t = d0 / (d0 - d1);
    return glm::vec3(glm::dvec3(from) + t * (glm::dvec3(e) - glm::dvec3(from)));
  };
  Scene far_corner, cut_corner;
  const std::uint32_t m1 = far_corner.addMaterial({}), m2 = cut_corner.addMaterial({});
  far_corner.addPolygonVertices({a, b, e}, m1);
  cut_corner.addPolygonVertices({a, b, cut(b), cut(a)}, m2);
  RenderOptions o;
  o.cull = CullMode::None;
  const Frame f = render(far_corner, c, o), g = render(cut_corner, c, o);
  std::size_t drawn = 0, coverage_differs = 0;
  double worst = 0;
  for (std::size_t k = 0; k < f.ids.size(); ++k) {
    const bool in_f = f.ids[k] != kNoPolygon, in_g = g.ids[k] != kNoPolygon;
    drawn += in_f;
    coverage_differs += in_f != in_g;
    if (in_f && in_g) worst = std::max(worst, std::abs(double(f.depth[k]) - double(g.depth[k])));
  }
  EXPECT_GT(drawn, 3000u);
  // The crossings agree to float rounding, so their snapped positions may differ on a pixel
  // whose centre lies within 1/256 px of the clipped edge
  EXPECT_LE(coverage_differs, 4u);
  EXPECT_LT(worst, 2e-6) << "the clipped edge moved";
  testing::printFigures(
      "clipping a vertex 1e6 units out on the far-away path: " + testing::grouped(drawn) +
      " pixels, " + std::to_string(coverage_differs) +
      " covered differently from the ordinary path, depth within " + fmt::format("{:.2g}", worst));
}

}  // namespace
}  // namespace hsr

// The pipeline's second product, for object-precision algorithms: every polygon that survives
// culling, clipped whole to the view volume and carried to window space, with its eye-space
// plane and the same depth plane and colour as its screen triangles. Its coordinates are the
// pipeline's float window positions (promoted to double), so snapping them yields exactly the
// vertices its screen triangles have; a non-planar polygon is given as its triangles.

#include <array>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "geometry/triangulate.hpp"
#include "pipeline/stages.hpp"

namespace hsr::detail {
namespace {

void emitPiece(const Context& ctx, PolygonId id, std::span<const std::uint32_t> vi,
               PolygonInfo& info, std::uint32_t piece, ChunkOut& out) {
  const WholeClip clipped = clipWholePolygon(ctx, vi, out);
  if (clipped == WholeClip::kOutside || clipped == WholeClip::kClippedAway) return;
  WindowPolygon wp;
  wp.vertices.reserve(out.poly.size());
  std::int64_t area = 0;  // doubled y-down area of the snapped polygon (shoelace)
  std::vector<WindowVertex>& wv = out.window_scratch;
  wv.clear();
  for (const ClipVertex& cv : out.poly) {
    wv.push_back(toWindow(cv.p, ctx.vp));
    if (!wv.back().ok) return;
  }
  for (std::size_t i = 0; i < wv.size(); ++i) {
    const WindowVertex& a = wv[i];
    const WindowVertex& b = wv[(i + 1) % wv.size()];
    area += a.fx * b.fy - b.fx * a.fy;
    wp.vertices.emplace_back(a.x, a.y, a.z);
  }
  if (area == 0) return;  // zero area on the sub-pixel grid: draws nothing
  // Facing as the screen triangles decide it (negative y-down area is counter-clockwise).
  wp.front = isFront(ctx, area < 0 ? 1 : -1, info.eye_orientation);
  if (culled(ctx.options.cull, wp.front)) return;
  wp.id = id;
  wp.piece = piece;
  wp.material = ctx.scene.material(id);
  wp.rgba = info.rgba;
  wp.transparent = info.transparent;
  wp.depth = depthPlaneOf(ctx, info);
  // The plane in eye space: Newell's normal turned by the view's rotation, through P.
  const glm::dvec3 n = polygonNormal(ctx.scene, vi);
  const glm::dvec3 n_eye = glm::dmat3(ctx.eye_from_world) * n;
  const glm::dvec3 p_eye(ctx.eye_from_world *
                         glm::dvec4(glm::dvec3(ctx.scene.position(vi[0])), 1.0));
  wp.eye_plane = glm::dvec4(n_eye, -glm::dot(n_eye, p_eye));
  out.polygons.push_back(std::move(wp));
}

}  // namespace

void emitWindowPolygon(const Context& ctx, PolygonId id, std::span<const std::uint32_t> vi,
                       PolygonInfo& info, ChunkOut& out) {
  if (info.planar) {
    emitPiece(ctx, id, vi, info, 0, out);
    return;
  }
  std::vector<Triangle> tris;
  triangulatePolygon(ctx.scene, id, tris);
  for (std::uint32_t k = 0; k < tris.size(); ++k) {
    PolygonInfo own = forTriangle(info, tris[k].v);
    emitPiece(ctx, id, std::span<const std::uint32_t>(tris[k].v), own, k, out);
  }
}

}  // namespace hsr::detail

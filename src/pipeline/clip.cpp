// Clip: triangles (and, in LINE/POINT mode and for the window-polygon product, whole
// polygons) against the view volume in homogeneous coordinates (geometry/clip.hpp), before
// the divide by w. A triangle wholly inside is not touched, so its edges stay where its
// vertices put them; one crossing a plane is cut and drawn as a fan from its first vertex,
// as GL's clipper emits it.

#include "pipeline/stages.hpp"

namespace hsr::detail {

void clipAndEmitTriangle(const Context& ctx, const glm::vec4 (&c)[3], PolygonId id,
                         PolygonInfo& info, ChunkOut& out) {
  unsigned codes[3];
  for (int k = 0; k < 3; ++k) codes[k] = outcode(c[k], ctx.cs);
  if (codes[0] & codes[1] & codes[2] & kViewVolume) {  // all outside one plane
    out.counts.clipped_away++;
    return;
  }
  const unsigned crossing = (codes[0] | codes[1] | codes[2]) & kMustClip;
  if (!crossing) {
    const WindowVertex w[3] = {toWindow(c[0], ctx.vp), toWindow(c[1], ctx.vp),
                               toWindow(c[2], ctx.vp)};
    if (w[0].ok && w[1].ok && w[2].ok)
      cullAndEmit(ctx, w, id, info, out);
    else
      out.counts.clipped_away++;
    return;
  }
  out.counts.clipped++;
  out.poly.assign({{c[0]}, {c[1]}, {c[2]}});
  clipPolygon(out.poly, crossing, ctx.cs, out.tmp);
  if (out.poly.size() < 3) {
    out.counts.clipped_away++;
    return;
  }
  std::vector<WindowVertex>& wv = out.window_scratch;
  wv.clear();
  bool ok = true;
  for (const ClipVertex& cv : out.poly) {
    wv.push_back(toWindow(cv.p, ctx.vp));
    ok = ok && wv.back().ok;
  }
  if (!ok) {
    out.counts.clipped_away++;
    return;
  }
  // The clipped polygon is convex: a fan from its first vertex, as GL's clipper emits. It is
  // k - 2 triangles where one went in.
  out.counts.clipped_added += wv.size() - 3;
  for (std::size_t k = 2; k < wv.size(); ++k) {
    const WindowVertex w[3] = {wv[0], wv[k - 1], wv[k]};
    cullAndEmit(ctx, w, id, info, out);
  }
}

WholeClip clipWholePolygon(const Context& ctx, std::span<const std::uint32_t> vi, ChunkOut& out) {
  out.poly.clear();
  unsigned all = ~0u, any = 0;
  for (std::uint32_t v : vi) {
    out.poly.push_back({ctx.clip[v]});
    const unsigned c = outcode(ctx.clip[v], ctx.cs);
    all &= c;
    any |= c;
  }
  if (all & kViewVolume) return WholeClip::kOutside;
  if (!(any & kMustClip)) return WholeClip::kInside;
  clipPolygon(out.poly, any & kMustClip, ctx.cs, out.tmp);
  return out.poly.size() < 3 ? WholeClip::kClippedAway : WholeClip::kClipped;
}

}  // namespace hsr::detail

// prepare(): the pipeline's stages in order, over fixed chunks of polygons whose outputs are
// joined in order. Guarantee: the output depends only on the scene, camera and options, never
// on the thread count.

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>

#include <glm/matrix.hpp>

#include "core/parallel.hpp"
#include "core/stopwatch.hpp"
#include "geometry/triangulate.hpp"
#include "pipeline/stages.hpp"

namespace hsr::detail {
namespace {

constexpr std::size_t kChunk = 2048;  // polygons per work item (fixed: determinism)

// The common case, kept lean and compiled as one piece: a triangle in FILL mode that needs no
// clipping. Its vertices were projected and snapped once each in the transform stage. The
// same decisions in the same order as the general path (describePolygon, then cullAndEmit),
// from the same inline pieces; its colour (a square root and a division) and depth plane are
// computed only for a triangle that is kept, four such triangles at a time (ShadeBatch).
// Returns false when the triangle needs the general path (clipping, or a non-finite vertex).
bool fastTriangle(const Context& ctx, PolygonId id, std::span<const std::uint32_t> vi,
                  ChunkOut& out) {
  const VertexOut& a = ctx.verts[vi[0]];
  const VertexOut& b = ctx.verts[vi[1]];
  const VertexOut& c = ctx.verts[vi[2]];
  if ((a.code | b.code | c.code) & (kMustClip | kNonFinite)) return false;
  const glm::dvec3 n = triangleNormal(ctx.scene, vi[0], vi[1], vi[2]);
  const double len2 = glm::dot(n, n);
  if (!usableNormal(len2)) {
    out.counts.degenerate_dropped++;
    return true;
  }
  if (a.code & b.code & c.code & (kLeft | kRight | kBottom | kTop)) {
    out.counts.clipped_away++;
    return true;
  }
  const int eye_orientation =
      eyeOrientation(n, glm::dvec3(ctx.scene.position(vi[0])), ctx.camera, ctx.view_dir);
  const std::int64_t fx[3] = {a.fx, b.fx, c.fx};
  const std::int64_t fy[3] = {a.fy, b.fy, c.fy};
  cullAndEmitWith(
      ctx, fx, fy, id, eye_orientation, [&]() -> ScreenTriangle& { return out.batch.slot(); },
      [&](const ScreenTriangle&) { out.batch.add(a, b, c, n, len2, out.triangles); }, out);
  return true;
}

// LINE and POINT mode: the polygon's own edges or vertices, after clipping the polygon whole,
// culled by the polygon's facing (the window area of the whole projected polygon, or the eye
// test). Edges and vertices made by clipping are not drawn.
void outlinePolygon(const Context& ctx, PolygonId id, std::span<const std::uint32_t> vi,
                    const PolygonInfo& info, std::uint64_t triangles, ChunkOut& out) {
  switch (clipWholePolygon(ctx, vi, out)) {
    case WholeClip::kOutside:
      out.counts.clipped_away += triangles;
      return;
    case WholeClip::kClippedAway:
      out.counts.clipped += triangles;
      out.counts.clipped_away += triangles;
      return;
    case WholeClip::kClipped:
      out.counts.clipped += triangles;
      break;
    case WholeClip::kInside:
      break;
  }
  const ClipPolygon& poly = out.poly;
  std::vector<WindowVertex>& wv = out.window_scratch;
  wv.clear();
  for (const ClipVertex& cv : poly) {
    wv.push_back(toWindow(cv.p, ctx.vp));
    if (!wv.back().ok) {
      out.counts.clipped_away += triangles;
      return;
    }
  }
  if (ctx.options.facing_test == FacingTest::WindowArea && ctx.options.cull != CullMode::None) {
    std::int64_t area = 0;  // doubled y-down area (shoelace)
    for (std::size_t i = 0; i < wv.size(); ++i) {
      const WindowVertex& a = wv[i];
      const WindowVertex& b = wv[(i + 1) % wv.size()];
      area += a.fx * b.fy - b.fx * a.fy;
    }
    if (area == 0) {
      out.counts.zero_area += triangles;
      return;
    }
    if (culled(ctx.options.cull, isFront(ctx, area < 0 ? 1 : -1, info.eye_orientation))) {
      out.counts.culled_backface += triangles;
      return;
    }
  }
  out.counts.triangles_rasterized += triangles;
  const bool lines = ctx.options.polygon_mode == PolygonMode::Line;
  for (std::size_t i = 0; i < wv.size(); ++i) {
    const WindowVertex& a = wv[i];
    const WindowVertex& b = wv[(i + 1) % wv.size()];
    if (lines) {
      if (poly[i].edge) out.lines.push_back({a.x, a.y, a.z, b.x, b.y, b.z, id, info.rgba});
    } else if (poly[i].original) {
      out.points.push_back({a.x, a.y, a.z, a.x, a.y, a.z, id, info.rgba});
    }
  }
}

void processPolygon(const Context& ctx, PolygonId id, const PrepareRequest& request, ChunkOut& out,
                    std::vector<Triangle>& tris) {
  const bool window_polygons = request.window_polygons;
  const Scene& scene = ctx.scene;
  const std::span<const std::uint32_t> vi = scene.polygon(id);
  const std::uint64_t triangles = vi.size() >= 3 ? vi.size() - 2 : 0;
  out.counts.triangles_in += triangles;
  if (ctx.object_state[scene.object(id)] == kObjectCulled) {
    out.counts.culled_frustum += triangles;
    return;
  }
  const PolygonMode mode = ctx.options.polygon_mode;
  if (vi.size() == 3 && mode == PolygonMode::Fill && !window_polygons &&
      fastTriangle(ctx, id, vi, out))
    return;
  PolygonInfo info = describePolygon(ctx, id, vi);
  if (info.degenerate) {
    out.counts.degenerate_dropped += triangles;
    return;
  }
  if (ctx.options.facing_test == FacingTest::EyePlane) {
    // The notes' test decides for the whole polygon at once.
    const bool front = (info.eye_orientation > 0) == (ctx.options.front_face == FrontFace::Ccw);
    if (culled(ctx.options.cull, front)) {
      out.counts.culled_backface += triangles;
      return;
    }
  }
  if (mode != PolygonMode::Fill) {
    outlinePolygon(ctx, id, vi, info, triangles, out);
    return;
  }
  if (window_polygons) emitWindowPolygon(ctx, id, vi, info, out);
  if (!request.triangles) return;
  // FILL: triangulate, then each triangle through clipping, projection and culling. Ear
  // clipping leaves out the zero-area corners of spikes and straight vertices.
  tris.clear();
  triangulatePolygon(scene, id, tris);
  out.counts.degenerate_dropped += triangles - tris.size();
  for (const Triangle& t : tris) {
    const glm::vec4 c[3] = {ctx.clip[t.v[0]], ctx.clip[t.v[1]], ctx.clip[t.v[2]]};
    if (info.planar) {
      clipAndEmitTriangle(ctx, c, id, info, out);
    } else {
      PolygonInfo own = forTriangle(info, t.v);
      clipAndEmitTriangle(ctx, c, id, own, out);
    }
  }
}

}  // namespace

namespace {

// Closes up the chunks' slots in `triangles` (each chunk's made() lies at or after where it
// belongs: right after the chunk before it when it could follow on, else in its own slot), or,
// where clipping made some chunk overflow its slot into a vector of its own, joins them all into a
// new array.
void joinTriangles(const std::vector<ChunkOut>& parts, ScreenTriangles& triangles) {
  const bool overflowed = std::any_of(parts.begin(), parts.end(), [&](const ChunkOut& p) {
    const std::span<const ScreenTriangle> made = p.triangles.made();
    return !made.empty() &&
           (made.data() < triangles.data() || made.data() >= triangles.data() + triangles.size());
  });
  if (!overflowed) {
    std::size_t end = 0;
    for (const ChunkOut& p : parts) {
      const std::span<const ScreenTriangle> made = p.triangles.made();
      if (made.data() != triangles.data() + end)  // forward, so overlapping is safe
        std::memmove(static_cast<void*>(triangles.data() + end), made.data(), made.size_bytes());
      end += made.size();
    }
    triangles.resize(end);
    return;
  }
  std::vector<std::size_t> offset(parts.size() + 1, 0);
  for (std::size_t c = 0; c < parts.size(); ++c)
    offset[c + 1] = offset[c] + parts[c].triangles.made().size();
  ScreenTriangles joined(offset.back());
  tbb::parallel_for(std::size_t(0), parts.size(), [&](std::size_t c) {
    const std::span<const ScreenTriangle> made = parts[c].triangles.made();
    std::copy(made.begin(), made.end(), joined.begin() + offset[c]);
  });
  triangles.swap(joined);
}

}  // namespace

void ChunkOut::reset() {
  triangles.reset(nullptr, 0);
  lines.clear();
  points.clear();
  polygons.clear();
  counts = Stats{};
}

struct PipelineScratch {
  std::vector<std::uint8_t> object_state;
  ClipVertices clip;
  VertexOuts verts;
  std::vector<ChunkOut> parts;
  std::vector<std::size_t> first;  // per chunk: where its slot starts in the output
  // Per chunk, once it is done: where its triangles end in the output, or kNoEnd when they
  // went to a vector of their own.
  std::unique_ptr<std::atomic<std::size_t>[]> end;
  std::size_t end_size = 0;
};

constexpr std::size_t kNoEnd = SIZE_MAX;

void prepare(const Scene& scene, const Camera& camera, const RenderOptions& options,
             const PrepareRequest& request, PreparedScene& out) {
  if (!out.scratch) out.scratch = std::make_shared<PipelineScratch>();
  PipelineScratch& scratch = *out.scratch;
  out.width = camera.width;
  out.height = camera.height;
  out.triangles.clear();
  out.lines.clear();
  out.points.clear();
  out.outline.clear();
  out.polygons.clear();
  out.stats = Stats{};
  out.stats.polygons_in = scene.polygonCount();

  // Transform: world -> eye -> clip for every vertex of an object not culled by its bounds.
  Stopwatch t0;
  const glm::mat4 mvp = camera.projection() * camera.view();
  // No guard band: x/y are clipped at the viewport, as llvmpipe does (its draw module runs
  // with guard_band_xy off), so edges of clipped triangles snap exactly as Mesa's do.
  const ClipSetup cs{1.0f, 1.0f};
  const Viewport vp = viewportOf(camera);
  cullObjects(scene, mvp, cs, options.frustum_cull, scratch.object_state);
  transformVertices(scene, mvp, cs, vp, scratch.object_state, scratch.clip, scratch.verts);
  out.stats.addStage("transform", t0.ms());

  // Cull, clip, project and snap, in fixed chunks of polygons joined in order.
  t0.restart();
  // Device coordinates (pixel-centre x, y down; window z) from clip coordinates, as toWindow
  // maps them; depth planes map by the inverse transpose of world -> device.
  const glm::dmat4 device_from_world = deviceFromWorld(camera);
  Context ctx{scene,
              camera,
              options,
              mvp,
              cs,
              vp,
              glm::normalize(glm::dvec3(camera.target) - glm::dvec3(camera.eye)),
              glm::transpose(glm::inverse(device_from_world)),
              device_from_world,
              glm::dmat4(camera.view()),
              scratch.clip,
              scratch.verts,
              scratch.object_state,
              {},
              {}};
  ctx.box_margin = request.samples ? kSampleMargin : 0;
  for (const Material& m : scene.materials) {
    ctx.material_rgb.push_back(materialRgb(m));
    ctx.material_alpha.push_back(materialAlphaBits(m));
  }
  ctx.material_rgb.push_back(Material{}.color);  // for a polygon naming no material
  ctx.material_alpha.push_back(0xFF000000u);
  const std::size_t n = scene.polygonCount();
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  std::vector<ChunkOut>& parts = scratch.parts;
  parts.resize(chunks);
  // Each chunk writes its triangles straight into the output, into a slot with room for as
  // many triangles as its polygons have; the slots are then closed up in chunk order. One
  // array on huge pages: a one-shot render first touches the output once, not a copy of it too.
  std::vector<std::size_t>& first = scratch.first;
  first.assign(chunks + 1, 0);
  if (request.triangles) {
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
      std::size_t expected = 0;
      for (std::size_t id = c * kChunk; id < std::min(n, (c + 1) * kChunk); ++id) {
        const std::size_t k = scene.polygon(static_cast<PolygonId>(id)).size();
        expected += k >= 3 ? k - 2 : 0;
      }
      first[c + 1] = expected;
    });
    for (std::size_t c = 0; c < chunks; ++c) first[c + 1] += first[c];
  }
  out.triangles.resize(first[chunks]);  // no fill: every triangle kept is written
  // A chunk whose predecessor is done when it starts writes its triangles right after that
  // one's (the room from there to its own slot's end holds at least as many as its own slot,
  // and no other chunk writes there), so that closing up moves nothing: at one thread the
  // chunks run in order and none moves; at more, each thread's run of chunks follows on.
  if (scratch.end_size < chunks) {
    scratch.end = std::make_unique<std::atomic<std::size_t>[]>(chunks);
    scratch.end_size = chunks;
  }
  std::atomic<std::size_t>* end_of = scratch.end.get();
  for (std::size_t c = 0; c < chunks; ++c) end_of[c].store(kNoEnd, std::memory_order_relaxed);
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
    ChunkOut& part = parts[c];
    part.reset();
    const std::size_t after = c > 0 ? end_of[c - 1].load(std::memory_order_acquire) : kNoEnd;
    const std::size_t start = after != kNoEnd ? after : first[c];
    part.triangles.reset(out.triangles.data() + start, first[c + 1] - start);
    part.batch.begin(ctx);
    std::vector<Triangle> tris;
    const std::size_t end = std::min(n, (c + 1) * kChunk);
    if (request.window_polygons) part.polygons.reserve(end - c * kChunk);
    for (std::size_t id = c * kChunk; id < end; ++id)
      processPolygon(ctx, static_cast<PolygonId>(id), request, part, tris);
    part.batch.flush(part.triangles);
    finishStreaming();
    const std::span<const ScreenTriangle> made = part.triangles.made();
    const bool in_place = made.empty() || made.data() == out.triangles.data() + start;
    end_of[c].store(in_place ? start + made.size() : kNoEnd, std::memory_order_release);
  });
  joinTriangles(parts, out.triangles);
  std::size_t polygons = 0;
  for (const ChunkOut& p : parts) polygons += p.polygons.size();
  out.polygons.reserve(polygons);
  for (ChunkOut& p : parts) {
    out.lines.insert(out.lines.end(), p.lines.begin(), p.lines.end());
    out.points.insert(out.points.end(), p.points.begin(), p.points.end());
    for (WindowPolygon& wp : p.polygons) out.polygons.push_back(std::move(wp));
    out.stats.merge(p.counts);
  }
  out.stats.lines_rasterized = out.lines.size();
  out.stats.points_rasterized = out.points.size();
  out.stats.addStage("cull+clip+project", t0.ms());

  if (options.outline) {
    t0.restart();
    findOutline(ctx, out);
    out.stats.addStage("outline", t0.ms());
  }
}

bool boxOutsideFrustum(const glm::dmat4& clip_from_world, const glm::dvec3& lo,
                       const glm::dvec3& hi) {
  glm::dvec4 c[8];
  for (int i = 0; i < 8; ++i)
    c[i] = clip_from_world *
           glm::dvec4((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z, 1.0);
  for (int axis = 0; axis < 3; ++axis)
    for (const double sign : {-1.0, 1.0}) {
      bool all_out = true;
      for (const glm::dvec4& p : c) all_out = all_out && sign * p[axis] > p.w;
      if (all_out) return true;
    }
  return false;
}

glm::dmat4 deviceFromWorld(const Camera& camera) {
  const glm::mat4 mvp = camera.projection() * camera.view();
  const double w = camera.width, h = camera.height;
  glm::dmat4 device_from_clip(1.0);
  device_from_clip[0][0] = w * 0.5;
  device_from_clip[1][1] = -h * 0.5;
  device_from_clip[2][2] = 0.5;
  device_from_clip[3] = glm::dvec4(w * 0.5 - 0.5, h * 0.5 - 0.5, 0.5, 1.0);
  return device_from_clip * glm::dmat4(mvp);
}

}  // namespace hsr::detail

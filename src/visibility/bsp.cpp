// Rendering from a BSP tree (bsp_tree.hpp), as the notes give it: at each node, find which
// side of the node's plane the eye is on; draw the subtree on the far side, then the node's
// own polygons, then the subtree on the eye's side. Drawn that way every polygon comes after
// everything that could be behind it, for any eye, with no depth test and no sort: a painter's
// order from one tree that serves every viewpoint.
//
//   eye in front of the plane:  back subtree, node polygons, front subtree
//   eye behind the plane:       front subtree, node polygons, back subtree
//   eye on the plane:           back subtree, front subtree (the node's polygons are edge-on)
//
// The improved traversal skips a subtree whose bounds lie wholly outside one plane of the view
// frustum (the near plane among them: behind the eye). With an orthographic camera the eye is
// the point at infinity behind it: its side of a plane is the side the view direction leaves.
//
// Each polygon of the tree is drawn as its pipeline polygon (culled, clipped, projected and
// shaded by the shared pipeline, so with its id, colour and depth plane) restricted to its
// side of every plane that cut it: a world plane restricted to the polygon's own plane is a
// line of the picture, and the two pieces of one cut take opposite sides of the same line, so
// they share out the parent's pixels exactly (raster/fill_polygons.hpp, paintPolygonPart).
// Coplanar polygons at one node paint as a group (the nearer float wins among them).
// Guarantee: each pixel shows the nearest polygon at its centre, as the z-buffer does, up to
// the tree's epsilon (a polygon within it of a plane is on it) and paintPolygonPart's ties
// (equal floats show the lower id; a float step apart, the nearer). Cost: O(nodes) to
// traverse plus the pixels painted; front to back on request. Tests: bsp_test.cpp.
//
// Tests: tests/visibility/bsp_test.cpp and every suite of the registry its capabilities join.

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "core/frame.hpp"
#include "hsr/bsp.hpp"
#include "core/stopwatch.hpp"
#include "raster/edge.hpp"
#include "raster/fill_polygons.hpp"
#include "visibility/algorithm.hpp"
#include "visibility/bsp.hpp"

namespace hsr::detail {

namespace {

// The steps `hsr explain bsp` shows: the tree being built node by node, then the polygons
// painted in the traversal's order.
constexpr std::string_view kStepSplitter = "choose splitter";
constexpr std::string_view kStepPaint = "paint";
constexpr std::string_view kStepDone = "done";

// A world polygon's outline in the picture (empty when a vertex lies behind the eye).
TraceOutline projectOutline(const std::vector<glm::dvec3>& vertices,
                            const glm::dmat4& device_from_world) {
  TraceOutline out;
  for (const glm::dvec3& v : vertices) {
    const glm::dvec4 h = device_from_world * glm::dvec4(v, 1.0);
    if (!(h.w > 0)) return {};
    out.emplace_back(static_cast<float>(h.x / h.w), static_cast<float>(h.y / h.w));
  }
  return out;
}

// The notes show a BSP tree being built from above, as a plan: the build steps are pictured
// on the scene seen from above (orthographic, looking down the camera's up axis, the view
// direction pointing up the picture), with the eye marked.
Camera birdsEye(const Scene& scene, const Camera& camera) {
  const Bounds b = scene.bounds();
  const float r = std::max(b.radius(), 1e-3f);
  const glm::vec3 up = glm::normalize(camera.up);
  glm::vec3 forward = camera.target - camera.eye;
  forward -= up * glm::dot(forward, up);
  if (!(glm::length(forward) > 1e-6f * glm::length(camera.target - camera.eye)))
    forward = glm::cross(up, glm::vec3(1, 0, 0));
  if (!(glm::length(forward) > 0)) forward = glm::cross(up, glm::vec3(0, 0, 1));
  Camera top = camera;
  top.ortho = true;
  top.ortho_half_height = 1.15f * r;
  top.target = b.center();
  top.eye = b.center() + up * (3.0f * r);
  top.up = glm::normalize(forward);
  top.near = r;
  top.far = 5.0f * r;
  return top;
}

// The pixels a piece may paint: the box of its parent's outline clipped by the piece's cut
// lines (the very lines its pixels are tested against), one pixel more each way for the
// snapping of the outline. Empty (x0 > x1) when nothing is left.
PixelBox pieceBox(const std::vector<glm::dvec2>& outline, const std::vector<PixelHalfPlane>& cuts,
                  const Frame& frame, std::vector<glm::dvec2>& region,
                  std::vector<glm::dvec2>& next) {
  region = outline;
  for (const PixelHalfPlane& h : cuts) {
    next.clear();
    // Keep the side the piece owns, with a margin of a thousandth of a pixel: only the box is
    // made here, never the decision for a pixel.
    const double margin = 1e-3 * std::hypot(h.a, h.b);
    auto inside = [&](const glm::dvec2& v) {
      const double value = (h.c + h.b * v.y) + h.a * v.x;
      return (h.negative ? -value : value) >= -margin;
    };
    auto value = [&](const glm::dvec2& v) {
      return (h.c + h.b * v.y) + h.a * v.x + (h.negative ? -margin : margin);
    };
    for (std::size_t i = 0; i < region.size(); ++i) {
      const glm::dvec2& u = region[i];
      const glm::dvec2& v = region[(i + 1) % region.size()];
      if (inside(u)) next.push_back(u);
      if (inside(u) != inside(v)) {
        const double fu = value(u), fv = value(v);
        next.push_back(u + (fu / (fu - fv)) * (v - u));
      }
    }
    region.swap(next);
    if (region.empty()) return {0, 0, -1, -1};
  }
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const glm::dvec2& v : region)
    x0 = std::min(x0, v.x), x1 = std::max(x1, v.x), y0 = std::min(y0, v.y), y1 = std::max(y1, v.y);
  if (!(x1 - x0 < 1e7 && y1 - y0 < 1e7)) return {0, 0, frame.width - 1, frame.height - 1};
  return {std::max(0, static_cast<int>(std::floor(x0)) - 1),
          std::max(0, static_cast<int>(std::floor(y0)) - 1),
          std::min(frame.width - 1, static_cast<int>(std::ceil(x1)) + 1),
          std::min(frame.height - 1, static_cast<int>(std::ceil(y1)) + 1)};
}

}  // namespace

void forEachBspPolygon(const BspTree& tree, const Camera& camera, bool front_to_back,
                       const std::function<void(const BspPolygon&, std::uint32_t)>& draw,
                       BspTraversalStats* stats) {
  if (tree.nodes.empty()) return;
  const glm::dmat4 clip_from_world = glm::dmat4(camera.projection()) * glm::dmat4(camera.view());
  const glm::dvec3 eye(camera.eye);
  const glm::dvec3 toward_eye = glm::normalize(glm::dvec3(camera.eye) - glm::dvec3(camera.target));
  // The eye's side of a node's plane: +1 in front, -1 behind, 0 on it.
  auto sideOfEye = [&](const BspNode& n) {
    if (camera.ortho) {
      const double d = glm::dot(glm::dvec3(n.plane), toward_eye);
      return d > 0 ? 1 : d < 0 ? -1 : 0;
    }
    return eyeSide(n, eye);
  };
  // A stack of work: a subtree to visit, or a node whose own polygons are due.
  struct Item {
    std::int32_t node;
    bool own;
  };
  std::vector<Item> stack{{0, false}};
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    const BspNode& n = tree.nodes[item.node];
    if (item.own) {
      for (std::uint32_t k = 0; k < n.polygon_count; ++k) {
        if (stats) ++stats->drawn;
        draw(tree.polygons[n.first_polygon + k], static_cast<std::uint32_t>(item.node));
      }
      continue;
    }
    if (boxOutsideFrustum(clip_from_world, n.lo, n.hi)) {
      if (stats) ++stats->skipped;
      continue;
    }
    if (stats) ++stats->visited;
    const int side = sideOfEye(n);
    // Back to front: the far side first. The stack runs last in, first out.
    std::int32_t far = side >= 0 ? n.back : n.front, near = side >= 0 ? n.front : n.back;
    if (front_to_back) std::swap(far, near);
    if (near >= 0) stack.push_back({near, false});
    if (side != 0) stack.push_back({item.node, true});
    if (far >= 0) stack.push_back({far, false});
  }
}

void drawBsp(const AlgorithmInput& in, Frame& frame) {
  detail::Stopwatch t0;
  BspTree built;
  if (!in.given) {
    // Explained: each node's step is noted as the tree is built and recorded once the build
    // has said how many nodes there are (a few evenly spaced are kept). The steps are seen on
    // the plan from above, which src/explain/ draws.
    struct NodeStep {
      std::uint32_t node;
      std::string caption;
      std::vector<TraceOutline> outlines;
    };
    std::vector<NodeStep> node_steps;
    std::function<void(const BspNodeReport&)> report;
    const Camera top = in.trace ? birdsEye(in.scene, in.camera) : Camera{};
    const glm::dmat4 plan_from_world = in.trace ? deviceFromWorld(top) : glm::dmat4(1.0);
    if (in.trace) {
      report = [&](const BspNodeReport& r) {
        std::vector<TraceOutline> outlines{projectOutline(r.splitter_vertices, plan_from_world)};
        for (const std::vector<glm::dvec3>& v : r.split)
          outlines.push_back(projectOutline(v, plan_from_world));
        // The eye: a small square, and a line to what it looks at.
        const glm::dvec4 e = plan_from_world * glm::dvec4(glm::dvec3(in.camera.eye), 1.0);
        const glm::dvec4 t = plan_from_world * glm::dvec4(glm::dvec3(in.camera.target), 1.0);
        const glm::vec2 tp(static_cast<float>(t.x / t.w), static_cast<float>(t.y / t.w));
        glm::vec2 ep(static_cast<float>(e.x / e.w), static_cast<float>(e.y / e.w));
        // An eye beyond the picture is marked at its edge, in its direction from the target.
        const glm::vec2 lo(6.0f),
            hi(static_cast<float>(top.width) - 7.0f, static_cast<float>(top.height) - 7.0f);
        for (int axis = 0; axis < 2; ++axis) {
          const float d = ep[axis] - tp[axis];
          if (ep[axis] > hi[axis] && d > 0) ep = tp + (ep - tp) * ((hi[axis] - tp[axis]) / d);
          if (ep[axis] < lo[axis] && d < 0) ep = tp + (ep - tp) * ((lo[axis] - tp[axis]) / d);
        }
        outlines.push_back({ep + glm::vec2(-3, -3), ep + glm::vec2(3, -3), ep + glm::vec2(3, 3),
                            ep + glm::vec2(-3, 3)});
        outlines.push_back({ep, tp});
        node_steps.push_back(
            {r.node,
             "Node " + std::to_string(r.node) + " (depth " + std::to_string(r.depth) +
                 "): polygon " + std::to_string(r.splitter) + " is chosen from a list of " +
                 std::to_string(r.list) + "; its plane sorts the others: " +
                 std::to_string(r.front) + " in front, " + std::to_string(r.behind) +
                 " behind (pieces included), " + std::to_string(r.split.size()) +
                 " split in two (outlined), " + std::to_string(r.on - 1) +
                 " more in its plane stay at the node. Seen from above: the eye is the small "
                 "square, looking along the line.",
             std::move(outlines)});
      };
    }
    built = buildBspTree(in.scene, in.options.bsp, {}, report);
    frame.stats.addStage("bsp build", t0.ms());
    for (NodeStep& step : node_steps)
      if (in.trace->wants(kStepSplitter, step.node, built.stats.nodes))
        in.trace->record(
            {kStepSplitter, std::move(step.caption), nullptr, std::move(step.outlines), &top});
  }
  const BspTree& tree = in.given ? *static_cast<const BspTree*>(in.given) : built;
  t0.restart();
  paintFromBspTree(tree, in, frame);
  frame.stats.addStage("bsp traverse + paint", t0.ms());
  frame.stats.state_bytes += tree.stats.bytes;
  frame.stats.addCounter("bsp: polygons in the tree", tree.stats.polygons);
  frame.stats.addCounter("bsp: splits", tree.stats.splits);
  frame.stats.addCounter("bsp: nodes", tree.stats.nodes);
  frame.stats.addCounter("bsp: depth", tree.stats.depth);
}

void paintFromBspTree(const BspTree& tree, const AlgorithmInput& in, Frame& frame) {
  const FrameView fb(frame);
  FragmentCounts fragments;
  const std::vector<WindowPolygon>& polygons = in.prepared.polygons;
  // The pipeline's polygons by id (a polygon culled or clipped away has none).
  std::vector<std::int32_t> by_id(in.scene.polygonCount(), -1);
  for (std::size_t i = 0; i < polygons.size(); ++i)
    if (polygons[i].id < by_id.size() && by_id[polygons[i].id] < 0)
      by_id[polygons[i].id] = static_cast<std::int32_t>(i);
  std::vector<glm::dvec2> outline, region, next;  // reused from polygon to polygon
  const glm::dmat4 device_from_world = deviceFromWorld(in.camera);
  const glm::dmat4 device_plane_from_world_plane = glm::transpose(glm::inverse(device_from_world));
  const glm::dmat4 device_plane_from_eye_plane =
      glm::transpose(glm::inverse(device_from_world * glm::inverse(glm::dmat4(in.camera.view()))));
  std::vector<PixelHalfPlane> cuts;
  std::vector<std::uint32_t> stamps;
  PaintGroup group;
  if (std::any_of(tree.nodes.begin(), tree.nodes.end(),
                  [](const BspNode& n) { return n.polygon_count > 1; })) {
    stamps.assign(static_cast<std::size_t>(frame.width) * frame.height, 0);
    group.stamps = stamps;
  }
  BspTraversalStats traversal;
  std::uint64_t painted = 0, to_paint = 0;
  if (in.trace)
    forEachBspPolygon(tree, in.camera, false,
                      [&](const BspPolygon&, std::uint32_t) { ++to_paint; });
  forEachBspPolygon(
      tree, in.camera, false,
      [&](const BspPolygon& p, std::uint32_t node) {
        if (p.id >= by_id.size() || by_id[p.id] < 0) return;
        std::size_t index = static_cast<std::size_t>(by_id[p.id]);
        while (index < polygons.size() && polygons[index].id == p.id &&
               polygons[index].piece != p.piece)
          ++index;
        if (index == polygons.size() || polygons[index].id != p.id)
          return;  // that triangle was culled
        const WindowPolygon& w = polygons[index];
        outline.clear();
        for (const glm::dvec3& v : w.vertices) outline.emplace_back(v.x, v.y);
        // Each cut's plane in device space, restricted to the polygon's own plane: the pixels
        // (x, y) on the piece's side. For a point in front of the eye (clip w > 0) the device
        // plane's value has the world plane's sign. The polygon's plane is its eye-space plane
        // carried to device space in double (its depth plane, made for writing floats, could
        // move a line cutting at a grazing angle by pixels); every piece of one polygon uses the
        // same, so two pieces of one cut take the two sides of one line.
        const glm::dvec4 own = device_plane_from_eye_plane * w.eye_plane;
        const bool edge_on =
            !(std::abs(own.z) > 1e-12 * (std::abs(own.x) + std::abs(own.y) + std::abs(own.w)));
        cuts.clear();
        for (std::uint32_t c = 0; c < p.cut_count; ++c) {
          const BspCut& cut = tree.cuts[p.first_cut + c];
          const glm::dvec4 d = device_plane_from_world_plane * tree.nodes[cut.node].plane;
          if (edge_on)
            cuts.push_back({d.x + d.z * w.depth.dzdx, d.y + d.z * w.depth.dzdy,
                            d.w + d.z * w.depth.z0, !cut.front});
          else
            cuts.push_back({d.x - d.z * own.x / own.z, d.y - d.z * own.y / own.z,
                            d.w - d.z * own.w / own.z, !cut.front});
        }
        const PixelBox box = pieceBox(outline, cuts, frame, region, next);
        if (box.x0 > box.x1) return;
        // Coplanar polygons at one node paint as a group: among themselves, the nearer float
        // depth wins, as in the z-buffer.
        group.stamp = node + 1;
        paintPolygonPart(outline, cuts, box, w.depth, w.id, w.rgba, fb, fragments,
                         tree.nodes[node].polygon_count > 1 ? &group : nullptr);
        if (in.trace && in.trace->wants(kStepPaint, painted, to_paint)) {
          const int side =
              in.camera.ortho ? 0 : eyeSide(tree.nodes[node], glm::dvec3(in.camera.eye));
          in.trace->record({kStepPaint,
                            "Paint polygon " + std::to_string(p.id) +
                                (p.cut_count == 1  ? std::string(" (a piece of it, cut once)")
                                 : p.cut_count > 1 ? " (a piece of it, cut " +
                                                         std::to_string(p.cut_count) + " times)"
                                                   : std::string()) +
                                ", held by node " + std::to_string(node) + ": " +
                                (side > 0 ? "the eye is in front of its plane, so the node's back "
                                            "subtree is already painted"
                                 : side < 0 ? "the eye is behind its plane, so the node's front "
                                              "subtree is already painted"
                                            : "the far side of its plane is already painted") +
                                "; the near side comes after it.",
                            &frame,
                            {projectOutline(p.vertices, device_from_world)}});
        }
        ++painted;
      },
      &traversal);
  frame.stats.fragments_tested += fragments.tested;
  frame.stats.fragments_written += fragments.written;
  frame.stats.state_bytes += frameBufferBytes(frame) + stamps.capacity() * sizeof(std::uint32_t);
  frame.stats.addCounter("bsp: polygons drawn", traversal.drawn);
  frame.stats.addCounter("bsp: nodes visited", traversal.visited);
  frame.stats.addCounter("bsp: subtrees skipped", traversal.skipped);
  if (in.trace && in.trace->wants(kStepDone, 0, 1))
    in.trace->record({kStepDone,
                      "Done: " + std::to_string(traversal.drawn) +
                          " polygons and pieces painted back to front with no depth "
                          "test, " +
                          std::to_string(traversal.skipped) +
                          " subtrees outside the view skipped; the same tree "
                          "serves any other eye.",
                      &frame,
                      {}});
}

}  // namespace hsr::detail

namespace hsr {

std::vector<PolygonId> bspOrder(const Bsp& bsp, const Camera& camera, bool front_to_back) {
  camera.validate();
  std::vector<PolygonId> order;
  detail::forEachBspPolygon(
      bsp.tree(), camera, front_to_back,
      [&](const detail::BspPolygon& p, std::uint32_t) { order.push_back(p.id); });
  return order;
}

}  // namespace hsr

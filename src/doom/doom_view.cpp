// A Doom level seen the way Doom's renderer sees it: the 2D BSP walked front to back, walls
// drawn column by column, each column closed by the nearest solid wall (Doom's R_RenderBSPNode,
// R_AddLine, R_StoreWallRange and R_RenderSegLoop, in floating point through hsr's camera).
//
//   1. Walk the tree from the root: at each node visit first the child on the eye's side of
//      the partition line, then the other, until every column is closed.
//   2. In a subsector, take each seg that faces the eye, cut it at the near plane and project
//      its ends to the columns it spans.
//   3. For each of those columns not yet closed, at the point of the seg seen through the
//      column's centre: the ceiling from the top of the column's opening down to the wall, the
//      upper wall (down to the sector behind's ceiling) or, for a one-sided line, the middle
//      wall, which closes the column; then the lower wall and the floor down to the bottom of
//      the opening. The opening shrinks to what the upper and lower walls leave: farther segs
//      draw only there (Doom's ceilingclip and floorclip).
//
// No depth is compared anywhere: the order of the walk is the visibility. Floors and ceilings
// are found pixel by pixel on their plane (the point the pixel's ray meets at the sector's
// height, down the tree to its subsector), so that their ids are the level scene's.
// The guarantee: pixel centres inside a wall's projection get the wall's id exactly as a
// z-buffer of the level scene gives them, except at column and row edges (a centre on an edge,
// and the z-buffer's snapped vertices); tests/doom/doom_test.cpp measures the agreement.
// Cost: O(segs visited + pixels); memory: the frame and two rows of clips.

#include <algorithm>
#include <cmath>

#include <fmt/core.h>

#include "core/frame.hpp"
#include "hsr/doom.hpp"
#include "hsr/error.hpp"
#include "pipeline/pipeline.hpp"
#include "doom/doom_view.hpp"

namespace hsr::doom {
namespace {

class ColumnRenderer {
 public:
  ColumnRenderer(const Map& map, const Nodes& nodes, const Level& level, const Camera& camera,
                 Frame& frame, std::vector<ViewStep>* steps, detail::Trace* trace,
                 std::uint64_t traced_segs)
      : map_(map),
        nodes_(nodes),
        level_(level),
        camera_(camera),
        frame_(frame),
        steps_(steps),
        trace_(trace),
        traced_segs_(traced_segs),
        m_(detail::deviceFromWorld(camera)),
        world_from_device_(glm::inverse(m_)),
        ceiling_clip_(std::size_t(camera.width), -1),
        floor_clip_(std::size_t(camera.width), camera.height),
        solid_(std::size_t(camera.width), 0),
        open_columns_(camera.width) {}

  // Step 1: the walk, front to back, with a stack.
  void walk() {
    std::vector<std::uint16_t> stack;
    stack.push_back(nodes_.nodes.empty() ? std::uint16_t(kSubsectorBit)
                                         : static_cast<std::uint16_t>(nodes_.nodes.size() - 1));
    std::size_t visits = 0;
    while (!stack.empty() && open_columns_ > 0) {
      const std::uint16_t child = stack.back();
      stack.pop_back();
      if (++visits > 2 * nodes_.nodes.size() + 1) throw Error("the nodes are not one tree");
      if (child & kSubsectorBit) {
        subsector(static_cast<std::uint16_t>(child & ~kSubsectorBit));
        continue;
      }
      const Node& n = nodes_.nodes.at(child);
      const double side =
          double(n.dx) * (camera_.eye.y - n.y) - double(n.dy) * (camera_.eye.x - n.x);
      const int near = side < 0 ? 0 : 1;  // Doom's R_PointOnSide: the right is the front
      stack.push_back(n.child[std::size_t(1 - near)]);
      stack.push_back(n.child[std::size_t(near)]);
    }
  }

 private:
  // Device x (pixel centres at integers) and clip w of a map point; both ignore height.
  double devX(double x, double y) const {
    return (m_[0][0] * x + m_[1][0] * y + m_[3][0]) / clipW(x, y);
  }
  double clipW(double x, double y) const { return m_[0][3] * x + m_[1][3] * y + m_[3][3]; }
  // Device y (top row 0, centres at integers) of height z at a map point with clip w `w`.
  double devY(double x, double y, double z, double w) const {
    return (m_[0][1] * x + m_[1][1] * y + m_[2][1] * z + m_[3][1]) / w;
  }
  double devZ(double x, double y, double z, double w) const {
    return (m_[0][2] * x + m_[1][2] * y + m_[2][2] * z + m_[3][2]) / w;
  }
  // The first row whose centre lies at or below device y: rows [rowAt(a), rowAt(b)) lie in [a, b).
  static int rowAt(double y) { return static_cast<int>(std::ceil(std::clamp(y, -1e6, 1e6))); }

  void subsector(std::uint16_t ss) {
    const Subsector& s = nodes_.subsectors.at(ss);
    if (std::size_t(s.first) + s.count > nodes_.segs.size())
      throw Error("a subsector's segs out of range");
    for (std::size_t i = s.first; i < std::size_t(s.first) + s.count && open_columns_ > 0; ++i)
      seg(i);
  }

  // Step 2.
  void seg(std::size_t index) {
    const Seg& sg = nodes_.segs[index];
    const Vertex& va = nodes_.vertices[sg.v1];
    const Vertex& vb = nodes_.vertices[sg.v2];
    double ax = va.x, ay = va.y, bx = vb.x, by = vb.y;
    const double dx = bx - ax, dy = by - ay;
    if (dx * (camera_.eye.y - ay) - dy * (camera_.eye.x - ax) >= 0)
      return;  // faces away (or edge-on)
    // Cut at the near plane: keep w >= near.
    const double near = camera_.near;
    double wa = clipW(ax, ay), wb = clipW(bx, by);
    if (wa < near && wb < near) return;
    if (wa < near) {
      const double t = (near - wa) / (wb - wa);
      ax += t * dx, ay += t * dy, wa = near;
    } else if (wb < near) {
      const double t = (near - wb) / (wa - wb);
      bx -= t * dx, by -= t * dy, wb = near;
    }
    const double xa = devX(ax, ay), xb = devX(bx, by);
    const int x0 = std::max(0, rowAt(std::min(xa, xb))),
              x1 = std::min(camera_.width, rowAt(std::max(xa, xb)));
    if (x0 >= x1) return;

    const Linedef& l = map_.linedefs[sg.linedef];
    const Sector& front = map_.sectors[map_.sidedefs[l.side[std::size_t(sg.side) & 1]].sector];
    const std::uint16_t back_side = l.side[std::size_t(1 - (sg.side & 1))];
    const Sector* back =
        back_side == kNoSide ? nullptr : &map_.sectors[map_.sidedefs[back_side].sector];
    ViewStep step{static_cast<std::uint16_t>(index), x0, x1, 0, back == nullptr};
    for (int x = x0; x < x1; ++x) {
      if (solid_[std::size_t(x)]) continue;
      ++step.drawn;
      column(x, va, vb, sg, front, back);
    }
    if (step.drawn == 0) return;
    if (steps_) steps_->push_back(step);
    ++segs_drawn_;
    if (trace_ && trace_->wants(detail::kStepDrawSeg, segs_drawn_ - 1, traced_segs_)) {
      const float left = float(x0) - 0.5f, right = float(x1) - 0.5f,
                  bottom = float(camera_.height) - 0.5f;
      trace_->record(
          {detail::kStepDrawSeg,
           fmt::format(
               "Seg {}, the {} side of linedef {}, spans columns {} to {}; the {} of them "
               "still open get its walls{}. {} columns remain open.{}",
               index, sg.side ? "back" : "front", sg.linedef, x0, x1 - 1, step.drawn,
               back ? ", and what lies beyond may draw only in the opening its upper and lower "
                      "walls leave"
                    : " and close (a one-sided line)",
               open_columns_,
               segs_drawn_ == 1 ? " Segs come front to back: at each node the tree is walked on "
                                  "the eye's side of the partition line first."
                                : ""),
           &frame_,
           {{{left, -0.5f}, {right, -0.5f}, {right, bottom}, {left, bottom}}}});
    }
  }

  // Step 3, one column.
  void column(int x, const Vertex& va, const Vertex& vb, const Seg& sg, const Sector& front,
              const Sector* back) {
    // The point of the seg's line seen through the column's centre.
    const double r0a = m_[0][0] * va.x + m_[1][0] * va.y + m_[3][0], r3a = clipW(va.x, va.y);
    const double r0d = m_[0][0] * (vb.x - va.x) + m_[1][0] * (vb.y - va.y);
    const double r3d = m_[0][3] * (vb.x - va.x) + m_[1][3] * (vb.y - va.y);
    const double denom = r0d - x * r3d;
    if (denom == 0) return;
    const double s = (x * r3a - r0a) / denom;
    const double px = va.x + s * (vb.x - va.x), py = va.y + s * (vb.y - va.y);
    const double w = clipW(px, py);
    if (!(w > 0)) return;
    const float depth = static_cast<float>(devZ(px, py, 0, w));
    const double contrast = va.y == vb.y ? 0.85 : va.x == vb.x ? 1.0 : 0.93;
    int& top = ceiling_clip_[std::size_t(x)];
    int& bottom = floor_clip_[std::size_t(x)];
    const int wall_top = rowAt(devY(px, py, front.ceiling, w));
    const int wall_bottom = rowAt(devY(px, py, front.floor, w));
    const std::uint32_t linedef = sg.linedef;
    const int side = sg.side & 1;

    // The ceiling above the wall and the floor below it (Doom marks them where this line
    // changes the height; a two-sided line between equal heights leaves them to what lies
    // beyond).
    const bool mark_ceiling = !back || back->ceiling != front.ceiling;
    const bool mark_floor = !back || back->floor != front.floor;
    if (mark_ceiling) flat(x, top + 1, std::min(wall_top, bottom), front.ceiling, true);
    if (mark_floor) flat(x, std::max(wall_bottom, top + 1), bottom, front.floor, false);

    if (!back) {
      fill(x, std::max(wall_top, top + 1), std::min(wall_bottom, bottom),
           level_.wall(linedef, side, WallPart::kMiddle), depth, w, contrast);
      close(x);
      return;
    }
    int new_top = top, new_bottom = bottom;
    if (back->ceiling < front.ceiling) {
      const int upper_bottom = rowAt(devY(px, py, std::max<double>(back->ceiling, front.floor), w));
      fill(x, std::max(wall_top, top + 1), std::min(upper_bottom, bottom),
           level_.wall(linedef, side, WallPart::kUpper), depth, w, contrast);
      new_top = std::max(top, std::min(upper_bottom, bottom) - 1);
    } else if (mark_ceiling) {
      new_top = std::max(top, std::min(wall_top, bottom) - 1);
    }
    if (back->floor > front.floor) {
      const int lower_top = rowAt(devY(px, py, std::min<double>(back->floor, front.ceiling), w));
      fill(x, std::max(lower_top, top + 1), std::min(wall_bottom, bottom),
           level_.wall(linedef, side, WallPart::kLower), depth, w, contrast);
      new_bottom = std::min(bottom, std::max(lower_top, top + 1));
    } else if (mark_floor) {
      new_bottom = std::min(bottom, std::max(wall_bottom, top + 1));
    }
    top = new_top, bottom = new_bottom;
    if (top + 1 >= bottom) close(x);
  }

  void close(int x) {
    if (!solid_[std::size_t(x)]) solid_[std::size_t(x)] = 1, --open_columns_;
  }

  void put(int x, int row, PolygonId id, float depth, double distance, double contrast = 1.0) {
    const std::size_t p = std::size_t(row) * std::size_t(camera_.width) + std::size_t(x);
    frame_.ids[p] = id;
    frame_.depth[p] = depth;
    frame_.color[p] = colour(id, distance, contrast);
    ++frame_.overdraw[p];
    ++frame_.stats.fragments_written;
  }

  void fill(int x, int from, int to, PolygonId id, float depth, double distance, double contrast) {
    from = std::max(from, 0), to = std::min(to, camera_.height);
    if (id == kNoPolygon) return;
    for (int row = from; row < to; ++row) put(x, row, id, depth, distance, contrast);
  }

  // Rows [from, to) of column x on the plane at `height`: each pixel's ray to the plane, the
  // point down the tree to its subsector, that subsector's floor or ceiling.
  void flat(int x, int from, int to, double height, bool ceiling) {
    from = std::max(from, 0), to = std::min(to, camera_.height);
    for (int row = from; row < to; ++row) {
      const glm::dvec4 far = world_from_device_ * glm::dvec4(x, row, 1.0, 1.0);
      const glm::dvec3 eye(camera_.eye), dir = glm::dvec3(far) / far.w - eye;
      if (dir.z == 0) continue;
      const double t = (height - eye.z) / dir.z;
      if (!(t > 0)) continue;
      const double px = eye.x + t * dir.x, py = eye.y + t * dir.y;
      const std::uint16_t ss = subsectorAt(nodes_, px, py);
      const PolygonId id = (ceiling ? level_.ceilings : level_.floors)[ss];
      if (id == kNoPolygon) continue;
      const double w = clipW(px, py);
      put(x, row, id, static_cast<float>(devZ(px, py, height, w)), w);
    }
  }

  // The material's colour dimmed with distance as Doom dims it (full up close, a quarter far
  // off), walls along the map's x axis a little darker than those along y (Doom's "fake
  // contrast"): a picture to read, not data (the ids and depth are).
  std::uint32_t colour(PolygonId id, double distance, double contrast) const {
    const std::uint32_t m = level_.scene.material(id);
    const glm::vec3 c =
        m < level_.scene.materials.size() ? level_.scene.materials[m].color : glm::vec3(0.8f);
    const double light = std::clamp(1.25 - distance / 2400.0, 0.25, 1.0) * contrast;
    const auto byte = [&](float v) {
      return std::uint32_t(std::clamp(std::lround(v * light * 255.0), 0l, 255l));
    };
    return byte(c.r) | byte(c.g) << 8 | byte(c.b) << 16 | 0xFF000000u;
  }

  const Map& map_;
  const Nodes& nodes_;
  const Level& level_;
  const Camera& camera_;
  Frame& frame_;
  std::vector<ViewStep>* steps_;
  detail::Trace* trace_;
  std::uint64_t traced_segs_, segs_drawn_ = 0;
  glm::dmat4 m_, world_from_device_;
  std::vector<int> ceiling_clip_, floor_clip_;  // per column: the rows above and below the opening
  std::vector<char> solid_;
  int open_columns_;
};

}  // namespace

Frame renderView(const Map& map, const Nodes& nodes, const Level& level, const Camera& camera,
                 std::vector<ViewStep>* trace) {
  return detail::renderDoomView(map, nodes, level, camera, trace, nullptr);
}

Agreement wallAgreement(const Level& level, const Frame& view, const Frame& reference) {
  if (view.width != reference.width || view.height != reference.height)
    throw Error("wallAgreement: frames of different sizes");
  Agreement a;
  const int w = reference.width, h = reference.height;
  const auto id = [&](int x, int y) {
    return reference.ids[std::size_t(y) * std::size_t(w) + std::size_t(x)];
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const PolygonId r = id(x, y);
      if (r == kNoPolygon || !level.isWall(r)) continue;
      ++a.wall_pixels;
      if (view.ids[std::size_t(y) * std::size_t(w) + std::size_t(x)] == r) {
        ++a.same;
        continue;
      }
      bool edge = false;
      for (int dy = -1; dy <= 1 && !edge; ++dy)
        for (int dx = -1; dx <= 1 && !edge; ++dx) {
          const int nx = x + dx, ny = y + dy;
          edge = nx < 0 || ny < 0 || nx >= w || ny >= h || id(nx, ny) != r;
        }
      if (!edge) ++a.away_from_edges;
    }
  return a;
}

}  // namespace hsr::doom

namespace hsr::detail {

Frame renderDoomView(const doom::Map& map, const doom::Nodes& nodes, const doom::Level& level,
                     const Camera& camera, std::vector<doom::ViewStep>* steps, Trace* trace) {
  camera.validate();
  if (camera.ortho) throw Error("the Doom view is a perspective view");
  Frame frame;
  // Traced: a first pass counts the segs drawn, so that the trace can space its pictures.
  std::vector<doom::ViewStep> counted;
  if (trace) {
    clearFrame(frame, camera.width, camera.height, RenderOptions{});
    doom::ColumnRenderer(map, nodes, level, camera, frame, &counted, nullptr, 0).walk();
  }
  clearFrame(frame, camera.width, camera.height, RenderOptions{});
  frame.stats.polygons_in = level.scene.polygonCount();
  doom::ColumnRenderer renderer(map, nodes, level, camera, frame, steps, trace, counted.size());
  renderer.walk();
  if (trace && trace->wants(kStepAllClosed, 0, 1))
    trace->record(
        {kStepAllClosed,
         fmt::format(
             "{} segs drew {} pixels; the walk stopped when every column was closed or the tree "
             "was done. No depth was compared: the order of the walk is the visibility.",
             counted.size(), frame.stats.fragments_written),
         &frame,
         {}});
  return frame;
}

}  // namespace hsr::detail

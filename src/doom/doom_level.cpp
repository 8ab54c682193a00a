// A Doom map seen by the rest of hsr: the level as a 3D Scene (walls from the linedefs,
// floors and ceilings from the tree's subsector regions), Doom's camera at a viewpoint, and
// the bird's-eye drawing of the partition (SVG). include/hsr/doom.hpp says what each holds.
// It stands beside the orchestrator: it joins the WAD reader (io) and the tree (visibility).

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/core.h>

#include "doom/doom_level.hpp"
#include "hsr/error.hpp"
#include "doom/doom_view.hpp"

namespace hsr::doom {

namespace {

using Point = std::array<double, 2>;
using Region = std::vector<Point>;

constexpr double kMargin = 64;  // map units around the linedefs' box: the regions' outer edge

// The part of a convex region on one side of a node's line: front (the right, side < 0) or back.
Region clipRegion(const Region& in, const Node& n, bool front) {
  Region out;
  const auto side = [&](const Point& p) {
    const double s = double(n.dx) * (p[1] - n.y) - double(n.dy) * (p[0] - n.x);
    return front ? -s : s;  // >= 0: kept
  };
  for (std::size_t i = 0; i < in.size(); ++i) {
    const Point& a = in[i];
    const Point& b = in[(i + 1) % in.size()];
    const double sa = side(a), sb = side(b);
    if (sa >= 0) out.push_back(a);
    if ((sa >= 0) != (sb >= 0)) {
      const double t = sa / (sa - sb);
      out.push_back({a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])});
    }
  }
  return out;
}

double area(const Region& r) {
  double a = 0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const Point& p = r[i];
    const Point& q = r[(i + 1) % r.size()];
    a += p[0] * q[1] - q[0] * p[1];
  }
  return a / 2;
}

struct MapBox {
  double left = 1e300, right = -1e300, bottom = 1e300, top = -1e300;
};

MapBox boxOf(const Map& map) {
  MapBox b;
  for (const Linedef& l : map.linedefs)
    for (std::uint16_t v : {l.v1, l.v2}) {
      b.left = std::min(b.left, double(map.vertices[v].x)),
      b.right = std::max(b.right, double(map.vertices[v].x));
      b.bottom = std::min(b.bottom, double(map.vertices[v].y)),
      b.top = std::max(b.top, double(map.vertices[v].y));
    }
  return b;
}

Region outerRegion(const Map& map) {
  const MapBox b = boxOf(map);
  return {{b.left - kMargin, b.bottom - kMargin},
          {b.right + kMargin, b.bottom - kMargin},
          {b.right + kMargin, b.top + kMargin},
          {b.left - kMargin, b.top + kMargin}};
}

// Walks the tree from the root with each node's region: visit(node or subsector, region, depth).
template <typename VisitNode, typename VisitLeaf>
void walkRegions(const Nodes& nodes, const Region& root, VisitNode visit_node,
                 VisitLeaf visit_leaf) {
  if (nodes.nodes.empty()) {
    visit_leaf(std::uint16_t{0}, root, 0);
    return;
  }
  struct Item {
    std::uint16_t child;
    Region region;
    int depth;
  };
  std::vector<Item> stack{{static_cast<std::uint16_t>(nodes.nodes.size() - 1), root, 0}};
  std::size_t visits = 0;
  while (!stack.empty()) {
    Item it = std::move(stack.back());
    stack.pop_back();
    if (++visits > 2 * nodes.nodes.size() + 1) throw Error("the nodes are not one tree");
    if (it.child & kSubsectorBit) {
      visit_leaf(static_cast<std::uint16_t>(it.child & ~kSubsectorBit), it.region, it.depth);
      continue;
    }
    const Node& n = nodes.nodes.at(it.child);
    visit_node(n, it.region, it.depth);
    stack.push_back({n.child[1], clipRegion(it.region, n, false), it.depth + 1});
    stack.push_back({n.child[0], clipRegion(it.region, n, true), it.depth + 1});
  }
}

std::uint16_t sectorOf(const Map& map, const Nodes& nodes, std::uint16_t subsector) {
  const Seg& seg = nodes.segs.at(nodes.subsectors.at(subsector).first);
  return map.sidedefs[map.linedefs[seg.linedef].side[std::size_t(seg.side) & 1]].sector;
}

glm::vec3 mix(const glm::vec3& a, const glm::vec3& b, double t) {
  return a + (b - a) * static_cast<float>(std::clamp(t, 0.0, 1.0));
}

}  // namespace

Level levelScene(const Map& map, const Nodes& nodes) {
  Level level;
  Scene& scene = level.scene;
  scene.name = map.name;
  level.walls.assign(map.linedefs.size() * 6, kNoPolygon);
  level.floors.assign(nodes.subsectors.size(), kNoPolygon);
  level.ceilings.assign(nodes.subsectors.size(), kNoPolygon);
  level.regions.assign(nodes.subsectors.size(), {});

  double lo = 1e300, hi = -1e300;
  for (const Sector& s : map.sectors)
    lo = std::min(lo, double(s.floor)), hi = std::max(hi, double(s.ceiling));
  const double span = std::max(1.0, hi - lo);

  // Materials: a wall's by its part and its sector's light (16 steps), a flat's by height (32).
  std::map<std::pair<int, int>, std::uint32_t> materials;
  const auto material = [&](int kind, int step, glm::vec3 colour, const char* name) {
    const auto [it, fresh] = materials.emplace(std::make_pair(kind, step), 0u);
    if (fresh) it->second = scene.addMaterial({colour, 1.0f, fmt::format("{} {}", name, step)});
    return it->second;
  };
  const auto wallMaterial = [&](WallPart part, const Sector& sector) {
    const int step = std::clamp(sector.light / 16, 0, 15);
    const float light = 0.4f + 0.6f * float(step) / 15.0f;
    static const glm::vec3 colours[3] = {
        {0.55f, 0.62f, 0.45f}, {0.78f, 0.70f, 0.60f}, {0.66f, 0.52f, 0.44f}};
    static const char* names[3] = {"lower wall, light", "wall, light", "upper wall, light"};
    return material(int(part), step, colours[int(part)] * light, names[int(part)]);
  };
  const auto flatMaterial = [&](bool ceiling, double height) {
    const int step = std::clamp(int((height - lo) / span * 31.0 + 0.5), 0, 31);
    const double t = step / 31.0;
    return ceiling ? material(4, step, mix({0.30f, 0.22f, 0.20f}, {0.85f, 0.72f, 0.55f}, t),
                              "ceiling, height")
                   : material(3, step, mix({0.16f, 0.20f, 0.36f}, {0.55f, 0.68f, 0.88f}, t),
                              "floor, height");
  };

  // Walls, one object per sector they face: lower, middle, upper.
  std::vector<std::vector<std::pair<std::uint32_t, int>>> facing(map.sectors.size());
  for (std::size_t i = 0; i < map.linedefs.size(); ++i)
    for (int side = 0; side < 2; ++side)
      if (map.linedefs[i].side[std::size_t(side)] != kNoSide)
        facing[map.sidedefs[map.linedefs[i].side[std::size_t(side)]].sector].push_back(
            {std::uint32_t(i), side});
  for (std::size_t s = 0; s < map.sectors.size(); ++s) {
    if (facing[s].empty()) continue;
    scene.beginObject(fmt::format("sector {} walls", s));
    for (const auto& facing_side : facing[s]) {
      const std::uint32_t i = facing_side.first;  // (not a structured binding: clang 14 cannot
      const int side = facing_side.second;        // capture one in the lambda below)
      const Linedef& l = map.linedefs[i];
      const Vertex a = map.vertices[side == 0 ? l.v1 : l.v2],
                   b = map.vertices[side == 0 ? l.v2 : l.v1];
      if (a.x == b.x && a.y == b.y) continue;
      const Sector& front = map.sectors[s];
      const std::uint16_t back_side = l.side[std::size_t(1 - side)];
      const auto quad = [&](WallPart part, double z0, double z1) {
        if (!(z1 > z0)) return;
        // Counterclockwise seen from the front (the right of a -> b): a is on the viewer's left.
        const glm::vec3 corners[4] = {
            {a.x, a.y, z0}, {b.x, b.y, z0}, {b.x, b.y, z1}, {a.x, a.y, z1}};
        level.walls[(std::size_t(i) * 2 + std::size_t(side)) * 3 + std::size_t(part)] =
            scene.addPolygonVertices({corners[0], corners[1], corners[2], corners[3]},
                                     wallMaterial(part, front));
      };
      if (back_side == kNoSide) {
        quad(WallPart::kMiddle, front.floor, front.ceiling);
      } else {
        const Sector& back = map.sectors[map.sidedefs[back_side].sector];
        quad(WallPart::kLower, front.floor, std::min<double>(back.floor, front.ceiling));
        quad(WallPart::kUpper, std::max<double>(back.ceiling, front.floor), front.ceiling);
      }
    }
  }
  level.wall_count = static_cast<PolygonId>(scene.polygonCount());

  // Floors and ceilings: each subsector's region, one object per sector.
  std::vector<std::vector<std::uint16_t>> in_sector(map.sectors.size());
  walkRegions(
      nodes, outerRegion(map), [](const Node&, const Region&, int) {},
      [&](std::uint16_t ss, const Region& region, int) {
        if (ss >= nodes.subsectors.size()) return;
        level.regions[ss] = region;
        in_sector[sectorOf(map, nodes, ss)].push_back(ss);
      });
  for (std::size_t s = 0; s < map.sectors.size(); ++s) {
    if (in_sector[s].empty()) continue;
    scene.beginObject(fmt::format("sector {} floor and ceiling", s));
    const Sector& sector = map.sectors[s];
    for (std::uint16_t ss : in_sector[s]) {
      const Region& r = level.regions[ss];
      if (r.size() < 3 || area(r) < 1e-6 || !(sector.ceiling > sector.floor)) continue;
      std::vector<glm::vec3> up, down;
      for (const Point& p : r) up.push_back({p[0], p[1], double(sector.floor)});
      for (auto it = r.rbegin(); it != r.rend(); ++it)
        down.push_back({(*it)[0], (*it)[1], double(sector.ceiling)});
      level.floors[ss] = scene.addPolygonVertices(up, flatMaterial(false, sector.floor));
      level.ceilings[ss] = scene.addPolygonVertices(down, flatMaterial(true, sector.ceiling));
    }
  }
  if (scene.polygonCount() == 0) throw Error(fmt::format("map {}: nothing to draw", map.name));
  return level;
}

Viewpoint playerStart(const Map& map) {
  for (const Thing& t : map.things)
    if (t.type == 1) return {double(t.x), double(t.y), double(t.angle), 41};
  throw Error(fmt::format("map {}: no player 1 start", map.name));
}

Camera viewCamera(const Map& map, const Nodes& nodes, const Viewpoint& view, int width,
                  int height) {
  const Sector& sector = map.sectors.at(sectorByTree(map, nodes, view.x, view.y));
  const MapBox b = boxOf(map);
  Camera c;
  c.width = width, c.height = height;
  const double a = view.angle_degrees * M_PI / 180.0;
  c.eye = {view.x, view.y, double(sector.floor) + view.eye_height};
  c.target = c.eye + glm::vec3(std::cos(a), std::sin(a), 0.0);
  c.up = {0, 0, 1};
  // 90 degrees across the width, square pixels
  c.fov_deg = static_cast<float>(2.0 * std::atan(double(height) / double(width)) * 180.0 / M_PI);
  c.near = 4.0f;
  c.far = static_cast<float>(std::hypot(b.right - b.left, b.top - b.bottom) + 2 * kMargin);
  c.validate();
  return c;
}

Scene loadLevel(const std::filesystem::path& path, std::string_view map_name) {
  const Wad wad = readWad(path);
  const auto maps = wad.maps();
  if (maps.empty()) throw Error(path.string() + ": the WAD holds no map");
  const Map map = readMap(wad, map_name.empty() ? std::string_view(maps.front()) : map_name);
  const Nodes nodes = buildNodes(map);
  Level level = levelScene(map, nodes);
  const Camera view = viewCamera(map, nodes, playerStart(map), 1600, 1000);
  SceneCamera c;
  c.eye = view.eye, c.target = view.target, c.up = view.up;
  c.fov_deg = view.fov_deg;
  c.far = view.far;
  // within the ratio fromSceneCamera keeps as it is
  c.near = std::max(view.near, view.far / 999.0f);
  level.scene.cameras.push_back(c);
  level.scene.name = path.filename().string() + ":" + map.name;
  return std::move(level.scene);
}

std::string mapSvg(const Map& map, const Nodes& nodes, int max_depth) {
  const MapBox b = boxOf(map);
  const double w = b.right - b.left + 2 * kMargin, h = b.top - b.bottom + 2 * kMargin;
  const double scale = 1600.0 / std::max(w, h);  // the drawing about 1600 px on its long side
  std::string out = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0f}\" height=\"{:.0f}\" viewBox=\"{} "
      "{} {} {}\">\n"
      "<title>{}: {} subsectors, {} nodes</title>\n<rect x=\"{}\" y=\"{}\" width=\"{}\" "
      "height=\"{}\" fill=\"#ffffff\"/>\n"
      "<g transform=\"scale(1,-1)\">\n",
      w * scale, h * scale, b.left - kMargin, -(b.top + kMargin), w, h, map.name,
      nodes.subsectors.size(), nodes.nodes.size(), b.left - kMargin, -(b.top + kMargin), w, h);
  const auto path = [](const Region& r) {
    std::string d;
    for (std::size_t i = 0; i < r.size(); ++i)
      d += fmt::format("{}{:.1f},{:.1f}", i ? " L" : "M", r[i][0], r[i][1]);
    return d + " Z";
  };
  std::string regions, partitions;
  const double stroke = 1.2 / scale;
  walkRegions(
      nodes, outerRegion(map),
      [&](const Node& n, const Region& r, int depth) {
        if (depth > max_depth || r.size() < 2) return;
        // The partition line inside the node's region: where it crosses the region's edges.
        std::vector<Point> hits;
        for (std::size_t i = 0; i < r.size(); ++i) {
          const Point& p = r[i];
          const Point& q = r[(i + 1) % r.size()];
          const double sp = double(n.dx) * (p[1] - n.y) - double(n.dy) * (p[0] - n.x);
          const double sq = double(n.dx) * (q[1] - n.y) - double(n.dy) * (q[0] - n.x);
          if (sp == 0)
            hits.push_back(p);
          else if ((sp < 0) != (sq < 0) && sq != 0)
            hits.push_back(
                {p[0] + sp / (sp - sq) * (q[0] - p[0]), p[1] + sp / (sp - sq) * (q[1] - p[1])});
        }
        if (hits.size() < 2) return;
        const double t = std::min(1.0, depth / 12.0);  // red at the root to blue 12 levels down
        const int red = int(220 * (1 - t) + 40 * t), green = int(40 + 60 * t),
                  blue = int(40 * (1 - t) + 220 * t);
        partitions += fmt::format(
            "<line x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\" "
            "stroke=\"#{:02x}{:02x}{:02x}\" "
            "stroke-width=\"{:.2f}\" stroke-opacity=\"{:.2f}\"><title>node depth "
            "{}</title></line>\n",
            hits[0][0], hits[0][1], hits[1][0], hits[1][1], red, green, blue,
            stroke * std::max(0.6, 4.0 - depth * 0.3), std::max(0.35, 1.0 - depth * 0.05), depth);
      },
      [&](std::uint16_t ss, const Region& r, int) {
        if (r.size() < 3) return;
        // A pastel per subsector, hues a golden angle apart
        const double hue = std::fmod(ss * 137.508, 360.0) / 60.0;
        const double x = 1 - std::abs(std::fmod(hue, 2.0) - 1);
        double rgb[3];
        const int k = int(hue);
        const double c[6][3] = {{1, x, 0}, {x, 1, 0}, {0, 1, x}, {0, x, 1}, {x, 0, 1}, {1, 0, x}};
        for (int i = 0; i < 3; ++i) rgb[i] = 0.72 + 0.25 * c[k % 6][i];
        regions += fmt::format(
            "<path d=\"{}\" fill=\"#{:02x}{:02x}{:02x}\"><title>subsector {}</title></path>\n",
            path(r), int(rgb[0] * 255), int(rgb[1] * 255), int(rgb[2] * 255), ss);
      });
  out += "<g stroke=\"none\">\n" + regions + "</g>\n<g stroke-linecap=\"round\">\n" + partitions +
         "</g>\n";
  out += "<g stroke-linecap=\"round\">\n";
  for (const Linedef& l : map.linedefs) {
    const Vertex a = map.vertices[l.v1], c = map.vertices[l.v2];
    const bool two = l.side[0] != kNoSide && l.side[1] != kNoSide;
    out += fmt::format(
        "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{}\" stroke-width=\"{:.2f}\"/>\n",
        a.x, a.y, c.x, c.y, two ? "#707070" : "#000000", stroke * (two ? 1.0 : 2.2));
  }
  out += "</g>\n";
  for (const Thing& t : map.things)
    if (t.type == 1)
      out += fmt::format(
          "<circle cx=\"{}\" cy=\"{}\" r=\"{:.1f}\" fill=\"#10a010\"><title>player 1 "
          "start</title></circle>\n",
          t.x, t.y, 5 * stroke * 4);
  out += "</g>\n</svg>\n";
  return out;
}

}  // namespace hsr::doom

namespace hsr::detail {

Frame renderDoomViewTraced(const doom::Map& map, const doom::Nodes& nodes, const doom::Level& level,
                           const Camera& camera, Trace* trace) {
  return renderDoomView(map, nodes, level, camera, nullptr, trace);
}

}  // namespace hsr::detail

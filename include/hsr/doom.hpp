#pragma once
// Doom levels: the notes' 2D BSP ("the first FPS" walks one front to back) on real maps.
//
// A WAD file is a header and a directory of named lumps; a map is a marker lump (MAP01, E1M1)
// followed by THINGS, LINEDEFS, SIDEDEFS, VERTEXES, SEGS, SSECTORS, NODES, SECTORS, REJECT and
// BLOCKMAP, in Doom's own little-endian record formats (kept here field for field). This
// header reads them (refusing malformed or hostile files with one line), builds a map's node
// tree as Doom node builders do, checks a tree, writes a WAD back with new nodes, turns a map
// into a 3D Scene and renders it as Doom's renderer does, walking the tree front to back.
//
//   const hsr::doom::Wad wad = hsr::doom::readWad("freedoom2.wad");
//   const hsr::doom::Map map = hsr::doom::readMap(wad, "MAP01");
//   hsr::doom::BuildStats stats;
//   const hsr::doom::Nodes nodes = hsr::doom::buildNodes(map, {}, &stats);
//   // stats.splits, stats.depth; checkNodes(map, nodes) lists what is wrong (nothing)

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hsr/camera.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"

namespace hsr::doom {

constexpr std::uint16_t kNoSide = 0xFFFF;        // a linedef side without a sidedef
constexpr std::uint16_t kSubsectorBit = 0x8000;  // a node child that is a subsector

using Name = std::array<char, 8>;  // a lump or texture name, NUL-padded, not terminated
std::string nameText(const Name& name);

struct Vertex {
  std::int16_t x = 0, y = 0;
};
struct Linedef {
  std::uint16_t v1 = 0, v2 = 0, flags = 0, special = 0, tag = 0;
  std::array<std::uint16_t, 2> side{kNoSide, kNoSide};  // front (right of v1->v2), back
};
struct Sidedef {
  std::int16_t x_offset = 0, y_offset = 0;
  Name upper{}, lower{}, middle{};
  std::uint16_t sector = 0;
};
struct Sector {
  std::int16_t floor = 0, ceiling = 0;
  Name floor_flat{}, ceiling_flat{};
  std::int16_t light = 0, special = 0, tag = 0;
};
struct Thing {
  std::int16_t x = 0, y = 0, angle = 0, type = 0, flags = 0;
};

// A seg: the part of one linedef side that lies in one subsector. `side` 0 runs v1->v2 of the
// linedef, 1 runs v2->v1; `offset` is its start's distance from that side's first vertex;
// `angle` its direction in binary angle units (65536 a turn).
struct Seg {
  std::uint16_t v1 = 0, v2 = 0;
  std::int16_t angle = 0;
  std::uint16_t linedef = 0;
  std::int16_t side = 0;
  std::int16_t offset = 0;
};
struct Subsector {
  std::uint16_t count = 0, first = 0;
};
// A partition line through (x, y) along (dx, dy). child[0] is the front (right) side, child[1]
// the back; kSubsectorBit marks a subsector. box[c] = {top, bottom, left, right} of child c.
struct Node {
  std::int16_t x = 0, y = 0, dx = 0, dy = 0;
  std::array<std::array<std::int16_t, 4>, 2> box{};
  std::array<std::uint16_t, 2> child{};
};

// A map's tree: its vertices (the map's own, then those the splits made), segs, subsectors and
// nodes, the root last as Doom has it. A map with a single subsector has no node.
struct Nodes {
  std::vector<Vertex> vertices;
  std::vector<Seg> segs;
  std::vector<Subsector> subsectors;
  std::vector<Node> nodes;
};

struct Map {
  std::string name;
  std::vector<Thing> things;
  std::vector<Linedef> linedefs;
  std::vector<Sidedef> sidedefs;
  std::vector<Vertex> vertices;  // the linedefs' vertices (the VERTEXES lump less the
                                 // shipped nodes' split vertices, found as those no linedef uses
                                 // past the last one a linedef uses)
  std::vector<Sector> sectors;
  std::optional<Nodes> shipped;  // the nodes the WAD holds, when it holds them in the vanilla
                                 // formats, every index in range, as one tree
  std::string shipped_problem;   // else why not, in one line ("map MAP01: seg 7 names vertex 12
                                 // of 12"): never read, only reported when they are asked for
};

struct Lump {
  std::string name;
  std::string bytes;
};
struct Wad {
  std::string kind;  // "IWAD" or "PWAD"
  std::vector<Lump> lumps;
  std::vector<std::string> maps() const;  // map marker names, in file order
};

// Reads a WAD. Refused with hsr::Error and one line naming the file: not a WAD, a directory or
// lump past the end of the file, a lump count beyond what the file can hold.
Wad readWad(const std::filesystem::path& path);
Wad parseWad(std::string_view bytes, const std::string& name);
// A map of the WAD by marker name (case-insensitive). Refused with one line: no such map, a
// lump missing, a size that is not a whole number of records, an index out of range (a
// linedef's vertex or sidedef, a sidedef's sector). Shipped nodes that are not one tree with
// every index in range are dropped, not refused.
Map readMap(const Wad& wad, std::string_view map_name);

// How the partition line is chosen at each node (buildNodes). Every distinct line through the
// node's segs is a candidate (one seg per line); the one of least cost wins, where
//   cost = split_cost * splits + |front - back|    (segs on each side, splits counted twice)
// and a line that leaves one side empty is no candidate. A node whose segs are convex (each in
// front of every other's line) and of one sector is a subsector.
struct BuildOptions {
  int split_cost = 128;
};
struct BuildStats {
  std::uint64_t sides = 0;  // linedef sides of nonzero length (the segs before splits)
  std::uint64_t segs = 0;
  std::uint64_t splits = 0;  // segs - sides
  std::uint64_t nodes = 0;
  std::uint64_t subsectors = 0;
  std::uint64_t depth = 0;  // nodes on the longest root-to-subsector path
  // Subsectors whose segs face more than one sector: convex, but where the map's sectors are
  // not closed or overlap (Doom shades such a subsector's floor as its first seg's sector).
  std::uint64_t mixed_subsectors = 0;
  double build_ms = 0;
};
// Builds the tree. Split points are rounded to whole map units, as the vanilla formats store
// them. Throws hsr::Error when the tree would pass the vanilla limits (65,535 segs or vertices,
// 32,767 nodes or subsectors) or 1,024 levels, or a linedef is too long for a partition.
Nodes buildNodes(const Map& map, const BuildOptions& options = {}, BuildStats* stats = nullptr);
// The same figures for a tree read from a WAD.
BuildStats nodeStats(const Map& map, const Nodes& nodes);

// What is wrong with a tree, one line each (empty: nothing). Checked: indices in range; every
// node is reached once and every subsector once; each subsector is convex (`tolerance` map
// units for rounded split points); each seg lies on its linedef at its offset; the segs of
// each linedef side cover it exactly once from end to end (no gap, no overlap).
std::vector<std::string> checkNodes(const Map& map, const Nodes& nodes, double tolerance = 1.5);

// Walks the tree from the root to the subsector holding (x, y), as Doom's R_PointInSubsector.
std::uint16_t subsectorAt(const Nodes& nodes, double x, double y);
// The sector of the subsector holding (x, y) (the sector of its first seg's sidedef).
std::uint16_t sectorByTree(const Map& map, const Nodes& nodes, double x, double y);
// The sector holding (x, y) found from the linedefs alone: the nearest linedef a ray from the
// point meets, and the side of it the point is on; nullopt outside the map (no linedef met, or
// the side met has no sidedef).
std::optional<std::uint16_t> sectorByLinedefs(const Map& map, double x, double y);

// The WAD with `nodes` replacing the named maps' VERTEXES, SEGS, SSECTORS and NODES (the
// linedefs' vertices first, unchanged; the split vertices after them); every other lump is
// copied byte for byte, in its place.
std::string wadBytes(const Wad& wad, const std::map<std::string, Nodes>& nodes);
void writeWad(const Wad& wad, const std::map<std::string, Nodes>& nodes,
              const std::filesystem::path& path);

// ---- The level in 3D, and as Doom draws it -----------------------------------------------
// `nodes` below: a tree of the map, as buildNodes makes and readMap keeps (indices in range).
// A viewpoint on the map: position, facing (degrees, 0 east, counterclockwise) and eye height
// above the floor under it (Doom's 41).
struct Viewpoint {
  double x = 0, y = 0, angle_degrees = 0, eye_height = 41;
};
// Player 1's start (thing type 1); refused when the map has none.
Viewpoint playerStart(const Map& map);

// Doom's camera for a viewpoint: the horizontal field of view 90 degrees across `width`, no
// pitch, the eye at the floor of the sector under it plus eye_height; map units, z up.
Camera viewCamera(const Map& map, const Nodes& nodes, const Viewpoint& view, int width, int height);

// The level as a Scene, z up, map units: every linedef side a wall of up to three quads (the
// lower and upper walls between two sectors' floors and ceilings, the middle of a one-sided
// line; a two-sided line's middle is open), facing the side's sector; and every subsector's
// region (its node path's half-planes clipped to the map's box, so the regions tile the plane)
// a floor and a ceiling polygon at its sector's heights. Walls are coloured by part and sector
// light, floors and ceilings by height. One object per sector. No sky: every upper wall is a
// wall, as the column renderer draws it.
enum class WallPart : int { kLower = 0, kMiddle = 1, kUpper = 2 };
struct Level {
  Scene scene;
  // The scene's polygon id of each wall: walls[(linedef * 2 + side) * 3 + part], kNoPolygon
  // where that side has no such wall (no sidedef, or no height between the two sectors).
  std::vector<PolygonId> walls;
  std::vector<PolygonId> floors, ceilings;  // per subsector (kNoPolygon: an empty region)
  std::vector<std::vector<std::array<double, 2>>> regions;  // per subsector, counterclockwise
  PolygonId wall(std::uint32_t linedef, int side, WallPart part) const {
    return walls[(std::size_t(linedef) * 2 + std::size_t(side)) * 3 + std::size_t(part)];
  }
  PolygonId wall_count = 0;  // walls come first: ids below this
  bool isWall(PolygonId id) const { return id < wall_count; }
};
Level levelScene(const Map& map, const Nodes& nodes);

// A map as a scene for every verb and algorithm of hsr: "FILE.wad:MAP01" (or FILE.wad, its
// first map) -> the level scene of the map's tree as buildNodes makes it, with player 1's start
// as the scene's camera (90 degrees across a 16:10 picture). loadScene reads this spelling.
Scene loadLevel(const std::filesystem::path& wad, std::string_view map_name = {});

// The first-person view drawn as Doom's renderer draws it (R_RenderBSPNode): the tree walked
// front to back from the eye; each seg facing the eye projected to the columns it spans and
// clipped against the columns solid walls have closed and the openings two-sided ones have
// left; each column of it drawn top to bottom: the ceiling down to the wall, the upper wall,
// the middle (a one-sided line: the column closes) or the opening, the lower wall, the floor.
// Through `camera` (viewCamera's: no pitch), pixel for pixel as the z-buffer samples the level's
// scene: ids are the Level's polygon ids, depth window z, colour the material's dimmed with
// distance as Doom dims it. `trace`, when given, receives each seg drawn with its columns.
struct ViewStep {
  std::uint16_t seg = 0;
  int x0 = 0, x1 = 0;   // the columns it spans on screen, [x0, x1)
  int drawn = 0;        // of which it drew (the others were closed)
  bool closes = false;  // a solid wall: its columns close
};
Frame renderView(const Map& map, const Nodes& nodes, const Level& level, const Camera& camera,
                 std::vector<ViewStep>* trace = nullptr);

// How far a view agrees with a reference rendering of the level scene (the z-buffer's) on
// walls: of the pixels where `reference` shows a wall, those where `view` has the same id, and
// of the others those that lie away from every edge (no pixel of another id in `reference`
// within one pixel): a difference an edge does not explain.
struct Agreement {
  std::uint64_t wall_pixels = 0, same = 0, away_from_edges = 0;
  double fraction() const { return wall_pixels ? double(same) / double(wall_pixels) : 1.0; }
};
Agreement wallAgreement(const Level& level, const Frame& view, const Frame& reference);

// The bird's-eye partition as the notes draw it: subsectors shaded, linedefs, and the
// partition lines clipped to their node's region, coloured by depth down to `max_depth`.
std::string mapSvg(const Map& map, const Nodes& nodes, int max_depth = 64);

}  // namespace hsr::doom

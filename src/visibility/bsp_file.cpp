// BSP files: a scene and its BSP tree, saved once and rendered from any viewpoint
// (docs/bsp-format.md describes the format; this file is its one implementation). It stands
// beside the orchestrator: it reads and writes the visibility layer's tree.
//
// Little-endian throughout. A 24-byte header: the magic "HSRBSP\x1a\n", the version (u32, 1),
// the CRC-32 (zlib's) of the payload (u32), the payload's size in bytes (u64). Then the payload:
// the build options, the build's figures, the epsilon, the scene (materials, camera, objects
// with their vertices and polygons) and the tree (nodes, then the polygons node by node, each
// with its cuts). Counts are u32; every count is checked against the bytes left before
// anything is allocated, so a hostile count cannot ask for more memory than the file holds.
// Reading refuses, with one line naming the file, anything saveBsp could not have written.
//
// Tests: tests/visibility/bsp_test.cpp (round trips, and every refusal of a damaged file) and
// fuzz/fuzz_bsp.cpp.

#include <zlib.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "hsr/bsp.hpp"
#include "hsr/error.hpp"
#include "hsr/output.hpp"
#include "visibility/bsp_tree.hpp"

namespace hsr {

namespace {

constexpr char kMagic[8] = {'H', 'S', 'R', 'B', 'S', 'P', '\x1a', '\n'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kHeaderBytes = 24;
constexpr std::uint32_t kMaxString = 4096;
constexpr std::uint32_t kMaxPolygonVertices = 1u << 20;

class Writer {
 public:
  void u8(std::uint8_t v) { out_.push_back(static_cast<char>(v)); }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) u8(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) u8(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void f32(float v) { u32(std::bit_cast<std::uint32_t>(v)); }
  void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
  void count(std::size_t n) {
    if (n > std::numeric_limits<std::uint32_t>::max()) throw Error("BSP file: a count beyond 2^32");
    u32(static_cast<std::uint32_t>(n));
  }
  void str(const std::string& s) {
    count(std::min<std::size_t>(s.size(), kMaxString));
    out_.append(s, 0, std::min<std::size_t>(s.size(), kMaxString));
  }
  std::string& bytes() { return out_; }

 private:
  std::string out_;
};

class Reader {
 public:
  Reader(std::string_view bytes, std::string where) : in_(bytes), where_(std::move(where)) {}
  [[noreturn]] void fail(const std::string& why) const { throw Error(where_ + ": " + why); }
  std::uint8_t u8() {
    need(1);
    return static_cast<std::uint8_t>(in_[at_++]);
  }
  std::uint32_t u32() {
    need(4);
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i)
      v |= std::uint32_t{static_cast<std::uint8_t>(in_[at_++])} << (8 * i);
    return v;
  }
  std::uint64_t u64() {
    const std::uint64_t lo = u32();
    return lo | (std::uint64_t{u32()} << 32);
  }
  std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
  float f32() { return std::bit_cast<float>(u32()); }
  double f64() { return std::bit_cast<double>(u64()); }
  double finite(const char* what) {
    const double v = f64();
    if (!std::isfinite(v)) fail(fmt::format("corrupt: {} is not a finite number", what));
    return v;
  }
  // A count of items of at least `item_bytes` each: never more than the bytes left hold.
  std::uint32_t count(std::size_t item_bytes, const char* what) {
    const std::uint32_t n = u32();
    if (static_cast<std::uint64_t>(n) * item_bytes > in_.size() - at_)
      fail(fmt::format("corrupt: {} {} need more bytes than the file has left", n, what));
    return n;
  }
  std::string str(const char* what) {
    const std::uint32_t n = count(1, what);
    if (n > kMaxString)
      fail(fmt::format("corrupt: a {} of {} bytes (at most {})", what, n, kMaxString));
    std::string s(in_.substr(at_, n));
    at_ += n;
    return s;
  }
  bool done() const { return at_ == in_.size(); }

 private:
  void need(std::size_t n) const {
    if (in_.size() - at_ < n) fail("truncated: the payload ends early");
  }
  std::string_view in_;
  std::size_t at_ = 0;
  std::string where_;
};

void writeScene(Writer& w, const Scene& s) {
  w.str(s.name);
  w.count(s.materials.size());
  for (const Material& m : s.materials) {
    w.f32(m.color.r), w.f32(m.color.g), w.f32(m.color.b), w.f32(m.alpha);
  }
  // The file keeps the scene's first camera, the one that frames it by default
  w.u8(s.cameras.empty() ? 0 : 1);
  if (!s.cameras.empty()) {
    const SceneCamera& c = s.cameras.front();
    for (const glm::vec3& v : {c.eye, c.target, c.up}) w.f32(v.x), w.f32(v.y), w.f32(v.z);
    w.f32(c.fov_deg), w.u8(c.ortho ? 1 : 0), w.f32(c.ortho_half_height), w.f32(c.near),
        w.f32(c.far);
  }
  w.count(s.objects.size());
  for (const Object& o : s.objects) {
    w.str(o.name);
    w.count(o.vertex_count);
    for (std::uint32_t v = 0; v < o.vertex_count; ++v) {
      const glm::vec3& p = s.position(o.first_vertex + v);
      w.f32(p.x), w.f32(p.y), w.f32(p.z);
    }
    w.count(o.polygon_count);
    for (std::uint32_t k = 0; k < o.polygon_count; ++k) {
      const PolygonId id = o.first_polygon + k;
      w.u32(s.material(id));
      w.count(s.polygon(id).size());
      for (const std::uint32_t v : s.polygon(id)) w.u32(v - o.first_vertex);
    }
  }
}

Scene readScene(Reader& r) {
  Scene s;
  s.name = r.str("scene name");
  const std::uint32_t materials = r.count(16, "materials");
  for (std::uint32_t i = 0; i < materials; ++i) {
    Material m;
    m.color.r = r.f32(), m.color.g = r.f32(), m.color.b = r.f32(), m.alpha = r.f32();
    s.addMaterial(m);
  }
  const std::uint8_t has_camera = r.u8();
  if (has_camera > 1) r.fail("corrupt: the camera flag is neither 0 nor 1");
  if (has_camera) {
    SceneCamera c;
    for (glm::vec3* v : {&c.eye, &c.target, &c.up}) v->x = r.f32(), v->y = r.f32(), v->z = r.f32();
    c.fov_deg = r.f32(), c.ortho = r.u8() != 0, c.ortho_half_height = r.f32(), c.near = r.f32(),
    c.far = r.f32();
    s.cameras.push_back(c);
  }
  const std::uint32_t objects = r.count(12, "objects");
  std::vector<std::uint32_t> local;
  for (std::uint32_t o = 0; o < objects; ++o) {
    s.beginObject(r.str("object name"));
    const std::uint32_t vertices = r.count(12, "vertices");
    for (std::uint32_t v = 0; v < vertices; ++v) {
      const float x = r.f32(), y = r.f32(), z = r.f32();
      s.addVertex({x, y, z});
    }
    const std::uint32_t polygons = r.count(8, "polygons");
    for (std::uint32_t k = 0; k < polygons; ++k) {
      const std::uint32_t material = r.u32();
      if (material >= s.materials.size())
        r.fail(fmt::format("corrupt: polygon {} uses material {} of {}", s.polygonCount(), material,
                           s.materials.size()));
      const std::uint32_t n = r.count(4, "polygon vertices");
      if (n < 3 || n > kMaxPolygonVertices)
        r.fail(fmt::format("corrupt: polygon {} has {} vertices", s.polygonCount(), n));
      local.resize(n);
      for (std::uint32_t& v : local) v = r.u32();
      for (const std::uint32_t v : local)  // checked here, so that the refusal names the file
        if (v >= vertices)
          r.fail(fmt::format("corrupt: polygon {} uses vertex {} of an object with {}",
                             s.polygonCount(), v, vertices));
      s.addPolygon(local, material);
    }
  }
  return s;
}

void writeTree(Writer& w, const detail::BspTree& t) {
  w.count(t.nodes.size());
  for (const detail::BspNode& n : t.nodes) {
    for (int i = 0; i < 4; ++i) w.f64(n.plane[i]);
    w.u32(n.first_polygon), w.u32(n.polygon_count), w.i32(n.front), w.i32(n.back);
  }
  w.count(t.polygons.size());
  for (const detail::BspPolygon& p : t.polygons) {
    w.u32(p.id), w.u32(p.piece);
    w.count(p.cut_count);
    for (std::uint32_t c = 0; c < p.cut_count; ++c) {
      w.u32(t.cuts[p.first_cut + c].node);
      w.u8(t.cuts[p.first_cut + c].front ? 1 : 0);
    }
    w.count(p.vertices.size());
    for (const glm::dvec3& v : p.vertices) w.f64(v.x), w.f64(v.y), w.f64(v.z);
  }
}

// The tree, checked to be one tree over `scene`'s polygons: each node but the root the child of
// exactly one node with a smaller index, the polygons stored node by node in node order, every
// index in range, every number finite, every plane of unit length.
detail::BspTree readTree(Reader& r, const Scene& scene) {
  detail::BspTree t;
  const std::uint32_t nodes = r.count(48, "nodes");
  t.nodes.resize(nodes);
  std::vector<std::uint8_t> parents(nodes, 0);
  std::uint64_t expected_first = 0;
  for (std::uint32_t i = 0; i < nodes; ++i) {
    detail::BspNode& n = t.nodes[i];
    for (int k = 0; k < 4; ++k) n.plane[k] = r.finite("a node's plane");
    if (std::abs(glm::length(glm::dvec3(n.plane)) - 1.0) > 1e-9)
      r.fail(fmt::format("corrupt: node {}'s plane normal is not of unit length", i));
    n.first_polygon = r.u32(), n.polygon_count = r.u32(), n.front = r.i32(), n.back = r.i32();
    if (n.first_polygon != expected_first)
      r.fail(fmt::format("corrupt: node {}'s polygons do not follow the previous node's", i));
    expected_first += n.polygon_count;
    for (const std::int32_t c : {n.front, n.back}) {
      if (c == -1) continue;
      if (c <= static_cast<std::int64_t>(i) || c >= static_cast<std::int64_t>(nodes) ||
          parents[c]++)
        r.fail(
            fmt::format("corrupt: node {} names child {}, which is not a node of one tree", i, c));
    }
  }
  for (std::uint32_t i = 1; i < nodes; ++i)
    if (!parents[i]) r.fail(fmt::format("corrupt: node {} belongs to no parent", i));
  const std::uint32_t polygons = r.count(16, "tree polygons");
  if (polygons != expected_first)
    r.fail(
        fmt::format("corrupt: the nodes hold {} polygons, the file {}", expected_first, polygons));
  t.polygons.resize(polygons);
  for (std::uint32_t i = 0; i < polygons; ++i) {
    detail::BspPolygon& p = t.polygons[i];
    p.id = r.u32(), p.piece = r.u32();
    if (p.id >= scene.polygonCount() ||
        p.piece + 2 >= std::max<std::size_t>(scene.polygon(p.id).size(), 3))
      r.fail(
          fmt::format("corrupt: tree polygon {} names polygon {} piece {}, which the scene lacks",
                      i, p.id, p.piece));
    const std::uint32_t cuts = r.count(5, "cuts");
    p.first_cut = static_cast<std::uint32_t>(t.cuts.size()), p.cut_count = cuts;
    for (std::uint32_t c = 0; c < cuts; ++c) {
      const std::uint32_t node = r.u32();
      const std::uint8_t front = r.u8();
      if (node >= nodes || front > 1)
        r.fail(fmt::format("corrupt: tree polygon {} has a cut by no node", i));
      t.cuts.push_back({node, front == 1});
    }
    const std::uint32_t vertices = r.count(24, "tree polygon vertices");
    if (vertices < 3 || vertices > kMaxPolygonVertices)
      r.fail(fmt::format("corrupt: tree polygon {} has {} vertices", i, vertices));
    p.vertices.resize(vertices);
    for (glm::dvec3& v : p.vertices)
      v.x = r.finite("a vertex"), v.y = r.finite("a vertex"), v.z = r.finite("a vertex");
  }
  return t;
}

}  // namespace

void saveBsp(const Bsp& bsp, const std::filesystem::path& path) {
  Writer w;
  const detail::BspTree& t = bsp.tree();
  w.str(bsp.options().splitter);
  w.u64(bsp.options().seed);
  w.u32(static_cast<std::uint32_t>(bsp.options().candidates));
  w.u64(t.stats.input_polygons), w.u64(t.stats.splits), w.f64(t.stats.build_ms);
  w.f64(t.epsilon);
  writeScene(w, bsp.scene());
  writeTree(w, t);
  const std::string& payload = w.bytes();
  Writer h;
  for (const char c : kMagic) h.u8(static_cast<std::uint8_t>(c));
  h.u32(kVersion);
  h.u32(static_cast<std::uint32_t>(crc32_z(
      crc32_z(0, nullptr, 0), reinterpret_cast<const Bytef*>(payload.data()), payload.size())));
  h.u64(payload.size());
  writeFileAtomically(path, {h.bytes(), payload});
}

Bsp loadBsp(const std::filesystem::path& path) {
  const std::string where = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw Error(where + ": no such file");
  std::ifstream in(path, std::ios::binary);
  std::string bytes;
  if (in) {
    std::ostringstream all;
    all << in.rdbuf();
    bytes = std::move(all).str();
  }
  if (!in) throw Error(where + ": cannot be read");
  return readBsp(bytes, where);
}

Bsp readBsp(std::string_view bytes, const std::string& where) {
  if (bytes.size() < kHeaderBytes || bytes.compare(0, 8, std::string_view(kMagic, 8)) != 0)
    throw Error(where + ": not an hsr BSP file (it does not begin with HSRBSP)");
  Reader header(bytes.substr(8, kHeaderBytes - 8), where);
  const std::uint32_t version = header.u32();
  const std::uint32_t crc = header.u32();
  const std::uint64_t size = header.u64();
  if (version != kVersion)
    throw Error(fmt::format("{}: BSP file version {}; this hsr reads version {}", where, version,
                            kVersion));
  if (size != bytes.size() - kHeaderBytes)
    throw Error(fmt::format(
        "{}: truncated or extended: the header says {} payload bytes, the file holds {}", where,
        size, bytes.size() - kHeaderBytes));
  const std::string_view payload = bytes.substr(kHeaderBytes);
  if (crc32_z(crc32_z(0, nullptr, 0), reinterpret_cast<const Bytef*>(payload.data()),
              payload.size()) != crc)
    throw Error(where + ": checksum mismatch: the file is corrupt");

  Reader r(payload, where);
  BspOptions options;
  options.splitter = r.str("splitter name");
  options.seed = r.u64();
  options.candidates = static_cast<int>(std::min<std::uint32_t>(r.u32(), 4096));
  detail::BspTree tree;
  tree.stats.input_polygons = r.u64(), tree.stats.splits = r.u64(), tree.stats.build_ms = r.f64();
  tree.epsilon = r.finite("the epsilon");
  if (tree.epsilon < 0) r.fail("corrupt: a negative epsilon");
  Scene scene = readScene(r);
  detail::BspTree read = readTree(r, scene);
  if (!r.done()) r.fail("corrupt: bytes after the tree");
  read.epsilon = tree.epsilon;
  read.stats.input_polygons = tree.stats.input_polygons;
  read.stats.splits = tree.stats.splits;
  read.stats.build_ms = tree.stats.build_ms;
  detail::finishBspTree(read);
  Bsp bsp;
  bsp.scene_ = std::make_shared<const Scene>(std::move(scene));
  bsp.tree_ = std::make_shared<const detail::BspTree>(std::move(read));
  bsp.options_ = options;
  return bsp;
}

std::string bspDot(const Bsp& bsp, std::size_t max_nodes) {
  const detail::BspTree& t = bsp.tree();
  std::string out = "digraph bsp {\n  node [shape=box, fontname=\"Helvetica\", fontsize=10];\n";
  auto ids = [&](const detail::BspNode& n) {
    std::string s;
    for (std::uint32_t k = 0; k < n.polygon_count && k < 8; ++k)
      s += (k ? ", " : "") + std::to_string(t.polygons[n.first_polygon + k].id);
    if (n.polygon_count > 8) s += fmt::format(" +{}", n.polygon_count - 8);
    return s;
  };
  const std::size_t shown = std::min(max_nodes, t.nodes.size());
  for (std::size_t i = 0; i < shown; ++i) {
    const detail::BspNode& n = t.nodes[i];
    out += fmt::format(
        "  n{} [label=\"node {}\\n{:.3f}x {:+.3f}y {:+.3f}z {:+.3f} = 0\\npolygons {}\"];\n", i, i,
        n.plane.x, n.plane.y, n.plane.z, n.plane.w, ids(n));
    if (n.front >= 0 && static_cast<std::size_t>(n.front) < shown)
      out += fmt::format("  n{} -> n{} [label=\"front\"];\n", i, n.front);
    if (n.back >= 0 && static_cast<std::size_t>(n.back) < shown)
      out += fmt::format("  n{} -> n{} [label=\"behind\", style=dashed];\n", i, n.back);
  }
  if (shown < t.nodes.size())
    out += fmt::format("  more [shape=plaintext, label=\"... {} more nodes\"];\n",
                       t.nodes.size() - shown);
  return out + "}\n";
}

std::string bspOutline(const Bsp& bsp, std::size_t max_nodes) {
  const detail::BspTree& t = bsp.tree();
  if (t.nodes.empty()) return "(empty tree)\n";
  std::vector<std::uint64_t> below(t.nodes.size(), 0);
  for (std::size_t i = t.nodes.size(); i-- > 0;) {
    below[i] = t.nodes[i].polygon_count;
    for (const std::int32_t c : {t.nodes[i].front, t.nodes[i].back})
      if (c >= 0) below[i] += below[c];
  }
  std::string out;
  std::size_t lines = 0;
  struct Item {
    std::int32_t node;
    int depth;
    const char* side;
  };
  std::vector<Item> stack{{0, 0, "root"}};
  while (!stack.empty() && lines < max_nodes) {
    const Item it = stack.back();
    stack.pop_back();
    const detail::BspNode& n = t.nodes[it.node];
    std::string ids;
    for (std::uint32_t k = 0; k < n.polygon_count && k < 6; ++k)
      ids += (k ? "," : "") + std::to_string(t.polygons[n.first_polygon + k].id);
    if (n.polygon_count > 6) ids += fmt::format(",... ({})", n.polygon_count);
    out += fmt::format(
        "{:{}}{} node {}: plane {:.3f}x {:+.3f}y {:+.3f}z {:+.3f} = 0; polygons {}; front {}, "
        "behind {}\n",
        "", 2 * it.depth, it.side, it.node, n.plane.x, n.plane.y, n.plane.z, n.plane.w, ids,
        n.front >= 0 ? below[n.front] : 0, n.back >= 0 ? below[n.back] : 0);
    ++lines;
    if (n.back >= 0) stack.push_back({n.back, it.depth + 1, "behind"});
    if (n.front >= 0) stack.push_back({n.front, it.depth + 1, "front"});
  }
  if (lines < t.nodes.size())
    out += fmt::format("... {} more nodes (--dot FILE writes them all)\n", t.nodes.size() - lines);
  return out;
}

}  // namespace hsr

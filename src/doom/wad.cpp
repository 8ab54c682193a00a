// WAD files: Doom's container of named lumps, and a map's lumps in the vanilla record formats
// (include/hsr/doom.hpp). Reading trusts nothing: every offset, size and count is checked
// against the bytes the file holds before anything is read or allocated, and every index a
// record holds against the table it points into. Writing copies every lump it does not replace
// byte for byte.
//
// Formats (little-endian): the header is "IWAD" or "PWAD", the lump count (i32) and the
// directory's offset (i32); the directory holds 16 bytes a lump: offset (i32), size (i32),
// name (8 bytes, NUL-padded). Records: THINGS 10 bytes, LINEDEFS 14, SIDEDEFS 30, VERTEXES 4,
// SEGS 12, SSECTORS 4, NODES 28, SECTORS 26.

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include <fmt/core.h>

#include "hsr/doom.hpp"
#include "hsr/error.hpp"
#include "hsr/output.hpp"

namespace hsr::doom {

namespace {

constexpr std::uint64_t kMaxWadBytes = 1ull << 31;  // the format's offsets are i32

// The lumps that may follow a map's marker, in the order Doom writes them.
constexpr std::array<std::string_view, 10> kMapLumps = {
    "THINGS",   "LINEDEFS", "SIDEDEFS", "VERTEXES", "SEGS",
    "SSECTORS", "NODES",    "SECTORS",  "REJECT",   "BLOCKMAP"};

bool isMapLump(std::string_view name) {
  return std::find(kMapLumps.begin(), kMapLumps.end(), name) != kMapLumps.end() ||
         name == "BEHAVIOR";
}

std::int32_t i32At(std::string_view b, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= std::uint32_t(static_cast<unsigned char>(b[at + i])) << (8 * i);
  return static_cast<std::int32_t>(v);
}

// Reads little-endian fields one after another from a record.
class Fields {
 public:
  explicit Fields(const char* p) : p_(reinterpret_cast<const unsigned char*>(p)) {}
  std::uint16_t u16() {
    const auto v = static_cast<std::uint16_t>(p_[0] | (p_[1] << 8));
    p_ += 2;
    return v;
  }
  std::int16_t i16() { return static_cast<std::int16_t>(u16()); }
  Name name() {
    Name n{};
    std::memcpy(n.data(), p_, 8);
    p_ += 8;
    return n;
  }

 private:
  const unsigned char* p_;
};

class Out {
 public:
  void u16(std::uint16_t v) {
    s_.push_back(static_cast<char>(v & 0xFF));
    s_.push_back(static_cast<char>(v >> 8));
  }
  void i16(std::int16_t v) { u16(static_cast<std::uint16_t>(v)); }
  void i32(std::int32_t v) {
    for (int i = 0; i < 4; ++i)
      s_.push_back(static_cast<char>((static_cast<std::uint32_t>(v) >> (8 * i)) & 0xFF));
  }
  void raw(std::string_view b) { s_.append(b); }
  std::string take() { return std::move(s_); }
  std::size_t size() const { return s_.size(); }

 private:
  std::string s_;
};

std::string upper(std::string_view s) {
  std::string u(s);
  for (char& c : u) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return u;
}

// The records of one lump, refused unless it is a whole number of them. `read` makes one from
// its fields in file order (a braced initializer evaluates its elements left to right).
template <typename T, typename Read>
std::vector<T> records(const Lump& lump, std::size_t size, const std::string& where, Read read) {
  if (lump.bytes.size() % size != 0)
    throw Error(fmt::format("{}: lump {} is {} bytes, not a whole number of {}-byte records", where,
                            lump.name, lump.bytes.size(), size));
  std::vector<T> out;
  out.reserve(lump.bytes.size() / size);
  for (std::size_t at = 0; at < lump.bytes.size(); at += size) {
    Fields f(lump.bytes.data() + at);
    out.push_back(read(f));
  }
  return out;
}

// The shipped nodes, or nullopt where they are absent, not vanilla, or do not hold together;
// then *problem says which (the first index out of range, with its table's length).
std::optional<Nodes> shippedNodes(const Lump* vertexes, const Lump* segs, const Lump* subsectors,
                                  const Lump* nodes, const Map& map, const std::string& where,
                                  std::string* problem) {
  const auto refuse = [&](std::string why) -> std::optional<Nodes> {
    *problem = where + ": " + std::move(why);
    return std::nullopt;
  };
  if (!segs || !subsectors || !nodes) return refuse("no SEGS, SSECTORS or NODES lump");
  if (segs->bytes.empty() || subsectors->bytes.empty())
    return refuse("empty SEGS or SSECTORS lump");
  if (segs->bytes.size() % 12 || subsectors->bytes.size() % 4 || nodes->bytes.size() % 28)
    return refuse(
        "SEGS, SSECTORS or NODES not in the vanilla format (their sizes are not whole records)");
  Nodes n;
  n.vertices = records<Vertex>(*vertexes, 4, where, [](Fields& f) {
    return Vertex{f.i16(), f.i16()};
  });
  n.segs = records<Seg>(*segs, 12, where, [](Fields& f) {
    return Seg{f.u16(), f.u16(), f.i16(), f.u16(), f.i16(), f.i16()};
  });
  n.subsectors = records<Subsector>(*subsectors, 4, where, [](Fields& f) {
    return Subsector{f.u16(), f.u16()};
  });
  n.nodes = records<Node>(*nodes, 28, where, [](Fields& f) {
    return Node{f.i16(),
                f.i16(),
                f.i16(),
                f.i16(),
                {{{f.i16(), f.i16(), f.i16(), f.i16()}, {f.i16(), f.i16(), f.i16(), f.i16()}}},
                {f.u16(), f.u16()}};
  });
  for (std::size_t i = 0; i < n.segs.size(); ++i) {
    const Seg& s = n.segs[i];
    if (s.v1 >= n.vertices.size() || s.v2 >= n.vertices.size())
      return refuse(
          fmt::format("seg {} names vertex {} of {}", i, std::max(s.v1, s.v2), n.vertices.size()));
    if (s.linedef >= map.linedefs.size())
      return refuse(
          fmt::format("seg {} names linedef {} of {}", i, s.linedef, map.linedefs.size()));
    if (s.side != 0 && s.side != 1) return refuse(fmt::format("seg {} has side {}", i, s.side));
    if (map.linedefs[s.linedef].side[s.side] == kNoSide)
      return refuse(fmt::format("seg {} runs along a side linedef {} does not have", i, s.linedef));
  }
  for (std::size_t i = 0; i < n.subsectors.size(); ++i) {
    const Subsector& s = n.subsectors[i];
    if (s.count == 0) return refuse(fmt::format("subsector {} has no seg", i));
    if (std::size_t(s.first) + s.count > n.segs.size())
      return refuse(fmt::format("subsector {} takes segs {} to {} of {}", i, s.first,
                                std::size_t(s.first) + s.count - 1, n.segs.size()));
  }
  for (std::size_t i = 0; i < n.nodes.size(); ++i)
    for (std::uint16_t c : n.nodes[i].child) {
      if ((c & kSubsectorBit) && (c & ~kSubsectorBit) >= n.subsectors.size())
        return refuse(fmt::format("node {} names subsector {} of {}", i, c & ~kSubsectorBit,
                                  n.subsectors.size()));
      if (!(c & kSubsectorBit) && c >= n.nodes.size())
        return refuse(fmt::format("node {} names node {} of {}", i, c, n.nodes.size()));
    }
  // One tree from the root (the last node): every node and subsector reached exactly once, so
  // that whatever walks it ends.
  std::vector<char> node_seen(n.nodes.size()), ss_seen(n.subsectors.size());
  std::vector<std::uint16_t> stack;
  if (n.nodes.empty()) {
    if (n.subsectors.size() != 1) return refuse("no node, but more than one subsector");
    ss_seen[0] = 1;
  } else {
    stack.push_back(static_cast<std::uint16_t>(n.nodes.size() - 1));
  }
  while (!stack.empty()) {
    const std::uint16_t id = stack.back();
    stack.pop_back();
    if (node_seen[id]++) return refuse(fmt::format("node {} is reached twice", id));
    for (std::uint16_t c : n.nodes[id].child) {
      if (!(c & kSubsectorBit))
        stack.push_back(c);
      else if (ss_seen[c & ~kSubsectorBit]++)
        return refuse(fmt::format("subsector {} is reached twice", c & ~kSubsectorBit));
    }
  }
  if (std::count(node_seen.begin(), node_seen.end(), 0) ||
      std::count(ss_seen.begin(), ss_seen.end(), 0))
    return refuse("not one tree: some node or subsector is not reached from the root");
  return n;
}

}  // namespace

std::string nameText(const Name& name) {
  std::string s(name.data(), name.size());
  s.resize(std::strlen(s.c_str()));
  return s;
}

std::vector<std::string> Wad::maps() const {
  std::vector<std::string> out;
  for (std::size_t i = 0; i + 1 < lumps.size(); ++i)
    if (lumps[i + 1].name == "THINGS" && !isMapLump(lumps[i].name)) out.push_back(lumps[i].name);
  return out;
}

Wad parseWad(std::string_view b, const std::string& name) {
  if (b.size() < 12)
    throw Error(fmt::format("{}: not a WAD file (shorter than its 12-byte header)", name));
  Wad wad;
  wad.kind = std::string(b.substr(0, 4));
  if (wad.kind != "IWAD" && wad.kind != "PWAD")
    throw Error(fmt::format("{}: not a WAD file (it does not start with IWAD or PWAD)", name));
  const std::int32_t count = i32At(b, 4), dir = i32At(b, 8);
  if (count < 0 || dir < 0)
    throw Error(fmt::format("{}: a negative lump count or directory offset", name));
  if (std::uint64_t(dir) + std::uint64_t(count) * 16 > b.size())
    throw Error(
        fmt::format("{}: its directory of {} lumps at byte {} runs past the end of the file "
                    "({} bytes)",
                    name, count, dir, b.size()));
  wad.lumps.reserve(static_cast<std::size_t>(count));
  for (std::int32_t i = 0; i < count; ++i) {
    const std::size_t at = std::size_t(dir) + std::size_t(i) * 16;
    const std::int32_t pos = i32At(b, at), size = i32At(b, at + 4);
    std::string lump_name(b.substr(at + 8, 8));
    lump_name.resize(std::strlen(lump_name.c_str()));
    for (char c : lump_name)
      if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126)
        throw Error(fmt::format("{}: lump {} has a name that is not printable text", name, i));
    if (pos < 0 || size < 0 || std::uint64_t(pos) + std::uint64_t(size) > b.size())
      throw Error(
          fmt::format("{}: lump {} ({}) of {} bytes at byte {} runs past the end of the file "
                      "({} bytes)",
                      name, i, lump_name, size, pos, b.size()));
    wad.lumps.push_back(
        {upper(lump_name), std::string(b.substr(std::size_t(pos), std::size_t(size)))});
  }
  return wad;
}

Wad readWad(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw Error(fmt::format("{}: no such file", name));
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw Error(fmt::format("{}: {}", name, ec.message()));
  if (size > kMaxWadBytes) throw Error(fmt::format("{}: larger than a WAD can be (2 GiB)", name));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(fmt::format("{}: cannot be opened", name));
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::uint64_t>(in.gcount()) != size)
    throw Error(fmt::format("{}: could not be read", name));
  return parseWad(bytes, name);
}

Map readMap(const Wad& wad, std::string_view map_name) {
  const std::string want = upper(map_name);
  std::size_t marker = wad.lumps.size();
  for (std::size_t i = 0; i + 1 < wad.lumps.size(); ++i)
    if (wad.lumps[i].name == want && wad.lumps[i + 1].name == "THINGS") {
      marker = i;
      break;
    }
  if (marker == wad.lumps.size()) {
    const auto names = wad.maps();
    throw Error(fmt::format(
        "no map {} in the WAD{}", want,
        names.empty() ? " (it holds no map)"
                      : fmt::format(" (it holds {} to {})", names.front(), names.back())));
  }
  const std::string where = "map " + want;
  std::map<std::string, const Lump*> lumps;
  for (std::size_t i = marker + 1; i < wad.lumps.size() && isMapLump(wad.lumps[i].name); ++i)
    lumps.emplace(wad.lumps[i].name, &wad.lumps[i]);
  if (lumps.count("BEHAVIOR"))
    throw Error(where + ": a Hexen-format map (BEHAVIOR lump); only Doom-format maps are read");
  for (const char* needed : {"THINGS", "LINEDEFS", "SIDEDEFS", "VERTEXES", "SECTORS"})
    if (!lumps.count(needed)) throw Error(fmt::format("{}: no {} lump", where, needed));

  Map map;
  map.name = want;
  map.things = records<Thing>(*lumps["THINGS"], 10, where, [](Fields& f) {
    return Thing{f.i16(), f.i16(), f.i16(), f.i16(), f.i16()};
  });
  map.linedefs = records<Linedef>(*lumps["LINEDEFS"], 14, where, [](Fields& f) {
    return Linedef{f.u16(), f.u16(), f.u16(), f.u16(), f.u16(), {f.u16(), f.u16()}};
  });
  map.sidedefs = records<Sidedef>(*lumps["SIDEDEFS"], 30, where, [](Fields& f) {
    return Sidedef{f.i16(), f.i16(), f.name(), f.name(), f.name(), f.u16()};
  });
  map.vertices = records<Vertex>(*lumps["VERTEXES"], 4, where, [](Fields& f) {
    return Vertex{f.i16(), f.i16()};
  });
  map.sectors = records<Sector>(*lumps["SECTORS"], 26, where, [](Fields& f) {
    return Sector{f.i16(), f.i16(), f.name(), f.name(), f.i16(), f.i16(), f.i16()};
  });
  if (map.linedefs.empty()) throw Error(where + ": no linedefs");
  if (map.sectors.empty()) throw Error(where + ": no sectors");
  std::size_t used = 0;
  for (std::size_t i = 0; i < map.linedefs.size(); ++i) {
    const Linedef& l = map.linedefs[i];
    if (l.v1 >= map.vertices.size() || l.v2 >= map.vertices.size())
      throw Error(fmt::format("{}: linedef {} names vertex {} of {}", where, i,
                              std::max(l.v1, l.v2), map.vertices.size()));
    for (std::uint16_t s : l.side)
      if (s != kNoSide && s >= map.sidedefs.size())
        throw Error(
            fmt::format("{}: linedef {} names sidedef {} of {}", where, i, s, map.sidedefs.size()));
    if (l.side[0] == kNoSide && l.side[1] == kNoSide)
      throw Error(fmt::format("{}: linedef {} has no sidedef on either side", where, i));
    used = std::max<std::size_t>(used, std::max(l.v1, l.v2) + 1u);
  }
  for (std::size_t i = 0; i < map.sidedefs.size(); ++i)
    if (map.sidedefs[i].sector >= map.sectors.size())
      throw Error(fmt::format("{}: sidedef {} names sector {} of {}", where, i,
                              map.sidedefs[i].sector, map.sectors.size()));
  const auto find = [&](const char* n) -> const Lump* {
    const auto it = lumps.find(n);
    return it == lumps.end() ? nullptr : it->second;
  };
  map.shipped = shippedNodes(find("VERTEXES"), find("SEGS"), find("SSECTORS"), find("NODES"), map,
                             where, &map.shipped_problem);
  map.vertices.resize(used);  // the shipped nodes' split vertices follow the linedefs' own
  return map;
}

std::string wadBytes(const Wad& wad, const std::map<std::string, Nodes>& replaced) {
  const auto encode = [](const Nodes& n) {
    std::map<std::string, std::string> out;
    Out v, s, ss, nd;
    for (const Vertex& x : n.vertices) v.i16(x.x), v.i16(x.y);
    for (const Seg& x : n.segs) {
      s.u16(x.v1), s.u16(x.v2), s.i16(x.angle), s.u16(x.linedef), s.i16(x.side), s.i16(x.offset);
    }
    for (const Subsector& x : n.subsectors) ss.u16(x.count), ss.u16(x.first);
    for (const Node& x : n.nodes) {
      nd.i16(x.x), nd.i16(x.y), nd.i16(x.dx), nd.i16(x.dy);
      for (const auto& box : x.box)
        for (std::int16_t b : box) nd.i16(b);
      nd.u16(x.child[0]), nd.u16(x.child[1]);
    }
    out["VERTEXES"] = v.take();
    out["SEGS"] = s.take();
    out["SSECTORS"] = ss.take();
    out["NODES"] = nd.take();
    return out;
  };
  // The lumps in order, a replaced map's group rebuilt in Doom's order with its node lumps new.
  std::vector<Lump> lumps;
  for (std::size_t i = 0; i < wad.lumps.size();) {
    const Lump& lump = wad.lumps[i];
    const bool marker =
        i + 1 < wad.lumps.size() && wad.lumps[i + 1].name == "THINGS" && !isMapLump(lump.name);
    const auto it = marker ? replaced.find(lump.name) : replaced.end();
    if (it == replaced.end()) {
      lumps.push_back(lump);
      ++i;
      continue;
    }
    lumps.push_back(lump);
    std::map<std::string, const Lump*> group;
    std::size_t j = i + 1;
    for (; j < wad.lumps.size() && isMapLump(wad.lumps[j].name); ++j)
      group.emplace(wad.lumps[j].name, &wad.lumps[j]);
    auto fresh = encode(it->second);
    for (std::string_view n : kMapLumps) {
      const std::string key(n);
      if (fresh.count(key))
        lumps.push_back({key, std::move(fresh[key])});
      else if (group.count(key))
        lumps.push_back(*group[key]);
    }
    i = j;
  }
  Out out;
  out.raw(wad.kind);
  std::uint64_t total = 12;
  for (const Lump& l : lumps) total += l.bytes.size();
  if (total + 16 * lumps.size() > kMaxWadBytes) throw Error("the WAD would pass 2 GiB");
  out.i32(static_cast<std::int32_t>(lumps.size()));
  out.i32(static_cast<std::int32_t>(total));
  for (const Lump& l : lumps) out.raw(l.bytes);
  std::size_t pos = 12;
  for (const Lump& l : lumps) {
    out.i32(static_cast<std::int32_t>(pos));
    out.i32(static_cast<std::int32_t>(l.bytes.size()));
    char name[8] = {};
    std::memcpy(name, l.name.data(), std::min<std::size_t>(8, l.name.size()));
    out.raw(std::string_view(name, 8));
    pos += l.bytes.size();
  }
  return out.take();
}

void writeWad(const Wad& wad, const std::map<std::string, Nodes>& nodes,
              const std::filesystem::path& path) {
  const std::string bytes = wadBytes(wad, nodes);
  writeFileAtomically(path, {bytes});
}

}  // namespace hsr::doom

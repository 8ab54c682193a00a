// libFuzzer target: bytes -> hsr::doom::parseWad -> every map (at most two) read, its nodes
// built and checked, written back and read again, turned into a level scene and drawn at 32x20
// through the tree from the player's start. hsr::Error is the expected answer to a bad file or
// map; anything else (crash, sanitizer report, huge allocation, hang) is a finding.

#include <cstddef>
#include <cstdint>
#include <string>

#include "hsr/doom.hpp"
#include "hsr/error.hpp"

namespace doom = hsr::doom;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    const doom::Wad wad = doom::parseWad(bytes, "fuzz.wad");
    int maps = 0;
    for (const std::string& name : wad.maps()) {
      if (++maps > 2) break;
      try {
        const doom::Map map = doom::readMap(wad, name);
        if (map.shipped) (void)doom::checkNodes(map, *map.shipped);
        const doom::Nodes nodes = doom::buildNodes(map);
        (void)doom::checkNodes(map, nodes);
        const doom::Map back =
            doom::readMap(doom::parseWad(doom::wadBytes(wad, {{name, nodes}}), "back.wad"), name);
        if (!back.shipped) __builtin_trap();  // our own nodes must read back as a tree
        const doom::Level level = doom::levelScene(map, nodes);
        (void)doom::mapSvg(map, nodes);
        const hsr::Camera camera = doom::viewCamera(map, nodes, doom::playerStart(map), 32, 20);
        (void)doom::renderView(map, nodes, level, camera);
      } catch (const hsr::Error&) {
      }
    }
  } catch (const hsr::Error&) {
  }
  return 0;
}

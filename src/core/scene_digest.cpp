// The scene digest (scene_digest.hpp).

#include "core/scene_digest.hpp"

#include <cstdint>

#include "core/bit_cast.hpp"

namespace hsr::detail {

std::uint64_t sceneFingerprint(const Scene& scene) {
  // Four lanes mixed apart, so that each step need not wait for the one before (it is done
  // every frame), then mixed together.
  std::uint64_t h[4] = {0x9E3779B97F4A7C15ull ^ scene.polygonCount(), 1, 2, 3};
  auto mix = [](std::uint64_t& lane, std::uint64_t v) {
    lane ^= v + 0x9E3779B97F4A7C15ull + (lane << 6) + (lane >> 2);
  };
  const std::vector<glm::vec3>& positions = scene.positions();
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const glm::vec3& p = positions[i];
    mix(h[i % 4], (std::uint64_t{bitCast<std::uint32_t>(p.x)} << 32 | bitCast<std::uint32_t>(p.y)) ^
                      (std::uint64_t{bitCast<std::uint32_t>(p.z)} << 17));
  }
  const std::size_t polygons = scene.polygonCount();
  for (PolygonId p = 0; p < polygons; ++p) mix(h[p % 4], scene.polygon(p).size());
  if (polygons > 0) {  // the polygons' vertex indices lie one after another
    const std::uint32_t* first = scene.polygon(0).data();
    const std::span<const std::uint32_t> last = scene.polygon(static_cast<PolygonId>(polygons - 1));
    const std::size_t n = static_cast<std::size_t>(last.data() + last.size() - first);
    for (std::size_t i = 0; i < n; ++i) mix(h[i % 4], first[i]);
  }
  for (int lane = 1; lane < 4; ++lane) mix(h[0], h[lane]);
  return h[0];
}

}  // namespace hsr::detail

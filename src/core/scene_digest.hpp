#pragma once
// A digest of a scene's positions and polygons, for what is built once per scene and kept
// while the scene is unchanged (the octree, the ray caster's hierarchy): a Scene has no
// revision counter to ask instead. It is computed every frame, so it is cheap: four lanes.

#include <cstdint>

#include "hsr/scene.hpp"

namespace hsr::detail {

std::uint64_t sceneFingerprint(const Scene& scene);

}  // namespace hsr::detail

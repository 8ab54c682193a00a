#pragma once
// Z-buffer (Catmull 1974; the notes' "Type 2a"): rasterize every triangle in any order and keep,
// per pixel, the nearest depth seen so far. Guarantee: bit-identical output at any thread
// count (tiles own their pixels; triangles keep submission order inside a tile).

#include "visibility/algorithm.hpp"

namespace hsr::detail {

void renderZBuffer(const AlgorithmInput& input, Frame& frame);
// Draws into an existing frame without clearing it (the GL facade's draw call).
void drawZBuffer(const AlgorithmInput& input, Frame& frame);

}  // namespace hsr::detail

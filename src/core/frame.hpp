#pragma once
// Frame buffers: sizing and clearing (glClear), reusing the memory a Frame already holds.

#include "hsr/render.hpp"

namespace hsr::detail {

// Sizes the buffers to width x height and clears them: colour to the clear colour, depth to
// the clear depth, no ids, overdraw 0; stats are reset.
void clearFrame(Frame& frame, int width, int height, const RenderOptions& options);

// The clear colour as packed RGBA8 (R in the low byte), as glClearColor quantises it.
std::uint32_t clearColorRgba(const RenderOptions& options);

// Bytes of the four buffers.
std::uint64_t frameBufferBytes(const Frame& frame);

}  // namespace hsr::detail

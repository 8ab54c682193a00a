#pragma once
// The Doom column renderer with its steps traced, for `hsr explain bsp2d` (the public
// hsr::doom::renderView is this with no trace).

#include "core/trace.hpp"
#include "hsr/doom.hpp"

namespace hsr::detail {

// Step names: the renderer's own (doom_view.cpp).
inline constexpr std::string_view kStepDrawSeg = "draw seg";
inline constexpr std::string_view kStepAllClosed = "every column closed";

Frame renderDoomView(const doom::Map& map, const doom::Nodes& nodes, const doom::Level& level,
                     const Camera& camera, std::vector<doom::ViewStep>* steps, Trace* trace);

}  // namespace hsr::detail

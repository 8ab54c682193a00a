#pragma once
// What `hsr explain bsp2d` needs from the Doom column renderer, at the orchestrator's level
// (src/explain/ stands on it, not on src/visibility/).

#include "core/trace.hpp"
#include "hsr/doom.hpp"

namespace hsr::detail {

// doom::renderView with its steps traced ("draw seg", then "every column closed").
Frame renderDoomViewTraced(const doom::Map& map, const doom::Nodes& nodes, const doom::Level& level,
                           const Camera& camera, Trace* trace);

}  // namespace hsr::detail

#pragma once
// The camera as JSON, both ways: what --stats, manifest.json and cameraJson write, and what
// --camera and --views read back (cameraFromJson in hsr/io.hpp).

#include <nlohmann/json.hpp>

#include "hsr/camera.hpp"

namespace hsr::detail {

nlohmann::ordered_json cameraObject(const Camera& camera);

}  // namespace hsr::detail

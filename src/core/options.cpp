// Render-state names as the CLI and the GL facade spell them.

#include <algorithm>
#include <cctype>
#include <string>

#include "hsr/error.hpp"
#include "hsr/render.hpp"

namespace hsr {
namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return out;
}

}  // namespace

CullMode parseCullMode(std::string_view s) {
  const std::string v = lower(s);
  if (v == "none") return CullMode::None;
  if (v == "back") return CullMode::Back;
  if (v == "front") return CullMode::Front;
  if (v == "both" || v == "front_and_back") return CullMode::FrontAndBack;
  throw Error("unknown cull mode '" + std::string(s) + "' (none, back, front, both)");
}

FrontFace parseFrontFace(std::string_view s) {
  const std::string v = lower(s);
  if (v == "ccw") return FrontFace::Ccw;
  if (v == "cw") return FrontFace::Cw;
  throw Error("unknown front face '" + std::string(s) + "' (ccw, cw)");
}

PolygonMode parsePolygonMode(std::string_view s) {
  const std::string v = lower(s);
  if (v == "fill") return PolygonMode::Fill;
  if (v == "line") return PolygonMode::Line;
  if (v == "point") return PolygonMode::Point;
  throw Error("unknown polygon mode '" + std::string(s) + "' (fill, line, point)");
}

DepthFunc parseDepthFunc(std::string_view s) {
  const std::string v = lower(s);
  if (v == "never") return DepthFunc::Never;
  if (v == "less") return DepthFunc::Less;
  if (v == "equal") return DepthFunc::Equal;
  if (v == "lequal") return DepthFunc::LEqual;
  if (v == "greater") return DepthFunc::Greater;
  if (v == "notequal") return DepthFunc::NotEqual;
  if (v == "gequal") return DepthFunc::GEqual;
  if (v == "always") return DepthFunc::Always;
  throw Error("unknown depth func '" + std::string(s) +
              "' (never, less, equal, lequal, greater, notequal, gequal, always)");
}

}  // namespace hsr

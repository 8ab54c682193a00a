// The registry's public face: the table's entries as AlgorithmInfo, lookup by name.

#include <string>
#include <vector>

#include "hsr/algorithms.hpp"
#include "hsr/error.hpp"
#include "visibility/algorithm.hpp"

namespace hsr {

namespace detail {

const AlgorithmEntry& findEntry(std::string_view name) {
  for (const AlgorithmEntry& e : algorithmTable())
    if (e.info.name == name) return e;
  std::string known;
  for (const AlgorithmEntry& e : algorithmTable()) {
    if (!known.empty()) known += ", ";
    known += e.info.name;
  }
  throw Error("unknown algorithm '" + std::string(name) + "' (known: " + known + ")");
}

}  // namespace detail

const std::vector<AlgorithmInfo>& algorithms() {
  static const std::vector<AlgorithmInfo> infos = [] {
    std::vector<AlgorithmInfo> v;
    for (const detail::AlgorithmEntry& e : detail::algorithmTable()) v.push_back(e.info);
    return v;
  }();
  return infos;
}

const AlgorithmInfo& findAlgorithm(std::string_view name) {
  detail::findEntry(name);  // throws, naming the known algorithms, when there is none
  for (const AlgorithmInfo& a : algorithms())
    if (a.name == name) return a;
  return algorithms().front();  // unreachable: findEntry found it
}

const AlgorithmInfo& referenceAlgorithm() {
  for (const AlgorithmInfo& a : algorithms())
    if (a.reference) return a;
  return algorithms().front();
}

const AlgorithmInfo* explainedBy(const AlgorithmInfo& info) {
  if (info.has(kExplain)) return &info;
  if (info.textbook || info.sibling.empty()) return nullptr;
  const AlgorithmInfo& textbook = findAlgorithm(info.sibling);
  return textbook.has(kExplain) ? &textbook : nullptr;
}

std::string_view toString(Precision p) { return p == Precision::kImage ? "image" : "object"; }

std::string_view toString(InputKind k) {
  switch (k) {
    case InputKind::kScreenTriangles:
      return "screen triangles";
    case InputKind::kWindowPolygons:
      return "window polygons";
    case InputKind::kWorldPolygons:
      return "world polygons";
    case InputKind::kMap2D:
      return "2D map";
  }
  return "?";
}

std::string capabilityList(std::uint32_t caps) {
  static constexpr std::pair<Capability, std::string_view> kNames[] = {
      {kExactSharedCoverage, "exact-coverage"},
      {kDepthFuncs, "depth-funcs"},
      {kDepthMask, "depth-mask"},
      {kPolygonModes, "polygon-modes"},
      {kOutline, "outline"},
      {kTransparency, "transparency"},
      {kVisibleSet, "visible-set"},
      {kExplain, "explain"},
      {kDrawOver, "draw-over"},
      {kBackToFront, "back-to-front"},
      {kAntialiasing, "antialiasing"},
      {kTieRule, "tie-rule"},
      {kZBufferFrame, "zbuffer-frame"},
  };
  std::string names;
  for (const auto& [cap, name] : kNames)
    if (caps & cap) {
      if (!names.empty()) names += ", ";
      names += name;
    }
  return names;
}

}  // namespace hsr

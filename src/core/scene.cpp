// Scene building and queries.

#include "hsr/scene.hpp"

#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "hsr/error.hpp"

namespace hsr {

void Bounds::extend(const glm::vec3& p) {
  lo = glm::min(lo, p);
  hi = glm::max(hi, p);
}

void Bounds::extend(const Bounds& b) {
  if (b.empty()) return;
  extend(b.lo);
  extend(b.hi);
}

float Bounds::radius() const { return empty() ? 0.0f : 0.5f * glm::length(hi - lo); }

void Scene::beginObject(std::string object_name) {
  Object o;
  o.name = std::move(object_name);
  o.first_polygon = static_cast<std::uint32_t>(polygonCount());
  o.first_vertex = static_cast<std::uint32_t>(positions_.size());
  objects.push_back(std::move(o));
}

void Scene::reserve(std::size_t vertices, std::size_t polygons, std::size_t corners) {
  positions_.reserve(positions_.size() + vertices);
  indices_.reserve(indices_.size() + corners);
  offsets_.reserve(offsets_.size() + polygons);
  polygon_material_.reserve(polygon_material_.size() + polygons);
  polygon_object_.reserve(polygon_object_.size() + polygons);
}

std::uint32_t Scene::addMaterial(const Material& m) {
  materials.push_back(m);
  return static_cast<std::uint32_t>(materials.size() - 1);
}

std::uint32_t Scene::addVertex(const glm::vec3& p) {
  if (objects.empty()) beginObject("object");
  Object& o = objects.back();
  o.bounds.extend(p);
  o.vertex_count++;
  positions_.push_back(p);
  return static_cast<std::uint32_t>(positions_.size() - 1 - o.first_vertex);
}

PolygonId Scene::addPolygon(std::span<const std::uint32_t> local_indices, std::uint32_t material) {
  if (objects.empty()) beginObject("object");
  Object& o = objects.back();
  if (local_indices.size() < 3)
    throw Error("polygon " + std::to_string(polygonCount()) + " has fewer than 3 vertices");
  for (std::uint32_t i : local_indices) {
    if (i >= o.vertex_count)
      throw Error("polygon " + std::to_string(polygonCount()) + " uses vertex " +
                  std::to_string(i) + " of an object with " + std::to_string(o.vertex_count));
    indices_.push_back(o.first_vertex + i);
  }
  if (indices_.size() > 0xFFFFFFF0u) throw Error("scene too large: over 4G polygon vertices");
  offsets_.push_back(static_cast<std::uint32_t>(indices_.size()));
  polygon_material_.push_back(material);
  polygon_object_.push_back(static_cast<std::uint32_t>(objects.size() - 1));
  o.polygon_count++;
  return static_cast<PolygonId>(polygonCount() - 1);
}

PolygonId Scene::addPolygon(std::initializer_list<std::uint32_t> local_indices,
                            std::uint32_t material) {
  return addPolygon(std::span<const std::uint32_t>(local_indices.begin(), local_indices.size()),
                    material);
}

PolygonId Scene::addPolygonVertices(std::span<const glm::vec3> vertices, std::uint32_t material) {
  std::vector<std::uint32_t> local;
  local.reserve(vertices.size());
  for (const glm::vec3& p : vertices) local.push_back(addVertex(p));
  return addPolygon(local, material);
}

PolygonId Scene::addPolygonVertices(std::initializer_list<glm::vec3> vertices,
                                    std::uint32_t material) {
  return addPolygonVertices(std::span<const glm::vec3>(vertices.begin(), vertices.size()),
                            material);
}

Bounds Scene::bounds() const {
  Bounds b;
  for (const Object& o : objects) b.extend(o.bounds);
  return b;
}

std::size_t Scene::triangleCount() const {
  std::size_t n = 0;
  for (std::size_t i = 0; i + 1 < offsets_.size(); ++i) {
    const std::size_t k = offsets_[i + 1] - offsets_[i];
    if (k >= 3) n += k - 2;
  }
  return n;
}

std::size_t Scene::memoryBytes() const {
  return positions_.capacity() * sizeof(glm::vec3) + indices_.capacity() * 4 +
         offsets_.capacity() * 4 + polygon_material_.capacity() * 4 +
         polygon_object_.capacity() * 4 + objects.capacity() * sizeof(Object) +
         materials.capacity() * sizeof(Material);
}

}  // namespace hsr

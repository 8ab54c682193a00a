#pragma once
// Scene: polygons in world space (every node transform already applied), each with a stable
// PolygonId = its index in load order. Vertices are shared through an index list, as in an
// indexed draw call, so a vertex is transformed once however many polygons use it.

#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace hsr {

using PolygonId = std::uint32_t;
inline constexpr PolygonId kNoPolygon = 0xFFFFFFFFu;  // "nothing drawn" in id buffers

struct Material {
  glm::vec3 color{0.8f, 0.8f, 0.8f};  // linear rgb in [0,1]
  float alpha = 1.0f;                 // 1 = opaque
  std::string name{};                 // the file's name for it ("" when it has none)
};

// Axis-aligned bounds; empty when lo > hi.
struct Bounds {
  glm::vec3 lo{std::numeric_limits<float>::infinity()};
  glm::vec3 hi{-std::numeric_limits<float>::infinity()};
  void extend(const glm::vec3& p);
  void extend(const Bounds& b);
  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  glm::vec3 center() const { return (lo + hi) * 0.5f; }
  float radius() const;  // half the diagonal
};

// A group of polygons culled together by its bounds (view-frustum culling). An object owns
// a contiguous range of polygons and a contiguous range of vertices.
struct Object {
  std::string name;
  std::uint32_t first_polygon = 0, polygon_count = 0;
  std::uint32_t first_vertex = 0, vertex_count = 0;
  Bounds bounds;
};

// A camera stored in the scene file (glTF); the first frames the scene unless another or none
// is chosen.
struct SceneCamera {
  glm::vec3 eye{0.0f}, target{0.0f, 0.0f, -1.0f}, up{0.0f, 1.0f, 0.0f};
  float fov_deg = 45.0f;
  bool ortho = false;
  float ortho_half_height = 1.0f;
  float near = 0.1f, far = 100.0f;
};

class Scene {
 public:
  std::string name;
  std::vector<Material> materials;
  std::vector<Object> objects;
  std::vector<SceneCamera> cameras;  // the file's, in its order

  // Building. beginObject starts a new object; vertices and polygons added afterwards belong
  // to it. Indices passed to addPolygon are relative to the current object's first vertex.
  void beginObject(std::string object_name);
  std::uint32_t addMaterial(const Material& m);
  std::uint32_t addVertex(const glm::vec3& p);
  PolygonId addPolygon(std::span<const std::uint32_t> local_indices, std::uint32_t material);
  PolygonId addPolygon(std::initializer_list<std::uint32_t> local_indices, std::uint32_t material);
  // Convenience: appends the vertices (unshared) and the polygon.
  PolygonId addPolygonVertices(std::span<const glm::vec3> vertices, std::uint32_t material);
  PolygonId addPolygonVertices(std::initializer_list<glm::vec3> vertices, std::uint32_t material);

  // Room for this many more vertices, polygons and polygon corners (an importer that knows
  // its counts: no regrowth).
  void reserve(std::size_t vertices, std::size_t polygons, std::size_t corners);

  // Reading.
  std::size_t polygonCount() const { return offsets_.size() - 1; }
  std::size_t vertexCount() const { return positions_.size(); }
  std::span<const std::uint32_t> polygon(PolygonId id) const {  // absolute vertex indices
    return {indices_.data() + offsets_[id], indices_.data() + offsets_[id + 1]};
  }
  const glm::vec3& position(std::uint32_t v) const { return positions_[v]; }
  const std::vector<glm::vec3>& positions() const { return positions_; }
  std::uint32_t material(PolygonId id) const { return polygon_material_[id]; }
  std::uint32_t object(PolygonId id) const { return polygon_object_[id]; }
  Bounds bounds() const;
  std::size_t triangleCount() const;  // sum of (n - 2) over polygons
  std::size_t memoryBytes() const;

 private:
  std::vector<glm::vec3> positions_;
  std::vector<std::uint32_t> indices_;
  std::vector<std::uint32_t> offsets_{0};
  std::vector<std::uint32_t> polygon_material_;
  std::vector<std::uint32_t> polygon_object_;
};

}  // namespace hsr

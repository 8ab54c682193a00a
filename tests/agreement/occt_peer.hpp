#pragma once
// Open CASCADE's polygonal hidden-line removal (HLRBRep_PolyAlgo; Debian's
// libocct-modeling-algorithms-dev and libocct-modeling-data-dev) as the peer of hsr's line
// drawings: the same triangles, seen by the same camera, the visible and hidden lines in hsr's
// window pixels. OCCT's headers stay in occt_peer.cpp.

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "hsr/camera.hpp"
#include "hsr/scene.hpp"

namespace hsr::testing {

// A triangle mesh with vertices shared by index: OCCT sees an edge between two triangles only
// where they share its two vertices.
struct OcctMesh {
  std::vector<glm::dvec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

// Every polygon of every object, fan-triangulated, equal positions welded into one vertex (an
// STL file repeats them per triangle).
OcctMesh occtMeshOf(const Scene& scene);

enum class OcctMode {
  // One planar face per triangle, edges shared: sharp edges (dihedral angle above the crease
  // angle), edges on the outline and the outline itself; smooth edges (Rg1) are left out.
  kFacePerTriangle,
  // The whole mesh as one face with one triangulation and per-node normals: OCCT draws its
  // outline (silhouette) only. For closed meshes without creases.
  kSingleFace,
};

struct OcctSegment {
  glm::dvec2 a, b;
};

struct OcctLines {
  std::vector<OcctSegment> visible, hidden;  // hsr window pixels (Camera: y down, centres at k)
  double build_ms = 0;  // the OCCT shape: faces, edges, triangulations, regularity
  double hlr_ms = 0;    // Load + Projector + Update + HLRBRep_PolyHLRToShape's compounds + reading
};

// Throws std::runtime_error when a vertex is not in front of the eye (perspective cameras).
OcctLines occtHiddenLines(const OcctMesh& mesh, const Camera& camera, OcctMode mode,
                          double crease_angle_deg = 45);

// Where `p` lands in hsr's window through the space and HLRAlgo_Projector that
// occtHiddenLines gives OCCT: for checking that mapping against camera.projection() * view().
glm::dvec2 occtPixelOf(const Camera& camera, const glm::dvec3& p);

}  // namespace hsr::testing

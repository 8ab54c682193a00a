// The Open CASCADE peer (occt_peer.hpp).
//
// HLRBRep_PolyAlgo hides in parallel projection only: HLRAlgo_PolyAlgo and HLRAlgo_PolyData,
// which do the hiding, compare projected x and y and never read the projector's focus (only
// the back-face and outline tests do). So OCCT is given the mesh already in hsr's window:
// x, y in pixels (y negated, to keep the space right-handed) and a depth that grows towards
// the eye, k / w for perspective cameras (w = -z in eye space). That map is projective: it
// keeps lines straight, planes flat, which triangle is in front and which side faces the eye,
// so a parallel view along -z of the mapped mesh is the camera's view of the mesh. The
// projector is then the identity (axonometric along z) and OCCT's 2D points are pixels.
//
// What HLRBRep_PolyHLRToShape's compounds carry (7.6.3's source, and the cube and sphere
// of occt_peer_test.cpp): each piece of line has the flags Rg1 (the edge's continuity is G1 or
// more), RgN (G2 or more), OutLine (an edge lying on the outline), IntLine (an outline drawn
// across a face's triangulation, not on an edge). VCompound / HCompound: every edge except
// the smooth ones (Rg1 and not OutLine), so sharp edges and smooth edges on the outline; the
// RgN compounds: G2 edges not on the outline (none here: we encode G1 at most);
// Rg1LineVCompound: smooth edges off the outline; OutLineVCompound / OutLineHCompound: the
// IntLine pieces, despite the name. With a face per triangle the outline runs along edges
// (VCompound); with one face it crosses the triangulation (OutLineVCompound).

#include "agreement/occt_peer.hpp"

#include <BRepLib_MakeEdge2d.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <ElSLib.hxx>
#include <GeomAbs_Shape.hxx>
#include <Geom2d_Line.hxx>
#include <Geom_Line.hxx>
#include <Geom_Plane.hxx>
#include <HLRAlgo_Projector.hxx>
#include <HLRBRep_PolyAlgo.hxx>
#include <HLRBRep_PolyHLRToShape.hxx>
#include <Poly_PolygonOnTriangulation.hxx>
#include <Poly_Triangulation.hxx>
#include <Precision.hxx>
#include <Standard_Version.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Ax2.hxx>
#include <gp_Ax3.hxx>
#include <gp_Pln.hxx>

#include <chrono>
#include <cmath>
#include <cstring>
#include <numbers>
#include <stdexcept>
#include <unordered_map>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

namespace hsr::testing {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// World -> OCCT's space (see the top of the file), from hsr's own matrices in double.
struct WindowSpace {
  glm::dmat4 view, projection;
  double width, height, depth_scale;
  bool ortho;

  explicit WindowSpace(const Camera& camera)
      : view(camera.view()),
        projection(camera.projection()),
        width(camera.width),
        height(camera.height),
        ortho(camera.ortho) {
    const double sx = projection[0][0] * width / 2;  // pixels per unit of x / w (or of x)
    const double distance = glm::length(glm::dvec3(camera.eye) - glm::dvec3(camera.target));
    depth_scale = ortho ? sx : sx * distance;  // depth in about the pixels' scale near target
  }

  gp_Pnt map(const glm::dvec3& p) const {
    const glm::dvec4 eye = view * glm::dvec4(p, 1.0);
    const glm::dvec4 clip = projection * eye;
    if (!(clip.w > 0)) throw std::runtime_error("OCCT peer: a vertex is not in front of the eye");
    const double x = (clip.x / clip.w + 1) / 2 * width - 0.5;
    const double y = (1 - clip.y / clip.w) / 2 * height - 0.5;
    return gp_Pnt(x, -y, ortho ? depth_scale * eye.z : depth_scale / -eye.z);
  }
};

// The identity, axonometric: OCCT's projected (x, y) is the mapped point's.
HLRAlgo_Projector windowProjector() {
  return HLRAlgo_Projector(gp_Ax2(gp::Origin(), gp::DZ(), gp::DX()));
}

glm::dvec2 pixelOf(const gp_Pnt2d& p) { return {p.X(), -p.Y()}; }

std::uint64_t edgeKey(std::uint32_t a, std::uint32_t b) {
  return a < b ? (std::uint64_t{a} << 32) | b : (std::uint64_t{b} << 32) | a;
}

// A planar face per triangle. The triangulation, UV nodes, pcurves and polygons on
// triangulation are made here rather than by BRepMesh_IncrementalMesh: the same data
// BRepMesh would give a triangle, without meshing each face.
TopoDS_Shape facePerTriangle(const OcctMesh& mesh, const std::vector<gp_Pnt>& at,
                             double crease_rad) {
  BRep_Builder builder;
  std::vector<TopoDS_Vertex> vertices(at.size());
  for (std::size_t i = 0; i < at.size(); ++i)
    builder.MakeVertex(vertices[i], at[i], Precision::Confusion());

  struct Edge {
    TopoDS_Edge edge;
    std::uint32_t from = 0;  // the edge runs from vertex `from` to the other
    int faces = 0;
    TopoDS_Face face[2];
    glm::dvec3 normal[2];  // the faces' normals in world space, for the crease angle
  };
  std::unordered_map<std::uint64_t, Edge> edges;
  edges.reserve(mesh.triangles.size() * 2);

  TopoDS_Shell shell;
  builder.MakeShell(shell);
  for (const auto& t : mesh.triangles) {
    const glm::dvec3 world_normal = glm::cross(mesh.vertices[t[1]] - mesh.vertices[t[0]],
                                               mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    const gp_Vec n = gp_Vec(at[t[0]], at[t[1]]).Crossed(gp_Vec(at[t[0]], at[t[2]]));
    // Degenerate in the world or in the window (seen edge-on): no face to draw
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || glm::length(world_normal) == 0 ||
        n.Magnitude() <= gp::Resolution())
      continue;
    const gp_Ax3 frame(at[t[0]], gp_Dir(n), gp_Dir(gp_Vec(at[t[0]], at[t[1]])));
    const gp_Pln plane(frame);
    TopoDS_Face face;
    builder.MakeFace(face, new Geom_Plane(plane), Precision::Confusion());
    Handle(Poly_Triangulation) triangulation = new Poly_Triangulation(3, 1, true, true);
    const gp_Dir dir(n);
    for (int k = 0; k < 3; ++k) {
      double u = 0, v = 0;
      ElSLib::Parameters(plane, at[t[k]], u, v);
      triangulation->SetNode(k + 1, at[t[k]]);
      triangulation->SetUVNode(k + 1, gp_Pnt2d(u, v));
      triangulation->SetNormal(k + 1, gp_Vec3f(float(dir.X()), float(dir.Y()), float(dir.Z())));
    }
    triangulation->SetTriangle(1, Poly_Triangle(1, 2, 3));
    TopoDS_Wire wire;
    builder.MakeWire(wire);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      Edge& e = edges[edgeKey(a, b)];
      const double length = at[a].Distance(at[b]);
      if (e.faces == 0) {
        builder.MakeEdge(e.edge, new Geom_Line(at[a], gp_Dir(gp_Vec(at[a], at[b]))),
                         Precision::Confusion());
        TopoDS_Vertex va = vertices[a], vb = vertices[b];
        va.Orientation(TopAbs_FORWARD);
        vb.Orientation(TopAbs_REVERSED);
        builder.Add(e.edge, va);
        builder.Add(e.edge, vb);
        builder.Range(e.edge, 0, length, true);
        e.from = a;
      }
      const bool forward = e.from == a;
      // On the plane, parameter s along the edge from `from` is arc length, as on the 3D line
      double u0 = 0, v0 = 0, u1 = 0, v1 = 0;
      ElSLib::Parameters(plane, at[e.from], u0, v0);
      ElSLib::Parameters(plane, at[e.from == a ? b : a], u1, v1);
      builder.UpdateEdge(e.edge, new Geom2d_Line(gp_Pnt2d(u0, v0), gp_Dir2d(u1 - u0, v1 - v0)),
                         face, Precision::Confusion());
      builder.Range(e.edge, face, 0, length);
      Handle(Poly_PolygonOnTriangulation) polygon = new Poly_PolygonOnTriangulation(2, true);
      const int na = k + 1, nb = (k + 1) % 3 + 1;
      polygon->SetNode(1, forward ? na : nb);
      polygon->SetNode(2, forward ? nb : na);
      polygon->SetParameter(1, 0);
      polygon->SetParameter(2, length);
      builder.UpdateEdge(e.edge, polygon, triangulation, TopLoc_Location());
      builder.Add(wire, forward ? e.edge : TopoDS::Edge(e.edge.Reversed()));
      if (e.faces < 2) {
        e.face[e.faces] = face;
        e.normal[e.faces] = glm::normalize(world_normal);
      }
      ++e.faces;
    }
    builder.Add(face, wire);
    builder.UpdateFace(face, triangulation);
    builder.Add(shell, face);
  }
  // Regularity from the world's dihedral angles: BRepLib::EncodeRegularity would measure them
  // in the window space, where a perspective camera bends them
  const double cos_crease = std::cos(crease_rad);
  for (auto& [key, e] : edges)
    if (e.faces == 2 && glm::dot(e.normal[0], e.normal[1]) >= cos_crease)
      builder.Continuity(e.edge, e.face[0], e.face[1], GeomAbs_G1);
  return shell;
}

// The whole mesh as one face: one triangulation with UV nodes and area-weighted node normals
// (HLRBRep_PolyAlgo computes node normals, which find the outline, only for triangulations with
// UV nodes; it takes the triangulation's own normals before a surface's, so no surface).
TopoDS_Shape singleFace(const OcctMesh& mesh, const std::vector<gp_Pnt>& at) {
  std::vector<std::array<std::uint32_t, 3>> kept;
  kept.reserve(mesh.triangles.size());
  std::vector<gp_Vec> normals(at.size(), gp_Vec(0, 0, 0));
  for (const auto& t : mesh.triangles) {
    const gp_Vec n = gp_Vec(at[t[0]], at[t[1]]).Crossed(gp_Vec(at[t[0]], at[t[2]]));
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || n.Magnitude() <= gp::Resolution()) continue;
    kept.push_back(t);
    for (int k = 0; k < 3; ++k) normals[t[k]] += n;
  }
  Handle(Poly_Triangulation) triangulation =
      new Poly_Triangulation(int(at.size()), int(kept.size()), true, true);
  for (std::size_t i = 0; i < at.size(); ++i) {
    const int node = int(i) + 1;
    triangulation->SetNode(node, at[i]);
    triangulation->SetUVNode(node, gp_Pnt2d(at[i].X(), at[i].Y()));
    const double m = normals[i].Magnitude();
    const gp_Vec n = m > 0 ? normals[i] / m : gp_Vec(0, 0, 1);
    triangulation->SetNormal(node, gp_Vec3f(float(n.X()), float(n.Y()), float(n.Z())));
  }
  for (std::size_t i = 0; i < kept.size(); ++i)
    triangulation->SetTriangle(
        int(i) + 1, Poly_Triangle(int(kept[i][0]) + 1, int(kept[i][1]) + 1, int(kept[i][2]) + 1));
  BRep_Builder builder;
  TopoDS_Face face;
  builder.MakeFace(face, triangulation);
  TopoDS_Compound compound;
  builder.MakeCompound(compound);
  builder.Add(compound, face);
  return compound;
}

void readSegments(const TopoDS_Shape& compound, std::vector<OcctSegment>& out) {
  if (compound.IsNull()) return;  // OCCT's "no line of this kind"
  for (TopExp_Explorer it(compound, TopAbs_EDGE); it.More(); it.Next()) {
    TopoDS_Vertex first, last;
    TopExp::Vertices(TopoDS::Edge(it.Current()), first, last);
    const gp_Pnt a = BRep_Tool::Pnt(first), b = BRep_Tool::Pnt(last);
    out.push_back({pixelOf(gp_Pnt2d(a.X(), a.Y())), pixelOf(gp_Pnt2d(b.X(), b.Y()))});
  }
}

}  // namespace

OcctMesh occtMeshOf(const Scene& scene) {
  OcctMesh mesh;
  // Weld by exact position (the float's bits; -0 and +0 alike)
  struct Key {
    float x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      std::uint32_t b[3];
      const float v[3] = {k.x + 0.0f, k.y + 0.0f, k.z + 0.0f};
      std::memcpy(b, v, sizeof b);
      return (std::size_t{b[0]} * 0x9E3779B97F4A7C15ull) ^
             (std::size_t{b[1]} * 0xC2B2AE3D27D4EB4Full) ^
             (std::size_t{b[2]} * 0x165667B19E3779F9ull);
    }
  };
  std::unordered_map<Key, std::uint32_t, Hash> welded;
  std::vector<std::uint32_t> index_of(scene.vertexCount());
  for (std::size_t v = 0; v < scene.vertexCount(); ++v) {
    const glm::vec3& p = scene.position(std::uint32_t(v));
    const auto [it, added] =
        welded.try_emplace(Key{p.x, p.y, p.z}, std::uint32_t(mesh.vertices.size()));
    if (added) mesh.vertices.emplace_back(p);
    index_of[v] = it->second;
  }
  mesh.triangles.reserve(scene.triangleCount());
  for (PolygonId id = 0; id < scene.polygonCount(); ++id) {
    const auto poly = scene.polygon(id);
    for (std::size_t k = 1; k + 1 < poly.size(); ++k)
      mesh.triangles.push_back({index_of[poly[0]], index_of[poly[k]], index_of[poly[k + 1]]});
  }
  return mesh;
}

OcctLines occtHiddenLines(const OcctMesh& mesh, const Camera& camera, OcctMode mode,
                          double crease_angle_deg) {
  OcctLines lines;
  auto t0 = Clock::now();
  const WindowSpace space(camera);
  std::vector<gp_Pnt> at;
  at.reserve(mesh.vertices.size());
  for (const glm::dvec3& p : mesh.vertices) at.push_back(space.map(p));
  const TopoDS_Shape shape =
      mode == OcctMode::kFacePerTriangle
          ? facePerTriangle(mesh, at, crease_angle_deg * std::numbers::pi / 180)
          : singleFace(mesh, at);
  lines.build_ms = msSince(t0);

  t0 = Clock::now();
  Handle(HLRBRep_PolyAlgo) algo = new HLRBRep_PolyAlgo();
  algo->Load(shape);
  algo->Projector(windowProjector());
  algo->Update();
  HLRBRep_PolyHLRToShape to_shape;
  to_shape.Update(algo);
  if (mode == OcctMode::kFacePerTriangle) {
    readSegments(to_shape.VCompound(), lines.visible);
    readSegments(to_shape.HCompound(), lines.hidden);
  }
  readSegments(to_shape.OutLineVCompound(), lines.visible);
  readSegments(to_shape.OutLineHCompound(), lines.hidden);
  lines.hlr_ms = msSince(t0);
  return lines;
}

glm::dvec2 occtPixelOf(const Camera& camera, const glm::dvec3& p) {
  gp_Pnt2d out;
  windowProjector().Project(WindowSpace(camera).map(p), out);
  return pixelOf(out);
}

}  // namespace hsr::testing

// Mesh files through assimp, and loadScene (a file, else a built-in scene).
// Guarantee: any input (missing, truncated, malformed, hostile) either loads into a Scene whose
// every position is finite and every index in range, or throws hsr::Error with one line that
// names the file. Polygons stay polygons (no triangulation); ids follow node order (root first,
// depth first, children in order), then each mesh's face order.

#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdio>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <new>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <assimp/GltfMaterial.h>
#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>
#include <glm/geometric.hpp>

#include "hsr/doom.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/scene.hpp"
#include "io/confined_io.hpp"
#include "io/import_preflight.hpp"
#include "io/import_sandbox.hpp"

namespace hsr {
namespace {

namespace fs = std::filesystem;

// Limits on untrusted input, checked before anything is allocated for it.
using detail::kMaxFileBytes;
constexpr std::uint64_t kMaxVertices = 50'000'000;
constexpr std::uint64_t kMaxPolygons = 50'000'000;
constexpr std::uint64_t kMaxNodes = 10'000'000;  // a node tree this big is an attack
using detail::kMaxCameras;

// The import's size limits, checked in 64 bits before anything is allocated for the meshes.
void checkSizeLimits(const std::string& file, std::uint64_t vertices, std::uint64_t polygons) {
  if (vertices > kMaxVertices)
    throw Error(file + ": too large (over " + std::to_string(kMaxVertices / 1000000) +
                "M vertices)");
  if (polygons > kMaxPolygons)
    throw Error(file + ": too large (over " + std::to_string(kMaxPolygons / 1000000) +
                "M polygons)");
}

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

bool finite(const aiMatrix4x4& m) {
  for (unsigned r = 0; r < 4; ++r)
    for (unsigned c = 0; c < 4; ++c)
      if (!std::isfinite(m[r][c])) return false;
  return true;
}

// Affine transform of a point in double precision (assimp matrices are row-major, column
// vectors, translation in the last column).
glm::vec3 transformPoint(const aiMatrix4x4& m, const aiVector3D& p) {
  const double x = p.x, y = p.y, z = p.z;
  return {static_cast<float>(m.a1 * x + m.a2 * y + m.a3 * z + m.a4),
          static_cast<float>(m.b1 * x + m.b2 * y + m.b3 * z + m.b4),
          static_cast<float>(m.c1 * x + m.c2 * y + m.c3 * z + m.c4)};
}

float clamp01(float v, float fallback) {
  return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : fallback;
}

// An assimp material as ours: glTF's base colour (with alpha, unless alphaMode is OPAQUE),
// else the diffuse colour and opacity.
Material convertMaterial(const aiMaterial* m) {
  Material out;
  if (!m) return out;
  // assimp's stand-in for a file without materials (an OBJ without an .mtl): hsr's one default
  aiString name;
  if (m->Get(AI_MATKEY_NAME, name) == AI_SUCCESS) {
    if (std::string_view(name.C_Str()) == AI_DEFAULT_MATERIAL_NAME) return out;
    out.name = name.C_Str();
  }
  aiColor4D c;
  bool have_alpha = false;
  if (m->Get(AI_MATKEY_BASE_COLOR, c) == AI_SUCCESS) {
    out.color = {clamp01(c.r, 0.8f), clamp01(c.g, 0.8f), clamp01(c.b, 0.8f)};
    out.alpha = clamp01(c.a, 1.0f);
    have_alpha = true;
    aiString mode;
    if (m->Get(AI_MATKEY_GLTF_ALPHAMODE, mode) == AI_SUCCESS &&
        std::string_view(mode.C_Str()) == "OPAQUE")
      out.alpha = 1.0f;
  } else if (m->Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS) {
    out.color = {clamp01(c.r, 0.8f), clamp01(c.g, 0.8f), clamp01(c.b, 0.8f)};
  }
  float opacity = 1.0f;
  if (!have_alpha && m->Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS)
    out.alpha = clamp01(opacity, 1.0f);
  // Opacity 0 is what several exporters write for "opaque" (OBJ's "d 0"); an invisible
  // material is never what a file meant to show
  if (out.alpha <= 0.0f) out.alpha = 1.0f;
  return out;
}

bool hasNoMaterials(const fs::path& path) {
  const std::string ext = detail::lowerExtension(path);
  return ext == ".ply" || ext == ".stl" || ext == ".off";
}

bool isGltf(const fs::path& path) {
  const std::string ext = detail::lowerExtension(path);
  return ext == ".gltf" || ext == ".glb";
}

// The node's transform to world space: the product of its ancestors' transforms.
aiMatrix4x4 globalTransform(const aiNode* node) {
  aiMatrix4x4 m = node->mTransformation;
  std::uint64_t depth = 0;
  for (const aiNode* p = node->mParent; p && depth < kMaxNodes; p = p->mParent, ++depth)
    m = p->mTransformation * m;
  return m;
}

// glTF: the first camera that a node places. A glTF camera sits at its node's origin, looks
// down the node's -Z with +Y up (assimp 5.2 also copies the node's translation into
// mPosition, which would count it twice, so aiCamera's own frame is not used). assimp stores
// yfov * aspect in mHorizontalFOV, and xmag in mOrthographicWidth with mAspect = xmag / ymag.
// The vertices of one mesh with identical positions (the same floats; 0 and -0 alike), joined:
// find(v) gives the first vertex of the mesh seen at v's position (v itself when it is the
// first). Open addressing on the vertices' indices, kept at most half full by doubling: sized
// by the distinct positions, not by the vertices (an STL repeats each about six times), so
// that it stays in the cache. O(1) a vertex.
class PositionJoin {
 public:
  void reset(const aiVector3D* vertices) {
    slots_.assign(1024, Slot{});
    used_ = 0;
    vertices_ = vertices;
  }
  unsigned find(unsigned v) {
    const aiVector3D& p = vertices_[v];
    const Slot key{bits(p.x), bits(p.y), bits(p.z), v};
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = hash(key) & mask;; i = (i + 1) & mask) {
      Slot& s = slots_[i];
      if (s.index == kEmpty) {
        s = key;
        if (2 * ++used_ > slots_.size()) grow();
        return v;
      }
      if (s.x == key.x && s.y == key.y && s.z == key.z) return s.index;
    }
  }

 private:
  static constexpr unsigned kEmpty = 0xFFFFFFFFu;
  // The position's bits beside the index: one cache line read a lookup
  struct Slot {
    std::uint32_t x = 0, y = 0, z = 0;
    unsigned index = kEmpty;
  };
  static std::uint32_t bits(float v) { return std::bit_cast<std::uint32_t>(v + 0.0f); }  // -0 as 0
  // The three words mixed (a multiply-xorshift finaliser), the table indexed by the high bits
  static std::size_t hash(const Slot& k) {
    std::uint64_t h =
        (std::uint64_t{k.x} << 32 | k.y) * 0x9E3779B97F4A7C15ull ^ k.z * 0xC2B2AE3D27D4EB4Full;
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 29;
    return static_cast<std::size_t>(h >> 24);
  }
  void grow() {
    std::vector<Slot> old(2 * slots_.size());
    old.swap(slots_);
    const std::size_t mask = slots_.size() - 1;
    for (const Slot& s : old) {
      if (s.index == kEmpty) continue;
      std::size_t i = hash(s) & mask;
      while (slots_[i].index != kEmpty) i = (i + 1) & mask;
      slots_[i] = s;
    }
  }
  std::vector<Slot> slots_;
  std::size_t used_ = 0;
  const aiVector3D* vertices_ = nullptr;
};

// A camera that makes no sense (non-finite, degenerate) is left out.
std::optional<SceneCamera> gltfCamera(const aiScene* ai, const aiCamera* cam, const Scene& scene) {
  if (!cam) return std::nullopt;
  const aiNode* node = ai->mRootNode->FindNode(cam->mName);
  if (!node) return std::nullopt;
  const aiMatrix4x4 m = globalTransform(node);
  if (!finite(m)) return std::nullopt;
  SceneCamera s;
  s.eye = transformPoint(m, aiVector3D(0, 0, 0));
  const glm::vec3 forward = transformPoint(m, aiVector3D(0, 0, -1)) - s.eye;
  const glm::vec3 up = transformPoint(m, aiVector3D(0, 1, 0)) - s.eye;
  if (!finite(s.eye) || !finite(forward) || !finite(up)) return std::nullopt;
  const float flen = glm::length(forward), ulen = glm::length(up);
  if (!(flen > 0.0f) || !(ulen > 0.0f)) return std::nullopt;
  s.target = s.eye + forward / flen;
  s.up = up / ulen;
  if (glm::length(glm::cross(forward / flen, s.up)) < 1e-3f) return std::nullopt;

  const float aspect = cam->mAspect > 0.0f && std::isfinite(cam->mAspect) ? cam->mAspect : 1.0f;
  if (cam->mHorizontalFOV == 0.0f && cam->mOrthographicWidth > 0.0f) {
    s.ortho = true;
    s.ortho_half_height = cam->mOrthographicWidth / aspect;
    if (!std::isfinite(s.ortho_half_height) || !(s.ortho_half_height > 0.0f)) return std::nullopt;
  } else {
    s.fov_deg = static_cast<float>(cam->mHorizontalFOV / aspect * 180.0 / 3.14159265358979323846);
    if (!std::isfinite(s.fov_deg) || !(s.fov_deg > 0.0f) || !(s.fov_deg < 180.0f))
      return std::nullopt;
  }
  // Clip planes: glTF may leave zfar out (an infinite projection); fit what is missing to
  // the scene's bounds
  const Bounds b = scene.bounds();
  const float reach = b.empty() ? 100.0f : glm::length(b.center() - s.eye) + 1.5f * b.radius();
  s.far = cam->mClipPlaneFar;
  s.near = cam->mClipPlaneNear;
  if (!std::isfinite(s.far) || !(s.far > 0.0f)) s.far = std::max(reach, 1e-3f);
  // A far plane beyond the whole scene only costs depth precision: pull it in
  if (reach > 0.0f && reach < s.far && reach > 2.0f * std::max(s.near, 0.0f)) s.far = reach;
  if (!std::isfinite(s.near) || !(s.near > 0.0f) || !(s.near < s.far)) s.near = s.far * 1e-4f;
  if (!std::isfinite(s.far) || !(s.far > s.near)) return std::nullopt;
  return s;
}

std::vector<SceneCamera> gltfCameras(const aiScene* ai, const Scene& scene) {
  std::vector<SceneCamera> cameras;
  if (!ai->mRootNode || !ai->mCameras) return cameras;
  for (unsigned i = 0; i < ai->mNumCameras && cameras.size() < kMaxCameras; ++i)
    if (const std::optional<SceneCamera> c = gltfCamera(ai, ai->mCameras[i], scene))
      cameras.push_back(*c);
  return cameras;
}

// Converts the imported assimp scene: one Object per mesh instance, in node order.
Scene convertScene(const aiScene* ai, const fs::path& path) {
  const std::string file = path.string();
  Scene scene;
  scene.name = path.filename().string();

  // Materials, in the file's order; one default appended if a mesh needs it. PLY, STL and OFF
  // have none: what assimp makes up for them (white for PLY, 0.6 grey for OFF) is hsr's one
  // default instead
  const bool made_up = hasNoMaterials(path);
  for (unsigned i = 0; i < ai->mNumMaterials && ai->mMaterials; ++i)
    scene.addMaterial(made_up ? Material{} : convertMaterial(ai->mMaterials[i]));
  std::uint32_t default_material = 0xFFFFFFFFu;

  if (!ai->mRootNode) throw Error(file + ": no polygons (the file holds no scene nodes)");

  std::uint64_t vertices_total = 0, polygons_total = 0, nodes_seen = 0;
  bool saw_points_or_lines = false;
  std::vector<std::uint32_t> remap, local;
  constexpr std::uint32_t kUnset = 0xFFFFFFFFu;
  PositionJoin joined;

  // Walk the node tree depth first, root first, children in order; an explicit stack so that
  // a deep hostile hierarchy cannot overflow the call stack
  std::vector<std::pair<const aiNode*, aiMatrix4x4>> stack;
  stack.emplace_back(ai->mRootNode, ai->mRootNode->mTransformation);
  while (!stack.empty()) {
    auto [node, transform] = stack.back();
    stack.pop_back();
    if (++nodes_seen > kMaxNodes) throw Error(file + ": too large (over 10M scene nodes)");
    const bool identity = transform.IsIdentity();

    for (unsigned k = 0; k < node->mNumMeshes && node->mMeshes; ++k) {
      const unsigned mesh_index = node->mMeshes[k];
      if (mesh_index >= ai->mNumMeshes || !ai->mMeshes || !ai->mMeshes[mesh_index])
        throw Error(file + ": node '" + std::string(node->mName.C_Str()) + "' refers to mesh " +
                    std::to_string(mesh_index) + " of " + std::to_string(ai->mNumMeshes));
      const aiMesh* mesh = ai->mMeshes[mesh_index];
      if (!mesh->mVertices || !mesh->mFaces || mesh->mNumFaces == 0) continue;

      // Size limits, in 64 bits, before any allocation
      vertices_total += mesh->mNumVertices;
      polygons_total += mesh->mNumFaces;
      checkSizeLimits(file, vertices_total, polygons_total);

      std::uint32_t material = mesh->mMaterialIndex;
      if (material >= scene.materials.size()) {
        if (default_material == 0xFFFFFFFFu) default_material = scene.addMaterial(Material{});
        material = default_material;
      }

      // Faces: points and lines are not polygons; vertices enter the scene on first use, so
      // that unused ones do not widen the object's bounds
      remap.assign(mesh->mNumVertices, kUnset);
      joined.reset(mesh->mVertices);
      bool object_started = false;
      for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
        const aiFace& face = mesh->mFaces[f];
        if (face.mNumIndices < 3 || !face.mIndices) {
          saw_points_or_lines = true;
          continue;
        }
        if (!object_started) {
          std::string name = node->mName.C_Str();
          const std::string mesh_name = mesh->mName.C_Str();
          name += name.empty() ? "" : ": ";
          name += mesh_name.empty() ? "mesh " + std::to_string(mesh_index) : mesh_name;
          scene.beginObject(std::move(name));
          object_started = true;
        }
        local.clear();
        for (unsigned j = 0; j < face.mNumIndices; ++j) {
          const unsigned v = face.mIndices[j];
          if (v >= mesh->mNumVertices)
            throw Error(file + ": face " + std::to_string(f) + " of mesh " +
                        std::to_string(mesh_index) + " uses vertex " + std::to_string(v) +
                        " but the mesh has " + std::to_string(mesh->mNumVertices));
          if (remap[v] == kUnset) {
            const aiVector3D& raw = mesh->mVertices[v];
            const glm::vec3 p =
                identity ? glm::vec3(raw.x, raw.y, raw.z) : transformPoint(transform, raw);
            if (!finite(p))
              throw Error(
                  file + ": vertex " + std::to_string(v) + " of mesh " +
                  std::to_string(mesh_index) + " is not finite" +
                  (finite(glm::vec3(raw.x, raw.y, raw.z)) ? " after its node's transform" : ""));
            // Identical positions in the file join into one shared vertex (assimp's
            // JoinIdenticalVertices did this, at 3x the cost of reading a binary PLY)
            const unsigned first = joined.find(v);
            remap[v] = first != v ? remap[first] : scene.addVertex(p);
          }
          local.push_back(remap[v]);
        }
        scene.addPolygon(local, material);
      }
    }

    // Children in order: pushed in reverse so the first is popped first
    if (node->mChildren) {
      for (unsigned c = node->mNumChildren; c-- > 0;) {
        const aiNode* child = node->mChildren[c];
        if (child) stack.emplace_back(child, transform * child->mTransformation);
      }
    }
  }

  if (scene.polygonCount() == 0)
    throw Error(file + (saw_points_or_lines ? ": no polygons (only points or lines)"
                                            : ": no polygons (the file holds no meshes)"));
  if (isGltf(path)) scene.cameras = gltfCameras(ai, scene);
  return scene;
}

// One line for a failed import, from assimp's error string or exception message (assimp
// catches std::bad_alloc itself and reports it as text).
Error assimpFailure(const std::string& file, std::string_view message,
                    const std::string& over_budget) {
  if (message.find("bad_alloc") != std::string_view::npos) return Error(over_budget);
  // assimp often repeats the full path; once at the front of the line is enough
  std::string line = detail::firstLine(message);
  const std::string name = fs::path(file).filename().string();
  for (std::size_t at = 0; !name.empty() && (at = line.find(file, at)) != std::string::npos;) {
    line.replace(at, file.size(), name);
    at += name.size();
  }
  return Error(file + ": assimp could not read it: " + line);
}

// Before any post-processing (which would spend minutes on a billion bogus vertices, and
// whose vertex joining would silently merge NaNs away): size limits, finite positions, and
// at least one polygon.
void preflight(const aiScene* ai, const std::string& file) {
  std::uint64_t vertices = 0, faces = 0;
  bool any_polygon = false, any_face = false;
  for (unsigned m = 0; m < ai->mNumMeshes && ai->mMeshes; ++m) {
    const aiMesh* mesh = ai->mMeshes[m];
    if (!mesh) continue;
    vertices += mesh->mNumVertices;
    faces += mesh->mNumFaces;
    checkSizeLimits(file, vertices, faces);
    if (mesh->mNumVertices > 0 && !mesh->mVertices)
      throw Error(file + ": mesh " + std::to_string(m) + " has no vertex positions");
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw Error(file + ": vertex " + std::to_string(v) + " of mesh " + std::to_string(m) +
                    " is not finite");
    }
    for (unsigned f = 0; f < mesh->mNumFaces && mesh->mFaces; ++f) {
      any_face = true;
      if (mesh->mFaces[f].mNumIndices >= 3 && mesh->mFaces[f].mIndices) {
        any_polygon = true;
        break;
      }
    }
  }
  if (!any_polygon)
    throw Error(file + (any_face ? ": no polygons (only points or lines)"
                                 : ": no polygons (the file holds no meshes)"));
}

// The importer proper (assimp), run inside the isolated child process. Every file it opens
// goes through a ConfinedIOSystem; on_open(bytes) hears of each one the model references.
Scene importWithAssimp(const fs::path& path, std::uintmax_t bytes, const std::string& over_budget,
                       bool allow_outside, std::function<void(std::uint64_t)> on_open,
                       std::unique_ptr<Assimp::Importer>* keep = nullptr) {
  const std::string file = path.string();
  try {
    // Header counts first: assimp allocates by them before reading any data
    const detail::HeaderFix fix = detail::checkHeaderAgainstSize(path, bytes);
    // No logger is attached: assimp stays quiet. With `keep`, the importer (and the scene it
    // holds: a million faces are a million allocations) outlives the call, for a child process
    // that answers and exits without freeing it
    auto owned = std::make_unique<Assimp::Importer>();
    Assimp::Importer& importer = *owned;
    if (keep) *keep = std::move(owned);
    auto* io = new detail::ConfinedIOSystem(path, allow_outside, std::move(on_open));
    importer.SetIOHandler(io);  // the importer owns it
    // A refused reference is the import's answer, whatever assimp made of the missing file
    const auto refused = [&] {
      if (!io->refusal().empty()) throw Error(io->refusal());
    };
    // A file with bones but no meshes must not grow a made-up skeleton mesh
    importer.SetPropertyBool(AI_CONFIG_IMPORT_NO_SKELETON_MESHES, true);
    // Read without post-processing, check, then post-process: no triangulation, so polygons
    // stay polygons and ids stay in file order
    if (fix.insert_cr_at > 0) {
      // The file as assimp must see it, "\r\n" ending the PLY header (HeaderFix)
      std::string data(static_cast<std::size_t>(bytes), '\0');
      std::FILE* f = std::fopen(file.c_str(), "rb");
      const bool read = f && std::fread(data.data(), 1, data.size(), f) == data.size();
      if (f) std::fclose(f);
      if (!read) throw Error(file + ": cannot read it");
      data.insert(static_cast<std::size_t>(fix.insert_cr_at), 1, '\r');
      const bool read_ok = importer.ReadFileFromMemory(data.data(), data.size(), 0, "ply");
      refused();
      if (!read_ok) throw assimpFailure(file, importer.GetErrorString(), over_budget);
    } else {
      const bool read_ok = importer.ReadFile(file, 0) != nullptr;
      refused();
      if (!read_ok) throw assimpFailure(file, importer.GetErrorString(), over_budget);
    }
    preflight(importer.GetScene(), file);
    // Identical vertices are joined by the conversion (PositionJoin), not by assimp
    const aiScene* ai = importer.ApplyPostProcessing(aiProcess_ValidateDataStructure);
    if (!ai) throw assimpFailure(file, importer.GetErrorString(), over_budget);
    return convertScene(ai, path);
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw Error(over_budget);
  } catch (const std::exception& e) {
    throw assimpFailure(file, e.what(), over_budget);
  } catch (...) {
    throw Error(file + ": assimp could not read it: unknown error");
  }
}

// The import runs in a child process (io/import_sandbox.hpp): a crash, a hang or runaway
// memory inside assimp becomes one clear hsr::Error here.
Scene importIsolated(const fs::path& path, std::uintmax_t bytes, const ImportLimits& limits) {
  const bool allow_outside = limits.allow_outside_references;
  return detail::importInSandbox(
      {.file = path.string(),
       .bytes = bytes,
       .limits = limits,
       .run = [&](const std::string& over_budget, std::function<void(std::uint64_t)> on_reference,
                  bool in_child) {
         if (!in_child) return importWithAssimp(path, bytes, over_budget, allow_outside, nullptr);
         // The importer (and the scene it holds: a million faces are a million allocations)
         // is left to the child's _exit, never freed
         std::unique_ptr<Assimp::Importer> importer;
         Scene scene = importWithAssimp(path, bytes, over_budget, allow_outside,
                                        std::move(on_reference), &importer);
         (void)importer.release();
         return scene;
       }});
}

}  // namespace

Scene loadMeshFile(const fs::path& path, const ImportLimits& limits) {
  const std::string file = path.string();
  // The file itself: exists, is a regular file (not a directory or a FIFO that would block),
  // not empty, not absurdly large
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)
    throw Error(file + ": " + ec.message());  // a loop of links, a folder it may not search
  if (ec || !fs::exists(status)) throw Error(file + ": no such file");
  if (fs::is_directory(status)) throw Error(file + ": is a directory, not a mesh file");
  if (!fs::is_regular_file(status)) throw Error(file + ": not a regular file");
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (ec) throw Error(file + ": cannot read its size: " + ec.message());
  if (bytes == 0) throw Error(file + ": file is empty");
  if (bytes > kMaxFileBytes) throw Error(file + ": too large (over 2 GiB)");

  return importIsolated(path, bytes, limits);
}

Scene loadScene(std::string_view spec, const ImportLimits& limits) {
  const std::string_view name = spec.substr(0, spec.find(':'));
  const auto builtin = [&] {
    for (const BuiltinScene& b : builtinScenes())
      if (!name.empty() && b.name.substr(0, b.name.find(':')) == name) return true;
    return false;
  };
  // An existing file wins over a built-in of the same name; a directory does not (a folder
  // named "demo" in the working directory is not a model: the built-in is meant)
  std::error_code dir_ec;
  if (!spec.empty() && !(builtin() && fs::is_directory(fs::path{std::string(spec)}, dir_ec))) {
    std::error_code ec;
    const fs::path path{std::string(spec)};
    const auto isWad = [](const fs::path& p) {
      std::string ext = p.extension().string();
      for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      return ext == ".wad";
    };
    if (fs::exists(path, ec))
      return isWad(path) ? doom::loadLevel(path) : loadMeshFile(path, limits);
    // FILE.wad:MAP01, a Doom map (hsr/doom.hpp)
    const std::size_t colon = spec.rfind(':');
    if (colon != std::string_view::npos) {
      const fs::path wad{std::string(spec.substr(0, colon))};
      if (isWad(wad) && fs::exists(wad, ec)) return doom::loadLevel(wad, spec.substr(colon + 1));
    }
    // A path that exists but cannot be reached (a loop of links, a folder it may not search)
    if (ec && ec != std::errc::no_such_file_or_directory && ec != std::errc::not_a_directory)
      throw Error(std::string(spec) + ": " + ec.message());
  }
  if (builtin()) return makeBuiltinScene(spec);
  throw Error("no such file or built-in scene: " + std::string(spec));
}

}  // namespace hsr

// Mesh files through assimp, and loadScene (a file, else a built-in scene).
// Guarantee: any input (missing, truncated, malformed, hostile) either loads into a Scene whose
// every position is finite and every index in range, or throws hsr::Error with one line that
// names the file. Polygons stay polygons (no triangulation); ids follow node order (root first,
// depth first, children in order), then each mesh's face order.

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <initializer_list>
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
#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "hsr/doom.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/scene.hpp"
#include "io/confined_io.hpp"
#include "io/import_preflight.hpp"

#include <poll.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#if defined(__SANITIZE_ADDRESS__)
#define HSR_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define HSR_ASAN 1
#endif
#endif
#ifndef HSR_ASAN
#define HSR_ASAN 0
#endif
#if HSR_ASAN
#include <sanitizer/common_interface_defs.h>
// From the sanitizer runtime's allocator interface (clang ships its header, GCC 12 does not)
extern "C" {
std::size_t __sanitizer_get_current_allocated_bytes();
int __sanitizer_install_malloc_and_free_hooks(void (*malloc_hook)(const volatile void*,
                                                                  std::size_t),
                                              void (*free_hook)(const volatile void*));
}
#endif
#ifndef HSR_FUZZING
#define HSR_FUZZING 0
#endif

namespace hsr {
namespace {

namespace fs = std::filesystem;

// Limits on untrusted input, checked before anything is allocated for it.
constexpr std::uintmax_t kMaxFileBytes = 2ull << 30;  // 2 GiB
constexpr std::uint64_t kMaxVertices = 50'000'000;
constexpr std::uint64_t kMaxPolygons = 50'000'000;
constexpr std::uint64_t kMaxNodes = 10'000'000;  // a node tree this big is an attack
constexpr std::uint32_t kMaxCameras = 4096;       // the file's cameras kept to choose from

// The import's size limits, checked in 64 bits before anything is allocated for the meshes.
void checkSizeLimits(const std::string& file, std::uint64_t vertices, std::uint64_t polygons) {
  if (vertices > kMaxVertices)
    throw Error(file + ": too large (over " + std::to_string(kMaxVertices / 1000000) +
                "M vertices)");
  if (polygons > kMaxPolygons)
    throw Error(file + ": too large (over " + std::to_string(kMaxPolygons / 1000000) +
                "M polygons)");
}

// The first line of an assimp message, trimmed (some span several lines).
std::string firstLine(std::string_view s) {
  s = s.substr(0, s.find_first_of("\r\n"));
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  return s.empty() ? std::string("unknown error") : std::string(s);
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
    std::uint64_t h = (std::uint64_t{k.x} << 32 | k.y) * 0x9E3779B97F4A7C15ull ^ k.z * 0xC2B2AE3D27D4EB4Full;
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
    if (const std::optional<SceneCamera> c = gltfCamera(ai, ai->mCameras[i], scene)) cameras.push_back(*c);
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
  std::string line = firstLine(message);
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

// ---- Isolation --------------------------------------------------------------------------
// assimp is third-party C++ that reads untrusted bytes, and some malformed files crash it
// (found by fuzzing: a binary PLY with a bodiless element segfaults inside its reader). So
// the import runs in a forked child process that sends the scene back through a pipe; a
// crash, a hang or runaway memory there becomes one clear hsr::Error here, never a crash.

void putU32(std::string& out, std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); }
void putF32(std::string& out, float v) { out.append(reinterpret_cast<const char*>(&v), 4); }
void putStr(std::string& out, const std::string& v) {
  putU32(out, static_cast<std::uint32_t>(v.size()));
  out += v;
}

static_assert(sizeof(glm::vec3) == 12, "positions are written as they lie in memory");

std::string serializeScene(const Scene& s) {
  std::string out;
  std::size_t corners = 0;
  for (PolygonId id = 0; id < s.polygonCount(); ++id) corners += s.polygon(id).size();
  // 12 bytes a vertex, 8 a polygon and 4 a corner, and the counts first (the reader reserves)
  out.reserve(64 + 12 * s.vertexCount() + 8 * s.polygonCount() + 4 * corners);
  putU32(out, static_cast<std::uint32_t>(s.vertexCount()));
  putU32(out, static_cast<std::uint32_t>(s.polygonCount()));
  putU32(out, static_cast<std::uint32_t>(corners));
  putStr(out, s.name);
  putU32(out, static_cast<std::uint32_t>(s.materials.size()));
  for (const Material& m : s.materials) {
    putF32(out, m.color.r);
    putF32(out, m.color.g);
    putF32(out, m.color.b);
    putF32(out, m.alpha);
    putStr(out, m.name);
  }
  putU32(out, static_cast<std::uint32_t>(s.cameras.size()));
  for (const SceneCamera& c : s.cameras) {
    for (const glm::vec3& v : {c.eye, c.target, c.up})
      for (int k = 0; k < 3; ++k) putF32(out, v[k]);
    putF32(out, c.fov_deg);
    putU32(out, c.ortho ? 1u : 0u);
    putF32(out, c.ortho_half_height);
    putF32(out, c.near);
    putF32(out, c.far);
  }
  putU32(out, static_cast<std::uint32_t>(s.objects.size()));
  for (const Object& o : s.objects) {
    putStr(out, o.name);
    putU32(out, o.vertex_count);
    // The positions as they lie in memory (three floats each), then each polygon as material,
    // count and local indices gathered into one piece: a million polygons, a million appends
    if (o.vertex_count > 0)
      out.append(reinterpret_cast<const char*>(&s.position(o.first_vertex)), 12 * std::size_t{o.vertex_count});
    putU32(out, o.polygon_count);
    std::vector<std::uint32_t> piece;
    for (PolygonId id = o.first_polygon; id < o.first_polygon + o.polygon_count; ++id) {
      const auto poly = s.polygon(id);
      piece.assign({s.material(id), static_cast<std::uint32_t>(poly.size())});
      for (std::uint32_t v : poly) piece.push_back(v - o.first_vertex);
      out.append(reinterpret_cast<const char*>(piece.data()), 4 * piece.size());
    }
  }
  return out;
}

class Reader {
 public:
  explicit Reader(std::string_view data) : data_(data) {}
  std::uint32_t u32() {
    std::uint32_t v;
    take(&v, 4);
    return v;
  }
  float f32() {
    float v;
    take(&v, 4);
    return v;
  }
  std::string str() {
    const std::uint32_t n = u32();
    if (n > data_.size() - pos_) throw Error("corrupt scene from the importer process");
    std::string v(data_.substr(pos_, n));
    pos_ += n;
    return v;
  }

 private:
  void take(void* dst, std::size_t n) {
    if (n > data_.size() - pos_) throw Error("corrupt scene from the importer process");
    std::memcpy(dst, data_.data() + pos_, n);
    pos_ += n;
  }
  std::string_view data_;
  std::size_t pos_ = 0;
};

Scene deserializeScene(std::string_view data) {
  Reader r(data);
  Scene s;
  const std::uint32_t vertices = r.u32(), polygons = r.u32(), corners = r.u32();
  if (12ull * vertices + 8ull * polygons + 4ull * corners > data.size())
    throw Error("corrupt scene from the importer process");
  s.reserve(vertices, polygons, corners);
  s.name = r.str();
  const std::uint32_t materials = r.u32();
  for (std::uint32_t i = 0; i < materials; ++i) {
    Material m;
    m.color.r = r.f32();
    m.color.g = r.f32();
    m.color.b = r.f32();
    m.alpha = r.f32();
    m.name = r.str();
    s.materials.push_back(m);
  }
  const std::uint32_t cameras = r.u32();
  if (cameras > kMaxCameras) throw Error("corrupt scene from the importer process");
  for (std::uint32_t i = 0; i < cameras; ++i) {
    SceneCamera c;
    for (glm::vec3* v : {&c.eye, &c.target, &c.up})
      for (int k = 0; k < 3; ++k) (*v)[k] = r.f32();
    c.fov_deg = r.f32();
    c.ortho = r.u32() != 0;
    c.ortho_half_height = r.f32();
    c.near = r.f32();
    c.far = r.f32();
    s.cameras.push_back(c);
  }
  const std::uint32_t objects = r.u32();
  std::vector<std::uint32_t> local;
  for (std::uint32_t o = 0; o < objects; ++o) {
    s.beginObject(r.str());
    const std::uint32_t verts = r.u32();
    for (std::uint32_t v = 0; v < verts; ++v) {
      glm::vec3 p;
      for (int k = 0; k < 3; ++k) p[k] = r.f32();
      s.addVertex(p);
    }
    const std::uint32_t polys = r.u32();
    for (std::uint32_t i = 0; i < polys; ++i) {
      const std::uint32_t material = r.u32();
      const std::uint32_t n = r.u32();
      local.clear();
      for (std::uint32_t k = 0; k < n; ++k) local.push_back(r.u32());
      s.addPolygon(local, material);
    }
  }
  return s;
}

bool writeAll(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

#if HSR_FUZZING
// Fuzzing: libFuzzer steers by the coverage counters of the process it runs in, and the
// import layer's own code (preflight, conversion) runs in the child. The child copies its
// counters (the linker's __sancov_cntrs section) into shared memory; the parent merges them.
extern "C" {
extern std::uint8_t __start___sancov_cntrs[] __attribute__((weak));
extern std::uint8_t __stop___sancov_cntrs[] __attribute__((weak));
}

class SharedCoverage {
 public:
  SharedCoverage() {
    if (__start___sancov_cntrs && +__stop___sancov_cntrs > +__start___sancov_cntrs)
      size_ = static_cast<std::size_t>(__stop___sancov_cntrs - __start___sancov_cntrs);
    if (size_ > 0) {
      void* p = ::mmap(nullptr, size_, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
      shared_ = p == MAP_FAILED ? nullptr : static_cast<std::uint8_t*>(p);
    }
  }
  ~SharedCoverage() {
    if (shared_) ::munmap(shared_, size_);
  }
  SharedCoverage(const SharedCoverage&) = delete;
  SharedCoverage& operator=(const SharedCoverage&) = delete;
  void publishFromChild() const {
    if (shared_) std::memcpy(shared_, __start___sancov_cntrs, size_);
  }
  void mergeIntoParent() const {
    if (!shared_) return;
    for (std::size_t i = 0; i < size_; ++i)
      __start___sancov_cntrs[i] = std::max(__start___sancov_cntrs[i], shared_[i]);
  }

 private:
  std::size_t size_ = 0;
  std::uint8_t* shared_ = nullptr;
};
#endif

// ---- Memory -------------------------------------------------------------------------------
// Some headers claim counts that assimp allocates before it reads any data (fuzzing found OFF
// and PLY files of a few hundred bytes that made it allocate 16 GB). checkHeaderAgainstSize
// refuses the ones we know; this limit bounds every other: what the import may allocate
// beyond what the process held when the child forked, sized by the file (ImportLimits).
// Measured (VmPeak growth): Debian's 579 assimp test models need at most 224 MB (a
// subdivided AC file of 2.8 KB, a Blender file of 86 KB); the densest OBJ (1M "f 1 2 3"
// lines, 8 MB) needs 140 bytes per byte, a binary STL 35, PLY and OFF 4 to 7.
constexpr std::uint64_t kBudgetPerFileByte = 256;
constexpr std::uint64_t kMinImportBudget = 1ull << 30;  // 1 GiB
constexpr std::uint64_t kMaxImportBudget = 16ull << 30;

std::uint64_t budgetFor(std::uint64_t bytes) {
  return std::clamp(
      bytes > kMaxImportBudget / kBudgetPerFileByte ? kMaxImportBudget : bytes * kBudgetPerFileByte,
      kMinImportBudget, kMaxImportBudget);
}

std::string overBudget(const std::string& file, std::uint64_t budget, std::uint64_t bytes,
                       bool with_references) {
  return fmt::format(
      "{}: importing it needs more than {} MiB, the limit for {} bytes of {}; "
      "refused (a corrupt count in the file?)",
      file, budget >> 20, bytes, with_references ? "the file and the files it references" : "file");
}

std::string overOuterLimit(const std::string& file, std::uint64_t limit, std::uint64_t budget) {
  return fmt::format(
      "{}: the import ran out of memory under this process's own address-space "
      "limit ({} MiB, set by ulimit -v or prlimit), below the {} MiB an import of "
      "this file may use; raise that limit",
      file, limit >> 20, budget >> 20);
}

// This process's address space in bytes (/proc/self/statm), 0 if unknown.
std::uint64_t addressSpaceBytes() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return 0;
  unsigned long long pages = 0;
  const bool read = std::fscanf(f, "%llu", &pages) == 1;
  std::fclose(f);
  const long page = ::sysconf(_SC_PAGESIZE);
  return read && page > 0 ? pages * static_cast<std::uint64_t>(page) : 0;
}

#if HSR_ASAN
// ASan's allocator reserves its whole heap up front, so small allocations never grow the
// address space: in the child, the live heap is watched too, after every allocation. Past the
// limit the child answers as it would on bad_alloc and leaves.
struct HeapWatch {
  std::uint64_t limit = 0;
  int fd = -1;
  const std::string* answer = nullptr;
  void (*before_exit)() = nullptr;
} g_heap_watch;

void heapWatchHook(const volatile void*, std::size_t) {
  if (__sanitizer_get_current_allocated_bytes() <= g_heap_watch.limit) return;
  if (g_heap_watch.before_exit) g_heap_watch.before_exit();
  writeAll(g_heap_watch.fd, g_heap_watch.answer->data(), g_heap_watch.answer->size());
  ::_exit(0);
}
void heapWatchFreeHook(const volatile void*) {}  // the runtime takes both hooks or neither

bool containsAny(std::string_view text, std::initializer_list<std::string_view> needles) {
  for (std::string_view s : needles)
    if (text.find(s) != std::string_view::npos) return true;
  return false;
}

// What the sanitizers print when an allocation fails (the child's address-space limit)...
bool isAllocationFailureReport(std::string_view report) {
  return containsAny(report, {"out of memory", "allocation-size-too-big",
                              "requested allocation size", "failed to allocate"});
}
// ...and when they find a bug (then the child exits, or aborts with abort_on_error=1).
bool isSanitizerReport(std::string_view report) {
  return containsAny(report,
                     {"ERROR: AddressSanitizer", "ERROR: LeakSanitizer",
                      "ERROR: UndefinedBehaviorSanitizer", "runtime error:", "ERROR: libFuzzer"});
}

// Whose bug a report is: assimp is not instrumented, but ASan's interceptors (memcpy,
// strlen...) catch some of its memory errors; the first stack frame in assimp or in our
// code (namespace hsr) decides. Those inside assimp are its bugs, contained in the child like
// its crashes (found by fuzz_gltf: a skin's inverse bind matrices copied 192 bytes past a
// 240-byte buffer). UBSan's reports (our code only) and any report without such a frame are
// ours.
bool isReportInsideAssimp(std::string_view report) {
  for (std::size_t at = report.find("\n    #"); at != std::string_view::npos;
       at = report.find("\n    #", at + 1)) {
    const std::string_view frame = report.substr(at + 1, report.find('\n', at + 1) - at - 1);
    if (frame.find("libassimp") != std::string_view::npos) return true;
    if (frame.find("hsr::") != std::string_view::npos) return false;
  }
  return false;
}

// The kind of a sanitizer report ("heap-buffer-overflow"), for the one-line refusal.
std::string reportKind(std::string_view report) {
  const std::size_t at = report.find("ERROR: AddressSanitizer: ");
  if (at == std::string_view::npos) return "a memory error";
  const std::string_view rest = report.substr(at + 25);
  return std::string(rest.substr(0, std::min(rest.find_first_of(" \n"), std::size_t{48})));
}
#endif

// The import's memory, in the child: at most `budget` more bytes of address space (and, under
// ASan, of live heap) than it held when it started. The budget starts from the model's size and
// grows with every file the model references; past it, the over-budget answer goes to the
// parent. Where this process's own hard limit (ulimit -v, prlimit) is lower, that limit binds,
// and the answer says so.
struct ChildMemory {
  std::string file;
  std::uint64_t base = 0;     // address space at the start, 0 if unknown
  std::uint64_t counted = 0;  // bytes of the model and its references
  std::uint64_t budget = 0;
  std::uint64_t model_bytes = 0;
  bool fixed = false;  // ImportLimits::memory_bytes was given
  rlim_t outer = RLIM_INFINITY;
  std::string line;    // the one line for running out...
  std::string answer;  // ...as the child's answer: 'E' + line
  void apply() {
    const bool outer_binds = base > 0 && outer != RLIM_INFINITY && base + budget > outer;
    line = outer_binds ? overOuterLimit(file, outer, budget)
                       : overBudget(file, budget, counted, counted != model_bytes);
    answer = "E" + line;
    if (base > 0) {
      const rlimit limit{outer_binds ? outer : base + budget, outer};
      ::setrlimit(RLIMIT_AS, &limit);
    }
  }
} g_child_memory;

#if HSR_ASAN
std::uint64_t g_heap_base = 0;
#endif

void limitChildMemory(const std::string& file, std::uint64_t model_bytes, std::uint64_t budget,
                      bool fixed, int answer_fd, void (*before_exit)()) {
  ChildMemory& m = g_child_memory;
  m.file = file;
  m.base = addressSpaceBytes();
  m.counted = m.model_bytes = model_bytes;
  m.budget = budget;
  m.fixed = fixed;
  rlimit outer{};
  if (::getrlimit(RLIMIT_AS, &outer) == 0) m.outer = outer.rlim_max;
  m.apply();
#if HSR_ASAN
  g_heap_base = __sanitizer_get_current_allocated_bytes();
  g_heap_watch = {g_heap_base + budget, answer_fd, &m.answer, before_exit};
  __sanitizer_install_malloc_and_free_hooks(heapWatchHook, heapWatchFreeHook);
#else
  (void)answer_fd;
  (void)before_exit;
#endif
}

// ConfinedIOSystem's report of a referenced file: the budget counts it (unless it was given).
void growChildMemory(std::uint64_t bytes) {
  ChildMemory& m = g_child_memory;
  m.counted += std::min<std::uint64_t>(bytes, kMaxFileBytes);
  if (m.fixed) return;
  m.budget = budgetFor(m.counted);
  m.apply();
#if HSR_ASAN
  g_heap_watch.limit = g_heap_base + m.budget;
#endif
}

// In the child: a crash inside assimp must end the child quietly by its signal (the parent
// reports it), not run the sanitizers' or libFuzzer's crash handlers as if the whole
// program had crashed.
void childCrashesBySignal() {
  for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(sig, SIG_DFL);
#if HSR_ASAN
  __sanitizer_set_death_callback(nullptr);
#endif
}

// What the child does before it leaves: under the fuzzer, hand its coverage to the parent.
#if HSR_FUZZING
const SharedCoverage* g_child_coverage = nullptr;
void publishChildCoverage() {
  if (g_child_coverage) g_child_coverage->publishFromChild();
}
constexpr void (*kBeforeChildExit)() = publishChildCoverage;
#else
constexpr void (*kBeforeChildExit)() = nullptr;
#endif

Scene importIsolated(const fs::path& path, std::uintmax_t bytes, const ImportLimits& limits) {
  const std::string file = path.string();
  const int timeout_seconds = std::max(limits.timeout_seconds, 1);
  const bool fixed = limits.memory_bytes > 0;
  const std::uint64_t budget = fixed ? limits.memory_bytes : budgetFor(bytes);
  const std::string over_budget = overBudget(file, budget, bytes, false);
  const bool allow_outside = limits.allow_outside_references;
#if HSR_FUZZING
  const SharedCoverage coverage;
  g_child_coverage = &coverage;
#endif
  // The answer comes through one pipe, the child's stderr through a second: what assimp or the
  // C++ runtime prints there ("terminate called after throwing...") is read, never shown raw,
  // and under the sanitizers it tells a failed allocation from a bug report.
  int fds[2], err_fds[2] = {-1, -1};
  const auto inProcess = [&] {
    return importWithAssimp(path, bytes, over_budget, allow_outside, nullptr);
  };
  if (::pipe(fds) != 0) return inProcess();  // no pipe: in process
  if (::pipe(err_fds) != 0) err_fds[0] = err_fds[1] = -1;
  const auto closeAll = [&] {
    for (int fd : {fds[0], fds[1], err_fds[0], err_fds[1]})
      if (fd >= 0) ::close(fd);
  };
  std::fflush(nullptr);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    closeAll();
    return inProcess();  // no fork: in process
  }
  if (pid == 0) {
    // Child: import, answer 'S' + scene or 'E' + message, and leave without running any
    // destructor or exit handler of the parent's state. It dies with the parent (a supervisor
    // that kills hsr must not leave an import running), also if the parent died before the
    // request took effect.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(1);
    for (const int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, SIG_DFL);
    ::close(fds[0]);
    if (err_fds[1] >= 0) {
      ::dup2(err_fds[1], STDERR_FILENO);
      ::close(err_fds[0]);
      ::close(err_fds[1]);
    }
    childCrashesBySignal();
    limitChildMemory(file, bytes, budget, fixed, fds[1], kBeforeChildExit);
    // The over-budget line changes as the references are counted: read where it is kept
    const std::string& over_answer = g_child_memory.answer;
    std::string answer;
    std::unique_ptr<Assimp::Importer> importer;  // left to _exit, never freed
    try {
      const Scene scene =
          importWithAssimp(path, bytes, g_child_memory.line, allow_outside, growChildMemory, &importer);
      answer.assign(1, 'S');
      answer += serializeScene(scene);
    } catch (const Error& e) {
      answer = std::string("E") + e.what();
    } catch (const std::bad_alloc&) {
      answer = over_answer;
    } catch (...) {
      answer = "E" + file + ": assimp could not read it: unknown error";
    }
    if (kBeforeChildExit) kBeforeChildExit();
    writeAll(fds[1], answer.data(), answer.size());
    ::_exit(0);
  }
  // Parent: read the whole answer (and the child's stderr) with a deadline, then reap the
  // child.
  ::close(fds[1]);
  if (err_fds[1] >= 0) ::close(err_fds[1]);
  std::string answer, child_stderr;
  char buf[1 << 16];
  // Reads what is waiting on fd into `to`; false at EOF. A runaway stream of diagnostics is
  // cut, not stored.
  const auto drain = [&](int fd, std::string& to) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0) return errno == EINTR;
    if (n > 0 && (&to == &answer || to.size() < (1u << 20)))
      to.append(buf, static_cast<std::size_t>(n));
    return n > 0;
  };
  bool timed_out = false;
  const auto started = std::chrono::steady_clock::now();
  auto next_progress = started + std::chrono::milliseconds(250);
  const auto deadline = started + std::chrono::seconds(timeout_seconds);
  pollfd p[2] = {{fds[0], POLLIN, 0}, {err_fds[0], POLLIN, 0}};
  const nfds_t watched = err_fds[0] >= 0 ? 2 : 1;
  // Until the answer's EOF: the child closed its end (answered, or died)
  while (p[0].fd >= 0) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                          deadline - std::chrono::steady_clock::now())
                          .count();
    if (left <= 0) {
      timed_out = true;
      break;
    }
    if (limits.progress) {
      const auto now = std::chrono::steady_clock::now();
      if (now >= next_progress) {
        limits.progress(std::chrono::duration<double>(now - started).count(), answer.size(), false);
        next_progress = now + std::chrono::milliseconds(250);
      }
    }
    if (::poll(p, watched, static_cast<int>(std::min<long long>(left, limits.progress ? 250 : 1000))) <= 0) continue;
    for (nfds_t k = 0; k < watched; ++k)
      if (p[k].fd >= 0 && (p[k].revents & (POLLIN | POLLHUP | POLLERR)) &&
          !drain(p[k].fd, k == 0 ? answer : child_stderr))
        p[k].fd = -1;
  }
  if (limits.progress)
    limits.progress(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(),
                    answer.size(), true);
  if (timed_out) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  // The child has ended: what it still wrote to stderr is waiting in the pipe
  if (p[1].fd >= 0)
    while (drain(p[1].fd, child_stderr)) {
    }
  ::close(fds[0]);
  if (err_fds[0] >= 0) ::close(err_fds[0]);
#if HSR_FUZZING
  g_child_coverage = nullptr;
  if (WIFEXITED(status)) coverage.mergeIntoParent();
#endif
  if (timed_out)
    throw Error(file + ": the importer did not finish within " + std::to_string(timeout_seconds) +
                " s; refused");
#if HSR_ASAN
  if (answer.empty() && (WIFSIGNALED(status) || WEXITSTATUS(status) != 0)) {
    if (isAllocationFailureReport(child_stderr)) throw Error(over_budget);
    if (isSanitizerReport(child_stderr) && isReportInsideAssimp(child_stderr))
      throw Error(file + ": the importer (assimp) failed on this file (" +
                  reportKind(child_stderr) + " inside assimp); refused as malformed");
    if (isSanitizerReport(child_stderr)) {
      // A sanitizer's report from the import child: a bug, never a refusal. Show it and
      // stop, as the sanitizer would have stopped the program had the import run in process.
      std::fprintf(stderr, "hsr: the import child for %s failed; its report:\n%s\n", file.c_str(),
                   child_stderr.c_str());
      std::abort();
    }
  }
#endif
  if (WIFSIGNALED(status)) {
    if (const std::string what = detail::uncaughtException(child_stderr); !what.empty())
      throw Error(file + ": the importer (assimp) failed on this file (" + what +
                  "); refused as malformed");
    throw Error(file + ": the importer (assimp) crashed on this file (signal " +
                std::to_string(WTERMSIG(status)) + "); refused as malformed");
  }
  // Whatever else the child printed is not shown: the answer is the one line
  if (answer.empty()) throw Error(file + ": the importer (assimp) ended without an answer");
  if (answer[0] == 'E') throw Error(answer.substr(1));
  return deserializeScene(std::string_view(answer).substr(1));
}

}  // namespace

namespace detail {

// What the C++ runtime printed when an exception escaped inside the importer ("terminate
// called after throwing an instance of 'T'\n  what():  message"), as "an exception it did not
// catch: T: message"; empty if it printed nothing of the kind.
std::string uncaughtException(std::string_view text) {
  constexpr std::string_view kThrown = "terminate called after throwing an instance of '";
  const std::size_t at = text.find(kThrown);
  if (at == std::string_view::npos)
    return text.find("terminate called") != std::string_view::npos ? "the C++ runtime terminated it"
                                                                   : "";
  std::string_view rest = text.substr(at + kThrown.size());
  std::string what(rest.substr(0, std::min<std::size_t>(rest.find('\''), 120)));
  if (const std::size_t w = rest.find("what():"); w != std::string_view::npos) {
    std::string_view message = rest.substr(w + 7);
    message.remove_prefix(std::min(message.find_first_not_of(' '), message.size()));
    what += ": " + firstLine(message.substr(0, std::min<std::size_t>(message.size(), 200)));
  }
  return "an exception it did not catch: " + what;
}

}  // namespace detail

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
    if (fs::exists(path, ec)) return isWad(path) ? doom::loadLevel(path) : loadMeshFile(path, limits);
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

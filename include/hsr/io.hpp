#pragma once
// Scene sources (mesh files through assimp, built-in scenes) and writers (PNG, NPY, JSON).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/mat4x4.hpp>

#include "hsr/camera.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"

namespace hsr {

// What a mesh import may spend and read. assimp runs in a child process that is killed after
// timeout_seconds (and with this process), and may use memory_bytes beyond what this process
// holds when it starts; past either limit the file is refused with one line. memory_bytes = 0
// sizes it by the input: 256 bytes per byte of the file and of every file it references (a
// dense OFF or OBJ needs up to 140), at least 1 GiB, at most 16 GiB. The files a model
// references (an OBJ's mtllib, a glTF's buffers) must be regular files inside the model's own
// folder tree, symbolic links resolved, unless allow_outside_references.
struct ImportLimits {
  int timeout_seconds = 120;
  std::uint64_t memory_bytes = 0;
  bool allow_outside_references = false;
  // Called about four times a second while an import runs (never for a built-in scene), with
  // the seconds spent and the bytes of the answer received so far, and once more with done
  // when it has ended (answered, refused or timed out): for showing progress.
  std::function<void(double seconds, std::uint64_t bytes_received, bool done)> progress;
};
// Loads SCENE: an existing file wins (a Doom WAD's first map as a level, hsr/doom.hpp:
// loadLevel; FILE.wad:MAP01 names another); otherwise a built-in name. Throws hsr::Error with a
// one-line reason (missing file, unreadable format, empty scene, non-finite coordinates...).
Scene loadScene(std::string_view spec, const ImportLimits& limits = {});
// Mesh files: anything assimp reads. Polygons stay polygons (no triangulation), node
// transforms are applied, ids follow node order then face order. Safe on untrusted input.
Scene loadMeshFile(const std::filesystem::path& path, const ImportLimits& limits = {});

// Wavefront OBJ text read without assimp, for the web page (which has no assimp): "v"
// vertices, "f" faces (v, v/vt, v//vn, v/vt/vn; negative indices count back), "o"/"g" begin an
// object, "usemtl" picks a material (coloured from a palette: no .mtl is read); the rest is
// left aside. Polygons stay polygons, ids in file order. Throws hsr::Error naming `name` and the
// line. Memory: a few times the text's size, whatever the text.
Scene parseObjText(std::string_view text, std::string name);

struct BuiltinScene {
  std::string_view name;  // e.g. "spheres:N"
  std::string_view summary;
};
const std::vector<BuiltinScene>& builtinScenes();
// Built-ins: demo, cyclic, penetrating, spheres:N, soup:N:SEED (N: digits with an optional
// k or M suffix). Deterministic. An N above max_triangles is refused (hsr::Error), before
// anything is built.
inline constexpr std::uint64_t kMaxBuiltinTriangles = 20'000'000;
Scene makeBuiltinScene(std::string_view spec, std::uint64_t max_triangles = kMaxBuiltinTriangles);

// Writers. Images are written top row first. Every file appears whole or not at all
// (hsr/output.hpp); on failure hsr::Error names the file and the reason, and an earlier file
// of the same name is left as it was.
void writePng(const std::filesystem::path& path, int width, int height, int channels,
              const std::uint8_t* pixels);
// The frame's pictures (kinds as picture() names them) each to its path, encoded in parallel;
// `decorate(kind, rgb)`, when given, draws on each before it is encoded (a legend).
void writePictures(
    const Frame& frame, const std::vector<std::pair<std::string, std::filesystem::path>>& pictures,
    const std::function<void(std::string_view, std::vector<std::uint8_t>&)>& decorate = {});
void writeNpy(const std::filesystem::path& path, int width, int height, const float* data);
void writeNpy(const std::filesystem::path& path, int width, int height, const std::uint32_t* data);
// A PNG in memory; checkPngSize refuses (hsr::Error naming `path`) a size it cannot encode,
// before anything is computed: at most 16384x16384 RGB.
std::string encodePng(int width, int height, int channels, const std::uint8_t* pixels);
void checkPngSize(const std::filesystem::path& path, long long width, long long height,
                  int channels);
// A frame's raw buffers as one set: DIR/depth.npy, ids.npy, overdraw.npy (coverage.npy too when
// the frame has a coverage buffer) and manifest.json,
// put in place together (a reader never sees the buffers of two frames mixed).
void writeRawFrame(const std::filesystem::path& dir, const Frame& frame, const std::string& scene,
                   const std::string& algorithm);

// What depth.npy holds:
//   kWindow: window z in [0, 1] as the depth test compares it, 1.0 where nothing was drawn;
//   kLinear: depth along the view axis in scene units, from the eye (orthographic: from the
//     eye's plane), +inf where nothing was drawn;
//   kDistance: distance from the eye along the ray through the pixel centre, in scene units
//     (orthographic: as kLinear, the rays being parallel), +inf where nothing was drawn.
// Scene units come from window z through the camera's projection, in double: the float window
// z bounds the precision (relative error about 2^-24 times far / near at the far plane).
enum class DepthKind { kWindow, kLinear, kDistance };
DepthKind depthKindNamed(std::string_view name);  // "window", "linear", "distance"; else Error
FrameBuffer<float> depthAs(const Frame& frame, const Camera& camera, DepthKind kind);

// Per pixel, the object (index into scene.objects) and the material (index into
// scene.materials) of the polygon shown; 4294967295 where nothing was drawn.
std::vector<std::uint32_t> objectsAt(const Frame& frame, const Scene& scene);
std::vector<std::uint32_t> materialsAt(const Frame& frame, const Scene& scene);
// Per pixel, 3 floats: the unit normal of the polygon shown (Newell's, from its vertices),
// turned to face the eye, in world or eye space (OpenGL's: x right, y up, looking down -z);
// NaN where nothing was drawn.
enum class NormalSpace { kNone, kWorld, kEye };
NormalSpace normalSpaceNamed(std::string_view name);  // "world", "eye"; else Error
std::vector<float> normalsAt(const Frame& frame, const Scene& scene, const Camera& camera,
                             NormalSpace space);

// As above, for data users: depth.npy as `depth` says; objects.npy and materials.npy (as
// objectsAt, materialsAt), so one object's mask is `objects == k`; normals.npy (height x width
// x 3) unless `normals` is kNone; and manifest.json also holding the camera (as cameraJson),
// what each file holds and the objects' and materials' tables.
inline const std::vector<std::string> kRawFiles = {"depth.npy",     "ids.npy",     "objects.npy",
                                                   "materials.npy", "normals.npy", "overdraw.npy",
                                                   "coverage.npy"};
void writeRawFrame(const std::filesystem::path& dir, const Frame& frame, const std::string& scene,
                   const std::string& algorithm, const Scene& scene_data, const Camera& camera,
                   DepthKind depth, NormalSpace normals = NormalSpace::kNone);

// The scene's objects as a JSON array, in index order: name, first_polygon and polygons (the
// object's polygon ids are first_polygon .. first_polygon + polygons - 1, as ids.npy holds).
std::string objectsJson(const Scene& scene);

// The camera as JSON: eye, target, up, fov_deg (or ortho_half_height), near, far, width,
// height, the 4x4 view and projection matrices and the camera's pose (camera to world) in
// OpenCV's and OpenGL's conventions (row-major: rows of the matrix as written on paper, acting
// on column vectors), and the pinhole intrinsics (Intrinsics, OpenCV's convention; null for
// an orthographic camera). "projection_from" says which of fov_deg, intrinsics and
// ortho_half_height the projection is made from.
std::string cameraJson(const Camera& camera);
// A camera read back from that JSON (or from a manifest.json or --stats file, whose "camera"
// it is): eye, target and up (or a pose_opencv / pose_opengl matrix), projection_kind,
// fov_deg, intrinsics or ortho_half_height, near, far, width, height. The same pixels as the
// run that wrote it. Throws hsr::Error naming the missing or malformed field.
Camera cameraFromJson(std::string_view text);
// Many views: a JSON array of cameras (or {"views": [...]}); a single camera is one view.
// Every field is needed, as for cameraFromJson.
inline constexpr std::size_t kMaxViews = 100000;
std::vector<Camera> camerasFromJson(std::string_view text);
// A list of views written by hand (--views): each needs only "eye" and "target" (or a pose).
// Left out: the size is the defaults' (--size), "up" is +y, the projection perspective with
// fov_deg 45, and near and far are fitted around the scene (fitDepth, once it is read) as
// auto-framing fits them. Fields given are read as cameraFromJson reads them; one message
// names every field of a view that is wrong, and the view.
struct ViewDefaults {
  int width = 800, height = 600;
};
struct ViewList {
  std::vector<Camera> cameras;
  std::vector<std::uint8_t> fit_near, fit_far;  // per view: left out, still to be fitted
  // Fits what was left out around `bounds`; throws naming the view where no pair results
  void fitDepth(const Bounds& bounds);
};
ViewList viewsFromJson(std::string_view text, const ViewDefaults& defaults);
// A camera's pose read from text: a 4x4 (or 3x4, the last row then 0 0 0 1) matrix, row by row,
// numbers separated by spaces, commas or brackets (a JSON array of rows, NumPy's savetxt).
glm::dmat4 poseFromText(std::string_view text);

// Pictures of a frame's buffers, RGB8 top row first.
std::vector<std::uint8_t> depthPicture(const Frame& frame);  // normalised grey, near = light
// The depth range of the drawn pixels, and a depth picture normalised over a given range
// (so that the pictures of a sequence share one scale).
struct DepthRange {
  float lo, hi;
};
DepthRange drawnDepthRange(const Frame& frame);
std::vector<std::uint8_t> depthPicture(const Frame& frame, DepthRange range);
std::vector<std::uint8_t> idPicture(const Frame& frame);        // golden-angle hues, bg black
std::vector<std::uint8_t> overdrawPicture(const Frame& frame);  // heatmap
// The same on a given scale (1 .. most fragments), so that pictures side by side share it
std::vector<std::uint8_t> overdrawPicture(const Frame& frame, std::uint32_t most);
// The two pictures' ramps at t in [0, 1], for legends: depth from the nearest drawn depth
// (light) to the farthest (dark grey); overdraw from 1 fragment to the most, on a log scale.
void depthRampColor(float t, std::uint8_t* rgb);
void overdrawRampColor(float t, std::uint8_t* rgb);
std::vector<std::uint8_t> picture(const Frame& frame, std::string_view kind);  // by name

std::string statsJson(const Frame& frame, const std::string& scene, const std::string& algorithm);
// The same with the camera used (as cameraJson) under "camera", the objects' table
// (objectsJson) under "objects" and the materials' (name, color, alpha, polygons) under
// "materials".
std::string statsJson(const Frame& frame, const std::string& scene, const std::string& algorithm,
                      const Scene& scene_data, const Camera& camera);

}  // namespace hsr

// Writers: PNG (libspng), NumPy .npy (format version 1.0) and stats JSON. The pictures of a
// frame's buffers are made in pictures.cpp. Buffers arrive top row first, as the files store
// them; nothing here flips rows.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <utility>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>
#include <spng.h>

#include "core/parallel.hpp"
#include "hsr/error.hpp"
#include "hsr/io.hpp"
#include "hsr/output.hpp"

#include "io/camera_json.hpp"
#include "io/pictures.hpp"

namespace hsr {
namespace {

using detail::framePixels;

std::size_t pixelCount(int width, int height, const std::filesystem::path& path) {
  if (width <= 0 || height <= 0)
    throw Error(path.string() + ": cannot write an image of size " + std::to_string(width) + "x" +
                std::to_string(height));
  return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
}

// NumPy .npy version 1.0: magic, version, little-endian u16 header length, a Python dict
// literal padded with spaces to a multiple of 64 bytes (as numpy writes it) ending in '\n',
// then the raw little-endian data in C order.
std::string npyHeader(int width, int height, const char* descr, int channels = 1) {
  std::string header = std::string("{'descr': '") + descr +
                       "', 'fortran_order': False, 'shape': (" + std::to_string(height) + ", " +
                       std::to_string(width) +
                       (channels > 1 ? ", " + std::to_string(channels) : "") + "), }";
  constexpr std::size_t kPrefix = 10;  // magic (6) + version (2) + header length (2)
  constexpr std::size_t kAlign = 64;
  const std::size_t total = (kPrefix + header.size() + 1 + kAlign - 1) / kAlign * kAlign;
  header.append(total - kPrefix - header.size() - 1, ' ');
  header.push_back('\n');
  const auto header_len = static_cast<std::uint16_t>(header.size());
  const char prefix[kPrefix] = {'\x93',
                                'N',
                                'U',
                                'M',
                                'P',
                                'Y',
                                1,
                                0,
                                static_cast<char>(header_len & 0xFF),
                                static_cast<char>(header_len >> 8)};
  return std::string(prefix, kPrefix) + header;
}

static_assert(std::endian::native == std::endian::little,
              ".npy data is written as the host holds it: little-endian hosts only");

template <typename T>
std::string_view npyData(int width, int height, const T* data, const std::filesystem::path& path,
                         int channels = 1) {
  static_assert(sizeof(T) == 4);
  return {reinterpret_cast<const char*>(data),
          pixelCount(width, height, path) * channels * sizeof(T)};
}

// The largest PNG hsr writes is the largest render (kMaxDimension squared, RGB): its filtered
// image, (width * channels + 1) * height bytes, stays below 2^31, which decoders that count
// in int (stb_image, and the encoder hsr used before) need. It was encoded and decoded in a
// test of this limit.
constexpr long long kMaxPngFilteredBytes = (16384LL * 3 + 1) * 16384LL;

}  // namespace

void checkPngSize(const std::filesystem::path& path, long long width, long long height,
                  int channels) {
  if (width <= 0 || height <= 0)
    throw Error(
        fmt::format("{}: cannot write an image of size {}x{}", path.string(), width, height));
  if (channels < 1 || channels > 4)
    throw Error(fmt::format("{}: a PNG has 1 to 4 channels, not {}", path.string(), channels));
  if (width > kMaxPngFilteredBytes || height > kMaxPngFilteredBytes ||
      (width * channels + 1) * height > kMaxPngFilteredBytes)
    throw Error(fmt::format(
        "{}: a {}x{} picture is larger than the PNG writer can encode (16384x16384 RGB at most)",
        path.string(), width, height));
}

// libspng over zlib at its fastest level (1), rows unfiltered: rendered pictures are flat
// regions, which deflate's matches take whole. Measured on spheres:100000 at 1920x1080: 9 to
// 15 ms a picture, smaller than Sub, Up or both tried per row (18 to 38 ms) and than
// stb_image_write's (zlib's default level, all five filters tried: 0.45 s for the four).
std::string encodePng(int width, int height, int channels, const std::uint8_t* pixels) {
  checkPngSize("PNG", width, height, channels);
  static constexpr std::uint8_t kColorType[5] = {
      0, SPNG_COLOR_TYPE_GRAYSCALE, SPNG_COLOR_TYPE_GRAYSCALE_ALPHA, SPNG_COLOR_TYPE_TRUECOLOR,
      SPNG_COLOR_TYPE_TRUECOLOR_ALPHA};
  const std::unique_ptr<spng_ctx, void (*)(spng_ctx*)> ctx(spng_ctx_new(SPNG_CTX_ENCODER),
                                                           spng_ctx_free);
  if (!ctx) throw std::bad_alloc();
  spng_ihdr ihdr{};
  ihdr.width = static_cast<std::uint32_t>(width);
  ihdr.height = static_cast<std::uint32_t>(height);
  ihdr.bit_depth = 8;
  ihdr.color_type = kColorType[channels];
  int err = spng_set_option(ctx.get(), SPNG_ENCODE_TO_BUFFER, 1);
  if (!err) err = spng_set_option(ctx.get(), SPNG_IMG_COMPRESSION_LEVEL, 1);
  if (!err) err = spng_set_option(ctx.get(), SPNG_FILTER_CHOICE, SPNG_DISABLE_FILTERING);
  if (!err) err = spng_set_ihdr(ctx.get(), &ihdr);
  if (!err)
    err = spng_encode_image(ctx.get(), pixels, static_cast<std::size_t>(width) * height * channels,
                            SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE);
  std::size_t size = 0;
  void* png = err ? nullptr : spng_get_png_buffer(ctx.get(), &size, &err);
  if (!png) {
    if (err == SPNG_EMEM || err == 0) throw std::bad_alloc();
    throw Error(std::string("PNG encoding failed: ") + spng_strerror(err));
  }
  std::string out(static_cast<const char*>(png), size);
  std::free(png);
  return out;
}

void writePng(const std::filesystem::path& path, int width, int height, int channels,
              const std::uint8_t* pixels) {
  checkPngSize(path, width, height, channels);
  writeFileAtomically(path, {encodePng(width, height, channels, pixels)});
}

void writePictures(
    const Frame& frame, const std::vector<std::pair<std::string, std::filesystem::path>>& pictures,
    const std::function<void(std::string_view, std::vector<std::uint8_t>&)>& decorate) {
  for (const auto& [kind, path] : pictures) checkPngSize(path, frame.width, frame.height, 3);
  // Drawn and encoded side by side (each picture is one thread's work), written in order
  std::vector<std::string> png(pictures.size());
  tbb::parallel_for(std::size_t{0}, pictures.size(), [&](std::size_t k) {
    std::vector<std::uint8_t> rgb = picture(frame, pictures[k].first);
    if (decorate) decorate(pictures[k].first, rgb);
    png[k] = encodePng(frame.width, frame.height, 3, rgb.data());
  });
  for (std::size_t k = 0; k < pictures.size(); ++k)
    writeFileAtomically(pictures[k].second, {png[k]});
}

void writeNpy(const std::filesystem::path& path, int width, int height, const float* data) {
  writeFileAtomically(path, {npyHeader(width, height, "<f4"), npyData(width, height, data, path)});
}

void writeNpy(const std::filesystem::path& path, int width, int height, const std::uint32_t* data) {
  writeFileAtomically(path, {npyHeader(width, height, "<u4"), npyData(width, height, data, path)});
}

namespace {

nlohmann::ordered_json objectsArray(const Scene& scene) {
  nlohmann::ordered_json a = nlohmann::ordered_json::array();
  for (const Object& o : scene.objects)
    a.push_back(
        {{"name", o.name}, {"first_polygon", o.first_polygon}, {"polygons", o.polygon_count}});
  return a;
}

nlohmann::ordered_json materialsArray(const Scene& scene) {
  std::vector<std::uint64_t> count(scene.materials.size(), 0);
  for (PolygonId id = 0; id < scene.polygonCount(); ++id)
    if (scene.material(id) < count.size()) ++count[scene.material(id)];
  nlohmann::ordered_json a = nlohmann::ordered_json::array();
  for (std::size_t m = 0; m < scene.materials.size(); ++m) {
    const Material& mat = scene.materials[m];
    a.push_back({{"name", mat.name},
                 {"color", {mat.color.r, mat.color.g, mat.color.b}},
                 {"alpha", mat.alpha},
                 {"polygons", count[m]}});
  }
  return a;
}

const char* normalsMeaning(NormalSpace space) {
  return space == NormalSpace::kEye
             ? "float32 x3 unit normal of the polygon shown, eye space (OpenGL: x right, y up, "
               "the eye looking down -z), turned to face the eye; nan where nothing was drawn"
             : "float32 x3 unit normal of the polygon shown, world space, turned to face the "
               "eye; nan where nothing was drawn";
}

const char* depthMeaning(DepthKind kind) {
  switch (kind) {
    case DepthKind::kWindow:
      return "float32 window z in [0, 1], 1.0 where nothing was drawn";
    case DepthKind::kLinear:
      return "float32 depth along the view axis from the eye (orthographic: from its plane), "
             "scene units, inf where nothing was drawn";
    case DepthKind::kDistance:
      return "float32 distance from the eye along the ray through the pixel centre, scene "
             "units, inf where nothing was drawn";
  }
  return "?";
}

void writeRaw(const std::filesystem::path& dir, const Frame& frame, const std::string& scene,
              const std::string& algorithm, const Scene* scene_data, const Camera* camera,
              DepthKind kind, NormalSpace normal_space) {
  const int w = frame.width, h = frame.height;
  const std::size_t n = pixelCount(w, h, dir);
  if (frame.depth.size() != n || frame.ids.size() != n || frame.overdraw.size() != n)
    throw Error(dir.string() + ": the frame has no depth, id or overdraw buffer to write");
  FrameBuffer<float> converted;
  if (camera && kind != DepthKind::kWindow) converted = depthAs(frame, *camera, kind);
  const float* depth = converted.empty() ? frame.depth.data() : converted.data();
  std::vector<std::uint32_t> objects, materials;
  std::vector<float> normals;
  if (scene_data) {
    objects = objectsAt(frame, *scene_data);
    materials = materialsAt(frame, *scene_data);
    if (camera && normal_space != NormalSpace::kNone)
      normals = normalsAt(frame, *scene_data, *camera, normal_space);
  }
  OutputDirectory out(dir, kRawFiles);
  out.write("depth.npy", {npyHeader(w, h, "<f4"), npyData(w, h, depth, dir)});
  if (scene_data) {
    out.write("objects.npy", {npyHeader(w, h, "<u4"), npyData(w, h, objects.data(), dir)});
    out.write("materials.npy", {npyHeader(w, h, "<u4"), npyData(w, h, materials.data(), dir)});
  }
  if (!normals.empty())
    out.write("normals.npy", {npyHeader(w, h, "<f4", 3), npyData(w, h, normals.data(), dir, 3)});
  out.write("ids.npy", {npyHeader(w, h, "<u4"), npyData(w, h, frame.ids.data(), dir)});
  out.write("overdraw.npy", {npyHeader(w, h, "<u4"), npyData(w, h, frame.overdraw.data(), dir)});
  const bool coverage = frame.coverage.size() == n;
  if (coverage)
    out.write("coverage.npy", {npyHeader(w, h, "<f4"), npyData(w, h, frame.coverage.data(), dir)});
  nlohmann::ordered_json about;
  about["scene"] = scene;
  about["algorithm"] = algorithm;
  about["width"] = w;
  about["height"] = h;
  about["rows"] = "top row first";
  about["depth.npy"] = depthMeaning(camera ? kind : DepthKind::kWindow);
  about["ids.npy"] = "uint32 polygon id, 4294967295 where nothing was drawn";
  about["overdraw.npy"] =
      coverage ? "uint32 fragments in the pixel's list (polygons reaching its samples)"
               : "uint32 fragments written at the pixel (passed the depth test)";
  if (coverage)
    about["coverage.npy"] = "float32 fraction of the pixel's samples covered by opaque polygons";
  if (scene_data) {
    about["objects.npy"] =
        "uint32 object index (the table below), 4294967295 where nothing was drawn";
    about["materials.npy"] =
        "uint32 material index (the table below), 4294967295 where nothing was drawn";
    if (!normals.empty()) about["normals.npy"] = normalsMeaning(normal_space);
    about["objects"] = objectsArray(*scene_data);
    about["materials"] = materialsArray(*scene_data);
  }
  if (camera) about["camera"] = detail::cameraObject(*camera);
  out.commit(about.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace));
}

}  // namespace

DepthKind depthKindNamed(std::string_view name) {
  if (name == "window") return DepthKind::kWindow;
  if (name == "linear") return DepthKind::kLinear;
  if (name == "distance") return DepthKind::kDistance;
  throw Error("depth '" + std::string(name) + "': window, linear or distance");
}

FrameBuffer<float> depthAs(const Frame& frame, const Camera& camera, DepthKind kind) {
  const std::size_t n = framePixels(frame);
  if (frame.depth.size() != n || frame.ids.size() != n)
    throw Error("the frame has no depth or id buffer to convert");
  if (frame.width != camera.width || frame.height != camera.height)
    throw Error("the frame's size differs from the camera's");
  FrameBuffer<float> out(frame.depth);
  if (kind == DepthKind::kWindow) return out;
  const glm::dmat4 p(camera.projection());
  const double w = frame.width, h = frame.height;
  for (int y = 0; y < frame.height; ++y)
    for (int x = 0; x < frame.width; ++x) {
      const std::size_t k = static_cast<std::size_t>(y) * frame.width + x;
      if (frame.ids[k] == kNoPolygon) {
        out[k] = std::numeric_limits<float>::infinity();
        continue;
      }
      // Window z to normalised device z, then back through the projection (OpenGL's: clip
      // z = p22 z_eye + p32, clip w = -z_eye in perspective, 1 in parallel)
      const double z_ndc = 2.0 * frame.depth[k] - 1.0;
      const double linear =
          camera.ortho ? -(z_ndc - p[3][2]) / p[2][2] : p[3][2] / (z_ndc + p[2][2]);
      double d = linear;
      if (kind == DepthKind::kDistance && !camera.ortho) {
        // The ray through the pixel centre, per unit of depth along the view axis
        const double x_ndc = 2.0 * (x + 0.5) / w - 1.0, y_ndc = 1.0 - 2.0 * (y + 0.5) / h;
        // (x_ndc = p00 X / -z - p20 for glFrustum's off-centre frustum; p20 = 0 when centred)
        const double u = (x_ndc + p[2][0]) / p[0][0], v = (y_ndc + p[2][1]) / p[1][1];
        d = linear * std::sqrt(1.0 + u * u + v * v);
      }
      out[k] = static_cast<float>(d);
    }
  return out;
}

void writeRawFrame(const std::filesystem::path& dir, const Frame& frame, const std::string& scene,
                   const std::string& algorithm) {
  writeRaw(dir, frame, scene, algorithm, nullptr, nullptr, DepthKind::kWindow, NormalSpace::kNone);
}

void writeRawFrame(const std::filesystem::path& dir, const Frame& frame, const std::string& scene,
                   const std::string& algorithm, const Scene& scene_data, const Camera& camera,
                   DepthKind depth, NormalSpace normals) {
  writeRaw(dir, frame, scene, algorithm, &scene_data, &camera, depth, normals);
}

namespace {
// Per pixel, what `of` says of the polygon shown (kNoPolygon where none is)
std::vector<std::uint32_t> perPixel(const Frame& frame, const Scene& scene,
                                    std::uint32_t (Scene::*of)(PolygonId) const) {
  std::vector<std::uint32_t> out(frame.ids.size(), kNoPolygon);
  for (std::size_t k = 0; k < out.size(); ++k)
    if (frame.ids[k] != kNoPolygon && frame.ids[k] < scene.polygonCount())
      out[k] = (scene.*of)(frame.ids[k]);
  return out;
}
}  // namespace

std::vector<std::uint32_t> objectsAt(const Frame& frame, const Scene& scene) {
  return perPixel(frame, scene, &Scene::object);
}

std::vector<std::uint32_t> materialsAt(const Frame& frame, const Scene& scene) {
  return perPixel(frame, scene, &Scene::material);
}

NormalSpace normalSpaceNamed(std::string_view name) {
  if (name == "world") return NormalSpace::kWorld;
  if (name == "eye") return NormalSpace::kEye;
  throw Error("normals '" + std::string(name) + "': world or eye");
}

std::vector<float> normalsAt(const Frame& frame, const Scene& scene, const Camera& camera,
                             NormalSpace space) {
  const std::size_t n = framePixels(frame);
  if (frame.ids.size() != n) throw Error("the frame has no id buffer to find normals with");
  std::vector<float> out(3 * n, std::numeric_limits<float>::quiet_NaN());
  if (space == NormalSpace::kNone) return out;
  // Each polygon shown once: Newell's normal in double (any vertex count, robust to a
  // slightly non-planar polygon), turned to face the eye, then into eye space if asked
  std::vector<std::uint32_t> slot(scene.polygonCount(), kNoPolygon);
  std::vector<glm::vec3> normal;
  const glm::dmat3 eye_from_world(glm::dmat4(camera.view()));
  const glm::dvec3 eye(camera.eye), toward_eye = glm::dvec3(camera.eye - camera.target);
  for (std::size_t k = 0; k < n; ++k) {
    const PolygonId id = frame.ids[k];
    if (id == kNoPolygon || id >= scene.polygonCount()) continue;
    if (slot[id] == kNoPolygon) {
      const auto poly = scene.polygon(id);
      glm::dvec3 nn(0.0);
      for (std::size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec3 a(scene.position(poly[i])), b(scene.position(poly[(i + 1) % poly.size()]));
        nn += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x),
                         (a.x - b.x) * (a.y + b.y));
      }
      const double len = glm::length(nn);
      glm::dvec3 unit = len > 0 ? nn / len : glm::dvec3(0.0);
      const glm::dvec3 view = camera.ortho ? toward_eye : eye - glm::dvec3(scene.position(poly[0]));
      if (glm::dot(unit, view) < 0) unit = -unit;
      if (space == NormalSpace::kEye) unit = eye_from_world * unit;
      slot[id] = static_cast<std::uint32_t>(normal.size());
      normal.push_back(glm::vec3(unit));
    }
    const glm::vec3& v = normal[slot[id]];
    out[3 * k] = v.x, out[3 * k + 1] = v.y, out[3 * k + 2] = v.z;
  }
  return out;
}

std::string objectsJson(const Scene& scene) {
  return objectsArray(scene).dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) +
         "\n";
}

namespace {
std::string statsJsonWith(const Frame& frame, const std::string& scene,
                          const std::string& algorithm, const Scene* scene_data,
                          const Camera* camera) {
  const Stats& s = frame.stats;
  nlohmann::ordered_json j;
  j["scene"] = scene;
  j["algorithm"] = algorithm;
  j["width"] = frame.width;
  j["height"] = frame.height;
  for (const Stats::Field& f : Stats::fields()) j[std::string(f.name)] = s.*f.value;
  nlohmann::ordered_json counters = nlohmann::ordered_json::object();
  for (const Counter& c : s.counters) counters[c.name] = c.value;
  j["counters"] = std::move(counters);
  nlohmann::ordered_json stages = nlohmann::ordered_json::array();
  for (const StageTime& st : s.stages) stages.push_back({{"name", st.name}, {"ms", st.ms}});
  j["stages"] = std::move(stages);
  j["total_ms"] = s.totalMs();
  if (camera) j["camera"] = detail::cameraObject(*camera);
  if (scene_data) {
    j["objects"] = objectsArray(*scene_data);
    j["materials"] = materialsArray(*scene_data);
  }
  // A scene named by a file path need not be UTF-8: replace what is not, never throw
  return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}
}  // namespace

std::string statsJson(const Frame& frame, const std::string& scene, const std::string& algorithm) {
  return statsJsonWith(frame, scene, algorithm, nullptr, nullptr);
}

std::string statsJson(const Frame& frame, const std::string& scene, const std::string& algorithm,
                      const Scene& scene_data, const Camera& camera) {
  return statsJsonWith(frame, scene, algorithm, &scene_data, &camera);
}

}  // namespace hsr

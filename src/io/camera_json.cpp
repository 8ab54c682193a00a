// The camera as JSON, both ways. Written: every value a reader needs to reproduce the view or
// use it elsewhere (matrices, intrinsics, poses). Read: the values hsr's own camera is made of
// (eye, target, up, the projection, near, far, size), so that a camera written by one run and
// read by the next renders the same pixels; the matrices are written for others and ignored.

#include "io/camera_json.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "hsr/error.hpp"
#include "hsr/io.hpp"

namespace hsr {
namespace detail {
namespace {

nlohmann::ordered_json matrixRows(const glm::dmat4& m) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (int r = 0; r < 4; ++r) rows.push_back({m[0][r], m[1][r], m[2][r], m[3][r]});  // m[col][row]
  return rows;
}

}  // namespace

nlohmann::ordered_json cameraObject(const Camera& c) {
  nlohmann::ordered_json j;
  j["eye"] = {c.eye.x, c.eye.y, c.eye.z};
  j["target"] = {c.target.x, c.target.y, c.target.z};
  j["up"] = {c.up.x, c.up.y, c.up.z};
  j["projection_kind"] = c.ortho ? "orthographic" : "perspective";
  j["projection_from"] = c.ortho ? "ortho_half_height" : c.intrinsics.given() ? "intrinsics" : "fov_deg";
  if (c.ortho)
    j["ortho_half_height"] = c.ortho_half_height;
  else
    j["fov_deg"] = c.fov_deg;
  j["near"] = c.near;
  j["far"] = c.far;
  j["width"] = c.width;
  j["height"] = c.height;
  j["view"] = matrixRows(glm::dmat4(c.view()));
  j["projection"] = matrixRows(glm::dmat4(c.projection()));
  j["pose_opencv"] = matrixRows(poseOf(c, PoseConvention::kOpenCV));
  j["pose_opengl"] = matrixRows(poseOf(c, PoseConvention::kOpenGL));
  if (c.ortho) {
    j["intrinsics"] = nullptr;
  } else {
    const Intrinsics k = intrinsicsOf(c);
    j["intrinsics"] = {{"fx", k.fx},
                       {"fy", k.fy},
                       {"cx", k.cx},
                       {"cy", k.cy},
                       {"convention",
                        "OpenCV: camera x right, y down, z forward; pixel centres at integers, "
                        "(0, 0) the top-left pixel's centre"}};
  }
  j["matrices"] =
      "row-major rows acting on column vectors; view: world to eye (OpenGL: the eye looks down "
      "-z, y up), projection: eye to clip (OpenGL, depth [-1, 1]); pose_opencv and pose_opengl: "
      "camera to world, the camera's axes in OpenCV's convention (x right, y down, z forward) "
      "or OpenGL's (x right, y up, looking down -z)";
  return j;
}

}  // namespace detail

namespace {

using Json = nlohmann::json;

[[noreturn]] void bad(const std::string& what) { throw Error("camera JSON: " + what); }

const Json& field(const Json& j, const char* name) {
  const auto it = j.find(name);
  if (it == j.end()) bad(std::string("\"") + name + "\" is missing");
  return *it;
}

double number(const Json& j, const char* name) {
  const Json& v = field(j, name);
  if (!v.is_number()) bad(std::string("\"") + name + "\" must be a number");
  const double d = v.get<double>();
  if (!std::isfinite(d)) bad(std::string("\"") + name + "\" is not finite");
  return d;
}

float floatNumber(const Json& j, const char* name) {
  const double d = number(j, name);
  if (std::abs(d) > std::numeric_limits<float>::max()) bad(std::string("\"") + name + "\" is beyond float's range");
  return static_cast<float>(d);
}

int size(const Json& j, const char* name) {
  const double d = number(j, name);
  if (d != std::floor(d) || d < 1 || d > Camera::kMaxDimension)
    bad(std::string("\"") + name + "\" must be a whole number of pixels from 1 to " +
        std::to_string(Camera::kMaxDimension));
  return static_cast<int>(d);
}

glm::vec3 vec3(const Json& j, const char* name) {
  const Json& v = field(j, name);
  if (!v.is_array() || v.size() != 3) bad(std::string("\"") + name + "\" must be [x, y, z]");
  glm::vec3 out;
  for (int k = 0; k < 3; ++k) {
    if (!v[k].is_number() || !std::isfinite(v[k].get<double>()))
      bad(std::string("\"") + name + "\" must hold three finite numbers");
    out[k] = v[k].get<float>();
  }
  return out;
}

glm::dmat4 matrix(const Json& v, const char* name) {
  if (!v.is_array() || v.size() != 4) bad(std::string("\"") + name + "\" must be 4 rows of 4 numbers");
  glm::dmat4 m(1.0);
  for (int r = 0; r < 4; ++r) {
    if (!v[r].is_array() || v[r].size() != 4) bad(std::string("\"") + name + "\" must be 4 rows of 4 numbers");
    for (int c = 0; c < 4; ++c) {
      if (!v[r][c].is_number()) bad(std::string("\"") + name + "\" must be 4 rows of 4 numbers");
      m[c][r] = v[r][c].get<double>();
    }
  }
  return m;
}

Camera cameraOf(const Json& in) {
  // A manifest.json or --stats file holds the camera under "camera"
  const Json& j = in.is_object() && in.contains("camera") && in["camera"].is_object() ? in["camera"] : in;
  if (!j.is_object()) bad("a camera must be a JSON object");
  Camera c;
  c.width = size(j, "width");
  c.height = size(j, "height");
  if (j.contains("eye")) {
    c.eye = vec3(j, "eye");
    c.target = vec3(j, "target");
    c.up = vec3(j, "up");
  } else if (j.contains("pose_opencv")) {
    setPose(c, matrix(j["pose_opencv"], "pose_opencv"), PoseConvention::kOpenCV);
  } else if (j.contains("pose_opengl")) {
    setPose(c, matrix(j["pose_opengl"], "pose_opengl"), PoseConvention::kOpenGL);
  } else {
    bad("give the view as \"eye\", \"target\" and \"up\", or as \"pose_opencv\" or \"pose_opengl\"");
  }
  const Json& kind = field(j, "projection_kind");
  if (kind == "orthographic") {
    c.ortho = true;
    c.ortho_half_height = floatNumber(j, "ortho_half_height");
  } else if (kind == "perspective") {
    const bool from_intrinsics = j.contains("projection_from") ? j["projection_from"] == "intrinsics"
                                                                : !j.contains("fov_deg");
    if (from_intrinsics) {
      const Json& k = field(j, "intrinsics");
      if (!k.is_object()) bad("\"intrinsics\" must be an object with fx, fy, cx and cy");
      c.intrinsics = {number(k, "fx"), number(k, "fy"), number(k, "cx"), number(k, "cy")};
      // All zero is how a camera says "none": refused here, never dropped for the default fov
      if (!(c.intrinsics.fx > 0) || !(c.intrinsics.fy > 0))
        bad("\"intrinsics\": fx and fy must be positive pixels");
    } else {
      c.fov_deg = floatNumber(j, "fov_deg");
    }
  } else {
    bad("\"projection_kind\" must be \"perspective\" or \"orthographic\"");
  }
  c.near = floatNumber(j, "near");
  c.far = floatNumber(j, "far");
  try {
    c.validate();
  } catch (const Error& e) {
    bad(e.what());
  }
  return c;
}

Json parse(std::string_view text) {
  Json j = Json::parse(text, nullptr, false);
  if (j.is_discarded()) bad("not valid JSON");
  return j;
}

}  // namespace

std::string cameraJson(const Camera& camera) { return detail::cameraObject(camera).dump(2) + "\n"; }

Camera cameraFromJson(std::string_view text) { return cameraOf(parse(text)); }

std::vector<Camera> camerasFromJson(std::string_view text) {
  // A list of views, bare or as {"views": [...]}, is read view by view: each becomes a Camera
  // as soon as its value is whole and is then dropped from the parsed tree, so that memory
  // stays the cameras' own (not the JSON tree of every view: 973 MB for a million), and the
  // count is checked as they come, so that a list past the limit is refused at its first view
  // too many, not after the whole file.
  enum class Top { kUnknown, kArray, kObject } top = Top::kUnknown;
  bool views_key = false;   // the top-level object's member being read is "views"
  int element_depth = -1;   // the depth of the list's elements once the list is open
  std::vector<Camera> cameras;
  const auto take = [&](const Json& view) {
    if (cameras.size() == kMaxViews) bad("more than " + std::to_string(kMaxViews) + " views");
    try {
      cameras.push_back(cameraOf(view));
    } catch (const Error& e) {
      throw Error("view " + std::to_string(cameras.size()) + ": " + e.what());
    }
  };
  const Json::parser_callback_t each = [&](int depth, Json::parse_event_t event, Json& parsed) {
    using E = Json::parse_event_t;
    if (depth == 0 && top == Top::kUnknown) {
      if (event == E::array_start) top = Top::kArray, element_depth = 1;
      if (event == E::object_start) top = Top::kObject;
      return true;
    }
    if (top == Top::kObject && depth == 1 && event == E::key) {
      views_key = parsed == "views";
      return true;
    }
    if (top == Top::kObject && views_key && depth == 1 && event == E::array_start) {
      element_depth = 2;
      return true;
    }
    if (top == Top::kObject && views_key && depth == 1 && event == E::array_end) {
      element_depth = -1;
      return true;
    }
    // A whole element of the list: an object, or any other value (which cameraOf refuses)
    if (depth == element_depth &&
        (event == E::object_end || event == E::array_end || event == E::value)) {
      take(parsed);
      return false;  // dropped from the tree
    }
    return true;
  };
  Json j = Json::parse(text, each, false);
  if (j.is_discarded()) bad("not valid JSON");
  const bool listed = top == Top::kArray || (j.is_object() && j.contains("views") && j["views"].is_array());
  if (!listed) return {cameraOf(j)};
  if (cameras.empty()) bad("the list of views is empty");
  return cameras;
}

glm::dmat4 poseFromText(std::string_view text) {
  // Brackets and commas as spaces: a JSON array of rows, NumPy's savetxt or a line of 16
  std::string s(text);
  for (char& ch : s)
    if (ch == '[' || ch == ']' || ch == ',' || ch == ';') ch = ' ';
  std::istringstream in(s);
  in.imbue(std::locale::classic());
  std::vector<double> v;
  std::string token;
  while (in >> token) {
    if (v.size() == 16) throw Error("pose: more than 16 numbers (give a 4x4 or 3x4 matrix)");
    std::size_t used = 0;
    double d = 0;
    try {
      d = std::stod(token, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != token.size()) throw Error("pose: '" + token.substr(0, 40) + "' is not a number");
    v.push_back(d);
  }
  if (v.size() != 16 && v.size() != 12)
    throw Error("pose: " + std::to_string(v.size()) +
                " numbers; a pose is a 4x4 (16) or 3x4 (12) matrix, row by row");
  glm::dmat4 m(1.0);
  for (std::size_t k = 0; k < v.size(); ++k) m[k % 4][k / 4] = v[k];
  return m;
}

}  // namespace hsr

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
  j["projection_from"] = c.ortho                ? "ortho_half_height"
                         : c.intrinsics.given() ? "intrinsics"
                                                : "fov_deg";
  if (c.ortho) {
    j["ortho_half_height"] = c.ortho_half_height;
  } else {
    // fov_deg only where it made the projection; the angles the projection gives in any case
    if (!c.intrinsics.given()) j["fov_deg"] = c.fov_deg;
    const FieldOfView fov = fieldOfView(c);
    j["fov_x_deg"] = fov.x_deg;
    j["fov_y_deg"] = fov.y_deg;
  }
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

std::string quoted(const char* name) { return std::string("\"") + name + "\""; }

// One camera object's fields, read with every problem noted, so that one message names every
// field that is missing or wrong (not the first alone). A field with a problem reads as its
// default, and the camera is refused at finish().
class Fields {
 public:
  explicit Fields(const Json& j) : j_(j) {}

  bool has(const char* name) const { return j_.contains(name); }
  const Json* find(const char* name) {
    const auto it = j_.find(name);
    if (it == j_.end()) {
      problem(quoted(name) + " is missing");
      return nullptr;
    }
    return &*it;
  }
  double number(const char* name) {
    const Json* v = find(name);
    if (!v) return 0;
    if (!v->is_number()) return problem(quoted(name) + " must be a number"), 0;
    const double d = v->get<double>();
    if (!std::isfinite(d)) return problem(quoted(name) + " is not finite"), 0;
    return d;
  }
  float floatNumber(const char* name, float otherwise) {
    const std::size_t before = problems_.size();
    const double d = number(name);
    if (problems_.size() > before) return otherwise;
    if (std::abs(d) > std::numeric_limits<float>::max())
      return problem(quoted(name) + " is beyond float's range"), otherwise;
    return static_cast<float>(d);
  }
  int size(const char* name, int otherwise) {
    const std::size_t before = problems_.size();
    const double d = number(name);
    if (problems_.size() > before) return otherwise;
    if (d != std::floor(d) || d < 1 || d > Camera::kMaxDimension)
      return problem(quoted(name) + " must be a whole number of pixels from 1 to " +
                     std::to_string(Camera::kMaxDimension)),
             otherwise;
    return static_cast<int>(d);
  }
  glm::vec3 vec3(const char* name, const glm::vec3& otherwise) {
    const Json* v = find(name);
    if (!v) return otherwise;
    if (!v->is_array() || v->size() != 3)
      return problem(quoted(name) + " must be [x, y, z]"), otherwise;
    glm::vec3 out;
    for (int k = 0; k < 3; ++k) {
      if (!(*v)[k].is_number() || !std::isfinite((*v)[k].get<double>()))
        return problem(quoted(name) + " must hold three finite numbers"), otherwise;
      const double d = (*v)[k].get<double>();
      if (std::abs(d) > std::numeric_limits<float>::max())
        return problem(quoted(name) + " is beyond float's range"), otherwise;
      out[k] = static_cast<float>(d);
    }
    return out;
  }
  // A 4x4 matrix, row by row; false (noted) when it is not one
  bool matrix(const char* name, glm::dmat4& m) {
    const Json* v = find(name);
    if (!v) return false;
    const auto wrong = [&] {
      return problem(quoted(name) + " must be 4 rows of 4 numbers"), false;
    };
    if (!v->is_array() || v->size() != 4) return wrong();
    m = glm::dmat4(1.0);
    for (int r = 0; r < 4; ++r) {
      const Json& row = (*v)[r];
      if (!row.is_array() || row.size() != 4) return wrong();
      for (int c = 0; c < 4; ++c) {
        if (!row[c].is_number()) return wrong();
        m[c][r] = row[c].get<double>();
      }
    }
    return true;
  }
  void problem(std::string what) { problems_.push_back(std::move(what)); }
  bool clean() const { return problems_.empty(); }
  const std::vector<std::string>& problems() const { return problems_; }
  // Throws naming every problem noted, in the order of the fields
  void finish() const {
    if (problems_.empty()) return;
    std::string all;
    for (const std::string& p : problems_) {
      if (!all.empty()) all += "; ";
      all += p;
    }
    bad(all);
  }

 private:
  const Json& j_;
  std::vector<std::string> problems_;
};

// How a camera object is read: strict (every field, as --camera and cameraFromJson read what
// hsr wrote, to render the same pixels) or as a view of a list, where what can be defaulted is.
struct Leave {
  const ViewDefaults* defaults = nullptr;  // null: strict
  bool near_out = false, far_out = false;  // set: the view left near or far out
};

Camera cameraOf(const Json& in, Leave& leave) {
  // A manifest.json or --stats file holds the camera under "camera"
  const Json& j =
      in.is_object() && in.contains("camera") && in["camera"].is_object() ? in["camera"] : in;
  if (!j.is_object()) bad("a camera must be a JSON object");
  const ViewDefaults* d = leave.defaults;
  Fields f(j);
  Camera c;
  if (d && !f.has("width") && !f.has("height")) {
    c.width = d->width;
    c.height = d->height;
  } else {
    c.width = f.size("width", c.width);
    c.height = f.size("height", c.height);
  }
  const bool posed = !f.has("eye") && (f.has("pose_opencv") || f.has("pose_opengl"));
  if (!posed && !f.has("eye") && !f.has("target")) {
    f.problem(d ? "give the view as \"eye\" and \"target\" (\"up\" +y unless given), or as "
                  "\"pose_opencv\" or \"pose_opengl\""
                : "give the view as \"eye\", \"target\" and \"up\", or as \"pose_opencv\" or "
                  "\"pose_opengl\"");
  } else if (!posed) {
    c.eye = f.vec3("eye", c.eye);
    c.target = f.vec3("target", c.target);
    if (!(d && !f.has("up"))) c.up = f.vec3("up", c.up);  // a view's up defaults to +y
  } else {
    glm::dmat4 pose;
    const char* name = f.has("pose_opencv") ? "pose_opencv" : "pose_opengl";
    if (f.matrix(name, pose)) {
      try {
        setPose(c, pose, f.has("pose_opencv") ? PoseConvention::kOpenCV : PoseConvention::kOpenGL);
      } catch (const Error& e) {
        f.problem(std::string(name) + ": " + e.what());
      }
    }
  }
  const bool kind_given = f.has("projection_kind");
  const Json kind = kind_given ? j["projection_kind"] : Json(d ? "perspective" : "");
  if (!kind_given && !d) {
    f.problem("\"projection_kind\" is missing");
  } else if (kind == "orthographic") {
    c.ortho = true;
    c.ortho_half_height = f.floatNumber("ortho_half_height", c.ortho_half_height);
  } else if (kind == "perspective") {
    const bool from_intrinsics = f.has("projection_from")
                                     ? j["projection_from"] == "intrinsics"
                                     : !f.has("fov_deg") && f.has("intrinsics");
    if (from_intrinsics) {
      const Json* k = f.find("intrinsics");
      if (k && !k->is_object()) {
        f.problem("\"intrinsics\" must be an object with fx, fy, cx and cy");
      } else if (k) {
        Fields fk(*k);
        c.intrinsics = {fk.number("fx"), fk.number("fy"), fk.number("cx"), fk.number("cy")};
        if (!fk.clean()) {
          for (const std::string& p : fk.problems()) f.problem("\"intrinsics\": " + p);
          c.intrinsics = {};
        } else if (!(c.intrinsics.fx > 0) || !(c.intrinsics.fy > 0)) {
          // All zero is how a camera says "none": refused here, never dropped for the default fov
          f.problem("\"intrinsics\": fx and fy must be positive pixels");
          c.intrinsics = {};
        }
      }
    } else if (!(d && !f.has("fov_deg"))) {  // a view's fov defaults to 45 degrees
      c.fov_deg = f.floatNumber("fov_deg", c.fov_deg);
    }
  } else {
    f.problem("\"projection_kind\" must be \"perspective\" or \"orthographic\"");
  }
  // A view may leave near and far out: fitted around the scene once it is read (fitDepth)
  leave.near_out = d && !f.has("near");
  leave.far_out = d && !f.has("far");
  if (!leave.near_out) c.near = f.floatNumber("near", c.near);
  if (!leave.far_out) c.far = f.floatNumber("far", c.far);
  f.finish();
  // Until fitted, a left-out plane stands where the given one leaves room
  if (leave.near_out && !leave.far_out) c.near = c.far * 1e-3f;
  if (leave.far_out && !leave.near_out) c.far = c.near * 2.0f + 1.0f;
  try {
    c.validate();
  } catch (const Error& e) {
    bad(e.what());
  }
  return c;
}

Camera cameraOf(const Json& in) {
  Leave strict;
  return cameraOf(in, strict);
}
Json parse(std::string_view text) {
  Json j = Json::parse(text, nullptr, false);
  if (j.is_discarded()) bad("not valid JSON");
  return j;
}

}  // namespace

std::string cameraJson(const Camera& camera) { return detail::cameraObject(camera).dump(2) + "\n"; }

Camera cameraFromJson(std::string_view text) { return cameraOf(parse(text)); }

namespace {

ViewList readViews(std::string_view text, const ViewDefaults* defaults) {
  // A list of views, bare or as {"views": [...]}, is read view by view: each becomes a Camera
  // as soon as its value is whole and is then dropped from the parsed tree, so that memory
  // stays the cameras' own (not the JSON tree of every view: 973 MB for a million), and the
  // count is checked as they come, so that a list past the limit is refused at its first view
  // too many, not after the whole file.
  enum class Top { kUnknown, kArray, kObject } top = Top::kUnknown;
  bool views_key = false;  // the top-level object's member being read is "views"
  int element_depth = -1;  // the depth of the list's elements once the list is open
  ViewList list;
  std::vector<Camera>& cameras = list.cameras;
  const auto take = [&](const Json& view) {
    if (cameras.size() == kMaxViews) bad("more than " + std::to_string(kMaxViews) + " views");
    Leave leave{defaults};
    try {
      cameras.push_back(cameraOf(view, leave));
    } catch (const Error& e) {
      throw Error("view " + std::to_string(cameras.size()) + ": " + e.what());
    }
    list.fit_near.push_back(leave.near_out);
    list.fit_far.push_back(leave.far_out);
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
  const bool listed =
      top == Top::kArray || (j.is_object() && j.contains("views") && j["views"].is_array());
  if (!listed) {
    Leave leave{defaults};
    list.cameras = {cameraOf(j, leave)};
    list.fit_near = {leave.near_out};
    list.fit_far = {leave.far_out};
    return list;
  }
  if (cameras.empty()) bad("the list of views is empty");
  return list;
}

}  // namespace

std::vector<Camera> camerasFromJson(std::string_view text) {
  return readViews(text, nullptr).cameras;
}

ViewList viewsFromJson(std::string_view text, const ViewDefaults& defaults) {
  return readViews(text, &defaults);
}

void ViewList::fitDepth(const Bounds& bounds) {
  for (std::size_t k = 0; k < cameras.size(); ++k) {
    if (!fit_near[k] && !fit_far[k]) continue;
    Camera& c = cameras[k];
    Camera fitted = c;
    fitNearFar(fitted, bounds);
    if (fit_near[k]) c.near = fit_far[k] ? fitted.near : std::min(fitted.near, c.far * 0.5f);
    if (fit_far[k]) c.far = fit_near[k] ? fitted.far : std::max(fitted.far, c.near * 2.0f);
    fit_near[k] = fit_far[k] = 0;
    try {
      c.validate();
    } catch (const Error& e) {
      throw Error("view " + std::to_string(k) +
                  ": near and far fitted around the scene: " + e.what());
    }
  }
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

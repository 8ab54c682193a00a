// hsr for Python: the library's scene, camera, render, GL facade and ray queries as a pybind11
// module (hsr._hsr; python/hsr/__init__.py is its public face). Arrays come back as NumPy
// arrays that own the buffers render() filled: moved, not copied (colour is the frame's RGBA
// bytes; depth in another convention, objects, materials and normals are computed once into
// their own buffers). The GIL is released while the library works, so Python threads can
// render side by side.

#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "hsr/algorithms.hpp"
#include "hsr/camera.hpp"
#include "hsr/error.hpp"
#include "hsr/frontend.hpp"
#include "hsr/gl.hpp"
#include "hsr/io.hpp"
#include "hsr/ray_scene.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"

namespace py = pybind11;

namespace {

static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "glm::vec3 must be three packed floats");

// A NumPy array that owns `v` (moved into the array's base object): no copy.
template <class T, class Elem = T, class Alloc = std::allocator<T>>
py::array adopt(std::vector<T, Alloc>&& v, std::vector<py::ssize_t> shape) {
  using Vector = std::vector<T, Alloc>;
  auto* heap = new Vector(std::move(v));
  py::capsule owner(heap, [](void* p) { delete static_cast<Vector*>(p); });
  return py::array_t<Elem>(shape, reinterpret_cast<Elem*>(heap->data()), owner);
}

glm::vec3 vec3Of(const py::handle& h, const char* what) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(h);
  if (!a || a.size() != 3) throw hsr::Error(std::string(what) + " must be 3 numbers");
  return {static_cast<float>(a.at(0)), static_cast<float>(a.at(1)), static_cast<float>(a.at(2))};
}

py::tuple tupleOf(const glm::vec3& v) { return py::make_tuple(v.x, v.y, v.z); }

py::array matrixOf(const glm::dmat4& m) {
  std::vector<double> rows(16);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) rows[4 * r + c] = m[c][r];
  return adopt(std::move(rows), {4, 4});
}

glm::dmat4 dmat4Of(const py::handle& h) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(h);
  if (!a || a.ndim() != 2 || a.shape(1) != 4 || (a.shape(0) != 4 && a.shape(0) != 3))
    throw hsr::Error("a pose is a 4x4 (or 3x4) matrix");
  glm::dmat4 m(1.0);
  for (py::ssize_t r = 0; r < a.shape(0); ++r)
    for (int c = 0; c < 4; ++c) m[c][r] = a.at(r, c);
  return m;
}

// N x 3 float32 rows, C-contiguous (converted once if given otherwise)
using Rows = py::array_t<float, py::array::c_style | py::array::forcecast>;
std::span<const glm::vec3> rowsOf(const Rows& a, const char* what) {
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw hsr::Error(std::string(what) + " must be an N x 3 array");
  return {reinterpret_cast<const glm::vec3*>(a.data()), static_cast<std::size_t>(a.shape(0))};
}

// One mesh as an object of the scene: vertices N x 3, faces M x k vertex indices (k >= 3)
void addMesh(hsr::Scene& scene, const Rows& vertices, const py::object& face_rows,
             const std::string& name, const py::object& color, float alpha,
             const std::string& material) {
  const std::span<const glm::vec3> v = rowsOf(vertices, "vertices");
  const py::array face_array = py::array::ensure(face_rows);  // an array, or a list of rows
  if (!face_array) throw hsr::Error("faces must be an M x k array of vertex indices");
  // Indices must be integers: a float array would be truncated (1.7 -> vertex 1), and a bool
  // array read as 0 and 1
  const char kind = face_array.dtype().kind();
  if (kind != 'i' && kind != 'u')
    throw hsr::Error("faces must be an integer array of vertex indices (got dtype " +
                     py::str(face_array.dtype()).cast<std::string>() + ")");
  const auto faces =
      py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(face_array);
  if (!faces) throw hsr::Error("faces must be an M x k array of vertex indices");
  if (faces.ndim() != 2 || faces.shape(1) < 3)
    throw hsr::Error("faces must be an M x k array of vertex indices, k >= 3");
  if (v.size() > 50'000'000 || faces.shape(0) > 50'000'000)
    throw hsr::Error("a mesh of over 50M vertices or faces");
  hsr::Material m;
  if (!color.is_none()) m.color = vec3Of(color, "color");
  m.alpha = alpha;
  m.name = material;
  const std::uint32_t mat = scene.addMaterial(m);
  scene.beginObject(name);
  for (const glm::vec3& p : v) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw hsr::Error("vertex " + std::to_string(&p - v.data()) + " is not finite");
    scene.addVertex(p);
  }
  const auto f = faces.unchecked<2>();
  std::vector<std::uint32_t> local(static_cast<std::size_t>(faces.shape(1)));
  for (py::ssize_t i = 0; i < faces.shape(0); ++i) {
    for (py::ssize_t j = 0; j < faces.shape(1); ++j) {
      const std::int64_t k = f(i, j);
      if (k < 0 || static_cast<std::uint64_t>(k) >= v.size())
        throw hsr::Error("face " + std::to_string(i) + " uses vertex " + std::to_string(k) +
                         " of " + std::to_string(v.size()));
      local[static_cast<std::size_t>(j)] = static_cast<std::uint32_t>(k);
    }
    scene.addPolygon(local, mat);
  }
}

py::dict frameArrays(hsr::Frame&& f, const hsr::Scene& scene, const hsr::Camera& camera,
                     hsr::DepthKind depth, hsr::NormalSpace normals, const std::string& algorithm) {
  const py::ssize_t h = f.height, w = f.width;
  std::vector<std::uint32_t> objects, materials;
  std::vector<float> normal;
  hsr::FrameBuffer<float> converted;
  std::string stats;
  {
    py::gil_scoped_release release;
    objects = hsr::objectsAt(f, scene);
    materials = hsr::materialsAt(f, scene);
    if (normals != hsr::NormalSpace::kNone) normal = hsr::normalsAt(f, scene, camera, normals);
    if (depth != hsr::DepthKind::kWindow) converted = hsr::depthAs(f, camera, depth);
    stats = hsr::statsJson(f, scene.name, algorithm, scene, camera);
  }
  py::dict d;
  py::array rgba = adopt<std::uint32_t, std::uint8_t>(std::move(f.color), {h, w, 4});
  d["rgba"] = rgba;
  d["color"] = rgba[py::make_tuple(py::ellipsis(), py::slice(0, 3, 1))];
  d["depth"] =
      converted.empty() ? adopt(std::move(f.depth), {h, w}) : adopt(std::move(converted), {h, w});
  d["ids"] = adopt(std::move(f.ids), {h, w});
  d["objects"] = adopt(std::move(objects), {h, w});
  d["materials"] = adopt(std::move(materials), {h, w});
  d["overdraw"] = adopt(std::move(f.overdraw), {h, w});
  d["normals"] = normal.empty() ? py::none() : py::object(adopt(std::move(normal), {h, w, 3}));
  d["coverage"] =
      f.coverage.empty() ? py::none() : py::object(adopt(std::move(f.coverage), {h, w}));
  d["stats"] = py::module_::import("json").attr("loads")(stats);
  return d;
}

// A Python value as the option table takes it: a bool, a whole number, a number, a string or a
// sequence of numbers (a NumPy array among them).
hsr::OptionValue optionValueOf(const std::string& name, py::handle v) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>();
  if (py::isinstance<py::int_>(v)) return v.cast<std::int64_t>();
  if (py::isinstance<py::float_>(v)) return v.cast<double>();
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (py::hasattr(v, "__index__")) return py::int_(v.attr("__index__")()).cast<std::int64_t>();
  if (py::hasattr(v, "__float__") && !py::hasattr(v, "__len__"))
    return py::float_(v.attr("__float__")()).cast<double>();
  try {
    return v.cast<std::vector<double>>();
  } catch (const py::cast_error&) {
    throw hsr::Error(name + " must be a bool, a number, a string or numbers (got " +
                     std::string(py::str(py::type::of(v).attr("__name__"))) + ")");
  }
}

// The options given to render() or view(), checked by the library's table (hsr/frontend.hpp)
// as the command line and the web page check them; `view` says which half the call takes.
hsr::OptionRequest requestOf(const py::dict& options, bool view) {
  hsr::OptionRequest r(hsr::FrontEnd::kPython);
  for (const auto& [key, value] : options) {
    const std::string name = py::str(key);
    const hsr::OptionSpec* spec = hsr::findOptionSpec(name);
    if (spec && spec->view != view && spec->offeredBy(hsr::FrontEnd::kPython))
      throw hsr::Error(name + (view ? " is a render option: give it to hsr.render()"
                                    : " sets the camera: give it to hsr.view()"));
    r.set(name, optionValueOf(name, value));
  }
  return r;
}

}  // namespace

PYBIND11_MODULE(_hsr, m) {
  m.doc() = "hsr: hidden-surface removal with every classic algorithm (the C++ core)";
  static py::exception<hsr::Error> error(m, "Error", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const hsr::Error& e) {
      PyErr_SetString(error.ptr(), e.what());
    }
  });

  py::class_<hsr::Scene>(m, "Scene",
                         "Polygons in world space; a polygon's id is its index in load order.")
      .def(py::init<>())
      .def_static(
          "load",
          [](const std::string& spec, bool allow_outside_refs) {
            hsr::ImportLimits limits;
            limits.allow_outside_references = allow_outside_refs;
            py::gil_scoped_release release;
            return hsr::loadScene(spec, limits);
          },
          py::arg("spec"), py::arg("allow_outside_refs") = false,
          "A model file (OBJ, PLY, STL, OFF, glTF, ...; imported in a sandboxed child process) or "
          "a "
          "built-in scene (demo, spheres:N, ...)")
      .def("add_mesh", &addMesh, py::arg("vertices"), py::arg("faces"), py::arg("name") = "",
           py::arg("color") = py::none(), py::arg("alpha") = 1.0f, py::arg("material") = "",
           "Adds an object: vertices N x 3, faces M x k vertex indices (counter-clockwise front); "
           "its polygons get the next ids")
      .def_readwrite("name", &hsr::Scene::name)
      .def_property_readonly("polygon_count", &hsr::Scene::polygonCount)
      .def_property_readonly("vertex_count", &hsr::Scene::vertexCount)
      .def_property_readonly("triangle_count", &hsr::Scene::triangleCount)
      .def_property_readonly("bounds",
                             [](const hsr::Scene& s) {
                               const hsr::Bounds b = s.bounds();
                               return py::make_tuple(tupleOf(b.lo), tupleOf(b.hi));
                             })
      .def_property_readonly("objects",
                             [](const hsr::Scene& s) {
                               py::list out;
                               for (const hsr::Object& o : s.objects)
                                 out.append(py::dict(py::arg("name") = o.name,
                                                     py::arg("first_polygon") = o.first_polygon,
                                                     py::arg("polygons") = o.polygon_count));
                               return out;
                             })
      .def_property_readonly(
          "materials",
          [](const hsr::Scene& s) {
            py::list out;
            for (const hsr::Material& mt : s.materials)
              out.append(py::dict(py::arg("name") = mt.name, py::arg("color") = tupleOf(mt.color),
                                  py::arg("alpha") = mt.alpha));
            return out;
          })
      .def_property_readonly("camera_count", [](const hsr::Scene& s) { return s.cameras.size(); })
      .def("__repr__", [](const hsr::Scene& s) {
        return "<hsr.Scene '" + s.name + "': " + std::to_string(s.polygonCount()) + " polygons, " +
               std::to_string(s.objects.size()) + " objects>";
      });

  py::class_<hsr::Camera>(m, "Camera",
                          "gluLookAt + gluPerspective / glOrtho, or pinhole intrinsics")
      .def(py::init<>())
      .def_property(
          "eye", [](const hsr::Camera& c) { return tupleOf(c.eye); },
          [](hsr::Camera& c, const py::object& v) { c.eye = vec3Of(v, "eye"); })
      .def_property(
          "target", [](const hsr::Camera& c) { return tupleOf(c.target); },
          [](hsr::Camera& c, const py::object& v) { c.target = vec3Of(v, "target"); })
      .def_property(
          "up", [](const hsr::Camera& c) { return tupleOf(c.up); },
          [](hsr::Camera& c, const py::object& v) { c.up = vec3Of(v, "up"); })
      .def_readwrite("fov", &hsr::Camera::fov_deg, "vertical field of view in degrees")
      .def_readwrite("ortho", &hsr::Camera::ortho)
      .def_readwrite("ortho_half_height", &hsr::Camera::ortho_half_height)
      .def_readwrite("near", &hsr::Camera::near)
      .def_readwrite("far", &hsr::Camera::far)
      .def_readwrite("width", &hsr::Camera::width)
      .def_readwrite("height", &hsr::Camera::height)
      .def_property(
          "intrinsics",
          [](const hsr::Camera& c) {
            const hsr::Intrinsics k = hsr::intrinsicsOf(c);
            return py::make_tuple(k.fx, k.fy, k.cx, k.cy);
          },
          [](hsr::Camera& c, const py::object& v) {
            if (v.is_none()) {
              c.intrinsics = {};
              return;
            }
            const auto t = v.cast<std::vector<double>>();
            if (t.size() != 4) throw hsr::Error("intrinsics are fx, fy, cx, cy");
            c.intrinsics = {t[0], t[1], t[2], t[3]};
          },
          "(fx, fy, cx, cy) in pixels, OpenCV's convention (pixel centres at integers); set None "
          "to project with fov again")
      .def("validate", &hsr::Camera::validate)
      .def("view_matrix", [](const hsr::Camera& c) { return matrixOf(glm::dmat4(c.view())); })
      .def("projection_matrix",
           [](const hsr::Camera& c) { return matrixOf(glm::dmat4(c.projection())); })
      .def(
          "pose",
          [](const hsr::Camera& c, const std::string& conv) {
            return matrixOf(hsr::poseOf(c, hsr::poseConventionNamed(conv)));
          },
          py::arg("convention") = "opencv", "camera to world, 4x4")
      .def(
          "set_pose",
          [](hsr::Camera& c, const py::object& pose, const std::string& conv) {
            hsr::setPose(c, dmat4Of(pose), hsr::poseConventionNamed(conv));
          },
          py::arg("pose"), py::arg("convention") = "opencv")
      .def("fit_near_far",
           [](hsr::Camera& c, const hsr::Scene& s) { hsr::fitNearFar(c, s.bounds()); })
      .def("orbit", &hsr::orbitView, py::arg("k"), py::arg("n"),
           "view k of n on a ring about the up axis")
      .def("to_json", &hsr::cameraJson)
      .def_static("from_json", &hsr::cameraFromJson)
      .def_static("list_from_json", &hsr::camerasFromJson)
      .def_static("frame", &hsr::frameScene, py::arg("scene"), py::arg("width") = 800,
                  py::arg("height") = 600, py::arg("camera_index") = 0,
                  "looks at the whole scene (the file's camera camera_index when it has one; -1 "
                  "ignores them)")
      .def("__repr__",
           [](const hsr::Camera& c) { return "<hsr.Camera " + hsr::cameraJson(c) + ">"; });

  m.def(
      "render",
      [](const hsr::Scene& scene, const hsr::Camera& camera, const std::string& depth,
         const std::string& normals, const py::dict& options) {
        const hsr::RenderOptions o = requestOf(options, false).options();
        const hsr::DepthKind kind = hsr::depthKindNamed(depth);
        const hsr::NormalSpace space =
            normals.empty() ? hsr::NormalSpace::kNone : hsr::normalSpaceNamed(normals);
        hsr::Frame f;
        {
          py::gil_scoped_release release;
          f = hsr::render(scene, camera, o);
        }
        return frameArrays(std::move(f), scene, camera, kind, space, o.algorithm);
      },
      py::arg("scene"), py::arg("camera"), py::arg("depth") = "window", py::arg("normals") = "",
      py::arg("options") = py::dict(),
      "renders with the options of hsr.options() whose view is False, by name");

  m.def(
      "view",
      [](const hsr::Scene& scene, const py::dict& options) {
        return requestOf(options, true)
            .camera(scene, scene.name.empty() ? "the scene" : scene.name);
      },
      py::arg("scene"), py::arg("options") = py::dict(),
      "the camera the view options of hsr.options() describe, fitted to scene where not given");

  m.def(
      "options",
      [] {
        static const char* kKinds[] = {"flag",   "integer", "number", "name",
                                       "vector", "text",    "file"};
        py::list out;
        for (const hsr::OptionSpec& o : hsr::optionSpecs()) {
          if (!o.offeredBy(hsr::FrontEnd::kPython)) continue;
          out.append(py::dict(
              py::arg("name") = std::string(o.name),
              py::arg("kind") = kKinds[static_cast<int>(o.kind)], py::arg("view") = o.view,
              py::arg("default") = std::string(o.default_text),
              py::arg("help") = std::string(o.help), py::arg("choices") = std::string(o.choices),
              py::arg("range") = py::make_tuple(o.lo, o.hi),
              py::arg("needs") = hsr::capabilityList(o.needs),
              py::arg("cli") = hsr::spelled(o.name, hsr::FrontEnd::kCli)));
        }
        return out;
      },
      "every option render() and view() take: name, kind, view, default, help, choices, range, "
      "the capability an algorithm needs to take it, and its command-line spelling");

  m.def(
      "render_files",
      [](const hsr::Scene& scene, const hsr::Camera& camera, const std::string& dir,
         const std::string& label, const std::string& algorithm, const std::string& depth,
         const std::string& normals, int threads, bool color) {
        hsr::RenderOptions o;
        o.algorithm = algorithm;
        o.threads = threads;
        const hsr::DepthKind kind = hsr::depthKindNamed(depth);
        const hsr::NormalSpace space =
            normals.empty() ? hsr::NormalSpace::kNone : hsr::normalSpaceNamed(normals);
        py::gil_scoped_release release;
        const hsr::Frame f = hsr::render(scene, camera, o);
        hsr::writeRawFrame(dir, f, label, algorithm, scene, camera, kind, space);
        if (color)
          hsr::writePng(std::filesystem::path(dir) / "color.png", f.width, f.height, 3,
                        hsr::picture(f, "color").data());
      },
      py::arg("scene"), py::arg("camera"), py::arg("dir"), py::arg("label"),
      py::arg("algorithm") = "zbuffer", py::arg("depth") = "window", py::arg("normals") = "",
      py::arg("threads") = 0, py::arg("color") = true,
      "renders and writes the raw set (as the CLI's --raw) into dir, and dir/color.png");

  m.def("algorithms", [] {
    py::list out;
    for (const hsr::AlgorithmInfo& i : hsr::algorithms())
      out.append(py::dict(
          py::arg("name") = std::string(i.name), py::arg("summary") = std::string(i.summary),
          py::arg("precision") = std::string(hsr::toString(i.precision)),
          py::arg("reference") = i.reference, py::arg("demonstration") = i.demonstration,
          py::arg("textbook") = i.textbook, py::arg("sibling") = std::string(i.sibling),
          py::arg("capabilities") = hsr::capabilityList(i.capabilities)));
    return out;
  });

  // The GL-style facade, as the notes write it
  py::module_ gl =
      m.def_submodule("gl", "the OpenGL-style controls: enable, depthMask, clear, cullFace, ...");
  py::enum_<hsr::gl::Capability>(gl, "Capability")
      .value("DEPTH_TEST", hsr::gl::DEPTH_TEST)
      .value("CULL_FACE", hsr::gl::CULL_FACE)
      .export_values();
  py::enum_<hsr::gl::Face>(gl, "Face")
      .value("FRONT", hsr::gl::FRONT)
      .value("BACK", hsr::gl::BACK)
      .value("FRONT_AND_BACK", hsr::gl::FRONT_AND_BACK)
      .export_values();
  py::enum_<hsr::gl::Winding>(gl, "Winding")
      .value("CW", hsr::gl::CW)
      .value("CCW", hsr::gl::CCW)
      .export_values();
  py::enum_<hsr::gl::Mode>(gl, "Mode")
      .value("POINT", hsr::gl::POINT)
      .value("LINE", hsr::gl::LINE)
      .value("FILL", hsr::gl::FILL)
      .export_values();
  gl.attr("COLOR_BUFFER_BIT") = static_cast<unsigned>(hsr::gl::COLOR_BUFFER_BIT);
  gl.attr("DEPTH_BUFFER_BIT") = static_cast<unsigned>(hsr::gl::DEPTH_BUFFER_BIT);
  py::class_<hsr::gl::Context>(gl, "Context")
      .def(py::init<const hsr::Camera&>())
      .def("enable", &hsr::gl::Context::enable)
      .def("disable", &hsr::gl::Context::disable)
      .def("isEnabled", &hsr::gl::Context::isEnabled)
      .def("depthMask", &hsr::gl::Context::depthMask)
      .def("depthFunc",
           [](hsr::gl::Context& c, const std::string& f) { c.depthFunc(hsr::parseDepthFunc(f)); })
      .def("clearColor", &hsr::gl::Context::clearColor)
      .def("clearDepth", &hsr::gl::Context::clearDepth)
      .def("clear", &hsr::gl::Context::clear)
      .def("cullFace", &hsr::gl::Context::cullFace)
      .def("frontFace", &hsr::gl::Context::frontFace)
      .def("polygonMode", &hsr::gl::Context::polygonMode)
      .def("pointSize", &hsr::gl::Context::pointSize)
      .def("setCamera", &hsr::gl::Context::setCamera)
      .def("draw", &hsr::gl::Context::draw, py::call_guard<py::gil_scoped_release>())
      .def("arrays", [](const hsr::gl::Context& c) {
        hsr::Frame f = c.frame();  // the context keeps its frame: one copy
        const py::ssize_t h = f.height, w = f.width;
        py::dict d;
        py::array rgba = adopt<std::uint32_t, std::uint8_t>(std::move(f.color), {h, w, 4});
        d["rgba"] = rgba;
        d["color"] = rgba[py::make_tuple(py::ellipsis(), py::slice(0, 3, 1))];
        d["depth"] = adopt(std::move(f.depth), {h, w});
        d["ids"] = adopt(std::move(f.ids), {h, w});
        d["overdraw"] = adopt(std::move(f.overdraw), {h, w});
        return d;
      });

  // Ray queries (hsr/ray_scene.hpp)
  py::class_<hsr::RayScene>(m, "RayScene", "a BVH over a scene's polygons, for arbitrary rays")
      .def(py::init<const hsr::Scene&, bool>(), py::arg("scene"), py::arg("opaque_only") = false,
           py::call_guard<py::gil_scoped_release>())
      .def(
          "intersect",
          [](const hsr::RayScene& rs, const Rows& origins, const Rows& directions, float tmax,
             float tmin) {
            const auto o = rowsOf(origins, "origins"), d = rowsOf(directions, "directions");
            if (o.size() != d.size()) throw hsr::Error("origins and directions differ in length");
            std::vector<hsr::RayHit> hits(o.size());
            {
              py::gil_scoped_release release;
              rs.intersect(o, d, hits, tmax, tmin);
            }
            const py::ssize_t n = static_cast<py::ssize_t>(hits.size());
            std::vector<float> t(hits.size()), u(hits.size()), v(hits.size()),
                normal(3 * hits.size());
            std::vector<std::uint32_t> polygon(hits.size()), object(hits.size());
            std::vector<std::uint8_t> front(hits.size());
            for (std::size_t k = 0; k < hits.size(); ++k) {
              const hsr::RayHit& h = hits[k];
              t[k] = h.t, u[k] = h.u, v[k] = h.v, polygon[k] = h.polygon, object[k] = h.object,
              front[k] = h.front;
              normal[3 * k] = h.normal.x, normal[3 * k + 1] = h.normal.y,
                         normal[3 * k + 2] = h.normal.z;
            }
            py::dict out;
            out["t"] = adopt(std::move(t), {n});
            out["polygon"] = adopt(std::move(polygon), {n});
            out["object"] = adopt(std::move(object), {n});
            out["u"] = adopt(std::move(u), {n});
            out["v"] = adopt(std::move(v), {n});
            out["normal"] = adopt(std::move(normal), {n, 3});
            out["front"] = adopt<std::uint8_t, bool>(std::move(front), {n});
            return out;
          },
          py::arg("origins"), py::arg("directions"),
          py::arg("tmax") = std::numeric_limits<float>::infinity(), py::arg("tmin") = 0.0f,
          "nearest hits of N rays: t (inf for none), polygon (4294967295 for none), object, u, v, "
          "normal, front")
      .def(
          "occluded",
          [](const hsr::RayScene& rs, const Rows& origins, const Rows& directions, float tmax,
             float tmin) {
            const auto o = rowsOf(origins, "origins"), d = rowsOf(directions, "directions");
            if (o.size() != d.size()) throw hsr::Error("origins and directions differ in length");
            std::vector<std::uint8_t> hit;
            {
              py::gil_scoped_release release;
              hit = rs.occluded(o, d, tmax, tmin);
            }
            const py::ssize_t n = static_cast<py::ssize_t>(hit.size());
            return adopt<std::uint8_t, bool>(std::move(hit), {n});
          },
          py::arg("origins"), py::arg("directions"),
          py::arg("tmax") = std::numeric_limits<float>::infinity(), py::arg("tmin") = 0.0f)
      .def_property_readonly("triangle_count", &hsr::RayScene::triangleCount);
}

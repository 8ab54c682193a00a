#pragma once
// One description of every option the front-ends offer (the `hsr` command, the Python module
// and the web page's module): its name, kind, range, default, which algorithms take it and its
// help line; and one request that turns the values a front-end was given into RenderOptions
// and a Camera, with the same checks and the same messages everywhere. A front-end adds only
// its spelling: the CLI writes clear_depth as --clear-depth (and an option that is on by
// default as the flag that turns it off: --no-depth-test, --flat), Python and the web page as
// clear_depth. An option added to the table appears in all three.
//
//   hsr::OptionRequest r(hsr::FrontEnd::kPython);
//   r.set("cull", std::string("back"));       // typed values (Python, JSON)
//   r.setText("eye", "1,2,3");                // or text as typed on a command line
//   const hsr::RenderOptions o = r.options();
//   const hsr::Camera c = r.camera(scene, "model.ply");

#include <cstdint>
#include <limits>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <glm/mat4x4.hpp>

#include "hsr/camera.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"

namespace hsr {

enum class FrontEnd { kCli, kPython, kWeb };

enum class OptionKind {
  kFlag,     // true or false
  kInteger,  // a whole number in [lo, hi]
  kNumber,   // a number in [lo, hi] ((lo, hi] with lo_open)
  kName,     // one of `choices`, in any case (as OpenGL's names)
  kVector,   // `count` numbers; on a command line joined by commas (size: WxH)
  kText,     // text the request reads itself (camera_index: N, or auto)
  kFile,     // a file the front-end reads and parses (camera, pose): the command line's alone
};

// Which front-ends offer an option (a bit per FrontEnd).
inline constexpr std::uint8_t kEveryFrontEnd = 0b111;
inline constexpr std::uint8_t kCommandLineOnly = 0b001;

struct OptionSpec {
  std::string_view name;  // as Python and the web page spell it
  OptionKind kind;
  bool view;                      // sets the camera; else the render state
  std::string_view default_text;  // as help shows it; empty: none (fitted, or the scene's)
  std::string_view help;
  std::string_view choices = {};  // kName: "none|back|front|both"; kVector: its form, "X,Y,Z"
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;  // the range excludes lo, hi
  std::string_view note = {};             // after the range in its message: " degrees", ", as ..."
  int count = 0;                          // kVector: how many numbers
  bool wide = false;                      // kNumber, kVector: a double (else held in a float)
  std::uint32_t needs = 0;      // a Capability: an algorithm without it refuses all but the
                                // default
  std::string_view trial = {};  // a value other than the default, as the CLI types it
  std::string_view cli = {};    // the CLI's spelling where it is not --name-with-dashes
  std::uint8_t front_ends = kEveryFrontEnd;

  bool offeredBy(FrontEnd fe) const { return (front_ends >> static_cast<int>(fe)) & 1; }
};

// Every option, the view's first, in the order help lists them.
std::span<const OptionSpec> optionSpecs();
// The option named `name` (as Python spells it), or nullptr.
const OptionSpec* findOptionSpec(std::string_view name);
// `name` as front-end `fe` spells it: "--clear-depth" or "clear_depth"; a flag whose CLI form
// turns it off is named by that form ("--no-depth-test").
std::string spelled(std::string_view name, FrontEnd fe);

// The one-letter edits (insertions, deletions, changes) from a to b: how near an unknown name
// is to a known one, for the front-ends' "did you mean".
std::size_t editDistance(std::string_view a, std::string_view b);

using OptionValue = std::variant<bool, std::int64_t, double, std::string, std::vector<double>>;

// The values one front-end was given; each is checked as it is set (hsr::Error with one line
// naming the option as that front-end spells it), the rest when the options or the camera are
// made (how the given values combine).
class OptionRequest {
 public:
  explicit OptionRequest(FrontEnd fe) : fe_(fe) {}
  FrontEnd frontEnd() const { return fe_; }

  // A typed value: a bool for a flag, a whole number for an integer (or a number with no
  // fraction), a number, a string for a name or text, numbers for a vector. An unknown name
  // is refused with the nearest known one.
  void set(std::string_view name, const OptionValue& value);
  // Text as typed on a command line, read by the option's kind ("1,2,3", "WxH", "4", "true").
  void setText(std::string_view name, std::string_view text);
  // The command line's files, read and parsed by it: `label` names the file in messages.
  void setCameraFile(std::string label, const Camera& camera);
  void setPoseFile(std::string label, const glm::dmat4& camera_to_world);

  bool given(std::string_view name) const { return values_.count(std::string(name)) > 0; }
  // The size given, if one was.
  bool size(int* width, int* height) const;
  // Text as help shows it: the value given, else the default.
  std::string text(std::string_view name) const;

  // The render state (from the defaults of RenderOptions where nothing was given).
  RenderOptions options() const;
  // The camera for `scene` (fitted to it where not given); `scene_label` names the scene in
  // messages.
  Camera camera(const Scene& scene, std::string_view scene_label) const;

 private:
  std::string name(std::string_view option) const { return spelled(option, fe_); }
  // Checks `value` against the table and keeps it; `got` is how a message quotes it.
  void put(const OptionSpec& spec, const OptionValue& value, const std::string& got);
  const OptionValue* value(std::string_view option) const;
  void checkFrameable(const Scene& scene, std::string_view label) const;
  Camera cameraFromFile() const;

  FrontEnd fe_;
  std::map<std::string, OptionValue, std::less<>> values_;
  Camera file_camera_;
  std::string file_camera_label_, pose_label_;
  glm::dmat4 pose_{1.0};
};

}  // namespace hsr

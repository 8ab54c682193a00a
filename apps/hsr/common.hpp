#pragma once
// What the verbs of `hsr` share: one-line errors, the check of a run's outputs before any work,
// warnings about a view, and the summary of a rendered frame.

#include <algorithm>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include <fmt/core.h>

#include "hsr/error.hpp"
#include "hsr/output.hpp"

#include "hsr/camera.hpp"
#include "hsr/io.hpp"
#include "hsr/render.hpp"
#include "hsr/scene.hpp"

namespace CLI {
class App;
}

namespace hsr::cli {

// Every option of `app` and its subcommands that takes a value refuses one that is a flag
// (`--stats --quiet` names no file called --quiet; `--eye -1,2,3` is still a value).
void refuseFlagsAsValues(CLI::App* app);
// Option values that are names (--cull BACK, --algorithm ZBuffer, --output Depth) are taken in
// any case: one rule for every option, as OpenGL's names read in either.
void lowercaseNameValues(CLI::App* app);
// "did you mean --size?" for a token of argv that names no option of `app` but is near one
// (edit distance at most 2); empty when none is.
std::string nearMissHint(CLI::App* app, int argc, const char* const* argv);
// `--eye 1 2 3`: the hint to join a vector's coordinates with commas (empty when none applies)
std::string commaHint(int argc, const char* const* argv);
// A parse error in words: an option given more times than it takes named with its count,
// not in the parser's terms ("At Most 1 required but received 2")
std::string plainParseMessage(std::string_view what);
// `hsr rendr`: a first argument that is no verb, no file and no built-in scene, but within two
// edits of a verb, gives "did you mean render?" (otherwise it would be read as a scene's name)
std::string verbMissHint(std::string_view first, const std::vector<std::string_view>& verbs);

namespace fs = std::filesystem;

// A message as one line on a terminal: control characters shown escaped, never acted on.
std::string printable(std::string_view s);
// "hsr: MESSAGE" on stderr, one line.
void printError(std::string_view message);

// The outputs of one run, checked before any work: no empty name, no output that is the input
// model or another output of the run, no file inside a directory that is replaced as a whole.
class OutputPlan {
 public:
  explicit OutputPlan(const std::string& scene) {
    std::error_code ec;
    if (fs::is_regular_file(scene, ec)) input_ = key(scene);
  }
  void file(std::string_view option, const std::string& path) {
    if (path.empty()) throw hsr::Error(fmt::format("{} \"\": an empty path names no file", option));
    add(option, path, false);
  }
  void directory(std::string_view option, const std::string& path,
                 const std::vector<std::string>& own_names = {}) {
    if (path.empty())
      throw hsr::Error(fmt::format("{} \"\": an empty path names no directory", option));
    add(option, path, true);
    hsr::checkOutputDirectory(path, own_names);
  }

 private:
  static fs::path key(const fs::path& p) {
    std::error_code ec;
    fs::path k = fs::weakly_canonical(fs::absolute(p), ec);
    return ec ? fs::absolute(p).lexically_normal() : k;
  }
  static bool inside(const fs::path& p, const fs::path& dir) {
    const auto [d, q] = std::mismatch(dir.begin(), dir.end(), p.begin(), p.end());
    return d == dir.end() && q != p.end();
  }
  void add(std::string_view option, const std::string& path, bool is_directory) {
    const fs::path k = key(path);
    if (!input_.empty() && (k == input_ || (is_directory && inside(input_, k))))
      throw hsr::Error(fmt::format("{} {}: {} the input model; refused, it would be overwritten",
                                   option, path, k == input_ ? "is" : "holds"));
    for (const Planned& o : planned_) {
      if (o.key == k)
        throw hsr::Error(
            fmt::format("{} {} and {} {} name the same output", o.option, o.path, option, path));
      if ((o.is_directory && inside(k, o.key)) || (is_directory && inside(o.key, k)))
        throw hsr::Error(
            fmt::format("{} {} lies inside {} {}, a directory that is replaced as a whole",
                        o.is_directory ? option : o.option, o.is_directory ? path : o.path,
                        o.is_directory ? o.option : option, o.is_directory ? o.path : path));
    }
    planned_.push_back({std::string(option), path, k, is_directory});
  }
  struct Planned {
    std::string option, path;
    fs::path key;
    bool is_directory;
  };
  fs::path input_;
  std::vector<Planned> planned_;
};

// A file name's stem, or a built-in scene's spec, made safe as a file name.
std::string sceneLabel(const std::string& spec);
// Refuses an output name whose extension says another format than the one written there:
// `-o model.pdf` for an SVG. A name without an extension (a device, a pipe) is taken as given.
// `extension` is lower case with its dot (".svg"); `what` names the format ("SVG drawings").
void requireExtension(std::string_view option, const std::string& path, std::string_view extension,
                      std::string_view what);
void warnIfEyeInside(const hsr::Scene& scene, const hsr::Camera& cam);
bool depthUnresolvable(const hsr::Camera& cam);  // far/near past what a float depth buffer resolves
bool warnIfDepthUnresolvable(const hsr::Camera& cam);  // true when it warned
// Refuses (hsr::Error) a frame in which nothing was drawn because every depth rounded to the
// clear value (depthUnresolvable), instead of writing an empty picture.
void refuseIfNothingResolved(const hsr::Frame& frame, const hsr::Camera& cam);
std::vector<std::string> splitList(const std::string& s);
void warnIfUnresolved(const hsr::Frame& f, const std::string& algorithm);
// The frame's counts and stage times, and the camera used when given (its intrinsics too).
// A legend in the bottom-right corner of the depth and overdraw pictures (the ramp and the
// values at its ends: window depth, fragments), where the picture has room for it.
void addLegend(const hsr::Frame& frame, std::string_view kind, std::vector<std::uint8_t>& rgb,
               const hsr::Camera& camera, hsr::DepthKind depth);
// When no pixel shows a polygon: a warning on stderr saying why (all culled, clipped, too
// small, or the depth function against the clear depth).
void warnIfNothingDrawn(const hsr::Frame& frame, const hsr::RenderOptions& options);
void printSummary(const hsr::Frame& f, const std::string& scene, const std::string& algorithm,
                  const std::vector<std::string>& written, const hsr::Camera* camera = nullptr);

}  // namespace hsr::cli

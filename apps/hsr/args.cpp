// The command line's view arguments: parsing and conversion (see args.hpp).

#include "args.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <utility>

#include <fmt/core.h>
#include <unistd.h>

#include "hsr/error.hpp"
#include "hsr/io.hpp"

namespace hsr::cli {

namespace fs = std::filesystem;

bool Args::given(std::string_view name) const {
  const auto it = option_text.find(name);
  return it != option_text.end() && !it->second.empty();
}

std::string Args::text(std::string_view name) const {
  if (given(name)) return option_text.find(name)->second;
  const hsr::OptionSpec* spec = hsr::findOptionSpec(name);
  return spec ? std::string(spec->default_text) : std::string();
}

void parseImageSize(const std::string& s, int* w, int* h) {
  hsr::OptionRequest r(hsr::FrontEnd::kCli);
  r.setText("size", s);
  r.size(w, h);
}

std::string readUserFile(const std::string& path, const char* option, std::uintmax_t limit) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) {
    if (ec &&
        ec != std::errc::no_such_file_or_directory)  // a loop of links, a folder it may not search
      throw hsr::Error(fmt::format("{} {}: {}", option, path, ec.message()));
    throw hsr::Error(fmt::format("{} {}: no such file", option, path));
  }
  if (!fs::is_regular_file(st)) {
    const char* what = fs::is_directory(st)        ? "a directory"
                       : fs::is_character_file(st) ? "a character device"
                       : fs::is_block_file(st)     ? "a block device"
                       : fs::is_fifo(st)           ? "a FIFO"
                       : fs::is_socket(st)         ? "a socket"
                                                   : "not a regular file";
    throw hsr::Error(fmt::format("{} {}: {}, not a file; name a file", option, path, what));
  }
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (ec || bytes > limit)
    throw hsr::Error(fmt::format("{} {}: {} (the limit is {} MiB)", option, path,
                                 ec ? "cannot read its size" : "too large", limit >> 20));
  std::ifstream in(path, std::ios::binary);
  std::string text(static_cast<std::size_t>(bytes), '\0');
  if (!in.read(text.data(), static_cast<std::streamsize>(text.size())))
    throw hsr::Error(fmt::format("{} {}: cannot be read", option, path));
  return text;
}

hsr::OptionRequest requestOf(const Args& a) {
  hsr::OptionRequest r(hsr::FrontEnd::kCli);
  for (const hsr::OptionSpec& spec : hsr::optionSpecs()) {
    if (!a.given(spec.name)) continue;
    const std::string& text = a.option_text.find(spec.name)->second;
    if (spec.name == "camera") {
      const std::string json = readUserFile(text, "--camera", 16u << 20);  // names itself
      try {
        r.setCameraFile(text, hsr::cameraFromJson(json));
      } catch (const hsr::Error& e) {
        throw hsr::Error(fmt::format("--camera {}: {}", text, e.what()));
      }
    } else if (spec.name == "pose") {
      const std::string matrix = readUserFile(text, "--pose", 1u << 20);  // names itself
      try {
        r.setPoseFile(text, hsr::poseFromText(matrix));
      } catch (const hsr::Error& e) {
        throw hsr::Error(fmt::format("--pose {}: {}", text, e.what()));
      }
    } else {
      r.setText(spec.name, text);
    }
  }
  return r;
}

hsr::Camera makeCamera(const Args& a, const hsr::Scene& scene) {
  return requestOf(a).camera(scene, a.scene);
}

hsr::RenderOptions makeOptions(const Args& a) { return requestOf(a).options(); }

namespace {

// The table's options that `keep` picks, as CLI11 options writing into a.option_text: a flag
// that is on by default as the flag that turns it off (--no-depth-test, --flat).
void addTableOptions(CLI::App* app, Args& a, bool (*keep)(const hsr::OptionSpec&)) {
  for (const hsr::OptionSpec& spec : hsr::optionSpecs()) {
    if (!spec.offeredBy(hsr::FrontEnd::kCli) || !keep(spec)) continue;
    const std::string flag = hsr::spelled(spec.name, hsr::FrontEnd::kCli);
    std::string& text = a.option_text[std::string(spec.name)];
    if (spec.kind == hsr::OptionKind::kFlag) {
      const std::string value = spec.default_text == "true" ? "false" : "true";
      app->add_flag_callback(
          flag, [&text, value] { text = value; }, std::string(spec.help));
      continue;
    }
    CLI::Option* o = app->add_option(flag, text, std::string(spec.help));
    switch (spec.kind) {
      case hsr::OptionKind::kInteger:
        o->type_name("INT");
        break;
      case hsr::OptionKind::kNumber:
        o->type_name("NUMBER");
        break;
      case hsr::OptionKind::kVector:
        o->type_name(spec.name == "size" ? "WxH" : spec.count == 3 ? "X,Y,Z" : "FX,FY,CX,CY");
        break;
      case hsr::OptionKind::kFile:
        o->type_name("FILE");
        break;
      default:
        o->type_name("NAME");
        break;
    }
    if (!spec.default_text.empty()) o->default_str(std::string(spec.default_text));
  }
}

bool isBspBuild(const hsr::OptionSpec& s) { return s.name.starts_with("bsp_"); }
bool isViewOrRender(const hsr::OptionSpec& s) { return !isBspBuild(s); }

}  // namespace

void addBspBuildOptions(CLI::App* app, Args& a) { addTableOptions(app, a, isBspBuild); }

void addViewOptions(CLI::App* app, Args& a) {
  app->add_option(
         "scene", a.scene,
         "mesh file (OBJ, PLY, STL, OFF, glTF, ...), a Doom map (FILE.wad:MAP01) or built-in scene")
      ->capture_default_str();
  addTableOptions(app, a, isViewOrRender);
  app->add_flag("--allow-outside-refs", a.allow_outside_refs,
                "let a model read files it references outside its own folder (mtllib, buffers)");
  addBspBuildOptions(app, a);
}

hsr::ImportLimits importLimits(const Args& a) {
  hsr::ImportLimits limits;
  limits.allow_outside_references = a.allow_outside_refs;
  // A long import shows how long it has run on a terminal (from its first second on)
  if (!a.quiet && ::isatty(STDERR_FILENO)) {
    const std::string name = fs::path(a.scene).filename().string();
    limits.progress = [name, shown = false](double seconds, std::uint64_t bytes,
                                            bool done) mutable {
      if (seconds < 1.0 && !shown) return;
      shown = true;
      fmt::print(
          stderr, "\r  importing {}: {:.1f} s{}{}", name, seconds,
          bytes > 0 ? fmt::format(", {:.0f} MiB received", bytes / 1048576.0) : std::string(),
          done ? "\n" : "");
    };
  }
  return limits;
}

}  // namespace hsr::cli

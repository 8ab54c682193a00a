// The layout of src/ (docs/architecture.md): each layer includes only itself and the layers
// below it, so the ground floor knows no stage and no arrow runs back up.
//   core < geometry < raster < pipeline < visibility < the orchestrator (src/*.cpp, *.hpp)
//   io stands at the side, on core alone. The two wings: doom (a WAD's maps, their 2D BSP, the
//   column view) on visibility and io; lines (the hidden-line drawings) on the orchestrator.
//   explain stands on the orchestrator and the doom wing; nothing below includes a wing.
// Public headers (include/hsr/) are the API and may be included anywhere.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>

namespace hsr {
namespace {

namespace fs = std::filesystem;

const std::map<std::string, std::set<std::string>>& allowed() {
  static const std::map<std::string, std::set<std::string>> m = {
      {"core", {"core"}},
      {"geometry", {"core", "geometry"}},
      {"raster", {"core", "geometry", "raster"}},
      {"pipeline", {"core", "geometry", "raster", "pipeline"}},
      {"visibility", {"core", "geometry", "raster", "pipeline", "visibility"}},
      {"io", {"core", "io"}},
      {"doom", {"core", "geometry", "raster", "pipeline", "visibility", "io", "doom"}},
      {"/", {"core", "geometry", "raster", "pipeline", "visibility", "io", "/"}},
      {"lines", {"core", "geometry", "raster", "pipeline", "visibility", "io", "/", "lines"}},
      {"explain", {"core", "explain", "/", "doom"}},
  };
  return m;
}

// The layer of a path relative to src/: its first folder, or "/" for files directly in src/.
std::string layerOf(const fs::path& rel) {
  return rel.has_parent_path() ? rel.begin()->string() : "/";
}

TEST(Layering, EveryIncludeRunsDownOrSideways) {
  const fs::path src = fs::path(HSR_SOURCE_DIR) / "src";
  ASSERT_TRUE(fs::is_directory(src)) << src;
  const std::regex include_re("^\\s*#\\s*include\\s+\"([^\"]+)\"");
  int files = 0, includes = 0;
  std::set<std::string> layers_seen;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(src)) {
    if (!e.is_regular_file()) continue;
    const fs::path rel = fs::relative(e.path(), src);
    const std::string layer = layerOf(rel);
    ASSERT_TRUE(allowed().count(layer)) << rel << ": a folder the layout does not name";
    layers_seen.insert(layer);
    ++files;
    std::ifstream in(e.path());
    std::string line;
    while (std::getline(in, line)) {
      std::smatch m;
      if (!std::regex_search(line, m, include_re)) continue;
      const fs::path target(m[1].str());
      if (*target.begin() == "hsr") continue;  // the public API
      ++includes;
      const std::string to = layerOf(target);
      EXPECT_TRUE(allowed().at(layer).count(to))
          << rel.string() << " (" << layer << ") includes " << target.string() << " (" << to << ")";
    }
  }
  EXPECT_GT(files, 40);
  EXPECT_GT(includes, 60);
  EXPECT_EQ(layers_seen.size(), allowed().size()) << "a layer of the layout has no file";
}

}  // namespace
}  // namespace hsr

// Stats: the one table of counts, and merging by it.

#include "hsr/stats.hpp"

#include <array>

namespace hsr {

std::span<const Stats::Field> Stats::fields() {
  static constexpr std::array<Field, 17> kFields = {{
      {"polygons_in", &Stats::polygons_in, "polygons of the scene"},
      {"triangles_in", &Stats::triangles_in, "triangles after triangulating the polygons"},
      {"degenerate_dropped", &Stats::degenerate_dropped,
       "triangles of polygons with zero area or non-finite vertices"},
      {"culled_frustum", &Stats::culled_frustum,
       "triangles of objects whose bounds lie outside the view"},
      {"clipped", &Stats::clipped, "triangles that crossed a clip plane"},
      {"clipped_added", &Stats::clipped_added, "triangles made by clipping, beyond those cut"},
      {"clipped_away", &Stats::clipped_away, "triangles entirely outside the view volume"},
      {"culled_backface", &Stats::culled_backface, "triangles removed by the cull mode"},
      {"zero_area", &Stats::zero_area, "triangles of zero area once snapped to the grid"},
      {"missed_pixel_centres", &Stats::missed_pixel_centres,
       "triangles whose bounding box holds no pixel centre"},
      {"triangles_rasterized", &Stats::triangles_rasterized,
       "triangles handed to the visibility algorithm"},
      {"lines_rasterized", &Stats::lines_rasterized, "LINE mode: polygon edges handed over"},
      {"points_rasterized", &Stats::points_rasterized, "POINT mode: vertices handed over"},
      {"outline_edges", &Stats::outline_edges, "silhouette and border edges drawn"},
      {"fragments_tested", &Stats::fragments_tested, "pixel samples that reached the depth test"},
      {"fragments_written", &Stats::fragments_written, "samples that passed and were written"},
      {"state_bytes", &Stats::state_bytes, "bytes of memory held by the algorithm"},
  }};
  return kFields;
}

void Stats::addStage(std::string name, double ms) {
  for (StageTime& s : stages) {
    if (s.name == name) {
      s.ms += ms;
      return;
    }
  }
  stages.push_back({std::move(name), ms});
}

void Stats::addCounter(std::string_view name, std::uint64_t n) {
  for (Counter& c : counters) {
    if (c.name == name) {
      c.value += n;
      return;
    }
  }
  counters.push_back({std::string(name), n});
}

std::uint64_t Stats::counter(std::string_view name) const {
  for (const Counter& c : counters)
    if (c.name == name) return c.value;
  return 0;
}

double Stats::totalMs() const {
  double t = 0.0;
  for (const StageTime& s : stages) t += s.ms;
  return t;
}

void Stats::merge(const Stats& other) {
  for (const Field& f : fields()) this->*f.value += other.*f.value;
  for (const Counter& c : other.counters) addCounter(c.name, c.value);
  for (const StageTime& s : other.stages) addStage(s.name, s.ms);
}

}  // namespace hsr

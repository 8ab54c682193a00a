#pragma once
// Stats: what one render did, counted and timed. Every count has a name and a stated unit in
// one table (Stats::fields()), which merging, the JSON writer and the CLI summary all loop
// over, so a count added here reaches each of them.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hsr {

struct StageTime {
  std::string name;
  double ms = 0.0;
};

// A count of an algorithm's own (BSP nodes, splits, subdivisions...).
struct Counter {
  std::string name;
  std::uint64_t value = 0;
};

struct Stats {
  // Where every triangle went. All these are TRIANGLES (a polygon of n vertices is n - 2 of
  // them; in LINE and POINT mode a polygon is judged whole and counts its n - 2), and they
  // add up:
  //   triangles_in + clipped_added = degenerate_dropped + culled_frustum + clipped_away
  //        + culled_backface + zero_area + missed_pixel_centres + triangles_rasterized
  std::uint64_t polygons_in = 0;           // polygons of the scene (the one count of polygons)
  std::uint64_t triangles_in = 0;          // after triangulating polygons
  std::uint64_t degenerate_dropped = 0;    // of polygons with zero area or non-finite vertices
  std::uint64_t culled_frustum = 0;        // of objects whose bounds lie outside the view
  std::uint64_t clipped = 0;               // crossed a clip plane (then counted by what is left)
  std::uint64_t clipped_added = 0;         // made by clipping: a triangle cut to k vertices is
                                           // k - 2 triangles, k - 3 more than went in
  std::uint64_t clipped_away = 0;          // entirely outside the view volume
  std::uint64_t culled_backface = 0;       // removed by the cull mode
  std::uint64_t zero_area = 0;             // zero area once snapped to the sub-pixel grid
  std::uint64_t missed_pixel_centres = 0;  // no pixel centre inside their bounding box
  std::uint64_t triangles_rasterized = 0;  // handed to the visibility algorithm
  std::uint64_t lines_rasterized = 0;      // LINE mode: polygon edges handed over
  std::uint64_t points_rasterized = 0;     // POINT mode: polygon vertices handed over
  std::uint64_t outline_edges = 0;         // silhouette and border edges drawn (--outline)
  // The visibility algorithm.
  std::uint64_t fragments_tested = 0;   // pixel samples that reached the depth test
  std::uint64_t fragments_written = 0;  // samples that passed and were written
  std::uint64_t state_bytes = 0;        // memory held by the algorithm's state
  std::vector<Counter> counters;        // the algorithm's own counts, by name
  std::vector<StageTime> stages;        // wall time per stage, in order

  void addStage(std::string name, double ms);
  void addCounter(std::string_view name, std::uint64_t n);
  std::uint64_t counter(std::string_view name) const;  // 0 when absent
  double totalMs() const;
  // Adds every count, counter and stage time of `other` (counters and stages by name).
  void merge(const Stats& other);

  // Every count, with its name (the JSON key) and what it counts, in the order above.
  struct Field {
    std::string_view name;
    std::uint64_t Stats::*value;
    std::string_view meaning;
  };
  static std::span<const Field> fields();
};

}  // namespace hsr

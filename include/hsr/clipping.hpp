#pragma once
// Weiler-Atherton polygon clipping: A∩B, A∪B, A−B and B−A of two regions bounded by polygons,
// convex or concave, with holes, decided exactly.
//
// Input: polygons on an integer grid (|x|, |y| <= kClipCoordinateLimit; hsr's window
// coordinates snapped to 1/256 pixel fit it with room to spare), or results of earlier
// operations on such polygons (exact regions, which carry each edge's line: see ExactPoint). A
// region is a set of polygons with holes whose interiors do not overlap; rings are simple and may
// touch one another only at points, never cross or run along one another; outer rings may be given
// either way round, and are made counter-clockwise, holes clockwise. invalidRegionReason() says
// what is wrong with a region that is not valid; booleanOp() assumes a valid one (it never crashes
// or loops on an invalid one, but its answer is then unspecified).
//
// Exactness: every decision (does a vertex lie on an edge, do two edges cross, which side of a
// boundary a piece lies on, which way a ring turns) is an exact sign in integer arithmetic.
// Vertices of a result are input vertices, or crossings of an edge of A with an edge of B,
// which are kept as exact rationals (x / d, y / d): nothing is rounded, so on integer input
// the areas of the results are exact, and area(A∩B) + area(A−B) = area(A) holds exactly.
//
// Output: simple rings, outer rings counter-clockwise (y up), holes clockwise, each hole under
// the outer ring that contains it; a ring passes each point at most once (regions that touch
// at a point come out as separate rings touching there); no vertex where the boundary runs
// straight on. Degenerate pieces (a polygon clipped by itself, collinear overlapping edges,
// touching at one point, one polygon inside the other, empty results) are decided exactly.
//
// Cost: O((n + m + k) log(n + m + k) + n m) for n and m vertices and k crossings (every pair of
// edges whose boxes overlap is tested), and memory linear in n + m + k.

#include <cstdint>
#include <string>
#include <vector>

namespace hsr {

inline constexpr std::int64_t kClipCoordinateLimit = std::int64_t{1} << 28;

struct GridPoint {
  std::int64_t x = 0, y = 0;
  bool operator==(const GridPoint&) const = default;
};
using GridRing = std::vector<GridPoint>;
struct GridPolygon {
  GridRing outer;
  std::vector<GridRing> holes;
};
using GridRegion = std::vector<GridPolygon>;

// A vertex of an exact region: (x / d, y / d) exactly, d > 0 (d = 1 for a grid point), and
// the line a x + b y + c = 0 that the ring's edge from this vertex to the next lies on, with
// the region on its left (a x + b y + c > 0 there). Every line is one through two grid points
// within the limit (|a|, |b| <= 2^29, |c| <= 2^58) and every vertex the crossing of two such
// lines (|x|, |y| < 2^89, d < 2^60): results of booleanOp() are, so they can be clipped again
// without rounding, as the hidden-surface algorithm does.
namespace detail {
// The double nearest to n / d (d > 0), ties to even: computed in integers, so it is the same
// on every platform (long double, which this once used, has 64 bits of mantissa on x86-64 and
// 113 in WebAssembly, and rounding through it twice differed between the two).
double nearestQuotient(__int128 n, std::int64_t d);
}  // namespace detail

struct ExactPoint {
  __int128 x = 0, y = 0;
  std::int64_t d = 1;
  std::int64_t a = 0, b = 0, c = 0;
  double xd() const { return detail::nearestQuotient(x, d); }  // x / d, rounded once
  double yd() const { return detail::nearestQuotient(y, d); }
};
using ExactRing = std::vector<ExactPoint>;
struct ExactPolygon {
  ExactRing outer;
  std::vector<ExactRing> holes;
};
using ExactRegion = std::vector<ExactPolygon>;

enum class BooleanOp { Intersection, Union, AMinusB, BMinusA };
const char* booleanOpName(BooleanOp op);  // "A∩B", "A∪B", "A−B", "B−A"

// Empty when `region` is valid input; otherwise one line naming the first fault found (the
// polygon, ring and vertex or edges). O(e²) for e edges in all.
std::string invalidRegionReason(const GridRegion& region);

// A op B, by Weiler-Atherton (see the top of this file).
ExactRegion booleanOp(const GridRegion& a, const GridRegion& b, BooleanOp op);
// The same on exact regions: results of booleanOp(), or grid regions through exactRegion().
// Rings obey the rules above (simple, touching only at points) and carry their edges' lines.
ExactRegion booleanOp(const ExactRegion& a, const ExactRegion& b, BooleanOp op);

// A grid region as an exact one: each edge's line through its two ends.
ExactRegion exactRegion(const GridRegion& region);

// Empty when the exact region's numbers are in range and each vertex lies on the lines of
// both its edges; otherwise one line saying where not. O(e) (it does not look for crossings:
// results of booleanOp() have none).
std::string invalidRegionReason(const ExactRegion& region);

// Area, holes subtracted: exactly, as a reduced fraction "p/q" (or "p" when whole); and in
// double. Exact areas use GMP.
std::string exactArea(const ExactRegion& region);
std::string exactArea(const GridRegion& region);
double area(const ExactRegion& region);

}  // namespace hsr

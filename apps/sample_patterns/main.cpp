// hsr_sample_patterns: how the A-buffer's 32- and 64-sample patterns (src/raster/samples.cpp)
// were found. Points in a pixel are placed to make the share of samples on one side of a
// straight edge close to the share of the pixel's area there, on average over random edges
// (Dobkin & Mitchell 1993, "Random-edge discrepancy of supersampling patterns"): simulated
// annealing on the 1/256 sub-pixel grid, from the Hammersley points, against a fixed set of
// random edges, then measured on other edges. A second stage, when asked for, anneals the
// result further against what the A-buffer test measures: the pixels that random triangles 2 to
// 12 pixels across reach only in part, where |samples covered / n - area covered| is the error.
//
//   hsr_sample_patterns N [ITERATIONS] [EDGES] [SEED] [TEMPERATURE]
//                         [TRIANGLE_ITERATIONS TRIANGLE_PIXELS TRIANGLE_SEED TRIANGLE_TEMPERATURE]
//
// prints the error before and after each stage (on 200,000 fresh edges, and on the partly
// covered pixels of fresh triangles) and the pattern as offsets from the pixel centre in 1/256
// pixel.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

namespace {

constexpr int kGrid = 256;  // sub-pixel units per pixel

// A straight edge through the unit pixel: the side nx * x + ny * y < d, and its area there.
struct Edge {
  double nx, ny, d, area;
};

// The area of the unit square where nx * x + ny * y < d (the square clipped by the half-plane).
double areaBelow(double nx, double ny, double d) {
  const double sx[4] = {0, 1, 1, 0}, sy[4] = {0, 0, 1, 1};
  double px[8], py[8];
  int m = 0;
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    const double fi = nx * sx[i] + ny * sy[i] - d, fj = nx * sx[j] + ny * sy[j] - d;
    if (fi < 0) px[m] = sx[i], py[m] = sy[i], ++m;
    if ((fi < 0) != (fj < 0)) {
      const double t = fi / (fi - fj);
      px[m] = sx[i] + t * (sx[j] - sx[i]), py[m] = sy[i] + t * (sy[j] - sy[i]), ++m;
    }
  }
  double a = 0;
  for (int i = 0; i < m; ++i) a += px[i] * py[(i + 1) % m] - px[(i + 1) % m] * py[i];
  return std::abs(a) / 2;
}

// Edges of uniformly random direction and offset that cross the pixel.
std::vector<Edge> randomEdges(int count, unsigned seed) {
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Edge> edges;
  while (static_cast<int>(edges.size()) < count) {
    const double angle = u(g) * 2 * std::numbers::pi, nx = std::cos(angle), ny = std::sin(angle);
    const double lo = std::min({0.0, nx, ny, nx + ny}), hi = std::max({0.0, nx, ny, nx + ny});
    const double d = lo + u(g) * (hi - lo);
    edges.push_back({nx, ny, d, areaBelow(nx, ny, d)});
  }
  return edges;
}

struct Point {
  int x, y;  // in 1/256 pixel from the pixel's corner, 1..255 (never on its border)
};

bool below(const Edge& e, Point p) { return e.nx * p.x / kGrid + e.ny * p.y / kGrid < e.d; }

double meanError(const std::vector<Point>& pts, const std::vector<Edge>& edges) {
  double sum = 0;
  for (const Edge& e : edges) {
    int c = 0;
    for (const Point& p : pts) c += below(e, p);
    sum += std::abs(static_cast<double>(c) / static_cast<double>(pts.size()) - e.area);
  }
  return sum / static_cast<double>(edges.size());
}

// A pixel (the unit square) that a triangle covers in part: inside where a[k] x + b[k] y + c[k]
// >= 0 for k = 0, 1, 2, and the area covered.
struct TrianglePixel {
  double a[3], b[3], c[3], area;
};

double clippedArea(const TrianglePixel& t) {
  std::vector<std::pair<double, double>> poly{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int k = 0; k < 3 && !poly.empty(); ++k) {
    std::vector<std::pair<double, double>> out;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const auto p = poly[i], q = poly[(i + 1) % poly.size()];
      const double fp = t.a[k] * p.first + t.b[k] * p.second + t.c[k],
                   fq = t.a[k] * q.first + t.b[k] * q.second + t.c[k];
      if (fp >= 0) out.push_back(p);
      if ((fp >= 0) != (fq >= 0)) {
        const double s = fp / (fp - fq);
        out.push_back({p.first + s * (q.first - p.first), p.second + s * (q.second - p.second)});
      }
    }
    poly = std::move(out);
  }
  double s = 0;
  for (std::size_t i = 0; i < poly.size(); ++i)
    s += poly[i].first * poly[(i + 1) % poly.size()].second -
         poly[(i + 1) % poly.size()].first * poly[i].second;
  return std::abs(s) / 2;
}

// The partly covered pixels of random triangles 2 to 12 pixels across, until there are `want`.
std::vector<TrianglePixel> trianglePixels(int want, unsigned seed) {
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(-0.5, 0.5), size_of(2, 12);
  std::vector<TrianglePixel> pixels;
  while (static_cast<int>(pixels.size()) < want) {
    const double size = size_of(g);
    double x[3], y[3];
    for (int i = 0; i < 3; ++i) x[i] = 20 + u(g) * size, y[i] = 20 + u(g) * size;
    const double twice_area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    if (std::abs(twice_area) < 1e-9) continue;
    if (twice_area < 0) std::swap(x[1], x[2]), std::swap(y[1], y[2]);
    const int x0 = static_cast<int>(std::floor(std::min({x[0], x[1], x[2]}))),
              x1 = static_cast<int>(std::floor(std::max({x[0], x[1], x[2]})));
    const int y0 = static_cast<int>(std::floor(std::min({y[0], y[1], y[2]}))),
              y1 = static_cast<int>(std::floor(std::max({y[0], y[1], y[2]})));
    for (int py = y0; py <= y1; ++py)
      for (int px = x0; px <= x1; ++px) {
        TrianglePixel t;
        for (int k = 0; k < 3; ++k) {  // edge k in the pixel's own coordinates, inside >= 0
          const double ax = x[k] - px, ay = y[k] - py, bx = x[(k + 1) % 3] - px,
                       by = y[(k + 1) % 3] - py;
          t.a[k] = -(by - ay), t.b[k] = bx - ax, t.c[k] = -(t.a[k] * ax + t.b[k] * ay);
        }
        t.area = clippedArea(t);
        if (t.area > 0 && t.area < 1 - 1e-12) pixels.push_back(t);
      }
  }
  return pixels;
}

bool covers(const TrianglePixel& t, Point p) {
  const double x = static_cast<double>(p.x) / kGrid, y = static_cast<double>(p.y) / kGrid;
  for (int k = 0; k < 3; ++k)
    if (t.a[k] * x + t.b[k] * y + t.c[k] < 0) return false;
  return true;
}

double meanError(const std::vector<Point>& pts, const std::vector<TrianglePixel>& pixels) {
  double sum = 0;
  for (const TrianglePixel& t : pixels) {
    int c = 0;
    for (const Point& p : pts) c += covers(t, p);
    sum += std::abs(static_cast<double>(c) / static_cast<double>(pts.size()) - t.area);
  }
  return sum / static_cast<double>(pixels.size());
}

// Simulated annealing of the points against a fixed set of cases: `inside(case, point)` says
// whether the point counts for the case, `target(case)` the share it should have.
template <class Case, class Inside>
void anneal(std::vector<Point>& pts, const std::vector<Case>& cases, Inside inside, int iterations,
            unsigned seed, double temperature, int max_step) {
  const int n = static_cast<int>(pts.size());
  std::vector<int> count(cases.size());
  for (std::size_t k = 0; k < cases.size(); ++k)
    for (const Point& p : pts) count[k] += inside(cases[k], p);
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const double t0 = temperature * 0.02 * static_cast<double>(cases.size()) / n;
  std::vector<std::pair<std::size_t, int>> changed;
  for (int it = 0; it < iterations; ++it) {
    // Move one point a few units; keep the move if the error falls, or by chance (less and
    // less often) if it rises
    const double t = t0 * (1.0 - static_cast<double>(it) / iterations);
    Point& p = pts[g() % static_cast<unsigned>(n)];
    const int step = 1 + static_cast<int>(g() % static_cast<unsigned>(max_step));
    const Point q{std::clamp(p.x + static_cast<int>(g() % (2 * step + 1)) - step, 1, kGrid - 1),
                  std::clamp(p.y + static_cast<int>(g() % (2 * step + 1)) - step, 1, kGrid - 1)};
    double delta = 0;
    changed.clear();
    for (std::size_t k = 0; k < cases.size(); ++k) {
      const int before = inside(cases[k], p), after = inside(cases[k], q);
      if (before == after) continue;
      const int c = count[k] - before + after;
      delta += std::abs(static_cast<double>(c) / n - cases[k].area) -
               std::abs(static_cast<double>(count[k]) / n - cases[k].area);
      changed.push_back({k, c});
    }
    if (delta < 0 || (t > 0 && u(g) < std::exp(-delta / t))) {
      p = q;
      for (const auto& [k, c] : changed) count[k] = c;
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: hsr_sample_patterns N [ITERATIONS] [EDGES] [SEED] [TEMPERATURE] "
                 "[TRIANGLE_ITERATIONS TRIANGLE_PIXELS TRIANGLE_SEED TRIANGLE_TEMPERATURE]\n");
    return 2;
  }
  const int n = std::atoi(argv[1]);
  const int iterations = argc > 2 ? std::atoi(argv[2]) : 400000;
  const int edge_count = argc > 3 ? std::atoi(argv[3]) : 40000;
  const unsigned seed = argc > 4 ? static_cast<unsigned>(std::atoi(argv[4])) : 5;
  const double temperature = argc > 5 ? std::atof(argv[5]) : 1.0;
  int bits = 0;
  while ((1 << bits) < n) ++bits;
  if (n < 2 || n > 256 || (1 << bits) != n || iterations < 0 || edge_count < 1 ||
      (argc > 6 && argc < 10)) {
    std::fprintf(stderr,
                 "hsr_sample_patterns: N must be a power of two from 2 to 256 (and the triangle "
                 "stage takes 4 numbers)\n");
    return 2;
  }

  // Start: the Hammersley points, sample i at ((i + 1/2) / n, (reverse(i) + 1/2) / n)
  std::vector<Point> pts(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    int r = 0;
    for (int b = 0; b < bits; ++b) r |= ((i >> b) & 1) << (bits - 1 - b);
    pts[i] = {static_cast<int>(std::lround((i + 0.5) / n * kGrid)),
              static_cast<int>(std::lround((r + 0.5) / n * kGrid))};
  }
  const std::vector<Edge> train = randomEdges(edge_count, 1 + seed * 10),
                          test = randomEdges(200000, 2);
  std::printf("%d samples: Hammersley %.5f", n, meanError(pts, test));

  anneal(pts, train, below, iterations, seed, temperature, 12);
  std::printf(
      ", annealed %.5f (mean |share of samples - share of area| over 200,000 random edges; "
      "1/(2n) = %.5f)\n",
      meanError(pts, test), 0.5 / n);
  if (argc > 9) {
    // Second stage: the partly covered pixels of random triangles
    const int tri_iterations = std::atoi(argv[6]), tri_pixels = std::atoi(argv[7]);
    const unsigned tri_seed = static_cast<unsigned>(std::atoi(argv[8]));
    const double tri_temperature = std::atof(argv[9]);
    const std::vector<TrianglePixel> tri_train = trianglePixels(tri_pixels, 100 + tri_seed),
                                     tri_test = trianglePixels(200000, 7);
    std::printf("triangles' partly covered pixels: before %.5f", meanError(pts, tri_test));
    anneal(pts, tri_train, covers, tri_iterations, tri_seed, tri_temperature, 8);
    std::printf(
        ", annealed %.5f (mean |share of samples - area covered| over 200,000 fresh pixels)\n",
        meanError(pts, tri_test));
  }
  for (int i = 0; i < n; ++i)
    std::printf("{%d, %d},%s", pts[i].x - kGrid / 2, pts[i].y - kGrid / 2, i % 8 == 7 ? "\n" : " ");
  return 0;
}

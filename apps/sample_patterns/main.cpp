// hsr_sample_patterns: how the A-buffer's 32- and 64-sample patterns (src/raster/samples.cpp)
// were found. Points in a pixel are placed to make the share of samples on one side of a
// straight edge close to the share of the pixel's area there, on average over random edges
// (Dobkin & Mitchell 1993, "Random-edge discrepancy of supersampling patterns"): simulated
// annealing on the 1/256 sub-pixel grid, from the Hammersley points, against a fixed set of
// random edges, then measured on other edges.
//
//   hsr_sample_patterns N [ITERATIONS] [EDGES] [SEED] [TEMPERATURE]
//
// prints the error before and after (mean |share of samples - share of area| over 200,000
// fresh edges) and the pattern as offsets from the pixel centre in 1/256 pixel.

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

bool below(const Edge& e, Point p) {
  return e.nx * p.x / kGrid + e.ny * p.y / kGrid < e.d;
}

double meanError(const std::vector<Point>& pts, const std::vector<Edge>& edges) {
  double sum = 0;
  for (const Edge& e : edges) {
    int c = 0;
    for (const Point& p : pts) c += below(e, p);
    sum += std::abs(static_cast<double>(c) / static_cast<double>(pts.size()) - e.area);
  }
  return sum / static_cast<double>(edges.size());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: hsr_sample_patterns N [ITERATIONS] [EDGES] [SEED] [TEMPERATURE]\n");
    return 2;
  }
  const int n = std::atoi(argv[1]);
  const int iterations = argc > 2 ? std::atoi(argv[2]) : 400000;
  const int edge_count = argc > 3 ? std::atoi(argv[3]) : 40000;
  const unsigned seed = argc > 4 ? static_cast<unsigned>(std::atoi(argv[4])) : 5;
  const double temperature = argc > 5 ? std::atof(argv[5]) : 1.0;
  int bits = 0;
  while ((1 << bits) < n) ++bits;
  if (n < 2 || n > 256 || (1 << bits) != n || iterations < 0 || edge_count < 1) {
    std::fprintf(stderr, "hsr_sample_patterns: N must be a power of two from 2 to 256\n");
    return 2;
  }

  // Start: the Hammersley points, sample i at ((i + 1/2) / n, (reverse(i) + 1/2) / n)
  std::vector<Point> pts(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    int r = 0;
    for (int b = 0; b < bits; ++b) r |= ((i >> b) & 1) << (bits - 1 - b);
    pts[i] = {static_cast<int>(std::lround((i + 0.5) / n * kGrid)), static_cast<int>(std::lround((r + 0.5) / n * kGrid))};
  }
  const std::vector<Edge> train = randomEdges(edge_count, 1 + seed * 10), test = randomEdges(200000, 2);
  std::printf("%d samples: Hammersley %.5f", n, meanError(pts, test));

  // Anneal: move one point a few units; keep the move if the error over the training edges
  // falls, or by chance (less and less often) if it rises
  std::vector<int> count(train.size());
  for (std::size_t k = 0; k < train.size(); ++k)
    for (const Point& p : pts) count[k] += below(train[k], p);
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const double t0 = temperature * 0.02 * static_cast<double>(train.size()) / n;
  std::vector<std::pair<std::size_t, int>> changed;
  for (int it = 0; it < iterations; ++it) {
    const double t = t0 * (1.0 - static_cast<double>(it) / iterations);
    Point& p = pts[g() % static_cast<unsigned>(n)];
    const int step = 1 + static_cast<int>(g() % 12);
    const Point q{std::clamp(p.x + static_cast<int>(g() % (2 * step + 1)) - step, 1, kGrid - 1),
                  std::clamp(p.y + static_cast<int>(g() % (2 * step + 1)) - step, 1, kGrid - 1)};
    double delta = 0;
    changed.clear();
    for (std::size_t k = 0; k < train.size(); ++k) {
      const int before = below(train[k], p), after = below(train[k], q);
      if (before == after) continue;
      const int c = count[k] - before + after;
      delta += std::abs(static_cast<double>(c) / n - train[k].area) - std::abs(static_cast<double>(count[k]) / n - train[k].area);
      changed.push_back({k, c});
    }
    if (delta < 0 || (t > 0 && u(g) < std::exp(-delta / t))) {
      p = q;
      for (const auto& [k, c] : changed) count[k] = c;
    }
  }
  std::printf(", annealed %.5f (mean |share of samples - share of area| over 200,000 random edges; "
              "1/(2n) = %.5f)\n",
              meanError(pts, test), 0.5 / n);
  for (int i = 0; i < n; ++i) std::printf("{%d, %d},%s", pts[i].x - kGrid / 2, pts[i].y - kGrid / 2, i % 8 == 7 ? "\n" : " ");
  return 0;
}

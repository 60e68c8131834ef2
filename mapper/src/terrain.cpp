// fitTerrain: the progressive morphological filter on a grid of cell heights, harmonic filling,
// and the keyframes' bound (terrain.hpp).
#include "hullmap/mapper/terrain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "hullmap/core/error.hpp"

namespace hullmap::mapper {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

void checkParams(const TerrainParams& p) {
  const auto bad = [](const char* field, const std::string& what) { throw Error::inParameter(field, what); };
  if (!(p.cell > 0.0) || !std::isfinite(p.cell)) bad("cell", "must be finite and > 0");
  if (!(p.max_object > 0.0) || !std::isfinite(p.max_object)) bad("max_object", "must be finite and > 0");
  if (!(p.slope >= 0.0) || !std::isfinite(p.slope)) bad("slope", "must be finite and >= 0");
  if (!(p.initial_threshold >= 0.0) || !std::isfinite(p.initial_threshold))
    bad("initial_threshold", "must be finite and >= 0");
  if (!(p.max_threshold >= p.initial_threshold) || !std::isfinite(p.max_threshold))
    bad("max_threshold", "must be finite and >= initial_threshold");
  if (!(p.low_share >= 0.0 && p.low_share < 1.0)) bad("low_share", "must be in [0, 1)");
  if (!(p.keyframe_clearance >= 0.0) || !std::isfinite(p.keyframe_clearance))
    bad("keyframe_clearance", "must be finite and >= 0");
  if (p.min_support < 1) bad("min_support", "must be >= 1");
}

/// Minimum (erode) or maximum (dilate) over a square window of half side `r` cells, separable;
/// cells at +inf (erode) / -inf (dilate) take no part beyond what they are.
std::vector<double> windowed(const std::vector<double>& z, std::size_t nx, std::size_t ny, std::size_t r, bool min) {
  const auto pick = [min](double a, double b) { return min ? std::min(a, b) : std::max(a, b); };
  std::vector<double> rows(z.size()), out(z.size());
  for (std::size_t j = 0; j < ny; ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      double v = z[j * nx + i];
      for (std::size_t k = i > r ? i - r : 0; k <= std::min(nx - 1, i + r); ++k) v = pick(v, z[j * nx + k]);
      rows[j * nx + i] = v;
    }
  for (std::size_t j = 0; j < ny; ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      double v = rows[j * nx + i];
      for (std::size_t k = j > r ? j - r : 0; k <= std::min(ny - 1, j + r); ++k) v = pick(v, rows[k * nx + i]);
      out[j * nx + i] = v;
    }
  return out;
}

/// Fills every cell not `fixed` by the harmonic interpolation of the fixed ones (Jacobi iterations
/// of the 4-neighbour mean), starting from `z` (finite everywhere).
void harmonicFill(std::vector<double>& z, const std::vector<char>& fixed, std::size_t nx, std::size_t ny,
                  double tolerance) {
  std::vector<double> next = z;
  for (int iteration = 0; iteration < 20000; ++iteration) {
    double change = 0.0;
    for (std::size_t j = 0; j < ny; ++j)
      for (std::size_t i = 0; i < nx; ++i) {
        const std::size_t c = j * nx + i;
        if (fixed[c]) continue;
        double sum = 0.0;
        int n = 0;
        if (i > 0) sum += z[c - 1], ++n;
        if (i + 1 < nx) sum += z[c + 1], ++n;
        if (j > 0) sum += z[c - nx], ++n;
        if (j + 1 < ny) sum += z[c + nx], ++n;
        next[c] = n > 0 ? sum / n : z[c];
        change = std::max(change, std::abs(next[c] - z[c]));
      }
    z.swap(next);
    if (change < tolerance) return;
  }
}

}  // namespace

Terrain fitTerrain(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& keyframes,
                   const TerrainParams& params) {
  checkParams(params);
  if (points.empty()) throw Error("terrain: no point");
  for (const auto& p : points)
    if (!p.allFinite()) throw Error("terrain: non-finite point");
  // The grid spans the points' bulk in x and in y: SLAM's gross outliers, kilometres away, would
  // make it a grid of billions of cells.
  Eigen::Vector2d lo, hi;
  for (int a = 0; a < 2; ++a) {
    std::vector<double> v;
    v.reserve(points.size());
    for (const auto& p : points) v.push_back(p[a]);
    const auto at = [&](double q) {
      const auto k = std::size_t(std::floor(q * double(v.size() - 1)));
      std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
      return v[k];
    };
    // The 1 % to 99 % quantiles grown by a tenth of their span, within the 0.1 % to 99.9 % ones: a
    // map with more than 0.1 % of gross outliers (SLAM's, kilometres away) keeps its grid small.
    const double q1 = at(0.01), q99 = at(0.99), margin = 0.1 * (q99 - q1);
    lo[a] = std::max(at(0.001), q1 - margin);
    hi[a] = std::min(at(0.999), q99 + margin);
  }
  if ((hi - lo).maxCoeff() / params.cell > 1e5)
    throw Error("cell: " + std::to_string(params.cell) + " makes a grid of more than 100000 cells a side");
  for (const auto& k : keyframes)
    if (!k.allFinite()) throw Error("terrain: non-finite keyframe");
  Terrain t;
  HeightField& f = t.surface;
  f.step = params.cell;
  f.origin = lo;
  f.nx = std::size_t(std::floor((hi.x() - lo.x()) / f.step)) + 1;
  f.ny = std::size_t(std::floor((hi.y() - lo.y()) / f.step)) + 1;
  const std::size_t n = f.nx * f.ny;
  // 1. Each cell's low height.
  std::vector<std::vector<double>> in_cell(n);
  for (const auto& p : points) {
    if (p.x() < lo.x() || p.y() < lo.y() || p.x() > hi.x() || p.y() > hi.y()) continue;
    const auto i = std::min(f.nx - 1, std::size_t((p.x() - lo.x()) / f.step));
    const auto j = std::min(f.ny - 1, std::size_t((p.y() - lo.y()) / f.step));
    in_cell[j * f.nx + i].push_back(p.z());
  }
  std::vector<double> z(n, kInf);
  for (std::size_t c = 0; c < n; ++c) {
    auto& zs = in_cell[c];
    if (zs.empty()) continue;
    const std::size_t k = std::size_t(std::floor(params.low_share * double(zs.size())));
    std::nth_element(zs.begin(), zs.begin() + std::ptrdiff_t(k), zs.end());
    z[c] = zs[k];
  }
  // 1b. Low outliers: a cell deeper than initial_threshold + slope * cell below the second lowest
  // of its measured 8-neighbours (2 of them at least) keeps only its points above that depth. Not the
  // median: beside a building most neighbours are its roof.
  const double depth = params.initial_threshold + params.slope * f.step;
  std::vector<double> raised = z;
  for (std::size_t j = 0; j < f.ny; ++j)
    for (std::size_t i = 0; i < f.nx; ++i) {
      const std::size_t c = j * f.nx + i;
      if (!std::isfinite(z[c])) continue;
      std::vector<double> around;
      for (std::size_t b = j > 0 ? j - 1 : 0; b <= std::min(f.ny - 1, j + 1); ++b)
        for (std::size_t a = i > 0 ? i - 1 : 0; a <= std::min(f.nx - 1, i + 1); ++a)
          if ((a != i || b != j) && std::isfinite(z[b * f.nx + a])) around.push_back(z[b * f.nx + a]);
      if (around.size() < 2) continue;
      std::nth_element(around.begin(), around.begin() + 1, around.end());
      const double floor = around[1] - depth;  // the second lowest: one neighbour may be an outlier too
      if (z[c] >= floor) continue;
      std::vector<double> kept;
      for (const double v : in_cell[c])
        if (v >= floor) kept.push_back(v);
      raised[c] = kInf;
      if (kept.empty()) continue;
      const std::size_t k = std::size_t(std::floor(params.low_share * double(kept.size())));
      std::nth_element(kept.begin(), kept.begin() + std::ptrdiff_t(k), kept.end());
      raised[c] = kept[k];
    }
  z.swap(raised);
  // 1c. Support: a height that too few points hold up is no measurement.
  for (std::size_t c = 0; c < n; ++c) {
    if (!std::isfinite(z[c])) continue;
    const auto held = std::count_if(in_cell[c].begin(), in_cell[c].end(),
                                    [&](double v) { return v >= z[c] && v <= z[c] + params.initial_threshold; });
    if (held >= params.min_support) continue;
    z[c] = kInf;
    ++t.unsupported_cells;
  }
  t.cells_with_points = 0;
  for (const double v : z) t.cells_with_points += std::isfinite(v) ? 1 : 0;
  // 2. The progressive morphological filter. Empty cells take no part in the minimum (+inf) and
  // none in the maximum (-inf there).
  t.ground.assign(n, 0);
  for (std::size_t c = 0; c < n; ++c) t.ground[c] = std::isfinite(z[c]) ? 1 : 0;
  std::vector<double> surface = z;
  const auto max_half = std::size_t(std::ceil(0.5 * params.max_object / f.step));
  std::size_t previous_width = 1;
  for (std::size_t half = 1;; half *= 2) {
    const std::size_t width = 2 * half + 1;
    std::vector<double> eroded = windowed(surface, f.nx, f.ny, half, true);
    for (std::size_t c = 0; c < n; ++c)
      if (!std::isfinite(surface[c])) eroded[c] = -kInf;
    std::vector<double> opened = windowed(eroded, f.nx, f.ny, half, false);
    const double threshold =
        half == 1 ? params.initial_threshold
                  : std::min(params.max_threshold,
                             params.initial_threshold + params.slope * double(width - previous_width) * f.step);
    for (std::size_t c = 0; c < n; ++c) {
      if (!std::isfinite(surface[c])) continue;
      if (surface[c] - opened[c] > threshold) t.ground[c] = 0;
      surface[c] = opened[c];
    }
    previous_width = width;
    if (half >= max_half) break;
  }
  // 3. Heights: measured at ground cells, interpolated elsewhere (from the mean of the ground
  // heights as the start).
  double sum = 0.0;
  for (std::size_t c = 0; c < n; ++c)
    if (t.ground[c]) sum += z[c], ++t.ground_cells;
  if (t.ground_cells == 0) throw Error("terrain: no cell of ground (every cell stands above its neighbours)");
  f.heights.assign(n, sum / double(t.ground_cells));
  for (std::size_t c = 0; c < n; ++c)
    if (t.ground[c]) f.heights[c] = z[c];
  harmonicFill(f.heights, t.ground, f.nx, f.ny, 1e-6 * f.step);
  boundBySlope(f, t.ground, params.slope);
  // 4. Under the keyframes.
  t.lowered = keepUnderKeyframes(f, keyframes, params.keyframe_clearance);
  return t;
}

std::vector<std::size_t> slopeSupport(const HeightField& f, const std::vector<char>& measured, double slope) {
  const std::size_t n = f.nx * f.ny, none = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> support(n, none);
  double lowest = kInf;
  for (std::size_t c = 0; c < n; ++c)
    if (measured[c]) lowest = std::min(lowest, f.heights[c]);
  if (!std::isfinite(lowest)) return support;
  const long nx = long(f.nx), ny = long(f.ny);
  for (long j = 0; j < ny; ++j)
    for (long i = 0; i < nx; ++i) {
      const std::size_t c = std::size_t(j * nx + i);
      if (measured[c]) continue;
      double best = kInf;
      // Ring r holds the nodes at Chebyshev distance r: each is at least r steps away.
      for (long r = 1; r < std::max(nx, ny); ++r) {
        if (best <= lowest + slope * f.step * double(r)) break;
        for (long b = j - r; b <= j + r; ++b) {
          if (b < 0 || b >= ny) continue;
          const long stride = (b == j - r || b == j + r) ? 1 : 2 * r;
          for (long a = i - r; a <= i + r; a += stride) {
            if (a < 0 || a >= nx) continue;
            const std::size_t m = std::size_t(b * nx + a);
            if (!measured[m]) continue;
            const double h = f.heights[m] + slope * f.step * std::hypot(double(a - i), double(b - j));
            if (h < best || (h == best && m < support[c])) {
              best = h;
              support[c] = m;
            }
          }
        }
      }
    }
  return support;
}

std::size_t boundBySlope(HeightField& f, const std::vector<char>& measured, double slope) {
  const std::vector<std::size_t> support = slopeSupport(f, measured, slope);
  std::size_t lowered = 0;
  for (std::size_t c = 0; c < support.size(); ++c) {
    const std::size_t m = support[c];
    if (m == std::numeric_limits<std::size_t>::max()) continue;
    const double di = double(c % f.nx) - double(m % f.nx), dj = double(c / f.nx) - double(m / f.nx);
    const double top = f.heights[m] + slope * f.step * std::hypot(di, dj);
    if (f.heights[c] > top) {
      f.heights[c] = top;
      ++lowered;
    }
  }
  return lowered;
}

std::size_t keepUnderKeyframes(HeightField& f, const std::vector<Eigen::Vector3d>& keyframes, double clearance) {
  std::size_t lowered = 0;
  for (const auto& k : keyframes) {
    const double top = k.z() - clearance;
    const double u = (k.x() - f.origin.x()) / f.step - 0.5, v = (k.y() - f.origin.y()) / f.step - 0.5;
    for (long j = long(std::floor(v)) - 1; j <= long(std::ceil(v)) + 1; ++j)
      for (long i = long(std::floor(u)) - 1; i <= long(std::ceil(u)) + 1; ++i) {
        if (i < 0 || j < 0 || i >= long(f.nx) || j >= long(f.ny)) continue;
        if (std::hypot(double(i) - u, double(j) - v) > 1.5) continue;  // the four nodes around it, and more
        double& h = f.heights[std::size_t(j) * f.nx + std::size_t(i)];
        if (h > top) {
          h = top;
          ++lowered;
        }
      }
  }
  return lowered;
}

}  // namespace hullmap::mapper

#include "hullmap/mapper/floor.hpp"
#include "hullmap/core/constants.hpp"
#include "hullmap/core/detail/cpu_clones.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <Eigen/Eigenvalues>

#include "hullmap/core/error.hpp"
#include "hullmap/core/number_text.hpp"
#include "hullmap/core/random.hpp"

namespace hullmap::mapper {
namespace {

constexpr std::size_t kEvaluationPoints = 200000;
constexpr std::size_t kScreenPoints = 2000;  ///< RANSAC candidates are screened on this many sample points
constexpr std::size_t kFinalists = 100;      ///< and the best this many counted on the whole sample

struct Counts {
  std::size_t inliers = 0;
  std::size_t beyond = 0;
};

/// Points as three columns: counting planes over them vectorises, over Eigen's points it does not
/// (a RANSAC search counts a thousand candidates on the same points).
struct Columns {
  std::vector<double> x, y, z;
  explicit Columns(const io::Points& points) {
    x.reserve(points.size());
    y.reserve(points.size());
    z.reserve(points.size());
    for (const io::Point& p : points) {
      x.push_back(p.x());
      y.push_back(p.y());
      z.push_back(p.z());
    }
  }
  std::size_t size() const { return x.size(); }
};

// The points within `band` of the plane and those beyond it on the outer side. The distance is
// Plane::signedDistance's to the bit: Eigen sums a 3-vector's dot product as (x + y) + z, and no
// clone may contract it (AVX2 is not FMA).
HULLMAP_AVX2_CLONES
Counts countColumns(const double* x, const double* y, const double* z, std::size_t n, double nx, double ny, double nz,
                    double offset, double band) {
  std::size_t inliers = 0, beyond = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double d = (nx * x[i] + ny * y[i]) + nz * z[i] - offset;
    inliers += std::abs(d) <= band ? 1 : 0;
    beyond += d < -band ? 1 : 0;
  }
  return Counts{inliers, beyond};
}

Counts count(const Columns& points, const Plane& plane, double band) {
  return countColumns(points.x.data(), points.y.data(), points.z.data(), points.size(), plane.normal.x(),
                      plane.normal.y(), plane.normal.z(), plane.offset, band);
}

// Least-squares plane through the inliers of `plane`: the smallest principal axis, oriented like
// `plane`'s normal (or kept equal to it when the tilt is fixed: then only the offset moves).
Plane refine(const io::Points& points, Plane plane, double band, bool fit_tilt) {
  for (int round = 0; round < 2; ++round) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    std::size_t n = 0;
    for (const io::Point& p : points) {
      if (std::abs(plane.signedDistance(p)) <= band) {
        mean += p;
        ++n;
      }
    }
    if (n < 3) return plane;
    mean /= static_cast<double>(n);
    if (fit_tilt) {
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      for (const io::Point& p : points) {
        if (std::abs(plane.signedDistance(p)) <= band) cov += (p - mean) * (p - mean).transpose();
      }
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
      Eigen::Vector3d normal = solver.eigenvectors().col(0);  // smallest eigenvalue first
      if (normal.dot(plane.normal) < 0.0) normal = -normal;
      plane.normal = normal.normalized();
    }
    plane.offset = plane.normal.dot(mean);
  }
  return plane;
}

double coverage(const io::Points& points, const Plane& plane, double band, double cell) {
  // In-plane axes.
  const Eigen::Vector3d a = plane.normal.unitOrthogonal();
  const Eigen::Vector3d b = plane.normal.cross(a);
  std::vector<double> us, vs;
  us.reserve(points.size());
  vs.reserve(points.size());
  for (const io::Point& p : points) {
    us.push_back(a.dot(p));
    vs.push_back(b.dot(p));
  }
  auto quantile = [](std::vector<double> v, double q) {
    const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return v[k];
  };
  const double u0 = quantile(us, 0.01), u1 = quantile(us, 0.99);
  const double v0 = quantile(vs, 0.01), v1 = quantile(vs, 0.99);
  std::unordered_set<std::uint64_t> all, covered;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (us[i] < u0 || us[i] > u1 || vs[i] < v0 || vs[i] > v1) continue;
    const auto cu = static_cast<std::uint64_t>((us[i] - u0) / cell);
    const auto cv = static_cast<std::uint64_t>((vs[i] - v0) / cell);
    const std::uint64_t key = (cu << 32) | cv;
    all.insert(key);
    if (std::abs(plane.signedDistance(points[i])) <= band) covered.insert(key);
  }
  return all.empty() ? 0.0 : static_cast<double>(covered.size()) / static_cast<double>(all.size());
}

void checkParams(const PlaneSearchParams& p) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw Error::inParameter("floor", what);
  };
  require(std::isfinite(p.band) && p.band > 0.0, "the plane band must be finite and > 0");
  require(p.up.allFinite() && p.up.norm() > 0.0, "the up hint must be a finite non-zero vector");
  require(std::isfinite(p.max_tilt_deg) && p.max_tilt_deg >= 0.0 && p.max_tilt_deg < 90.0,
          "the largest tilt must be in [0, 90) degrees");
  require(std::isfinite(p.min_inlier_share) && std::isfinite(p.max_beyond_share) && std::isfinite(p.min_coverage),
          "acceptance shares must be finite");
  require(std::isfinite(p.coverage_cell) && p.coverage_cell >= 0.0, "the coverage cell must be finite and >= 0");
  require(p.iterations >= 1, "RANSAC needs at least one iteration");
  require(p.sample_points >= 3, "RANSAC needs a sample of at least 3 points");
}

}  // namespace

PlaneFit findBoundingPlane(const io::Points& points, PlaneSide side, const PlaneSearchParams& params) {
  checkParams(params);
  for (const io::Point& p : points) {
    if (!p.allFinite()) throw Error::inParameter("floor", "non-finite point");
  }
  PlaneFit fit;
  if (points.size() < 3) {
    fit.reason = "fewer than 3 points";
    return fit;
  }
  // Into the map: up for a floor, down for a ceiling.
  const Eigen::Vector3d inward = (side == PlaneSide::kFloor ? 1.0 : -1.0) * params.up.normalized();
  const double min_cos = std::cos(params.max_tilt_deg * kPi / 180.0);

  core::RandomDraws draw(params.seed);
  io::Points sample;
  if (points.size() <= params.sample_points) {
    sample = points;
  } else {
    sample.reserve(params.sample_points);
    for (std::size_t i = 0; i < params.sample_points; ++i) sample.push_back(points[draw.index(points.size())]);
  }
  const double band = params.band;
  const auto max_beyond = static_cast<std::size_t>(params.max_beyond_share * static_cast<double>(sample.size()));

  // Preemptive scoring: every candidate is counted on kScreenPoints drawn from the sample (a fixed
  // draw), and only the kFinalists best of them on the whole sample, where the most inliers wins as
  // before. A candidate that could win on the sample but ranks below the finalists on a tenth of it
  // is rare; counting every candidate on everything cost iterations x sample_points tests (20M:
  // most of a 20k-point build).
  io::Points screen_points;
  if (sample.size() <= kScreenPoints) {
    screen_points = sample;
  } else {
    screen_points.reserve(kScreenPoints);
    for (std::size_t i = 0; i < kScreenPoints; ++i) screen_points.push_back(sample[draw.index(sample.size())]);
  }
  const auto max_beyond_screen =
      static_cast<std::size_t>(params.max_beyond_share * static_cast<double>(screen_points.size()));
  // Every candidate is drawn first (one generator, in order), then counted in parallel.
  std::vector<Plane> drawn_planes;
  for (int it = 0; it < params.iterations; ++it) {
    Plane candidate;
    const io::Point& p0 = sample[draw.index(sample.size())];
    if (params.fit_tilt) {
      const io::Point& p1 = sample[draw.index(sample.size())];
      const io::Point& p2 = sample[draw.index(sample.size())];
      Eigen::Vector3d n = (p1 - p0).cross(p2 - p0);
      const double len = n.norm();
      if (!(len > 0.0) || !std::isfinite(len)) continue;
      n /= len;
      if (n.dot(inward) < 0.0) n = -n;
      if (n.dot(inward) < min_cos) continue;
      candidate.normal = n;
    } else {
      candidate.normal = inward;
    }
    candidate.offset = candidate.normal.dot(p0);
    drawn_planes.push_back(candidate);
  }
  const Columns screen_columns(screen_points);
  std::vector<Counts> screen_counts(drawn_planes.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, drawn_planes.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i)
                        screen_counts[i] = count(screen_columns, drawn_planes[i], band);
                    });
  std::vector<std::pair<std::size_t, int>> screened;  // (inliers on the screen, candidate index)
  std::vector<Plane> candidates;
  for (std::size_t i = 0; i < drawn_planes.size(); ++i) {
    if (screen_counts[i].beyond > max_beyond_screen) continue;
    screened.emplace_back(screen_counts[i].inliers, static_cast<int>(candidates.size()));
    candidates.push_back(drawn_planes[i]);
  }
  // The finalists: most inliers on the screen first, ties to the earlier draw.
  std::stable_sort(screened.begin(), screened.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  if (screened.size() > kFinalists) screened.resize(kFinalists);
  std::sort(screened.begin(), screened.end(), [](const auto& x, const auto& y) { return x.second < y.second; });
  const Columns sample_columns(sample);
  std::vector<Counts> finalist_counts(screened.size());
  tbb::parallel_for(std::size_t{0}, screened.size(), [&](std::size_t k) {
    finalist_counts[k] = count(sample_columns, candidates[static_cast<std::size_t>(screened[k].second)], band);
  });
  bool have = false;
  Plane best;
  std::size_t best_inliers = 0;
  for (std::size_t k = 0; k < screened.size(); ++k) {
    const Plane& candidate = candidates[static_cast<std::size_t>(screened[k].second)];
    const Counts& c = finalist_counts[k];
    if (c.beyond > max_beyond) continue;
    if (!have || c.inliers > best_inliers) {
      have = true;
      best = candidate;
      best_inliers = c.inliers;
    }
  }
  if (!have) {
    fit.reason = "no candidate plane within the tilt limit with few points beyond it";
    return fit;
  }
  // Refinement and coverage on at most kEvaluationPoints of the points (a fixed draw): on a map of
  // millions they would otherwise cost more than the search; the counts below use every point.
  const io::Points* evaluation = &points;
  io::Points drawn;
  if (points.size() > kEvaluationPoints) {
    drawn.reserve(kEvaluationPoints);
    for (std::size_t i = 0; i < kEvaluationPoints; ++i) drawn.push_back(points[draw.index(points.size())]);
    evaluation = &drawn;
  }
  fit.plane = refine(*evaluation, best, band, params.fit_tilt);
  const Counts all = count(Columns(points), fit.plane, band);
  const double n = static_cast<double>(points.size());
  fit.inliers = all.inliers;
  fit.inlier_share = static_cast<double>(all.inliers) / n;
  fit.beyond_share = static_cast<double>(all.beyond) / n;
  fit.tilt_deg = std::acos(std::clamp(fit.plane.normal.dot(inward), -1.0, 1.0)) * 180.0 / kPi;
  const double cell = params.coverage_cell > 0.0 ? params.coverage_cell : 10.0 * band;
  fit.coverage = coverage(*evaluation, fit.plane, band, cell);

  if (fit.inlier_share < params.min_inlier_share) {
    fit.reason = "inlier share " + std::to_string(fit.inlier_share) + " < " + std::to_string(params.min_inlier_share);
  } else if (fit.beyond_share > params.max_beyond_share) {
    fit.reason =
        "share beyond the plane " + std::to_string(fit.beyond_share) + " > " + std::to_string(params.max_beyond_share);
  } else if (fit.coverage < params.min_coverage) {
    fit.reason = "coverage " + std::to_string(fit.coverage) + " < " + std::to_string(params.min_coverage);
  } else if (fit.tilt_deg > params.max_tilt_deg) {
    fit.reason = "tilt " + std::to_string(fit.tilt_deg) + " deg > " + std::to_string(params.max_tilt_deg);
  } else {
    fit.found = true;
  }
  return fit;
}

Eigen::Isometry3d levelingTransform(const Plane& floor) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond::FromTwoVectors(floor.normal, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation() = Eigen::Vector3d(0.0, 0.0, -floor.offset);
  return t;
}

Plane horizontalPlane(double height, PlaneSide side) {
  Plane p;
  p.normal = Eigen::Vector3d(0.0, 0.0, side == PlaneSide::kFloor ? 1.0 : -1.0);
  p.offset = side == PlaneSide::kFloor ? height : -height;
  return p;
}

PlaneSetting parsePlaneSetting(const std::string& option, const std::string& text) {
  PlaneSetting s;
  if (text == "auto") return s;
  if (text == "none") {
    s.mode = PlaneSetting::Mode::kNone;
    return s;
  }
  double value = 0.0;
  if (!core::parseDouble(text, value) || !std::isfinite(value)) {
    throw Error(option + ": expected auto, none or a height (a finite number), got '" + text + "'");
  }
  s.mode = PlaneSetting::Mode::kHeight;
  s.height = value;
  return s;
}

std::vector<SurfaceClass> classifySurfaces(const std::vector<Eigen::Vector3d>& centres,
                                           const std::optional<Plane>& floor, const std::optional<Plane>& ceiling,
                                           double band) {
  if (!(band >= 0.0) || !std::isfinite(band))
    throw Error::inParameter("floor", "the surface band must be finite and >= 0");
  std::vector<SurfaceClass> classes(centres.size(), SurfaceClass::kObstacle);
  for (std::size_t i = 0; i < centres.size(); ++i) {
    if (floor && floor->signedDistance(centres[i]) <= band) {
      classes[i] = SurfaceClass::kFloor;
    } else if (ceiling && ceiling->signedDistance(centres[i]) <= band) {
      classes[i] = SurfaceClass::kCeiling;
    }
  }
  return classes;
}

}  // namespace hullmap::mapper

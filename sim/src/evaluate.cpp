// Scoring a build against a ground truth (evaluate): the observed points' owners, the hulls' volumes
// and false parts, random segments checked as `hullmap check` does. The truth's readers and its
// signed distance are ground_truth.cpp.
#include "hullmap/sim/evaluate.hpp"
#include "hullmap/core/constants.hpp"
#include "hullmap/core/random.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include <Eigen/Geometry>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/core/error.hpp"

namespace hullmap::sim {
namespace {

using V3 = Eigen::Vector3d;

// A point uniform in [0, 1)^3. Its coordinates are drawn one statement at a time, z first (the order
// the documented numbers were made in): the arguments of one call are not sequenced, and gcc and
// clang draw them in opposite orders.
V3 unitCubePoint(core::RandomDraws& rng) {
  const double z = rng.uniform();
  const double y = rng.uniform();
  const double x = rng.uniform();
  return {x, y, z};
}

/// A hull as half-spaces n . x <= d (n unit).
struct HullPlanes {
  std::vector<std::pair<V3, double>> planes;
  std::vector<V3> vertices;
  V3 lo, hi;
  int obstacle = 0;
  int part = -1;
  double volume = 0.0;
  std::size_t voxels = 0;
  bool contains(const V3& p, double tolerance = 1e-9) const {
    if ((p.array() < lo.array() - tolerance).any() || (p.array() > hi.array() + tolerance).any()) return false;
    for (const auto& [n, d] : planes)
      if (n.dot(p) > d + tolerance) return false;
    return true;
  }
};

HullPlanes planesOf(const hulls::ConvexHull& hull, int obstacle, int part, double volume) {
  HullPlanes out;
  out.obstacle = obstacle;
  out.part = part;
  out.volume = volume;
  out.vertices = hull.vertices;
  out.lo = out.hi = hull.vertices.empty() ? V3::Zero() : hull.vertices[0];
  for (const auto& v : hull.vertices) {
    out.lo = out.lo.cwiseMin(v);
    out.hi = out.hi.cwiseMax(v);
  }
  for (const auto& t : hull.triangles) {
    const V3& a = hull.vertices[std::size_t(t[0])];
    V3 n = (hull.vertices[std::size_t(t[1])] - a).cross(hull.vertices[std::size_t(t[2])] - a);
    if (n.norm() == 0) continue;
    n.normalize();
    out.planes.emplace_back(n, n.dot(a));
  }
  return out;
}

std::vector<HullPlanes> hullsOf(const std::vector<hulls::Obstacle>& obstacles) {
  std::vector<HullPlanes> hulls;
  for (const auto& o : obstacles) {
    if (o.parts.empty()) {
      hulls.push_back(planesOf(o.hull, o.id, -1, o.volume));
      hulls.back().voxels = o.voxel_count;
    }
    for (std::size_t p = 0; p < o.parts.size(); ++p) {
      hulls.push_back(planesOf(o.parts[p].hull, o.id, int(p), o.parts[p].volume));
      hulls.back().voxels = o.parts[p].voxel_count;
    }
  }
  return hulls;
}

/// The point of a box or cylinder shape nearest p (p itself inside).
V3 project(const TruthShape& s, const V3& p) {
  const V3 d = p - s.center;
  if (s.shape == TruthShape::Shape::kBox) {
    const double c = std::cos(s.yaw), n = std::sin(s.yaw);
    V3 local(c * d.x() + n * d.y(), -n * d.x() + c * d.y(), d.z());
    local = local.cwiseMax(-0.5 * s.size).cwiseMin(0.5 * s.size);
    return s.center + V3(c * local.x() - n * local.y(), n * local.x() + c * local.y(), local.z());
  }
  const double r = 0.5 * s.size.x(), radial = std::hypot(d.x(), d.y());
  V3 q = d;
  if (radial > r) q.head<2>() *= r / radial;
  q.z() = std::clamp(q.z(), -0.5 * s.size.z(), 0.5 * s.size.z());
  return s.center + q;
}

/// Distance from the convex hull of `vertices` to a box or cylinder shape (0 when they meet):
/// Frank-Wolfe on f(x) = d(x)^2 / 2 over the hull (d the shape's distance, convex, f smooth with
/// gradient x - project(x)), run until the duality gap is below 1e-12 of the squared extent or 200
/// iterations; the value is exact to that gap (f(x) - gap <= f* <= f(x)).
double convexDistance(const std::vector<V3>& vertices, const TruthShape& s) {
  V3 x = vertices.front();
  double fx = kInf;
  for (const V3& v : vertices) {
    const double f = 0.5 * (v - project(s, v)).squaredNorm();
    if (f < fx) {
      fx = f;
      x = v;
    }
  }
  for (int iteration = 0; iteration < 200 && fx > 0.0; ++iteration) {
    const V3 g = x - project(s, x);
    const V3* best = &vertices.front();
    for (const V3& v : vertices)
      if (v.dot(g) < best->dot(g)) best = &v;
    const double gap = g.dot(x - *best);
    if (gap <= 1e-12 * (1.0 + g.squaredNorm())) break;
    // Line search on [x, best]: f is convex along it; ternary steps on the exact f.
    double lo = 0.0, hi = 1.0;
    const V3 d = *best - x;
    for (int k = 0; k < 60; ++k) {
      const double a = lo + (hi - lo) / 3.0, b = hi - (hi - lo) / 3.0;
      const V3 pa = x + a * d, pb = x + b * d;
      if ((pa - project(s, pa)).squaredNorm() <= (pb - project(s, pb)).squaredNorm())
        hi = b;
      else
        lo = a;
    }
    const V3 next = x + 0.5 * (lo + hi) * d;
    const double fn = 0.5 * (next - project(s, next)).squaredNorm();
    if (!(fn < fx)) break;
    x = next;
    fx = fn;
  }
  return std::sqrt(2.0 * fx);
}

/// Distance from a hull to a true shape: exact for boxes, cylinders and their unions
/// (convexDistance); for a mesh or a height field the least over the hull's vertices and `samples`
/// (points in it), 0 when one of them is inside.
double hullDistance(const std::vector<V3>& vertices, const std::vector<V3>& samples, const TruthShape& s) {
  switch (s.shape) {
    case TruthShape::Shape::kBox:
    case TruthShape::Shape::kCylinder:
      return convexDistance(vertices, s);
    case TruthShape::Shape::kUnion: {
      double best = kInf;
      for (const auto& part : s.parts) best = std::min(best, convexDistance(vertices, part));
      return best;
    }
    case TruthShape::Shape::kMesh:
    case TruthShape::Shape::kHeightField: {
      double best = kInf;
      for (const V3& p : vertices) best = std::min(best, s.signedDistance(p));
      for (const V3& p : samples) best = std::min(best, s.signedDistance(p));
      return std::max(best, 0.0);
    }
  }
  return kInf;
}

void checkEvaluateParams(std::size_t points, std::size_t weights, const EvaluateParams& params) {
  if (!(params.radius >= 0) || !std::isfinite(params.radius))
    throw Error("evaluate: --radius must be >= 0, got " + std::to_string(params.radius));
  if (!(params.margin >= 0) || !std::isfinite(params.margin))
    throw Error("evaluate: --margin must be >= 0, got " + std::to_string(params.margin));
  if (weights != 0 && weights != points)
    throw Error("evaluate: " + std::to_string(weights) + " weights for " + std::to_string(points) + " points");
  if (!(params.sample_step > 0) || !(params.segment_length > 0.2))
    throw Error("evaluate: sample_step must be > 0 and segment_length > 0.2");
  if (params.ends == SegmentEnds::kCorridor) {
    if (params.path.empty()) throw Error("evaluate: corridor ends need the camera's path (no keyframe given)");
    if (!(params.corridor_width > 0) || !std::isfinite(params.corridor_width) || !(params.corridor_height > 0) ||
        !std::isfinite(params.corridor_height))
      throw Error("evaluate: corridor_width and corridor_height must be finite and > 0");
  }
}

/// kCorridor's test of an endpoint: within the width of the path's polyline in (x, y), and no higher
/// than corridor_height above the keyframe nearest to it in (x, y).
class Corridor {
 public:
  explicit Corridor(const EvaluateParams& p) : path_(p.path), width_(p.corridor_width), height_(p.corridor_height) {}
  bool holds(const V3& q) const {
    double best = kInf, nearest_key = kInf, top = -kInf;
    const Eigen::Vector2d x = q.head<2>();
    for (std::size_t k = 0; k < path_.size(); ++k) {
      const double d = (path_[k].head<2>() - x).norm();
      if (d < nearest_key) nearest_key = d, top = path_[k].z() + height_;
      if (k + 1 == path_.size()) {
        best = std::min(best, d);
        continue;
      }
      const Eigen::Vector2d a = path_[k].head<2>(), b = path_[k + 1].head<2>();
      const double len2 = (b - a).squaredNorm();
      const double t = len2 > 0 ? std::clamp((x - a).dot(b - a) / len2, 0.0, 1.0) : 0.0;
      best = std::min(best, (a + t * (b - a) - x).norm());
    }
    return best <= width_ && q.z() <= top;
  }

 private:
  const std::vector<V3>& path_;
  double width_, height_;
};

// Observed points: each belongs to the one shape whose surface is nearest (|signed distance|
// smallest, ties to the lower index), when that is within surface_margin. A floor point at the
// foot of a wall lies on the floor, not on the wall 3 cm away. Fills e.truth's labels, points_near,
// points_inside and parts.
void scoreObservedPoints(const std::vector<HullPlanes>& hulls, const GroundTruth& truth, const std::vector<V3>& points,
                         const std::vector<std::uint32_t>& weights, const EvaluateParams& params, Evaluation& e) {
  e.truth.resize(truth.shapes.size());
  for (std::size_t s = 0; s < truth.shapes.size(); ++s) {
    e.truth[s].label = truth.shapes[s].label;
    e.truth[s].surface = truth.shapes[s].surface;
  }
  // Per hull, the weight of the observed points inside it by the shape they belong to.
  std::vector<std::vector<double>> held(hulls.size(), std::vector<double>(truth.shapes.size(), 0.0));
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double w = weights.empty() ? 1.0 : double(weights[i]);
    std::size_t owner = truth.shapes.size();
    double nearest = kInf;
    for (std::size_t s = 0; s < truth.shapes.size(); ++s) {
      const double d = std::abs(truth.shapes[s].signedDistance(points[i]));
      if (d < nearest) {
        nearest = d;
        owner = s;
      }
    }
    if (owner == truth.shapes.size() || nearest > params.surface_margin) continue;
    bool inside = false;
    for (std::size_t h = 0; h < hulls.size(); ++h) {
      if (!hulls[h].contains(points[i])) continue;
      inside = true;
      held[h][owner] += w;
    }
    e.truth[owner].points_near += w;
    if (inside) e.truth[owner].points_inside += w;
  }
  // A part represents the shape that owns the largest weight of the observed points it holds.
  for (std::size_t h = 0; h < hulls.size(); ++h) {
    const auto most = std::max_element(held[h].begin(), held[h].end());  // the first of equals
    if (most == held[h].end() || !(*most > 0)) continue;
    e.truth[std::size_t(most - held[h].begin())].parts.emplace_back(hulls[h].obstacle, hulls[h].part);
  }
}

// Volumes and touching, by Monte Carlo in each hull (params.seed); the false parts.
void scoreVolumes(const std::vector<HullPlanes>& hulls, const GroundTruth& truth, const EvaluateParams& params,
                  Evaluation& e) {
  core::RandomDraws rng(params.seed);
  double union_var = 0, outside_var = 0, far_var = 0;
  for (std::size_t h = 0; h < hulls.size(); ++h) {
    const HullPlanes& hull = hulls[h];
    e.hull_volume += hull.volume;
    std::vector<char> touches(truth.shapes.size(), 0);
    std::vector<V3> inside_samples;  // for meshes' distances
    std::size_t got = 0, in_union = 0, outside = 0, far = 0;
    for (std::size_t tries = 0; got < params.volume_samples && tries < 200 * params.volume_samples; ++tries) {
      const V3 p = hull.lo + (hull.hi - hull.lo).cwiseProduct(unitCubePoint(rng));
      if (!hull.contains(p, 0.0)) continue;
      ++got;
      inside_samples.push_back(p);
      double nearest = kInf;
      for (std::size_t s = 0; s < truth.shapes.size(); ++s) {
        const double d = truth.shapes[s].signedDistance(p);
        nearest = std::min(nearest, d);
        if (d <= params.touch_margin) touches[s] = 1;
      }
      bool first = true;
      for (std::size_t g = 0; g < h && first; ++g) first = !hulls[g].contains(p, 0.0);
      if (!first) continue;
      ++in_union;
      if (nearest > 0) ++outside;
      if (nearest > params.far_margin) ++far;
    }
    for (std::size_t s = 0; s < truth.shapes.size(); ++s)
      if (touches[s]) e.truth[s].parts_touching.emplace_back(hull.obstacle, hull.part);
    // A false part: its hull comes no closer than false_tolerance to any true obstacle.
    if (!hull.vertices.empty()) {
      double nearest = kInf;
      for (std::size_t s = 0; s < truth.shapes.size() && nearest > params.false_tolerance; ++s)
        nearest = std::min(nearest, hullDistance(hull.vertices, inside_samples, truth.shapes[s]));
      if (nearest > params.false_tolerance) {
        e.false_parts.push_back({hull.obstacle, hull.part, hull.voxels, hull.volume, nearest});
        e.false_volume += hull.volume;
      }
    }
    if (got == 0) continue;
    const double n = double(got);
    const auto add = [&](std::size_t count, double& value, double& var) {
      const double p = double(count) / n;
      value += hull.volume * p;
      var += hull.volume * hull.volume * p * (1 - p) / n;
    };
    add(in_union, e.union_volume, union_var);
    add(outside, e.outside_volume, outside_var);
    add(far, e.far_volume, far_var);
  }
  e.union_volume_se = std::sqrt(union_var);
  e.outside_volume_se = std::sqrt(outside_var);
  e.far_volume_se = std::sqrt(far_var);
}

// Random segments in the free volume, drawn from the truth and params.seed only (two builds are
// scored on the same ones), each with the truth's verdict and its deepest shape.
struct SampledSegments {
  std::vector<collision::Segment> segments;
  std::vector<int> verdict;                             // 1 deep, 2 clear, 0 neither
  std::vector<std::pair<std::size_t, double>> deepest;  // the shape nearest along it, radius - distance
};

// Nothing when the truth is empty or no segment is asked for.
std::optional<SampledSegments> sampleSegments(const GroundTruth& truth, const EvaluateParams& params) {
  V3 lo = V3::Constant(kInf), hi = V3::Constant(-kInf);
  for (const auto& s : truth.shapes) {
    lo = lo.cwiseMin(s.aabb_min);
    hi = hi.cwiseMax(s.aabb_max);
  }
  if (!lo.allFinite() || params.segments == 0) return std::nullopt;
  core::RandomDraws rng(params.seed + 1);
  const bool free_ends = params.ends != SegmentEnds::kInTruthBox;
  const bool in_corridor = params.ends == SegmentEnds::kCorridor;
  const Corridor corridor(params);
  if (free_ends) {
    lo -= V3::Constant(params.radius + params.clear_margin + 0.5);
    hi += V3::Constant(params.radius + params.clear_margin + 0.5);
  }
  const double free_distance = params.radius + params.clear_margin;
  // Segments stay on the map's side of its floors and ceilings: nothing flies through a floor. Over a
  // height field, the side is that of its surface at the point's (x, y) (its rim's beside the grid).
  double above = -kInf, below = kInf;
  std::vector<const HeightGrid*> grounds;
  for (const auto& s : truth.shapes) {
    if (!s.surface) continue;
    if (s.shape == TruthShape::Shape::kHeightField)
      grounds.push_back(&s.grid);
    else if (s.kind == "floor")
      above = std::max(above, s.aabb_max.z() + free_distance);
    else
      below = std::min(below, s.aabb_min.z() - free_distance);
  }
  const auto onMapSide = [&](const V3& p) {
    for (const HeightGrid* g : grounds)
      if (p.z() < *g->heightAt(p.head<2>().cwiseMax(g->origin).cwiseMin(g->corner())) + free_distance) return false;
    return p.z() >= above && p.z() <= below;
  };
  SampledSegments sampled;
  auto& segments = sampled.segments;
  for (std::size_t tries = 0; segments.size() < params.segments && tries < 1000 * params.segments; ++tries) {
    const V3 a = lo + (hi - lo).cwiseProduct(unitCubePoint(rng));
    // A direction uniform on the sphere, and a length in [0.2, segment_length].
    const double z = 2 * rng.uniform() - 1, phi = 2 * kPi * rng.uniform(), r = std::sqrt(1 - z * z);
    const double length = 0.2 + (params.segment_length - 0.2) * rng.uniform();
    const V3 b = a + length * V3(r * std::cos(phi), r * std::sin(phi), z);
    if (in_corridor && (!corridor.holds(a) || !corridor.holds(b))) continue;
    if (free_ends && (truth.signedDistance(a) < free_distance || truth.signedDistance(b) < free_distance)) continue;
    if (!free_ends && ((b.array() < lo.array()).any() || (b.array() > hi.array()).any())) continue;
    if (!onMapSide(a) || !onMapSide(b)) continue;
    const std::size_t steps = std::size_t(std::ceil(length / params.sample_step));
    const double spacing = length / double(steps);
    double nearest = kInf;
    std::size_t nearest_shape = 0;
    for (std::size_t k = 0; k <= steps; ++k) {
      const V3 p = a + (b - a) * (double(k) / double(steps));
      for (std::size_t s = 0; s < truth.shapes.size(); ++s) {
        const double d = truth.shapes[s].signedDistance(p);
        if (d < nearest) {
          nearest = d;
          nearest_shape = s;
        }
      }
    }
    // The exact minimum lies in [nearest - spacing / 2, nearest].
    int v = 0;
    if (nearest < params.radius - params.depth_margin)
      v = 1;
    else if (nearest - 0.5 * spacing > params.radius + params.clear_margin)
      v = 2;
    segments.push_back({a, b});
    sampled.verdict.push_back(v);
    sampled.deepest.emplace_back(nearest_shape, params.radius - nearest);
  }
  return sampled;
}

// The build's checks of the sampled segments against the truth's verdicts: deep ones missed, clear
// ones blocked (false alarms), and the parts those hit.
/// The weight of the points within `radius` of the segment [a, b] (each 1 without weights).
double weightNear(const V3& a, const V3& b, double radius, const std::vector<V3>& points,
                  const std::vector<std::uint32_t>& weights) {
  const V3 lo = a.cwiseMin(b) - V3::Constant(radius), hi = a.cwiseMax(b) + V3::Constant(radius);
  const V3 d = b - a;
  const double len2 = d.squaredNorm();
  double sum = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const V3& p = points[i];
    if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
    const double t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
    if ((a + t * d - p).squaredNorm() <= radius * radius) sum += weights.empty() ? 1.0 : double(weights[i]);
  }
  return sum;
}

void scoreSegments(const std::vector<hulls::Obstacle>& obstacles, const std::vector<collision::Surface>& surfaces,
                   const GroundTruth& truth, const std::vector<V3>& points, const std::vector<std::uint32_t>& weights,
                   const EvaluateParams& params, const SampledSegments& sampled, Evaluation& e) {
  const auto& segments = sampled.segments;
  const auto& verdict = sampled.verdict;
  const auto& deepest = sampled.deepest;
  e.segments = segments.size();
  const collision::HullChecker checker(obstacles, surfaces);
  const std::vector<collision::SegmentCheck> checks = checker.checkBatch(segments, params.radius + params.margin);
  std::map<std::pair<int, int>, std::size_t> hit;
  for (std::size_t k = 0; k < segments.size(); ++k) {
    if (verdict[k] == 1) {
      ++e.deep;
      const bool unseen = weightNear(segments[k].a, segments[k].b, params.radius, points, weights) < params.seen_points;
      e.deep_unseen += unseen ? 1 : 0;
      if (!checks[k].collides) {
        ++e.missed;
        e.missed_unseen += unseen ? 1 : 0;
        e.missed_segments.push_back(
            {segments[k].a, segments[k].b, truth.shapes[deepest[k].first].label, deepest[k].second, unseen});
      }
    } else if (verdict[k] == 2) {
      ++e.clear;
      if (checks[k].collides) {
        ++e.false_alarms;
        ++hit[{checks[k].obstacle, checks[k].part}];
      }
    }
  }
  for (const auto& [hull, count] : hit) e.false_alarm_hulls.push_back({hull.first, hull.second, count});
  std::stable_sort(e.false_alarm_hulls.begin(), e.false_alarm_hulls.end(),
                   [](const FalseAlarmHull& a, const FalseAlarmHull& b) { return a.segments > b.segments; });
}

}  // namespace

Evaluation evaluate(const std::vector<hulls::Obstacle>& obstacles, const GroundTruth& truth,
                    const std::vector<V3>& points, const std::vector<std::uint32_t>& weights,
                    const EvaluateParams& params, const std::vector<collision::Surface>& surfaces) {
  checkEvaluateParams(points.size(), weights.size(), params);
  Evaluation e;
  const std::vector<HullPlanes> hulls = hullsOf(obstacles);
  e.parts = hulls.size();
  scoreObservedPoints(hulls, truth, points, weights, params, e);
  scoreVolumes(hulls, truth, params, e);
  const std::optional<SampledSegments> sampled = sampleSegments(truth, params);
  if (sampled) scoreSegments(obstacles, surfaces, truth, points, weights, params, *sampled, e);
  return e;
}

nlohmann::json evaluationToJson(const Evaluation& e, const EvaluateParams& p) {
  using nlohmann::json;
  json truth = json::array();
  for (const auto& t : e.truth) {
    json touching = json::array();
    for (const auto& [o, part] : t.parts_touching) touching.push_back({{"obstacle", o}, {"part", part}});
    json representing = json::array();
    for (const auto& [o, part] : t.parts) representing.push_back({{"obstacle", o}, {"part", part}});
    truth.push_back({{"label", t.label},
                     {"surface", t.surface},
                     {"points_near", t.points_near},
                     {"points_inside", t.points_inside},
                     {"share_inside", t.points_near > 0 ? json(t.points_inside / t.points_near) : json(nullptr)},
                     {"parts", representing},
                     {"parts_touching", touching}});
  }
  json missed = json::array();
  for (const auto& m : e.missed_segments)
    missed.push_back({{"from", {m.from.x(), m.from.y(), m.from.z()}},
                      {"to", {m.to.x(), m.to.y(), m.to.z()}},
                      {"truth", m.truth},
                      {"depth", m.depth},
                      {"unseen", m.unseen}});
  json false_alarm_hulls = json::array();
  for (const auto& h : e.false_alarm_hulls)
    false_alarm_hulls.push_back({{"obstacle", h.obstacle}, {"part", h.part}, {"segments", h.segments}});
  json false_parts = json::array();
  for (const auto& f : e.false_parts)
    false_parts.push_back({{"obstacle", f.obstacle},
                           {"part", f.part},
                           {"voxels", f.voxels},
                           {"volume", f.volume},
                           {"distance", f.distance}});
  return {{"format", "hullmap-evaluation/1"},
          {"parameters",
           {{"radius", p.radius},
            {"surface_margin", p.surface_margin},
            {"touch_margin", p.touch_margin},
            {"far_margin", p.far_margin},
            {"depth_margin", p.depth_margin},
            {"clear_margin", p.clear_margin},
            {"margin", p.margin},
            {"volume_samples", p.volume_samples},
            {"segments", p.segments},
            {"segment_length", p.segment_length},
            {"segment_ends", p.ends == SegmentEnds::kFree         ? "free"
                             : p.ends == SegmentEnds::kInTruthBox ? "in_truth_box"
                                                                  : "corridor"},
            {"false_tolerance", p.false_tolerance},
            {"sample_step", p.sample_step},
            {"seen_points", p.seen_points},
            {"seed", p.seed}}},
          {"truth", truth},
          {"parts", e.parts},
          {"false_parts", false_parts},
          {"false_volume", e.false_volume},
          {"volume",
           {{"hulls", e.hull_volume},
            {"union", e.union_volume},
            {"union_se", e.union_volume_se},
            {"outside_truth", e.outside_volume},
            {"outside_truth_se", e.outside_volume_se},
            {"far_from_truth", e.far_volume},
            {"far_from_truth_se", e.far_volume_se}}},
          {"segments",
           {{"count", e.segments},
            {"deep", e.deep},
            {"missed", e.missed},
            {"deep_unseen", e.deep_unseen},
            {"missed_unseen", e.missed_unseen},
            {"clear", e.clear},
            {"false_alarms", e.false_alarms},
            {"false_alarm_hulls", false_alarm_hulls},
            {"missed_segments", missed}}}};
}

}  // namespace hullmap::sim

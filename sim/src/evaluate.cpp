// Two jobs for now: reading ground truth (JSON, OBJ) and scoring a build against it. Issue 26 moves
// the ground-truth type and its readers to sim/ with the scene generators; that splits this file.
#include "hullmap/core/constants.hpp"
#include "hullmap/core/random.hpp"
#include "hullmap/sim/evaluate.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <sstream>

#include <Eigen/Geometry>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/core/error.hpp"

namespace hullmap::sim {
namespace {

using V3 = Eigen::Vector3d;

/// Uniform in [0, 1) from 53 random bits (the same on every standard library).
double uniform(std::mt19937_64& rng) { return core::unitInterval(rng()); }

// A point uniform in [0, 1)^3. Its coordinates are drawn one statement at a time, z first (the order
// the documented numbers were made in): the arguments of one call are not sequenced, and gcc and
// clang draw them in opposite orders.
V3 unitCubePoint(std::mt19937_64& rng) {
  const double z = uniform(rng);
  const double y = uniform(rng);
  const double x = uniform(rng);
  return {x, y, z};
}

/// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5).
V3 closestOnTriangle(const V3& p, const V3& a, const V3& b, const V3& c) {
  const V3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const V3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const V3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

/// Signed distance of a 2D or 3D axis-aligned box of half extents h centred at the origin.
template <class V>
double boxDistance(const V& q_abs_minus_h) {
  const double outside = q_abs_minus_h.cwiseMax(0.0).norm();
  const double inside = std::min(q_abs_minus_h.maxCoeff(), 0.0);
  return outside + inside;
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
  if (s.kind == TruthShape::Kind::kBox) {
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
/// (convexDistance); for a mesh the least over the hull's vertices and `samples` (points in it).
double hullDistance(const std::vector<V3>& vertices, const std::vector<V3>& samples, const TruthShape& s) {
  switch (s.kind) {
    case TruthShape::Kind::kBox:
    case TruthShape::Kind::kCylinder:
      return convexDistance(vertices, s);
    case TruthShape::Kind::kUnion: {
      double best = kInf;
      for (const auto& part : s.parts) best = std::min(best, convexDistance(vertices, part));
      return best;
    }
    case TruthShape::Kind::kMesh: {
      double best = kInf;
      for (const V3& p : vertices) best = std::min(best, s.signedDistance(p));
      for (const V3& p : samples) best = std::min(best, s.signedDistance(p));
      return std::max(best, 0.0);
    }
  }
  return kInf;
}

void finishShape(TruthShape& s) {
  if (s.kind == TruthShape::Kind::kUnion) {
    s.aabb_min = V3::Constant(kInf);
    s.aabb_max = V3::Constant(-kInf);
    for (const auto& part : s.parts) {
      s.aabb_min = s.aabb_min.cwiseMin(part.aabb_min);
      s.aabb_max = s.aabb_max.cwiseMax(part.aabb_max);
    }
    return;
  }
  if (s.kind == TruthShape::Kind::kMesh) {
    s.aabb_min = V3::Constant(kInf);
    s.aabb_max = V3::Constant(-kInf);
    for (const auto& t : s.triangles)
      for (const auto& v : t) {
        s.aabb_min = s.aabb_min.cwiseMin(v);
        s.aabb_max = s.aabb_max.cwiseMax(v);
      }
    return;
  }
  V3 half = 0.5 * s.size;
  if (s.kind == TruthShape::Kind::kBox) {
    const double c = std::abs(std::cos(s.yaw)), n = std::abs(std::sin(s.yaw));
    half = V3(c * half.x() + n * half.y(), n * half.x() + c * half.y(), half.z());
  }
  s.aabb_min = s.center - half;
  s.aabb_max = s.center + half;
}

GroundTruth readJsonTruth(const std::string& path, std::istream& in) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(path + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
  }
  const auto fail = [&](const std::string& where, const std::string& what) -> void {
    throw Error(path + ": " + where + ": " + what);
  };
  if (!doc.is_object() || !doc.contains("obstacles") || !doc["obstacles"].is_array())
    fail("top level", "expected an object with an \"obstacles\" array");
  const auto vec3 = [&](const nlohmann::json& j, const std::string& where) {
    if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
      fail(where, "expected [x, y, z]");
    const V3 v(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
    if (!v.allFinite()) fail(where, "non-finite number");
    return v;
  };
  GroundTruth truth;
  const auto& list = doc["obstacles"];
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string at = "obstacles[" + std::to_string(k) + "]";
    const auto& j = list[k];
    if (!j.is_object()) fail(at, "expected an object");
    const auto primitive = [&](const nlohmann::json& j, const std::string& at) {
      TruthShape s;
      const std::string shape = j.contains("shape") && j["shape"].is_string() ? j["shape"].get<std::string>() : "";
      if (shape == "box") {
        s.kind = TruthShape::Kind::kBox;
      } else if (shape == "cylinder") {
        s.kind = TruthShape::Kind::kCylinder;
      } else {
        fail(at + ".shape", "expected \"box\" or \"cylinder\"");
      }
      if (!j.contains("center")) fail(at, "missing \"center\"");
      if (!j.contains("size")) fail(at, "missing \"size\"");
      s.center = vec3(j["center"], at + ".center");
      s.size = vec3(j["size"], at + ".size");
      if (!(s.size.array() > 0).all()) fail(at + ".size", "extents must be positive");
      if (j.contains("yaw")) {
        if (!j["yaw"].is_number() || !std::isfinite(j["yaw"].get<double>())) fail(at + ".yaw", "expected a number");
        s.yaw = j["yaw"].get<double>();
      }
      s.label = shape;
      finishShape(s);
      return s;
    };
    TruthShape s;
    if (j.contains("shape") && j["shape"] == "union") {
      if (!j.contains("parts") || !j["parts"].is_array() || j["parts"].empty())
        fail(at + ".parts", "a union needs a non-empty \"parts\" array");
      s.kind = TruthShape::Kind::kUnion;
      for (std::size_t p = 0; p < j["parts"].size(); ++p)
        s.parts.push_back(primitive(j["parts"][p], at + ".parts[" + std::to_string(p) + "]"));
      s.label = "union";
    } else {
      s = primitive(j, at);
    }
    const std::string shape = j.contains("kind") && j["kind"].is_string() ? j["kind"].get<std::string>() : s.label;
    s.surface = shape == "floor" || shape == "ceiling";
    s.label = shape + " " + std::to_string(k);
    finishShape(s);
    truth.shapes.push_back(std::move(s));
  }
  return truth;
}

GroundTruth readObjTruth(const std::string& path, std::istream& in) {
  std::vector<V3> vertices;
  GroundTruth truth;
  TruthShape current;
  current.kind = TruthShape::Kind::kMesh;
  current.label = "mesh";
  const auto flush = [&] {
    if (!current.triangles.empty()) {
      finishShape(current);
      truth.shapes.push_back(current);
    }
    current.triangles.clear();
  };
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    std::istringstream s(line);
    std::string tag;
    if (!(s >> tag) || tag[0] == '#') continue;
    const std::string where = path + ":" + std::to_string(number);
    if (tag == "v") {
      V3 v;
      if (!(s >> v.x() >> v.y() >> v.z()) || !v.allFinite()) throw Error(where + ": expected v x y z");
      vertices.push_back(v);
    } else if (tag == "o" || tag == "g") {
      flush();
      std::string name;
      std::getline(s >> std::ws, name);
      current.label = name.empty() ? "mesh" : name;
    } else if (tag == "f") {
      std::vector<std::size_t> ring;
      for (std::string item; s >> item;) {
        long index = 0;
        try {
          index = std::stol(item.substr(0, item.find('/')));
        } catch (const std::exception&) {
          throw Error(where + ": bad face index \"" + item + "\"");
        }
        if (index < 0) index += long(vertices.size()) + 1;  // OBJ's relative indices
        if (index < 1 || index > long(vertices.size()))
          throw Error(where + ": face index " + item + " out of range (1.." + std::to_string(vertices.size()) + ")");
        ring.push_back(std::size_t(index - 1));
      }
      if (ring.size() < 3) throw Error(where + ": a face needs at least 3 vertices");
      for (std::size_t k = 1; k + 1 < ring.size(); ++k)
        current.triangles.push_back({vertices[ring[0]], vertices[ring[k]], vertices[ring[k + 1]]});
    }
  }
  flush();
  if (truth.shapes.empty()) throw Error(path + ": no faces");
  return truth;
}

}  // namespace

double TruthShape::signedDistance(const V3& p) const {
  switch (kind) {
    case Kind::kBox: {
      const V3 d = p - center;
      const double c = std::cos(yaw), s = std::sin(yaw);
      const V3 local(c * d.x() + s * d.y(), -s * d.x() + c * d.y(), d.z());
      return boxDistance<V3>(local.cwiseAbs() - 0.5 * size);
    }
    case Kind::kCylinder: {
      const V3 d = p - center;
      const Eigen::Vector2d q(std::hypot(d.x(), d.y()) - 0.5 * size.x(), std::abs(d.z()) - 0.5 * size.z());
      return boxDistance<Eigen::Vector2d>(q);
    }
    case Kind::kUnion: {
      double best = kInf;
      for (const auto& part : parts) best = std::min(best, part.signedDistance(p));
      return best;
    }
    case Kind::kMesh: {
      double best = kInf;
      double winding = 0.0;
      for (const auto& t : triangles) {
        best = std::min(best, (p - closestOnTriangle(p, t[0], t[1], t[2])).norm());
        // Solid angle of the triangle seen from p (Van Oosterom and Strackee 1983).
        const V3 a = t[0] - p, b = t[1] - p, c = t[2] - p;
        const double la = a.norm(), lb = b.norm(), lc = c.norm();
        const double num = a.dot(b.cross(c));
        const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
        winding += 2.0 * std::atan2(num, den);
      }
      winding /= 4.0 * kPi;
      return std::abs(winding) >= 0.5 ? -best : best;
    }
  }
  return kInf;
}

double GroundTruth::signedDistance(const V3& p) const {
  double best = kInf;
  for (const auto& s : shapes) best = std::min(best, s.signedDistance(p));
  return best;
}

GroundTruth readGroundTruth(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open");
  std::string lower = path;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (lower.size() >= 4 && lower.compare(lower.size() - 4, 4, ".obj") == 0) return readObjTruth(path, in);
  return readJsonTruth(path, in);
}

namespace {

void checkEvaluateParams(std::size_t points, std::size_t weights, const EvaluateParams& params) {
  if (!(params.radius >= 0) || !std::isfinite(params.radius))
    throw Error("evaluate: --radius must be >= 0, got " + std::to_string(params.radius));
  if (weights != 0 && weights != points)
    throw Error("evaluate: " + std::to_string(weights) + " weights for " + std::to_string(points) + " points");
  if (!(params.sample_step > 0) || !(params.segment_length > 0.2))
    throw Error("evaluate: sample_step must be > 0 and segment_length > 0.2");
}

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
  std::mt19937_64 rng(params.seed);
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
  std::mt19937_64 rng(params.seed + 1);
  const bool free_ends = params.ends == SegmentEnds::kFree;
  if (free_ends) {
    lo -= V3::Constant(params.radius + params.clear_margin + 0.5);
    hi += V3::Constant(params.radius + params.clear_margin + 0.5);
  }
  const double free_distance = params.radius + params.clear_margin;
  // Segments stay on the map's side of its floors and ceilings: nothing flies through a floor.
  double above = -kInf, below = kInf;
  for (const auto& s : truth.shapes) {
    if (!s.surface) continue;
    if (s.label.rfind("floor", 0) == 0)
      above = std::max(above, s.aabb_max.z() + free_distance);
    else
      below = std::min(below, s.aabb_min.z() - free_distance);
  }
  const auto onMapSide = [&](const V3& p) { return p.z() >= above && p.z() <= below; };
  SampledSegments sampled;
  auto& segments = sampled.segments;
  for (std::size_t tries = 0; segments.size() < params.segments && tries < 1000 * params.segments; ++tries) {
    const V3 a = lo + (hi - lo).cwiseProduct(unitCubePoint(rng));
    // A direction uniform on the sphere, and a length in [0.2, segment_length].
    const double z = 2 * uniform(rng) - 1, phi = 2 * kPi * uniform(rng), r = std::sqrt(1 - z * z);
    const double length = 0.2 + (params.segment_length - 0.2) * uniform(rng);
    const V3 b = a + length * V3(r * std::cos(phi), r * std::sin(phi), z);
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
void scoreSegments(const std::vector<hulls::Obstacle>& obstacles, const std::vector<collision::HalfSpace>& surfaces,
                   const GroundTruth& truth, const EvaluateParams& params, const SampledSegments& sampled,
                   Evaluation& e) {
  const auto& segments = sampled.segments;
  const auto& verdict = sampled.verdict;
  const auto& deepest = sampled.deepest;
  e.segments = segments.size();
  const collision::HullChecker checker(obstacles, surfaces);
  const std::vector<collision::SegmentCheck> checks = checker.checkBatch(segments, params.radius);
  std::map<std::pair<int, int>, std::size_t> hit;
  for (std::size_t k = 0; k < segments.size(); ++k) {
    if (verdict[k] == 1) {
      ++e.deep;
      if (!checks[k].collides) {
        ++e.missed;
        e.missed_segments.push_back(
            {segments[k].a, segments[k].b, truth.shapes[deepest[k].first].label, deepest[k].second});
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
                    const EvaluateParams& params, const std::vector<collision::HalfSpace>& surfaces) {
  checkEvaluateParams(points.size(), weights.size(), params);
  Evaluation e;
  const std::vector<HullPlanes> hulls = hullsOf(obstacles);
  e.parts = hulls.size();
  scoreObservedPoints(hulls, truth, points, weights, params, e);
  scoreVolumes(hulls, truth, params, e);
  const std::optional<SampledSegments> sampled = sampleSegments(truth, params);
  if (sampled) scoreSegments(obstacles, surfaces, truth, params, *sampled, e);
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
                      {"depth", m.depth}});
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
            {"volume_samples", p.volume_samples},
            {"segments", p.segments},
            {"segment_length", p.segment_length},
            {"segment_ends", p.ends == SegmentEnds::kFree ? "free" : "in_truth_box"},
            {"false_tolerance", p.false_tolerance},
            {"sample_step", p.sample_step},
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
            {"clear", e.clear},
            {"false_alarms", e.false_alarms},
            {"false_alarm_hulls", false_alarm_hulls},
            {"missed_segments", missed}}}};
}

}  // namespace hullmap::sim

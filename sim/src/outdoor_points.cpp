// The map points of the street (SceneLayout::kOutdoor): tries on the visible surfaces, kept where a
// keyframe sees them; noise, outliers and gross outliers (sample_scene.hpp states them exactly).
#include <algorithm>
#include <cmath>
#include <optional>

#include "outdoor_scene.hpp"
#include "scene_patches.hpp"

namespace hullmap::sim::detail {
namespace {

using V3 = Eigen::Vector3d;

constexpr double kSightRange = 40.0;        // metres: a camera sees no farther
constexpr double kTanHalfWidth = 1.0;       // tan 45 degrees: the view is 90 degrees wide
constexpr double kTanHalfHeight = 0.70021;  // tan 35 degrees: and 70 degrees high
constexpr std::size_t kTryChunk = 4096;     // tries per independently seeded generator
constexpr double kOutlierHeight = 12.0;     // outliers lie up to this far above the terrain

// The surfaces points are drawn on: the ground's triangles, the objects' sides and tops, each with
// its outward normal (zero for a cylinder's side, whose normal is radial at the point).
struct Surfaces {
  std::vector<Patch> patches;
  std::vector<V3> normals;
  std::vector<double> cumulative;  // areas summed in order
};

// `parts`: the truth's primitives, the ground's height field first.
Surfaces outdoorSurfaces(const std::vector<TruthShape>& parts) {
  Surfaces s;
  const HeightGrid& g = parts.front().grid;
  const auto node = [&](std::size_t i, std::size_t j) {
    return V3(g.origin.x() + g.step * double(i), g.origin.y() + g.step * double(j), g.at(i, j));
  };
  for (std::size_t j = 0; j + 1 < g.ny; ++j) {
    for (std::size_t i = 0; i + 1 < g.nx; ++i) {
      const V3 a = node(i, j), b = node(i + 1, j), c = node(i + 1, j + 1), d = node(i, j + 1);
      for (const auto& [u, v] : {std::pair<V3, V3>(b - a, c - a), std::pair<V3, V3>(c - a, d - a)}) {
        Patch t;
        t.type = Patch::Type::kTriangle;
        t.c = a;
        t.a = u;
        t.b = v;
        t.area = 0.5 * u.cross(v).norm();
        t.part = 0;
        s.patches.push_back(t);
        s.normals.push_back(u.cross(v).normalized());  // up: both triangles turn counter-clockwise
      }
    }
  }
  for (std::size_t k = 1; k < parts.size(); ++k) {
    const std::size_t first = s.patches.size();
    if (parts[k].shape == TruthShape::Shape::kBox)
      addBoxFaces(parts[k], k, true, s.patches);
    else
      addCylinder(parts[k], k, s.patches);
    for (std::size_t f = first; f < s.patches.size(); ++f) {
      const Patch& patch = s.patches[f];
      V3 n = V3::UnitZ();  // a disc's
      if (patch.type == Patch::Type::kCylinderSide) n = V3::Zero();
      if (patch.type == Patch::Type::kRect) n = patch.a.cross(patch.b).normalized();
      if (n.dot(patch.c - parts[k].center) < 0.0) n = -n;
      s.normals.push_back(n);
    }
  }
  double area = 0.0;
  for (const Patch& patch : s.patches) s.cumulative.push_back(area += patch.area);
  return s;
}

// Whether the segment [a, b] meets the part (an axis-aligned box or an upright cylinder).
bool meets(const TruthShape& part, const V3& a, const V3& b) {
  if ((a.cwiseMin(b).array() > part.aabb_max.array()).any() || (a.cwiseMax(b).array() < part.aabb_min.array()).any())
    return false;
  const bool box = part.shape == TruthShape::Shape::kBox;
  const V3 d = b - a;
  double t0 = 0.0, t1 = 1.0;
  for (int axis = box ? 0 : 2; axis < 3 && t0 <= t1; ++axis) {
    if (d[axis] == 0.0) continue;  // inside the slab: the aabb test above saw to that
    const double u = (part.aabb_min[axis] - a[axis]) / d[axis], v = (part.aabb_max[axis] - a[axis]) / d[axis];
    t0 = std::max(t0, std::min(u, v));
    t1 = std::min(t1, std::max(u, v));
  }
  if (t0 > t1 || box) return t0 <= t1;
  // The cylinder: where the segment's (x, y) lies within the radius, t in [u0, u1].
  const Eigen::Vector2d e = a.head<2>() - part.center.head<2>(), f = d.head<2>();
  const double r = 0.5 * part.size.x(), qa = f.squaredNorm(), qb = 2.0 * e.dot(f), qc = e.squaredNorm() - r * r;
  if (qa == 0.0) return qc <= 0.0;
  const double disc = qb * qb - 4.0 * qa * qc;
  if (disc < 0.0) return false;
  const double root = std::sqrt(disc);
  return std::max(t0, (-qb - root) / (2.0 * qa)) <= std::min(t1, (-qb + root) / (2.0 * qa));
}

struct Camera {
  V3 position;
  Eigen::Matrix3d axes;  // columns: right, down, forward
};

// Whether the camera sees q on a surface of outward normal n: within kSightRange, in its view, on
// the surface's front, the line of sight (up to 1 cm before q) clear of every object's part.
bool sees(const Camera& camera, const V3& q, const V3& n, const std::vector<TruthShape>& parts) {
  const V3 d = q - camera.position;
  const double distance = d.norm();
  if (distance > kSightRange || distance < 0.01 || n.dot(d) >= 0.0) return false;
  const V3 local = camera.axes.transpose() * d;
  if (local.z() <= 0.0 || std::abs(local.x()) > kTanHalfWidth * local.z() ||
      std::abs(local.y()) > kTanHalfHeight * local.z())
    return false;
  const V3 end = q - d * (0.01 / distance);
  for (std::size_t k = 1; k < parts.size(); ++k)
    if (meets(parts[k], camera.position, end)) return false;
  return true;
}

// One try: a point on the surfaces (an object's on a face edge with chance edge_fraction), kept when
// no object's point lies under the terrain, no other object's part holds it and a camera sees it.
std::optional<V3> tryPoint(const SceneParams& p, const Surfaces& s, const std::vector<TruthShape>& parts,
                           const std::vector<Camera>& cameras, core::RandomDraws& rng) {
  const double x = rng.uniform() * s.cumulative.back();
  const auto k = static_cast<std::size_t>(std::upper_bound(s.cumulative.begin(), s.cumulative.end() - 1, x) -
                                          s.cumulative.begin());
  const Patch& patch = s.patches[k];
  const bool ground = patch.part == 0;
  const V3 q = samplePatch(patch, !ground && rng.uniform() < p.edge_fraction, rng);
  if (!ground) {
    const std::optional<double> h = parts.front().grid.heightAt(q.head<2>());
    if (h && q.z() < *h) return std::nullopt;
  }
  for (std::size_t j = 1; j < parts.size(); ++j)
    if (j != patch.part && covers(parts[j], q)) return std::nullopt;
  V3 n = s.normals[k];
  if (patch.type == Patch::Type::kCylinderSide) {
    n = q - parts[patch.part].center;
    n.z() = 0.0;
    n.normalize();
  }
  for (const Camera& camera : cameras)
    if (sees(camera, q, n, parts)) return q;
  return std::nullopt;
}

}  // namespace

void sampleOutdoorPoints(const SceneParams& p, core::RandomDraws& rng, Scene& scene) {
  const std::vector<TruthShape> parts = scene.truth.primitives();
  const Surfaces surfaces = outdoorSurfaces(parts);
  std::vector<Camera> cameras;
  for (const io::Keyframe& k : scene.reference) cameras.push_back({k.position, k.orientation.toRotationMatrix()});
  const auto tries = static_cast<std::size_t>(std::llround(p.density * surfaces.cumulative.back()));
  std::vector<std::vector<V3>> kept((tries + kTryChunk - 1) / kTryChunk);
  forEachSeeded(tries, p.seed, kTryChunk, [&](core::RandomDraws& local, std::size_t, std::size_t chunk) {
    if (const std::optional<V3> q = tryPoint(p, surfaces, parts, cameras, local))
      kept[chunk].push_back(*q + p.noise_sigma * local.normal3());
  });
  std::vector<V3>& points = scene.map_points;
  for (const std::vector<V3>& some : kept) points.insert(points.end(), some.begin(), some.end());

  const HeightGrid& ground = parts.front().grid;
  const auto outliers = static_cast<std::size_t>(std::llround(
      p.outlier_fraction / std::max(1e-12, 1.0 - p.outlier_fraction) * static_cast<double>(points.size())));
  for (std::size_t i = 0; i < outliers; ++i) {
    const double up = rng.uniform(0.0, kOutlierHeight);  // then y, then x: one draw a statement
    const double y = rng.uniform(ground.origin.y(), ground.corner().y());
    const Eigen::Vector2d xy(rng.uniform(ground.origin.x(), ground.corner().x()), y);
    points.emplace_back(xy.x(), xy.y(), *ground.heightAt(xy) + up);
  }
  for (std::size_t i = 0; i < p.gross_outliers; ++i) {
    const V3 direction = rng.unitVector();  // then the distance
    points.push_back(rng.uniform(1e5, 1e6) * direction);
  }
  for (std::size_t i = points.size(); i > 1; --i) std::swap(points[i - 1], points[rng.index(i)]);
}

}  // namespace hullmap::sim::detail

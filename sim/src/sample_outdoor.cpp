// The street of generateScene (SceneLayout::kOutdoor): a terrain that is no plane, a street along y
// with the camera path on it, buildings, trees, parked cars and posts beside it, and the output
// frame whose monocular scale drifts along the path. The points are outdoor_points.cpp's, the GPS
// log outdoor_gps.cpp's; sample_scene.hpp states the scene exactly.
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include <tbb/parallel_for.h>

#include "hullmap/core/error.hpp"
#include "hullmap/core/number_text.hpp"
#include "outdoor_scene.hpp"
#include "scene_patches.hpp"
#include "scene_random.hpp"

namespace hullmap::sim::detail {
namespace {

using V2 = Eigen::Vector2d;
using V3 = Eigen::Vector3d;

constexpr double kTerrainStep = 1.0;      // the height field's node spacing, metres
constexpr double kStreetHalfWidth = 5.0;  // the street is 10 m wide
constexpr double kTrackEndMargin = 10.0;  // the camera path starts and ends this far inside the area
constexpr double kAreaBorder = 0.5;       // objects' footprints keep this far inside the area

// The street's centreline, x = bend sin(2 pi y / length), and its slope dx/dy.
struct Street {
  double bend = 0.0, length = 0.0;
  double centre(double y) const { return bend * std::sin(2.0 * kPi * y / length); }
  double slope(double y) const { return bend * 2.0 * kPi / length * std::cos(2.0 * kPi * y / length); }
};

// The terrain: the slopes plus the bumps, on the grid covering the area (sides rounded up to whole
// metres, centred on the origin), heights rounded to 0.1 mm. Draws the bumps from `rng`.
HeightGrid terrain(const SceneParams& p, core::RandomDraws& rng) {
  HeightGrid g;
  g.step = kTerrainStep;
  const double width = std::ceil(p.track_width), length = std::ceil(p.track_length);
  g.nx = static_cast<std::size_t>(width / kTerrainStep) + 1;
  g.ny = static_cast<std::size_t>(length / kTerrainStep) + 1;
  g.origin = V2(-0.5 * width, -0.5 * length);
  struct Bump {
    V2 centre;
    double height = 0.0, sigma = 1.0;
  };
  std::vector<Bump> bumps(p.bumps);
  for (Bump& b : bumps) {  // one draw a statement, in this order
    const double y = rng.uniform(-0.5 * length, 0.5 * length);
    const double x = rng.uniform(-0.5 * width, 0.5 * width);
    b.centre = V2(x, y);
    b.height = rng.uniform(-p.bump_height, p.bump_height);
    b.sigma = rng.uniform(5.0, 15.0);
  }
  g.heights.resize(g.nx * g.ny);
  for (std::size_t j = 0; j < g.ny; ++j) {
    for (std::size_t i = 0; i < g.nx; ++i) {
      const V2 q = g.origin + g.step * V2(double(i), double(j));
      double h = p.slope_across * q.x() + p.slope_along * q.y();
      for (const Bump& b : bumps) h += b.height * std::exp(-(q - b.centre).squaredNorm() / (2.0 * b.sigma * b.sigma));
      g.heights[j * g.nx + i] = std::round(h * 1e4) / 1e4;
    }
  }
  return g;
}

// Keyframes evenly spaced by arc length along the centreline, kTrackEndMargin inside the area's
// ends, kOutdoorCameraHeight above the terrain, looking along the street, pitched down.
std::vector<io::Keyframe> streetKeyframes(const SceneParams& p, const Street& street, const HeightGrid& ground) {
  const double y0 = ground.origin.y() + kTrackEndMargin, y1 = ground.corner().y() - kTrackEndMargin;
  const auto steps = static_cast<std::size_t>(std::ceil((y1 - y0) / 0.05));
  std::vector<double> arc(steps + 1, 0.0);
  const auto yAt = [&](std::size_t k) { return y0 + (y1 - y0) * double(k) / double(steps); };
  for (std::size_t k = 1; k <= steps; ++k)
    arc[k] = arc[k - 1] + std::hypot(yAt(k) - yAt(k - 1), street.centre(yAt(k)) - street.centre(yAt(k - 1)));
  const double pitch = p.camera_pitch_deg * kPi / 180.0;
  std::vector<io::Keyframe> keyframes(p.keyframes);
  for (std::size_t i = 0; i < p.keyframes; ++i) {
    const double target = arc.back() * double(i) / double(p.keyframes - 1);
    const std::size_t k = std::min<std::size_t>(
        steps, std::max<std::size_t>(1, std::lower_bound(arc.begin(), arc.end(), target) - arc.begin()));
    const double f = std::clamp((target - arc[k - 1]) / (arc[k] - arc[k - 1]), 0.0, 1.0);
    const double y = yAt(k - 1) + f * (yAt(k) - yAt(k - 1));
    const V2 xy(street.centre(y), y);
    io::Keyframe& key = keyframes[i];
    key.stamp = 1.0 + 0.5 * static_cast<double>(i);
    key.position = V3(xy.x(), xy.y(), *ground.heightAt(xy) + kOutdoorCameraHeight);
    const V3 along = V3(street.slope(y), 1.0, 0.0).normalized();
    key.orientation = cameraLookingAlong(std::cos(pitch) * along - std::sin(pitch) * V3::UnitZ());
  }
  return keyframes;
}

// The lowest terrain over the rectangle [lo, hi] (inside the grid), exactly: the surface is linear on
// each triangle, so its minimum over the rectangle lies at a vertex of a triangle clipped by it: a
// node inside, a corner, or where an edge of the rectangle crosses a grid line or a diagonal.
double lowestGround(const HeightGrid& g, const V2& lo, const V2& hi) {
  double low = kInf;
  const auto take = [&](double x, double y) {
    const V2 q = V2(x, y).cwiseMax(lo).cwiseMin(hi);
    low = std::min(low, *g.heightAt(q));
  };
  const auto nodes = [&](double a, double b, double o) {  // node indices k with a <= o + k step <= b
    return std::pair<long, long>(long(std::ceil((a - o) / g.step)), long(std::floor((b - o) / g.step)));
  };
  for (const double x : {lo.x(), hi.x()})
    for (const double y : {lo.y(), hi.y()}) take(x, y);
  const auto [i0, i1] = nodes(lo.x(), hi.x(), g.origin.x());
  const auto [j0, j1] = nodes(lo.y(), hi.y(), g.origin.y());
  for (long i = i0; i <= i1; ++i) {
    const double x = g.origin.x() + g.step * double(i);
    take(x, lo.y());
    take(x, hi.y());
    for (long j = j0; j <= j1; ++j) take(x, g.origin.y() + g.step * double(j));
  }
  for (long j = j0; j <= j1; ++j) {
    take(lo.x(), g.origin.y() + g.step * double(j));
    take(hi.x(), g.origin.y() + g.step * double(j));
  }
  // Diagonals: x - y = origin.x - origin.y + k step.
  const auto [k0, k1] = nodes(lo.x() - hi.y(), hi.x() - lo.y(), g.origin.x() - g.origin.y());
  for (long k = k0; k <= k1; ++k) {
    const double d = g.origin.x() - g.origin.y() + g.step * double(k);
    take(lo.y() + d, lo.y());
    take(hi.y() + d, hi.y());
    take(lo.x(), lo.x() - d);
    take(hi.x(), hi.x() - d);
  }
  return low;
}

// Distance from the point q to the segment [a, b], in the plane.
double pointSegmentDistance(const V2& q, const V2& a, const V2& b) {
  const V2 d = b - a;
  const double t = d.squaredNorm() > 0.0 ? std::clamp((q - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  return (a + t * d - q).norm();
}

// Distance from the segment [a, b] to the rectangle [lo, hi], in the plane (0 when they meet).
double segmentRectDistance(const V2& a, const V2& b, const V2& lo, const V2& hi) {
  double t0 = 0.0, t1 = 1.0;  // Liang-Barsky: the part of the segment inside the rectangle
  for (int axis = 0; axis < 2 && t0 <= t1; ++axis) {
    const double d = b[axis] - a[axis];
    if (d == 0.0) {
      if (a[axis] < lo[axis] || a[axis] > hi[axis]) t0 = 2.0;
      continue;
    }
    const double u = (lo[axis] - a[axis]) / d, v = (hi[axis] - a[axis]) / d;
    t0 = std::max(t0, std::min(u, v));
    t1 = std::min(t1, std::max(u, v));
  }
  if (t0 <= t1) return 0.0;
  const auto toRect = [&](const V2& q) { return (lo - q).cwiseMax(q - hi).cwiseMax(0.0).norm(); };
  double best = std::min(toRect(a), toRect(b));
  for (const V2& corner : {lo, hi, V2(lo.x(), hi.y()), V2(hi.x(), lo.y())})
    best = std::min(best, pointSegmentDistance(corner, a, b));
  return best;
}

// Horizontal distance from an object's parts (a box's rectangle, a cylinder's disc) to the path.
double pathDistance(const TruthShape& object, const std::vector<V2>& path) {
  double best = kInf;
  for (const TruthShape& part : object.primitives()) {
    const V2 c = part.center.head<2>(), h = 0.5 * part.size.head<2>();
    for (std::size_t k = 0; k + 1 < path.size(); ++k) {
      const double d = part.shape == TruthShape::Shape::kBox
                           ? segmentRectDistance(path[k], path[k + 1], c - h, c + h)
                           : std::max(0.0, pointSegmentDistance(c, path[k], path[k + 1]) - h.x());
      best = std::min(best, d);
    }
  }
  return best;
}

// A cylinder standing on z = z0 up to z1 at (x, y), `width` across.
TruthShape column(double x, double y, double width, double z0, double z1) {
  return TruthShape::cylinder(V3(x, y, 0.5 * (z0 + z1)), V3(width, width, z1 - z0));
}

// Drafts: an object's parts at their place in (x, y), standing on z = 0 (the ground under them),
// for the street point at `y` on `side` (+1: east, -1: west). Sizes as sample_scene.hpp states.
std::vector<TruthShape> buildingDraft(const Street& s, double y, double side, core::RandomDraws& rng) {
  const double along = rng.uniform(8.0, 20.0);
  const double deep = rng.uniform(6.0, 12.0);
  const double high = rng.uniform(5.0, 15.0);
  const double near = s.centre(y) + side * (kStreetHalfWidth + rng.uniform(4.0, 8.0));
  const double far = near + side * deep;
  return {boxBetween(V3(std::min(near, far), y - 0.5 * along, 0.0), V3(std::max(near, far), y + 0.5 * along, high))};
}

std::vector<TruthShape> treeDraft(const Street& s, double y, double side, core::RandomDraws& rng) {
  const double x = s.centre(y) + side * (kStreetHalfWidth + rng.uniform(1.0, 5.0));
  const double trunk = rng.uniform(0.25, 0.45);
  const double trunk_height = rng.uniform(1.8, 3.0);
  const double crown = rng.uniform(2.5, 4.5);
  const double crown_height = rng.uniform(2.0, 4.0);
  std::vector<TruthShape> parts{column(x, y, trunk, 0.0, trunk_height)};
  if (rng.uniform() < 0.5)
    parts.push_back(column(x, y, crown, trunk_height, trunk_height + crown_height));
  else
    parts.push_back(boxBetween(V3(x - 0.5 * crown, y - 0.5 * crown, trunk_height),
                               V3(x + 0.5 * crown, y + 0.5 * crown, trunk_height + crown_height)));
  return parts;
}

std::vector<TruthShape> carDraft(const Street& s, double y, double side, core::RandomDraws& rng) {
  const double length = rng.uniform(3.8, 4.8);
  const double width = rng.uniform(1.7, 1.9);
  const double height = rng.uniform(1.4, 1.7);
  const double x = s.centre(y) + side * (kStreetHalfWidth - 0.3 - 0.5 * width);
  return {boxBetween(V3(x - 0.5 * width, y - 0.5 * length, 0.0), V3(x + 0.5 * width, y + 0.5 * length, height))};
}

std::vector<TruthShape> postDraft(const Street& s, double y, double side, core::RandomDraws& rng) {
  const double width = rng.uniform(0.1, 0.2);
  const double height = rng.uniform(2.5, 5.0);
  return {column(s.centre(y) + side * (kStreetHalfWidth + rng.uniform(0.3, 0.8)), y, width, 0.0, height)};
}

// The draft's parts set on the lowest ground under its foot (the parts standing on z = 0: a tree's
// trunk), those reaching `depth` below it.
TruthShape settled(const std::string& kind, const std::vector<TruthShape>& draft, const HeightGrid& ground,
                   double depth) {
  double base = kInf;
  for (const TruthShape& part : draft) {
    const Footprint f = footprint(part);
    if (part.center.z() - 0.5 * part.size.z() == 0.0) base = std::min(base, lowestGround(ground, f.lo, f.hi));
  }
  std::vector<TruthShape> parts;
  for (const TruthShape& part : draft) {
    V3 lo = part.center - 0.5 * part.size, hi = part.center + 0.5 * part.size;
    lo.z() = lo.z() == 0.0 ? base - depth : base + lo.z();
    hi.z() += base;
    parts.push_back(part.shape == TruthShape::Shape::kBox
                        ? boxBetween(lo, hi)
                        : column(part.center.x(), part.center.y(), part.size.x(), lo.z(), hi.z()));
  }
  return object(kind, std::move(parts));
}

using Draft = std::function<std::vector<TruthShape>(const Street&, double, double, core::RandomDraws&)>;

// One kind of object: its name in the truth, its count's field, how it is drafted, how deep it reaches.
struct ObjectKind {
  const char* kind;
  const char* field;
  std::size_t count;
  Draft draft;
  double depth;
};

// Each kind's objects in turn, each drafted at a random point of the street on a random side until
// its footprint is kAreaBorder inside the area, kSceneObstacleGap from the others' and
// kOutdoorPathMargin from the path, then settled. Throws naming the count when 10000 drafts fail.
void placeObjects(const SceneParams& p, const Street& street, const HeightGrid& ground, const std::vector<V2>& path,
                  core::RandomDraws& rng, Scene& scene) {
  const V2 lo = ground.origin + V2::Constant(kAreaBorder), hi = ground.corner() - V2::Constant(kAreaBorder);
  const ObjectKind kinds[] = {{"building", "buildings", p.buildings, buildingDraft, 0.5},
                              {"tree", "trees", p.trees, treeDraft, 0.3},
                              {"car", "cars", p.cars, carDraft, 0.3},
                              {"post", "posts", p.posts, postDraft, 0.3}};
  std::vector<Footprint> placed;
  for (const ObjectKind& k : kinds) {
    for (std::size_t n = 0; n < k.count; ++n) {
      bool done = false;
      for (int attempt = 0; attempt < 10000 && !done; ++attempt) {
        const double y = rng.uniform(lo.y(), hi.y());
        const double side = rng.uniform() < 0.5 ? -1.0 : 1.0;
        const std::vector<TruthShape> draft = k.draft(street, y, side, rng);
        const TruthShape local = object(k.kind, draft);
        const Footprint f = footprint(local);
        if ((f.lo.array() < lo.array()).any() || (f.hi.array() > hi.array()).any()) continue;
        if (pathDistance(local, path) < kOutdoorPathMargin) continue;
        done = std::all_of(placed.begin(), placed.end(),
                           [&f](const Footprint& other) { return gap(f, other) >= kSceneObstacleGap; });
        if (done) {
          placed.push_back(f);
          scene.truth.add(settled(k.kind, draft, ground, k.depth));
        }
      }
      if (!done) {
        char gap_text[core::kShortestTextMax], length_text[core::kShortestTextMax];
        const std::string apart(gap_text, core::writeShortest(gap_text, kSceneObstacleGap));
        const std::string length(length_text,
                                 core::writeShortest(length_text, ground.corner().y() - ground.origin.y()));
        throw Error::inParameter(k.field, "cannot place " + std::to_string(k.count) + " " + k.field + " " + apart +
                                              " m from the other objects beside a " + length +
                                              " m street (fewer, or a longer track_length)");
      }
    }
  }
}

// The output frame (see sample_scene.hpp): with orbslam_frame, each keyframe's scale drifting along
// the path, the keyframes and points written from the nearest path segment; else the map frame.
void toDriftingFrame(const SceneParams& p, Scene& scene) {
  const std::vector<io::Keyframe>& ref = scene.reference;
  const std::size_t n = ref.size();
  scene.keyframes = ref;
  scene.points = scene.map_points;
  scene.keyframe_scales.assign(n, 1.0);
  if (!p.orbslam_frame) return;
  std::vector<double> arc(n, 0.0);
  for (std::size_t k = 1; k < n; ++k) arc[k] = arc[k - 1] + (ref[k].position - ref[k - 1].position).norm();
  const Eigen::Matrix3d r = ref.front().orientation.toRotationMatrix().transpose();
  const Eigen::Quaterniond rq(r);
  std::vector<V3> written(n, V3::Zero());
  for (std::size_t k = 0; k < n; ++k) {
    scene.keyframe_scales[k] = p.monocular_scale * (1.0 + p.scale_drift * arc[k] / arc.back());
    if (k > 0)
      written[k] = written[k - 1] + 0.5 * (scene.keyframe_scales[k - 1] + scene.keyframe_scales[k]) *
                                        (r * (ref[k].position - ref[k - 1].position));
    scene.keyframes[k].position = written[k];
    scene.keyframes[k].orientation = (rq * ref[k].orientation).normalized();
  }
  scene.output_scale = p.monocular_scale;
  scene.output_rotation = r;
  scene.output_translation = -p.monocular_scale * (r * ref.front().position);
  const std::vector<double>& s = scene.keyframe_scales;
  tbb::parallel_for(std::size_t{0}, scene.points.size(), [&](std::size_t i) {
    const V3& q = scene.map_points[i];
    std::size_t best = 0;
    double best_f = 0.0, best_d = kInf;
    for (std::size_t k = 0; k + 1 < n; ++k) {
      const V2 a = ref[k].position.head<2>(), d = ref[k + 1].position.head<2>() - a;
      const double f = std::clamp((q.head<2>() - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      const double dist = (a + f * d - q.head<2>()).squaredNorm();
      if (dist < best_d) {
        best_d = dist;
        best = k;
        best_f = f;
      }
    }
    const double f = best_f;
    const V3 on = (1.0 - f) * ref[best].position + f * ref[best + 1].position;
    scene.points[i] =
        (1.0 - f) * written[best] + f * written[best + 1] + ((1.0 - f) * s[best] + f * s[best + 1]) * (r * (q - on));
  });
}

}  // namespace

Scene generateOutdoorScene(const SceneParams& p) {
  core::RandomDraws rng(p.seed);
  Scene scene;
  const HeightGrid ground = terrain(p, rng);
  scene.truth.add(TruthShape::heightField(ground, "ground"));
  const Street street{ground.corner().x() - ground.origin.x() < 40.0 ? 1.5 : 3.0,
                      ground.corner().y() - ground.origin.y()};
  scene.reference = streetKeyframes(p, street, ground);
  std::vector<V2> path;
  for (const io::Keyframe& k : scene.reference) path.push_back(k.position.head<2>());
  placeObjects(p, street, ground, path, rng, scene);
  sampleOutdoorPoints(p, rng, scene);
  toDriftingFrame(p, scene);
  scene.gps = gpsLog(p, scene.reference, rng);
  return scene;
}

}  // namespace hullmap::sim::detail

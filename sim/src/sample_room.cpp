// The realistic room of generateScene (SceneLayout::kRoom): walls, floor, furniture that is not
// convex, sparse ORB-SLAM-like points, the first camera's frame at a monocular scale.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "hullmap/core/error.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "scene_patches.hpp"
#include "scene_random.hpp"

namespace hullmap::sim::detail {
namespace {

constexpr double kWallThickness = 0.1;  // the truth's walls and floor are 10 cm thick, outside the room

// A box or cylinder as `part` (a primitive of kind box or cylinder), at `center` with `size`.
TruthShape reshaped(const TruthShape& part, const Eigen::Vector3d& center, const Eigen::Vector3d& size) {
  return part.shape == TruthShape::Shape::kBox ? TruthShape::box(center, size) : TruthShape::cylinder(center, size);
}

// `o`'s primitives moved by `shift` in x and y, as an object of o's kind.
TruthShape shifted(const TruthShape& o, const Eigen::Vector2d& shift) {
  std::vector<TruthShape> parts;
  for (const TruthShape& part : o.primitives()) {
    Eigen::Vector3d center = part.center;
    center.head<2>() += shift;
    parts.push_back(reshaped(part, center, part.size));
  }
  return object(o.kind, std::move(parts));
}

// A piece of furniture with its footprint's lower corner at the origin, standing on z = 0.
TruthShape furniture(const SceneParams& p, core::RandomDraws& rng) {
  std::string kind;
  std::vector<TruthShape> parts;
  const double max_height = std::min(2.2, p.room_height - 0.3);
  const double pick = rng.uniform();
  if (pick < 0.3) {
    kind = "l_shelf";
    const double la = rng.uniform(1.0, 1.8), lb = rng.uniform(0.8, 1.5), d = rng.uniform(0.3, 0.45);
    const double h = rng.uniform(1.2, max_height);
    // Arm A along x, arm B along y starting where A ends: the two boxes touch, never overlap.
    parts.push_back(boxBetween({0, 0, 0}, {la, d, h}));
    parts.push_back(boxBetween({0, d, 0}, {d, d + lb, h}));
  } else if (pick < 0.6) {
    kind = "table";
    const double w = rng.uniform(0.8, 1.6), l = rng.uniform(0.6, 1.0), top = rng.uniform(0.72, 0.78);
    const double leg = 0.05, inset = 0.05, thick = 0.04;
    parts.push_back(boxBetween({0, 0, top - thick}, {w, l, top}));
    for (int i = 0; i < 4; ++i) {
      const double x = (i & 1) ? w - inset - leg : inset;
      const double y = (i & 2) ? l - inset - leg : inset;
      parts.push_back(boxBetween({x, y, 0}, {x + leg, y + leg, top - thick}));
    }
  } else if (pick < 0.8) {
    kind = "box";
    parts.push_back(
        boxBetween({0, 0, 0}, {rng.uniform(0.4, 1.2), rng.uniform(0.4, 1.2), rng.uniform(0.6, max_height)}));
  } else {
    kind = "cylinder";
    const double d = rng.uniform(0.3, 0.8), h = rng.uniform(0.6, max_height);
    parts.push_back(TruthShape::cylinder(Eigen::Vector3d(0.5 * d, 0.5 * d, 0.5 * h), Eigen::Vector3d(d, d, h)));
  }
  // A quarter turn half of the time (about the footprint's corner, then back into x, y >= 0).
  if (rng.uniform() < 0.5) {
    for (TruthShape& part : parts) {
      const Eigen::Vector3d center(-part.center.y(), part.center.x(), part.center.z());
      part = reshaped(part, center, Eigen::Vector3d(part.size.y(), part.size.x(), part.size.z()));
    }
    const TruthShape turned = object(kind, std::move(parts));
    return shifted(turned, -footprint(turned).lo);
  }
  return object(kind, std::move(parts));
}

// The camera loop's ellipse (semi-axes lx, ly) sampled every 0.25 degrees, for the placement gaps.
std::vector<Eigen::Vector2d> loopSamples(double lx, double ly) {
  std::vector<Eigen::Vector2d> samples(1440);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const double a = 2.0 * kPi * static_cast<double>(i) / static_cast<double>(samples.size());
    samples[i] = Eigen::Vector2d(lx * std::cos(a), ly * std::sin(a));
  }
  return samples;
}

// Distance from a footprint to the nearest sample of the loop.
double loopGap(const Footprint& f, const std::vector<Eigen::Vector2d>& loop) {
  double best = 1e300;
  for (const auto& q : loop) best = std::min(best, (f.lo - q).cwiseMax(q - f.hi).cwiseMax(0.0).norm());
  return best;
}

// FurniturePlacement::kAnywhere: the local footprint (lower corner at the origin, `extent`) moved to
// a random place in the room of half sides (hx, hy): against a wall with chance `wall_fraction` (its
// back 3 to 10 cm from the wall's face, anywhere along it), else kSceneObstacleGap from every wall.
// Returns the shift, or nothing when the piece does not fit.
std::optional<Eigen::Vector2d> anywhereShift(const Eigen::Vector2d& extent, double hx, double hy, double wall_fraction,
                                             core::RandomDraws& rng) {
  const double g = kSceneObstacleGap;
  if (rng.uniform() < wall_fraction) {
    const std::size_t wall = rng.index(4);  // -x, +x, -y, +y
    const double back = rng.uniform(0.03, 0.10);
    // `across`: the axis normal to the wall's face; `along`: the axis along it.
    const int across = wall < 2 ? 0 : 1, along = 1 - across;
    const Eigen::Vector2d half(hx, hy);
    if (extent[along] > 2.0 * half[along] - 0.06 || extent[across] > 2.0 * half[across] - back) return std::nullopt;
    Eigen::Vector2d shift;
    shift[along] = rng.uniform(-half[along] + 0.03, half[along] - 0.03 - extent[along]);
    shift[across] = wall % 2 == 0 ? -half[across] + back : half[across] - back - extent[across];
    return shift;
  }
  if (extent.x() > 2.0 * (hx - g) || extent.y() > 2.0 * (hy - g)) return std::nullopt;
  // One draw a statement, y first (the order maps/ was made in): the arguments of one call are not
  // sequenced, and gcc and clang draw them in opposite orders.
  const double y = rng.uniform(-hy + g, hy - g - extent.y());
  const double x = rng.uniform(-hx + g, hx - g - extent.x());
  return Eigen::Vector2d(x, y);
}

// The room's measures, which every step below reads.
struct Room {
  double half = 0.0, half_y = 0.0;    // half the room's extent in x and y
  double height = 0.0;                // the walls' height
  double loop_x = 0.0, loop_y = 0.0;  // the camera loop's half axes
  bool circle = false;                // the loop is a circle
};

// Floor and walls (their inner faces are the room's boundary).
void addShell(const Room& room, Scene& scene) {
  const double t = kWallThickness, half = room.half, half_y = room.half_y, zh = room.height;
  scene.truth.add(boxBetween({-half - t, -half_y - t, -t}, {half + t, half_y + t, 0}, "floor"));
  scene.truth.add(boxBetween({-half - t, -half_y - t, 0}, {-half, half_y + t, zh}, "wall"));
  scene.truth.add(boxBetween({half, -half_y - t, 0}, {half + t, half_y + t, zh}, "wall"));
  scene.truth.add(boxBetween({-half, -half_y - t, 0}, {half, -half_y, zh}, "wall"));
  scene.truth.add(boxBetween({-half, half_y, 0}, {half, half_y + t, zh}, "wall"));
}

// Where a piece of furniture of `extent` goes inside the camera loop (its lower corner's shift), or
// nothing when this draw does not fit.
std::optional<Eigen::Vector2d> insideLoopShift(const Eigen::Vector2d& extent, const Room& room,
                                               core::RandomDraws& rng) {
  if (room.circle) {
    const double reach = room.loop_x - kSceneObstacleGap - 0.5 * extent.norm();
    if (reach <= 0.0) return std::nullopt;
    const double centre_y = rng.uniform(-reach, reach);  // y first, as in anywhereShift
    const Eigen::Vector2d centre(rng.uniform(-reach, reach), centre_y);
    if (centre.norm() > reach) return std::nullopt;
    return Eigen::Vector2d(centre - 0.5 * extent);
  }
  // Inside the ellipse: the footprint grown by the gap has its corners inside it.
  const double loop_x = room.loop_x, loop_y = room.loop_y;
  const double rx = loop_x - kSceneObstacleGap - 0.5 * extent.x(), ry = loop_y - kSceneObstacleGap - 0.5 * extent.y();
  if (rx <= 0.0 || ry <= 0.0) return std::nullopt;
  const double centre_y = rng.uniform(-ry, ry);  // y first, as in anywhereShift
  const Eigen::Vector2d centre(rng.uniform(-rx, rx), centre_y);
  const Eigen::Vector2d h = 0.5 * extent + Eigen::Vector2d::Constant(kSceneObstacleGap);
  for (int c = 0; c < 4; ++c) {
    const Eigen::Vector2d q = centre + Eigen::Vector2d((c & 1) ? h.x() : -h.x(), (c & 2) ? h.y() : -h.y());
    if ((q.x() / loop_x) * (q.x() / loop_x) + (q.y() / loop_y) * (q.y() / loop_y) > 1.0) return std::nullopt;
  }
  return Eigen::Vector2d(centre - 0.5 * extent);
}

// Furniture kSceneObstacleGap apart from each other and from the camera loop: inside the loop, or
// (kAnywhere) anywhere in the room. Throws when a piece finds no place in 10000 draws.
void addFurniture(const SceneParams& p, const Room& room, core::RandomDraws& rng, Scene& scene) {
  const std::vector<Eigen::Vector2d> loop = room.circle && p.placement == FurniturePlacement::kInsideLoop
                                                ? std::vector<Eigen::Vector2d>{}
                                                : loopSamples(room.loop_x, room.loop_y);
  // The samples are at most 2 pi max(lx, ly) / 1440 apart: the gap to the curve is within half that.
  const double loop_slack = kPi * std::max(room.loop_x, room.loop_y) / 1440.0;
  std::vector<Footprint> placed;
  for (std::size_t n = 0; n < p.obstacles; ++n) {
    bool done = false;
    for (int attempt = 0; attempt < 10000 && !done; ++attempt) {
      TruthShape f = furniture(p, rng);
      const Footprint local = footprint(f);
      const Eigen::Vector2d extent = local.hi - local.lo;
      const auto shift = p.placement == FurniturePlacement::kAnywhere
                             ? anywhereShift(extent, room.half, room.half_y, p.wall_fraction, rng)
                             : insideLoopShift(extent, room, rng);
      if (!shift) continue;
      f = shifted(f, *shift);
      const Footprint fp = footprint(f);
      if (!loop.empty() && p.placement == FurniturePlacement::kAnywhere &&
          loopGap(fp, loop) < kSceneObstacleGap + loop_slack)
        continue;
      done = std::all_of(placed.begin(), placed.end(),
                         [&fp](const Footprint& other) { return gap(fp, other) >= kSceneObstacleGap; });
      if (done) {
        placed.push_back(fp);
        scene.truth.add(f);
      }
    }
    if (!done) {
      throw Error("scene parameters: cannot place " + std::to_string(p.obstacles) + " pieces of furniture " +
                  std::to_string(kSceneObstacleGap) + " m apart in a room of " + std::to_string(p.room_size) + " x " +
                  std::to_string(2.0 * room.half_y) + " m (obstacles too many for room_size)");
    }
  }
}

// Visible patches: the floor's top, the walls' inner faces, furniture's tops and sides.
std::vector<Patch> visiblePatches(const Scene& scene, const Room& room) {
  std::vector<Patch> patches;
  std::size_t part = 0;
  for (const auto& object : scene.truth.shapes) {
    for (const auto& o : object.primitives()) {
      if (object.kind == "floor") {
        Patch top;
        top.c = Eigen::Vector3d(0, 0, 0);
        top.a = Eigen::Vector3d(room.half, 0, 0);
        top.b = Eigen::Vector3d(0, room.half_y, 0);
        top.area = 4.0 * room.half * room.half_y;
        top.part = part;
        patches.push_back(top);
      } else if (object.kind == "wall") {
        // The face toward the room's centre.
        const Eigen::Vector3d h = 0.5 * o.size;
        Patch face;
        face.part = part;
        if (o.size.x() < o.size.y()) {
          const double x = o.center.x() > 0 ? room.half : -room.half;
          face.c = Eigen::Vector3d(x, 0, 0.5 * room.height);
          face.a = Eigen::Vector3d(0, room.half_y, 0);
        } else {
          const double y = o.center.y() > 0 ? room.half_y : -room.half_y;
          face.c = Eigen::Vector3d(0, y, 0.5 * room.height);
          face.a = Eigen::Vector3d(room.half, 0, 0);
        }
        face.b = Eigen::Vector3d(0, 0, h.z());
        face.area = 4.0 * face.a.norm() * face.b.norm();
        patches.push_back(face);
      } else if (o.shape == TruthShape::Shape::kBox) {
        addBoxFaces(o, part, true, patches);
      } else {
        addCylinder(o, part, patches);
      }
      ++part;
    }
  }
  return patches;
}

// The points, in chunks of kChunk drawn in parallel from seeds of their own: on the visible patches
// (redrawn where furniture hides them), with noise; outliers in the room; gross outliers far away.
// Then shuffled with `rng`.
void samplePoints(const SceneParams& p, const Room& room, core::RandomDraws& rng, Scene& scene) {
  // Only furniture hides surfaces (a wall's foot on the floor is a visible edge, as is a box's).
  const std::vector<TruthShape> parts = scene.truth.primitives();
  std::vector<bool> hides;
  for (const auto& object : scene.truth.shapes)
    for (std::size_t k = 0; k < object.primitives().size(); ++k)
      hides.push_back(object.kind != "floor" && object.kind != "wall");
  const std::vector<Patch> patches = visiblePatches(scene, room);
  std::vector<double> cumulative;
  double area = 0.0;
  for (const auto& patch : patches) cumulative.push_back(area += patch.area);

  const auto surface = static_cast<std::size_t>(std::llround(p.density * area));
  const auto outliers = static_cast<std::size_t>(
      std::llround(p.outlier_fraction / std::max(1e-12, 1.0 - p.outlier_fraction) * static_cast<double>(surface)));
  const std::size_t gross = p.gross_outliers;
  const std::size_t n = surface + outliers + gross;
  scene.points.resize(n);
  forEachSeeded(n, p.seed, kChunk, [&](core::RandomDraws& local, std::size_t i, std::size_t) {
    Eigen::Vector3d& q = scene.points[i];
    if (i < surface) {
      while (true) {
        const double x = local.uniform() * area;
        const auto k = static_cast<std::size_t>(std::upper_bound(cumulative.begin(), cumulative.end() - 1, x) -
                                                cumulative.begin());
        const Patch& patch = patches[k];
        q = samplePatch(patch, local.uniform() < p.edge_fraction, local);
        bool hidden = false;
        for (std::size_t j = 0; j < parts.size() && !hidden; ++j) {
          hidden = hides[j] && j != patch.part && covers(parts[j], q);
        }
        if (!hidden) break;
      }
      q += p.noise_sigma * local.normal3();
    } else if (i < surface + outliers) {
      const double z = local.uniform(0.0, room.height);  // z, y, x: as normal3()
      const double y = local.uniform(-room.half_y, room.half_y);
      q = Eigen::Vector3d(local.uniform(-room.half, room.half), y, z);
    } else {
      const Eigen::Vector3d direction = local.unitVector();  // then the distance: as normal3()
      q = local.uniform(1e5, 1e6) * direction;
    }
  });
  for (std::size_t i = n; i > 1; --i) std::swap(scene.points[i - 1], scene.points[rng.index(i)]);
}

// Keyframes: a loop at about kCameraHeight, each camera looking at the room's axis, pitched down.
std::vector<io::Keyframe> roomCameraLoop(const SceneParams& p, const Room& room) {
  const double pitch = p.camera_pitch_deg * kPi / 180.0;
  return cameraLoop(p.keyframes, room.loop_x, room.loop_y, [&](double a, const Eigen::Vector3d& position) {
    // Toward the room's vertical axis.
    const Eigen::Vector3d inward = room.circle ? Eigen::Vector3d(-std::cos(a), -std::sin(a), 0.0)
                                               : Eigen::Vector3d(-position.x(), -position.y(), 0.0).normalized();
    return Eigen::Vector3d(std::cos(pitch) * inward - std::sin(pitch) * Eigen::Vector3d::UnitZ());
  });
}

// The output frame: the first camera's, scaled (p_out = s R0^T (p - t0)), when p.orbslam_frame; the
// points and keyframes moved into it (scene.reference stays in the room's frame).
void toOutputFrame(const SceneParams& p, Scene& scene) {
  if (p.orbslam_frame) {
    const io::Keyframe& first = scene.reference.front();
    scene.output_scale = p.monocular_scale;
    scene.output_rotation = first.orientation.toRotationMatrix().transpose();
    scene.output_translation = -p.monocular_scale * (scene.output_rotation * first.position);
  }
  const double s = scene.output_scale;
  const Eigen::Matrix3d& r = scene.output_rotation;
  const Eigen::Vector3d& tr = scene.output_translation;
  transformPoints(scene.points, [&](const Eigen::Vector3d& q) -> Eigen::Vector3d { return s * (r * q) + tr; });
  const Eigen::Quaterniond rq(r);
  scene.keyframes = scene.reference;
  for (io::Keyframe& k : scene.keyframes) {
    k.position = s * (r * k.position) + tr;
    k.orientation = (rq * k.orientation).normalized();
  }
}

}  // namespace

Scene generateRoomScene(const SceneParams& p) {
  core::RandomDraws rng(p.seed);
  Room room;
  room.half = 0.5 * p.room_size;
  room.half_y = 0.5 * (p.room_width > 0.0 ? p.room_width : p.room_size);
  room.height = p.room_height;
  room.loop_x = p.loop_fraction * p.room_size;
  room.loop_y = p.loop_fraction * 2.0 * room.half_y;
  room.circle = room.loop_x == room.loop_y;
  Scene scene;
  addShell(room, scene);
  addFurniture(p, room, rng, scene);
  samplePoints(p, room, rng, scene);
  scene.reference = roomCameraLoop(p, room);
  toOutputFrame(p, scene);
  return scene;
}

}  // namespace hullmap::sim::detail

#pragma once

// What the scene generators share to build objects, place them and sample their surfaces
// (sample_room.cpp, sample_outdoor.cpp, outdoor_points.cpp): boxes and unions, surface patches of
// boxes, cylinders and triangles, points on them, and (x, y) footprints. Not installed.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hullmap/core/constants.hpp"
#include "hullmap/sim/ground_truth.hpp"
#include "scene_random.hpp"

namespace hullmap::sim::detail {

// The box from corner lo to corner hi, of `kind`.
inline TruthShape boxBetween(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const std::string& kind = "box") {
  return TruthShape::box(0.5 * (lo + hi), hi - lo, kind);
}

// A true object of `kind` made of `parts`: their union, or the one part itself.
inline TruthShape object(const std::string& kind, std::vector<TruthShape> parts) {
  if (parts.size() > 1) return TruthShape::unionOf(kind, std::move(parts));
  const TruthShape& part = parts.front();
  return part.shape == TruthShape::Shape::kBox ? TruthShape::box(part.center, part.size, kind)
                                               : TruthShape::cylinder(part.center, part.size, kind);
}

// A visible surface patch: a rectangle c + u a + v b (u, v in [-1, 1]), a cylinder's side or its
// top disc, or a triangle c + u a + v b (u, v >= 0, u + v <= 1). The room draws again the points on
// it that fall on or inside another piece of furniture's part: faces where parts touch, the floor
// under furniture, a leg's top under the table top.
struct Patch {
  enum class Type { kRect, kCylinderSide, kDisc, kTriangle } type = Type::kRect;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  Eigen::Vector3d a = Eigen::Vector3d::Zero();  // rect half-axis; cylinder: (radius, half height, 0)
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  double area = 0.0;
  std::size_t part = 0;  // index into the flat parts list (itself is never a rejecter)
};

// The box's sides (and its top when `top`) as patches of `part`, those of zero area left out.
inline void addBoxFaces(const TruthShape& o, std::size_t part, bool top, std::vector<Patch>& patches) {
  const Eigen::Vector3d h = 0.5 * o.size;
  auto rect = [&](const Eigen::Vector3d& c, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    Patch p;
    p.c = c;
    p.a = a;
    p.b = b;
    p.area = 4.0 * a.norm() * b.norm();
    p.part = part;
    if (p.area > 0.0) patches.push_back(p);
  };
  const Eigen::Vector3d x(h.x(), 0, 0), y(0, h.y(), 0), z(0, 0, h.z());
  if (top) rect(o.center + z, x, y);
  rect(o.center + x, y, z);
  rect(o.center - x, y, z);
  rect(o.center + y, x, z);
  rect(o.center - y, x, z);
}

// The cylinder's side and top disc as patches of `part`.
inline void addCylinder(const TruthShape& o, std::size_t part, std::vector<Patch>& patches) {
  const double r = 0.5 * o.size.x(), hz = 0.5 * o.size.z();
  Patch side;
  side.type = Patch::Type::kCylinderSide;
  side.c = o.center;
  side.a = Eigen::Vector3d(r, hz, 0);
  side.area = 2.0 * kPi * r * 2.0 * hz;
  side.part = part;
  patches.push_back(side);
  Patch disc = side;
  disc.type = Patch::Type::kDisc;
  disc.c = o.center + Eigen::Vector3d(0, 0, hz);
  disc.area = kPi * r * r;
  patches.push_back(disc);
}

// A point on the patch, uniform by area; `on_edge`: on its rim instead (rectangles: an edge chosen by
// length; a side: its top rim; a disc: its circle; a triangle: ignored).
inline Eigen::Vector3d samplePatch(const Patch& p, bool on_edge, core::RandomDraws& rng) {
  switch (p.type) {
    case Patch::Type::kRect: {
      double u = rng.uniform(-1.0, 1.0), v = rng.uniform(-1.0, 1.0);
      if (on_edge) {
        // One of the four edges, by length.
        const double la = p.a.norm(), lb = p.b.norm();
        if (rng.uniform() * (la + lb) < la)
          v = rng.uniform() < 0.5 ? -1.0 : 1.0;
        else
          u = rng.uniform() < 0.5 ? -1.0 : 1.0;
      }
      return p.c + u * p.a + v * p.b;
    }
    case Patch::Type::kCylinderSide: {
      const double angle = 2.0 * kPi * rng.uniform();
      const double z = on_edge ? p.a.y() : rng.uniform(-p.a.y(), p.a.y());
      return p.c + Eigen::Vector3d(p.a.x() * std::cos(angle), p.a.x() * std::sin(angle), z);
    }
    case Patch::Type::kTriangle: {
      double u = rng.uniform(), v = rng.uniform();
      if (u + v > 1.0) {
        u = 1.0 - u;
        v = 1.0 - v;
      }
      return p.c + u * p.a + v * p.b;
    }
    case Patch::Type::kDisc:
    default: {
      const double angle = 2.0 * kPi * rng.uniform();
      const double r = on_edge ? p.a.x() : p.a.x() * std::sqrt(rng.uniform());
      return p.c + Eigen::Vector3d(r * std::cos(angle), r * std::sin(angle), 0.0);
    }
  }
}

// On or inside the part (1e-9 m slack).
inline bool covers(const TruthShape& o, const Eigen::Vector3d& q) {
  const Eigen::Vector3d d = q - o.center;
  const Eigen::Vector3d h = 0.5 * o.size;
  if (o.shape == TruthShape::Shape::kBox) return (d.cwiseAbs() - h).maxCoeff() <= 1e-9;
  return std::hypot(d.x(), d.y()) <= h.x() + 1e-9 && std::abs(d.z()) <= h.z() + 1e-9;
}

// Footprint (x, y) bounds of an object, for the placement gaps.
struct Footprint {
  Eigen::Vector2d lo, hi;
};

inline Footprint footprint(const TruthShape& object) {
  Footprint f{Eigen::Vector2d::Constant(1e300), Eigen::Vector2d::Constant(-1e300)};
  for (const auto& p : object.primitives()) {
    f.lo = f.lo.cwiseMin((p.center - 0.5 * p.size).head<2>());
    f.hi = f.hi.cwiseMax((p.center + 0.5 * p.size).head<2>());
  }
  return f;
}

// The gap between two footprints (negative when they overlap): the larger of the x and y gaps.
inline double gap(const Footprint& a, const Footprint& b) {
  const Eigen::Vector2d d = (a.lo - b.hi).cwiseMax(b.lo - a.hi);
  return d.maxCoeff();
}

}  // namespace hullmap::sim::detail

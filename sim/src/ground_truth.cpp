// The ground truth (the scene generator's and the one a build is scored against): its shapes (boxes,
// cylinders, unions, meshes, height fields), their signed distance, and its JSON both ways (maps/'s
// ground_truth.json), with the reader of OBJ meshes.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "hullmap/collision/convex_distance.hpp"
#include "hullmap/core/constants.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/sim/ground_truth.hpp"

namespace hullmap::sim {
namespace {

using V3 = Eigen::Vector3d;

/// Signed distance of a 2D or 3D axis-aligned box of half extents h centred at the origin.
template <class V>
double boxDistance(const V& q_abs_minus_h) {
  const double outside = q_abs_minus_h.cwiseMax(0.0).norm();
  const double inside = std::min(q_abs_minus_h.maxCoeff(), 0.0);
  return outside + inside;
}

/// A floor or a ceiling: a bound of the map.
bool isSurface(const std::string& kind) { return kind == "floor" || kind == "ceiling"; }

/// The aabb of a box or cylinder: its centre -/+ its half extents (a turned box's, about z).
void setPrimitiveAabb(TruthShape& s) {
  V3 half = 0.5 * s.size;
  if (s.shape == TruthShape::Shape::kBox) {
    const double c = std::abs(std::cos(s.yaw)), n = std::abs(std::sin(s.yaw));
    half = V3(c * half.x() + n * half.y(), n * half.x() + c * half.y(), half.z());
  }
  s.aabb_min = s.center - half;
  s.aabb_max = s.center + half;
}

/// A shape of `kind`, labelled so, a surface when its kind is floor or ceiling.
TruthShape ofKind(TruthShape::Shape shape, const std::string& kind) {
  TruthShape s;
  s.shape = shape;
  s.kind = kind;
  s.label = kind;
  s.surface = isSurface(kind);
  return s;
}

/// A box or cylinder as ground_truth.json writes it ("yaw" only when turned).
nlohmann::json primitiveToJson(const TruthShape& s) {
  if (s.shape != TruthShape::Shape::kBox && s.shape != TruthShape::Shape::kCylinder)
    throw Error("ground truth: " + s.label + ": a union's part must be a box or a cylinder");
  nlohmann::json j{{"shape", s.shape == TruthShape::Shape::kBox ? "box" : "cylinder"},
                   {"center", {s.center.x(), s.center.y(), s.center.z()}},
                   {"size", {s.size.x(), s.size.y(), s.size.z()}}};
  if (s.yaw != 0.0) j["yaw"] = s.yaw;
  return j;
}

[[noreturn]] void failAt(const std::string& path, const std::string& where, const std::string& what) {
  throw Error(path + ": " + where + ": " + what);
}

/// A "heightfield" entry of ground_truth.json at `at`, of `kind` (without one, "heightfield"); every
/// field checked, errors "<path>: <at>.<field>: <what>".
TruthShape readHeightField(const std::string& path, const nlohmann::json& j, const std::string& at,
                           const std::optional<std::string>& kind) {
  for (const char* key : {"origin", "step", "size", "heights"})
    if (!j.contains(key)) failAt(path, at, std::string("missing \"") + key + "\"");
  HeightGrid grid;
  const auto& origin = j["origin"];
  if (!origin.is_array() || origin.size() != 2 || !origin[0].is_number() || !origin[1].is_number())
    failAt(path, at + ".origin", "expected [x, y]");
  grid.origin = Eigen::Vector2d(origin[0].get<double>(), origin[1].get<double>());
  if (!grid.origin.allFinite()) failAt(path, at + ".origin", "non-finite number");
  if (!j["step"].is_number() || !(j["step"].get<double>() > 0) || !std::isfinite(j["step"].get<double>()))
    failAt(path, at + ".step", "expected a finite number > 0");
  grid.step = j["step"].get<double>();
  const auto& size = j["size"];
  if (!size.is_array() || size.size() != 2 || !size[0].is_number_unsigned() || !size[1].is_number_unsigned() ||
      size[0].get<std::size_t>() < 2 || size[1].get<std::size_t>() < 2)
    failAt(path, at + ".size", "expected [nx, ny], whole numbers >= 2");
  grid.nx = size[0].get<std::size_t>();
  grid.ny = size[1].get<std::size_t>();
  const auto& heights = j["heights"];
  if (!heights.is_array()) failAt(path, at + ".heights", "expected an array of numbers");
  // nx and ny each at most the count of heights, so their product cannot overflow when it matches.
  if (grid.nx > heights.size() || grid.ny > heights.size() || grid.nx * grid.ny != heights.size())
    failAt(path, at + ".heights",
           "expected nx * ny = " + size[0].dump() + " * " + size[1].dump() + " numbers, got " +
               std::to_string(heights.size()));
  grid.heights.reserve(heights.size());
  for (std::size_t k = 0; k < heights.size(); ++k) {
    if (!heights[k].is_number() || !std::isfinite(heights[k].get<double>()))
      failAt(path, at + ".heights[" + std::to_string(k) + "]", "expected a finite number");
    grid.heights.push_back(heights[k].get<double>());
  }
  return TruthShape::heightField(std::move(grid), kind.value_or("heightfield"));
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
    // A box or cylinder of `kind` (without one, of its shape's name).
    const auto primitive = [&](const nlohmann::json& j, const std::string& at, const std::optional<std::string>& kind) {
      const std::string shape = j.contains("shape") && j["shape"].is_string() ? j["shape"].get<std::string>() : "";
      if (shape != "box" && shape != "cylinder") fail(at + ".shape", "expected \"box\" or \"cylinder\"");
      if (!j.contains("center")) fail(at, "missing \"center\"");
      if (!j.contains("size")) fail(at, "missing \"size\"");
      const V3 center = vec3(j["center"], at + ".center");
      const V3 size = vec3(j["size"], at + ".size");
      if (!(size.array() > 0).all()) fail(at + ".size", "extents must be positive");
      double yaw = 0.0;
      if (j.contains("yaw")) {
        if (!j["yaw"].is_number() || !std::isfinite(j["yaw"].get<double>())) fail(at + ".yaw", "expected a number");
        yaw = j["yaw"].get<double>();
      }
      const std::string named = kind.value_or(shape);
      return shape == "box" ? TruthShape::box(center, size, named, yaw) : TruthShape::cylinder(center, size, named);
    };
    std::optional<std::string> kind;
    if (j.contains("kind") && j["kind"].is_string()) kind = j["kind"].get<std::string>();
    if (j.contains("shape") && j["shape"] == "heightfield") {
      truth.add(readHeightField(path, j, at, kind));
    } else if (j.contains("shape") && j["shape"] == "union") {
      if (!j.contains("parts") || !j["parts"].is_array() || j["parts"].empty())
        fail(at + ".parts", "a union needs a non-empty \"parts\" array");
      std::vector<TruthShape> parts;
      for (std::size_t p = 0; p < j["parts"].size(); ++p)
        parts.push_back(primitive(j["parts"][p], at + ".parts[" + std::to_string(p) + "]", std::nullopt));
      truth.add(TruthShape::unionOf(kind.value_or("union"), std::move(parts)));
    } else {
      truth.add(primitive(j, at, kind));
    }
  }
  return truth;
}

GroundTruth readObjTruth(const std::string& path, std::istream& in) {
  std::vector<V3> vertices;
  GroundTruth truth;
  std::string label = "mesh";
  std::vector<std::array<V3, 3>> triangles;
  const auto flush = [&] {
    if (!triangles.empty()) truth.shapes.push_back(TruthShape::mesh(label, std::move(triangles)));
    triangles.clear();
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
      label = name.empty() ? "mesh" : name;
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
        triangles.push_back({vertices[ring[0]], vertices[ring[k]], vertices[ring[k + 1]]});
    }
  }
  flush();
  if (truth.shapes.empty()) throw Error(path + ": no faces");
  return truth;
}

}  // namespace

TruthShape TruthShape::box(const V3& center, const V3& size, const std::string& kind, double yaw) {
  TruthShape s = ofKind(Shape::kBox, kind);
  s.center = center;
  s.size = size;
  s.yaw = yaw;
  setPrimitiveAabb(s);
  return s;
}

TruthShape TruthShape::cylinder(const V3& center, const V3& size, const std::string& kind) {
  TruthShape s = ofKind(Shape::kCylinder, kind);
  s.center = center;
  s.size = size;
  setPrimitiveAabb(s);
  return s;
}

TruthShape TruthShape::unionOf(const std::string& kind, std::vector<TruthShape> parts) {
  TruthShape s = ofKind(Shape::kUnion, kind);
  s.parts = std::move(parts);
  s.aabb_min = V3::Constant(kInf);
  s.aabb_max = V3::Constant(-kInf);
  for (const auto& part : s.parts) {
    s.aabb_min = s.aabb_min.cwiseMin(part.aabb_min);
    s.aabb_max = s.aabb_max.cwiseMax(part.aabb_max);
  }
  return s;
}

TruthShape TruthShape::mesh(const std::string& label, std::vector<std::array<V3, 3>> triangles) {
  TruthShape s = ofKind(Shape::kMesh, "mesh");
  s.label = label;
  s.triangles = std::move(triangles);
  s.aabb_min = V3::Constant(kInf);
  s.aabb_max = V3::Constant(-kInf);
  for (const auto& t : s.triangles)
    for (const auto& v : t) {
      s.aabb_min = s.aabb_min.cwiseMin(v);
      s.aabb_max = s.aabb_max.cwiseMax(v);
    }
  return s;
}

TruthShape TruthShape::heightField(HeightGrid grid, const std::string& kind) {
  const auto fail = [&](const std::string& what) { throw Error("ground truth: heightfield " + kind + ": " + what); };
  if (grid.nx < 2 || grid.ny < 2) fail("needs at least 2 x 2 nodes");
  if (grid.heights.size() / grid.nx != grid.ny || grid.heights.size() % grid.nx != 0)
    fail("needs nx * ny heights, got " + std::to_string(grid.heights.size()));
  if (!(grid.step > 0) || !std::isfinite(grid.step) || !grid.origin.allFinite()) fail("needs a finite step > 0");
  TruthShape s = ofKind(Shape::kHeightField, kind);
  s.surface = true;
  double lo = kInf, hi = -kInf;
  for (double h : grid.heights) {
    if (!std::isfinite(h)) fail("non-finite height");
    lo = std::min(lo, h);
    hi = std::max(hi, h);
  }
  s.aabb_min = V3(grid.origin.x(), grid.origin.y(), lo);
  s.aabb_max = V3(grid.corner().x(), grid.corner().y(), hi);
  s.grid = std::move(grid);
  return s;
}

std::optional<double> HeightGrid::heightAt(const Eigen::Vector2d& xy) const {
  const Eigen::Vector2d far = corner();
  if (!(xy.array() >= origin.array()).all() || !(xy.array() <= far.array()).all()) return std::nullopt;
  const Eigen::Vector2d u = (xy - origin) / step;
  const std::size_t i = std::min(std::size_t(u.x()), nx - 2), j = std::min(std::size_t(u.y()), ny - 2);
  const double fu = u.x() - double(i), fv = u.y() - double(j);
  const double a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
  // Triangle (a, b, c) where fu >= fv, else (a, c, d).
  return fu >= fv ? a + fu * (b - a) + fv * (c - b) : a + fv * (d - a) + fu * (c - d);
}

double HeightGrid::distance(const V3& p) const {
  const Eigen::Vector2d xy = p.head<2>();
  const Eigen::Vector2d near = xy.cwiseMax(origin).cwiseMin(corner());
  // The surface point over the grid's point nearest p's (x, y) bounds the answer: only cells whose
  // square lies within that bound of p's (x, y) can hold a nearer point.
  double best2 = (xy - near).squaredNorm() + std::pow(p.z() - *heightAt(near), 2);
  const double reach = std::sqrt(best2);
  const auto cells = [&](double v, double o, std::size_t n) {
    const double last = double(n - 2);
    const double lo = std::clamp(std::floor((v - reach - o) / step), 0.0, last);
    const double hi = std::clamp(std::floor((v + reach - o) / step), 0.0, last);
    return std::pair<std::size_t, std::size_t>(std::size_t(lo), std::size_t(hi));
  };
  const auto [i0, i1] = cells(p.x(), origin.x(), nx);
  const auto [j0, j1] = cells(p.y(), origin.y(), ny);
  // Distance from v to [lo, lo + span] along one axis.
  const auto outside = [](double v, double lo, double span) { return std::max({0.0, lo - v, v - lo - span}); };
  for (std::size_t j = j0; j <= j1; ++j) {
    const double y = origin.y() + step * double(j);
    const double dy = outside(p.y(), y, step);
    if (dy * dy >= best2) continue;
    for (std::size_t i = i0; i <= i1; ++i) {
      const double x = origin.x() + step * double(i);
      const double dx = outside(p.x(), x, step);
      const double h00 = at(i, j), h10 = at(i + 1, j), h11 = at(i + 1, j + 1), h01 = at(i, j + 1);
      const double lo = std::min({h00, h10, h11, h01}), hi = std::max({h00, h10, h11, h01});
      const double dz = outside(p.z(), lo, hi - lo);
      if (dx * dx + dy * dy + dz * dz >= best2) continue;
      const V3 a(x, y, h00), b(x + step, y, h10), c(x + step, y + step, h11), d(x, y + step, h01);
      best2 = std::min(best2, (p - collision::closestPointOnTriangle(p, a, b, c)).squaredNorm());
      best2 = std::min(best2, (p - collision::closestPointOnTriangle(p, a, c, d)).squaredNorm());
    }
  }
  return std::sqrt(best2);
}

TruthShapeRange TruthShape::primitives() const {
  return shape == Shape::kUnion ? TruthShapeRange(parts.data(), parts.size()) : TruthShapeRange(this, 1);
}

double TruthShape::signedDistance(const V3& p) const {
  switch (shape) {
    case Shape::kBox: {
      const V3 d = p - center;
      const double c = std::cos(yaw), s = std::sin(yaw);
      const V3 local(c * d.x() + s * d.y(), -s * d.x() + c * d.y(), d.z());
      return boxDistance<V3>(local.cwiseAbs() - 0.5 * size);
    }
    case Shape::kCylinder: {
      const V3 d = p - center;
      const Eigen::Vector2d q(std::hypot(d.x(), d.y()) - 0.5 * size.x(), std::abs(d.z()) - 0.5 * size.z());
      return boxDistance<Eigen::Vector2d>(q);
    }
    case Shape::kUnion: {
      double best = kInf;
      for (const auto& part : parts) best = std::min(best, part.signedDistance(p));
      return best;
    }
    case Shape::kMesh: {
      double best = kInf;
      double winding = 0.0;
      for (const auto& t : triangles) {
        best = std::min(best, (p - collision::closestPointOnTriangle(p, t[0], t[1], t[2])).norm());
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
    case Shape::kHeightField: {
      const double d = grid.distance(p);
      const std::optional<double> h = grid.heightAt(p.head<2>());
      return h && p.z() < *h ? -d : d;
    }
  }
  return kInf;
}

void GroundTruth::add(TruthShape shape) {
  shape.label = shape.kind + " " + std::to_string(shapes.size());
  shapes.push_back(std::move(shape));
}

std::vector<TruthShape> GroundTruth::primitives() const {
  std::vector<TruthShape> out;
  for (const auto& s : shapes)
    for (const auto& p : s.primitives()) out.push_back(p);
  return out;
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

nlohmann::json groundTruthToJson(const GroundTruth& truth, bool write_kinds) {
  nlohmann::json list = nlohmann::json::array();
  for (const TruthShape& s : truth.shapes) {
    nlohmann::json entry;
    if (s.shape == TruthShape::Shape::kMesh) throw Error("ground truth: " + s.label + ": a mesh has no JSON form");
    if (s.shape == TruthShape::Shape::kHeightField) {
      const HeightGrid& g = s.grid;
      entry = {{"shape", "heightfield"},
               {"origin", {g.origin.x(), g.origin.y()}},
               {"step", g.step},
               {"size", {g.nx, g.ny}},
               {"heights", g.heights}};
    } else if (s.shape == TruthShape::Shape::kUnion) {
      entry["shape"] = "union";
      nlohmann::json parts = nlohmann::json::array();
      for (const TruthShape& part : s.parts) parts.push_back(primitiveToJson(part));
      entry["parts"] = parts;
    } else {
      entry = primitiveToJson(s);
    }
    if (write_kinds) entry["kind"] = s.kind;
    list.push_back(entry);
  }
  return list;
}

}  // namespace hullmap::sim

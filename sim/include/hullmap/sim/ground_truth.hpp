#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace hullmap::sim {

struct TruthShape;

/// A terrain's heights on a square grid, z = h(x, y), map frame, map units. The surface is
/// triangulated: each cell (i, j)-(i + 1, j + 1) is two triangles split along its diagonal from node
/// (i, j) to node (i + 1, j + 1). Built by TruthShape::heightField, which checks it.
struct HeightGrid {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  ///< (x, y) of node (0, 0)
  double step = 1.0;                                 ///< node spacing along x and along y, > 0
  std::size_t nx = 0, ny = 0;                        ///< nodes along x and along y, >= 2 each
  /// Row-major, a row per y: heights[j * nx + i] is z at node (i, j), (x, y) = origin + step (i, j).
  std::vector<double> heights;

  double at(std::size_t i, std::size_t j) const { return heights[j * nx + i]; }
  /// (x, y) of the last node, origin + step (nx - 1, ny - 1): the grid covers [origin, corner()].
  Eigen::Vector2d corner() const { return origin + step * Eigen::Vector2d(double(nx - 1), double(ny - 1)); }
  /// The surface's height at (x, y), on its triangles; nothing outside [origin, corner()].
  std::optional<double> heightAt(const Eigen::Vector2d& xy) const;
  /// Exact distance from p (finite) to the triangulated surface: the closest point of each triangle
  /// that can be nearer than the surface point over the grid's point nearest p. Visits the cells
  /// within that point's distance r of p in (x, y): O(r^2 / step^2) of them, few near the surface.
  double distance(const Eigen::Vector3d& p) const;
};

/// A run of shapes lying one after another in memory (a union's parts, or one shape alone), for
/// range-for; valid while the shape it was taken from is.
class TruthShapeRange {
 public:
  TruthShapeRange(const TruthShape* first, std::size_t count) : first_(first), count_(count) {}
  const TruthShape* begin() const { return first_; }
  const TruthShape* end() const;
  std::size_t size() const { return count_; }
  const TruthShape& operator[](std::size_t i) const;

 private:
  const TruthShape* first_;
  std::size_t count_;
};

/// One true obstacle, z-up map frame, map units (metres for a metric map): what the scene
/// generator makes, ground_truth.json holds and evaluate scores against.
struct TruthShape {
  enum class Shape { kBox, kCylinder, kMesh, kUnion, kHeightField } shape = Shape::kBox;
  /// What it is: the JSON's "kind" ("box", "table", "wall", "floor", "ground", ...); without one,
  /// the shape's name ("box", "cylinder", "union", "mesh", "heightfield").
  std::string kind = "box";
  std::string label;  ///< "box 3", "table 6" (kind and index), or the OBJ object's name
  /// A floor, ceiling or height field: a bound of the map, left out of the obstacles; random segments
  /// stay between them (docs/DESIGN_NOTES.md, "ground_truth.hpp: TruthShape::surface").
  bool surface = false;
  std::vector<TruthShape> parts;                          ///< kUnion: the primitives (boxes, cylinders)
  Eigen::Vector3d center = Eigen::Vector3d::Zero();       ///< box centre; cylinder axis centre
  Eigen::Vector3d size = Eigen::Vector3d::Ones();         ///< box extents; cylinder (2r, 2r, height)
  double yaw = 0.0;                                       ///< box rotation about z, radians
  std::vector<std::array<Eigen::Vector3d, 3>> triangles;  ///< mesh: a closed surface
  HeightGrid grid;                                        ///< height field: the terrain
  Eigen::Vector3d aabb_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d aabb_max = Eigen::Vector3d::Zero();

  /// A box of `size` centred at `center`, turned by `yaw` about z, of `kind`, with its aabb. The
  /// factories label a shape by its kind and mark kinds "floor" and "ceiling" as surfaces.
  static TruthShape box(const Eigen::Vector3d& center, const Eigen::Vector3d& size, const std::string& kind = "box",
                        double yaw = 0.0);
  /// An upright cylinder, `size` (2r, 2r, height), its axis centred at `center`, of `kind`, with its aabb.
  static TruthShape cylinder(const Eigen::Vector3d& center, const Eigen::Vector3d& size,
                             const std::string& kind = "cylinder");
  /// The union of `parts` (boxes and cylinders), of `kind`, its aabb theirs.
  static TruthShape unionOf(const std::string& kind, std::vector<TruthShape> parts);
  /// A closed triangle mesh of kind "mesh", labelled `label`, with its aabb.
  static TruthShape mesh(const std::string& label, std::vector<std::array<Eigen::Vector3d, 3>> triangles);
  /// A terrain, of `kind`, always a surface: its solid is everything below the grid's surface over
  /// [origin, corner()]; its aabb spans that in x and y and the heights' range in z. Throws
  /// hullmap::Error when the grid is not nx x ny >= 2 x 2 finite heights at a finite step > 0.
  static TruthShape heightField(HeightGrid grid, const std::string& kind = "heightfield");

  /// The primitives it is made of: a union's parts, else the shape itself.
  TruthShapeRange primitives() const;

  /// Exact signed distance: negative inside, positive outside. A mesh is inside by its winding
  /// number (>= 1/2), its distance the exact point-triangle minimum. A height field: the distance to
  /// its triangulated surface (HeightGrid::distance), negative below the surface over the grid; its
  /// vertical sides are no part of it (beside the grid the distance is to the surface's rim).
  double signedDistance(const Eigen::Vector3d& p) const;
};

inline const TruthShape* TruthShapeRange::end() const { return first_ + count_; }
inline const TruthShape& TruthShapeRange::operator[](std::size_t i) const { return first_[i]; }

/// The ground truth: boxes and cylinders (walls and floors are boxes), unions of them, height fields
/// (terrain) and/or meshes.
struct GroundTruth {
  std::vector<TruthShape> shapes;

  /// Appends `shape` labelled "<kind> <index>", as readGroundTruth labels the shapes of a JSON file.
  void add(TruthShape shape);
  /// Copies of every shape's primitives (TruthShape::primitives), in order.
  std::vector<TruthShape> primitives() const;
  /// Smallest signed distance over the shapes (+infinity without shapes).
  double signedDistance(const Eigen::Vector3d& p) const;
};

/// Reads ground truth: a JSON file as maps/room/ground_truth.json ({"obstacles": [{"shape": "box" |
/// "cylinder", "center": [x,y,z], "size": [sx,sy,sz], optional "yaw"}]}; "shape": "union" with
/// "parts": [primitives] for an object made of several (maps/README.md); "shape": "heightfield" with
/// "origin": [x, y], "step", "size": [nx, ny] and "heights" (nx * ny, row-major) for a terrain;
/// optional "kind", where "floor" and "ceiling" mark a bounding surface), or an OBJ mesh (`v` and
/// `f` lines; each `o` object one true obstacle, the whole file one when it has none; polygons are
/// fanned). Throws hullmap::Error "<path>: <what>" (line numbers for OBJ).
GroundTruth readGroundTruth(const std::string& path);

/// The "obstacles" array of ground_truth.json, which readGroundTruth reads back as `truth`: with
/// `write_kinds` each shape's "kind"; without, none (the reader then takes each shape's name for its
/// kind, as for plain boxes and cylinders). Throws hullmap::Error for a mesh, which has no JSON form.
nlohmann::json groundTruthToJson(const GroundTruth& truth, bool write_kinds);

}  // namespace hullmap::sim

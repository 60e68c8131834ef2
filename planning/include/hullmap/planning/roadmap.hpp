#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/hulls/obstacles.hpp"

namespace hullmap::planning {

/// Axis-aligned rectangle in the ground plane (z-up map frame, metres).
struct Bounds2d {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
};

/// Settings of buildRoadmap. Units: metres, z-up map frame.
struct RoadmapParams {
  double z0 = -1e300;  ///< flight band: obstacles whose [z_min, z_max] meets [z0, z1] count
  double z1 = 1e300;
  std::optional<Bounds2d> bounds;  ///< default: the obstacles' footprint bounds grown by `margin`
  double margin = 1.0;             ///< growth of the default bounds on every side, metres (> 0)
  /// Edges whose clearance is below this plus `tolerance` are dropped (this is the radius R): a kept
  /// edge's polyline, whose chords lie up to `tolerance` nearer than its arc, keeps R.
  double min_clearance = 0.0;
  double tolerance = 1e-3;  ///< parabolic arcs: every polyline point lies on the arc, and every
                            ///< chord is within this distance of it (metres, > 0)
};

/// A roadmap node: a Voronoi vertex, ground plane.
struct RoadmapNode {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
};

/// Where a Voronoi edge's defining site comes from.
struct SiteRef {
  int obstacle = -1;  ///< index into Roadmap::footprints; -1: the bounds
  bool is_point = false;
  Eigen::Vector2d a = Eigen::Vector2d::Zero();  ///< the point, or the segment's first end
  Eigen::Vector2d b = Eigen::Vector2d::Zero();  ///< the segment's second end (== a for a point)
};

/// A roadmap edge: a piece of the generalized Voronoi diagram between two sites of different
/// obstacles (or an obstacle and the bounds).
struct RoadmapEdge {
  int from = 0;  ///< node indices; polyline.front() is node `from`
  int to = 0;
  std::vector<Eigen::Vector2d> polyline;  ///< points on the exact bisector; straight edges have 2
  double length = 0.0;                    ///< of the polyline, metres
  double clearance = 0.0;                 ///< min distance to the nearest site along the exact arc
  SiteRef site_a;                         ///< the two sites the edge is equidistant to
  SiteRef site_b;
};

/// The roadmap graph and how it was made.
struct Roadmap {
  Bounds2d bounds;
  double z0 = 0.0, z1 = 0.0;  ///< the band used: as given, less what the surfaces take
  double min_clearance = 0.0;
  double tolerance = 0.0;
  /// The sites' polygons, counter-clockwise outer boundaries: the parts' footprints in the band,
  /// clipped to the bounds, those that meet merged into their exact union (rounded to double).
  std::vector<std::vector<Eigen::Vector2d>> footprints;
  /// The holes of each footprint (free space enclosed by it, e.g. a room inside a ring of walls);
  /// empty for most; parallel to footprints.
  std::vector<std::vector<std::vector<Eigen::Vector2d>>> holes;
  std::vector<std::vector<int>> obstacle_groups;  ///< Obstacle::id of each footprint's members
  std::vector<RoadmapNode> nodes;
  std::vector<RoadmapEdge> edges;
};

/// Exact generalized Voronoi diagram of the footprints in the band, inside the bounds, with CGAL's
/// segment Delaunay graph (filtered exact predicates; sites: every footprint edge plus the four
/// bounds edges). The sites are the footprints of the obstacles' convex parts (an obstacle without
/// parts: its footprint), each kept if its own z range meets the band. Footprints are clipped to the
/// bounds, and footprints that touch or overlap are replaced by the exact union of the group (a
/// polygon that may have holes: a ring of walls leaves the room inside free), its outer boundary and
/// hole boundaries inserted as sites. Keeps the Voronoi edges between sites of
/// different obstacles or an obstacle and the bounds, drops edges touching the outside of the
/// bounds, inside a footprint, or with clearance < min_clearance + tolerance. The clearance of an edge is its
/// exact minimum along the arc (closed form per bisector type: point-point, point-segment parabola,
/// segment-segment line), not a sampled one. `surfaces` (a floor, a ceiling: solid half-spaces)
/// bound the band: it is cut to what lies above every floor's solid and below every ceiling's over
/// the bounds (Roadmap::z0, z1 say what is left), so no roadmap point is inside them; a planner's
/// exact checks keep the drone's radius from them. Throws hullmap::Error naming the parameter at
/// fault (empty bounds, tolerance <= 0, a footprint with fewer than 3 vertices naming its id, "z0/z1"
/// when nothing of the band is left between the surfaces).
Roadmap buildRoadmap(const std::vector<hulls::Obstacle>& obstacles, const RoadmapParams& params,
                     const std::vector<collision::Surface>& surfaces = {});

/// Distance from `p` to the site (point or segment), metres.
double siteDistance(const SiteRef& site, const Eigen::Vector2d& p);

/// The roadmap as JSON text (format "hullmap-roadmap/1", documented in docs/PLANNING.md).
std::string roadmapJson(const Roadmap& roadmap);

/// Writes roadmapJson atomically to `path`; throws hullmap::Error naming `path`.
void writeRoadmapJson(const std::string& path, const Roadmap& roadmap);

}  // namespace hullmap::planning

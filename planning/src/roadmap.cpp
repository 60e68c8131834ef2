// buildRoadmap: the Voronoi roadmap of the footprints, in its steps: the band's footprints and the
// bounds, their exact union (mergedFootprints), CGAL's segment Delaunay graph and its vertices
// (voronoiVertices), the traced bisectors and their guard (guardedClearance), the canonical order.
// Its plane geometry is in polygon_2d, roadmap.json in roadmap_json.cpp.
#include "hullmap/planning/roadmap.hpp"
#include "hullmap/core/convex_hull_2d.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Gmpzf.h>
#include <CGAL/Polygon_set_2.h>
#include <CGAL/Segment_Delaunay_graph_filtered_traits_2.h>
#include <CGAL/Segment_Delaunay_graph_hierarchy_2.h>
#include <CGAL/Segment_Delaunay_graph_traits_2.h>
#include <CGAL/Simple_cartesian.h>
#include <Eigen/Geometry>

#include "hullmap/core/error.hpp"
#include "polygon_2d.hpp"

namespace hullmap::planning {
namespace {

// Filtered traits: every predicate is exact (interval arithmetic, falling back to exact numbers);
// Field_with_sqrt_tag lets the constructions (Voronoi vertices) use sqrt in double. Footprints
// that meet are replaced by their exact union first, so sites meet only at shared ends.
using Kernel = CGAL::Simple_cartesian<double>;
// The exact fallback of the filtered predicates computes in a ring (no division): Gmpzf (an exact
// binary float: a GMP integer times a power of two, every double exactly) does ring arithmetic
// without the gcd that the default Gmpq runs after every operation.
using ExactRingKernel = CGAL::Simple_cartesian<CGAL::Gmpzf>;
using Traits = CGAL::Segment_Delaunay_graph_filtered_traits_without_intersections_2<
    Kernel, CGAL::Field_with_sqrt_tag, ExactRingKernel, CGAL::Integral_domain_without_division_tag>;
using Sdg = CGAL::Segment_Delaunay_graph_hierarchy_2<Traits>;  // hierarchy: fast point location
// Voronoi vertices are constructed in double with sqrt: the filtered traits fall back to an exact
// ring construction that divides by zero on some degenerate faces (collinear sites, which voxel
// footprints have plenty of); a non-finite result marks the face unusable instead.
using DoubleTraits = CGAL::Segment_Delaunay_graph_traits_without_intersections_2<Kernel, CGAL::Field_with_sqrt_tag>;
// Exact union of footprints that meet (a ring of wall parts becomes a polygon with a hole).
using ExactKernel = CGAL::Exact_predicates_exact_constructions_kernel;
using ExactPolygon = CGAL::Polygon_2<ExactKernel>;
using ExactPolygonWithHoles = CGAL::Polygon_with_holes_2<ExactKernel>;
using ExactPolygonSet = CGAL::Polygon_set_2<ExactKernel>;

Eigen::Vector2d toEigen(const Kernel::Point_2& p) { return {CGAL::to_double(p.x()), CGAL::to_double(p.y())}; }

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void unite(int a, int b) { parent[find(a)] = find(b); }
};

/// Which footprints (by index) and whether the bounds have `p` on their boundary, within `eps`.
/// Geometric, because CGAL splits overlapping collinear edges of different obstacles into pieces
/// whose ends come from different input segments.
struct Boundaries {
  std::vector<std::vector<std::vector<Eigen::Vector2d>>> polygons;  ///< per footprint: outer, holes
  std::vector<Eigen::AlignedBox<double, 2>> boxes;
  Eigen::AlignedBox<double, 2> bounds;
  double eps = 0.0;

  std::vector<int> owners(const Eigen::Vector2d& p) const {
    std::vector<int> out;
    for (std::size_t i = 0; i < polygons.size(); ++i) {
      if (boxes[i].exteriorDistance(p) > eps) continue;
      bool on = false;
      for (const auto& poly : polygons[i])
        for (std::size_t k = 0; k < poly.size() && !on; ++k)
          on = segmentDistance(poly[k], poly[(k + 1) % poly.size()], p) <= eps;
      if (on) out.push_back(static_cast<int>(i));
    }
    const Eigen::Vector2d lo = bounds.min(), hi = bounds.max();
    if (std::min({std::abs(p.x() - lo.x()), std::abs(p.x() - hi.x()), std::abs(p.y() - lo.y()),
                  std::abs(p.y() - hi.y())}) <= eps)
      out.push_back(static_cast<int>(polygons.size()));
    return out;
  }
};

SiteRef siteRef(const Sdg::Site_2& s, const std::vector<int>& owner, int bounds_owner) {
  SiteRef r;
  r.obstacle = owner.empty() || owner.front() == bounds_owner ? -1 : owner.front();
  r.is_point = s.is_point();
  if (s.is_point()) {
    r.a = r.b = toEigen(s.point());
  } else {
    const auto seg = s.segment();
    r.a = toEigen(seg.source());
    r.b = toEigen(seg.target());
  }
  return r;
}

/// Fills edge.polyline between the Voronoi vertices a and b and edge.clearance, per bisector type.
void traceBisector(RoadmapEdge& edge, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double tolerance) {
  const SiteRef& sa = edge.site_a;
  const SiteRef& sb = edge.site_b;
  edge.polyline = {a, b};
  if (sa.is_point && sb.is_point) {
    // Straight bisector; the distance to a point along a segment is minimal at its closest point.
    edge.clearance = segmentDistance(a, b, sa.a);
    return;
  }
  if (!sa.is_point && !sb.is_point) {
    // Straight bisector; the distance to a segment's interior is linear along it: min at an end.
    edge.clearance = std::min(siteDistance(sa, a), siteDistance(sa, b));
    return;
  }
  // Point p and segment s: a parabola. With t along s's line and n its normal towards p, the arc is
  // foot(t) + h(t) n with h(t) = ((t - tp)^2 + d^2) / (2 d): the distance to both sites, minimal
  // at t = tp. A chord over [t, t + dt] lies within dt^2 / (8 d) of the arc (measured along n, an
  // upper bound of the true distance), so dt = sqrt(8 d tolerance) keeps every chord within it.
  const SiteRef& point = sa.is_point ? sa : sb;
  const SiteRef& segment = sa.is_point ? sb : sa;
  const Eigen::Vector2d o = segment.a;
  const Eigen::Vector2d u = (segment.b - segment.a).normalized();
  Eigen::Vector2d n(-u.y(), u.x());
  double d = (point.a - o).dot(n);
  if (d < 0) {
    n = -n;
    d = -d;
  }
  const double tp = (point.a - o).dot(u);
  const double ta = (a - o).dot(u);
  const double tb = (b - o).dot(u);
  auto h = [&](double t) { return ((t - tp) * (t - tp) + d * d) / (2 * d); };
  if (!(d > 1e-12)) {
    edge.clearance = std::min(siteDistance(point, a), siteDistance(point, b));
    return;
  }
  edge.clearance = h(std::clamp(tp, std::min(ta, tb), std::max(ta, tb)));
  const double step = std::sqrt(8 * d * tolerance);
  const auto pieces = static_cast<std::size_t>(std::min(1e5, std::ceil(std::abs(tb - ta) / step)));
  if (pieces <= 1) return;
  edge.polyline.clear();
  edge.polyline.push_back(a);
  for (std::size_t i = 1; i < pieces; ++i) {
    const double t = ta + (tb - ta) * static_cast<double>(i) / static_cast<double>(pieces);
    edge.polyline.push_back(o + t * u + h(t) * n);
  }
  edge.polyline.push_back(b);
}

/// The band with the floor and ceiling taken out: above the highest point of each floor-like
/// surface's solid over the bounds rectangle [lo, hi] (its normal up), below the lowest point of each
/// ceiling-like one's. Throws hullmap::Error naming z0/z1 when nothing of the band is left.
std::pair<double, double> bandBetweenSurfaces(double z0, double z1, const std::vector<collision::Surface>& surfaces,
                                              const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  const double given0 = z0, given1 = z1;
  std::string limiting;
  for (const auto& h : surfaces) {
    if (h.field) continue;  // the ground's height varies: the checks keep the roadmap's edges off it
    if (std::abs(h.normal.z()) < 1e-9) continue;  // a wall-like surface bounds no height
    double extreme =
        h.normal.z() > 0 ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
    for (const Eigen::Vector2d& c : {lo, Eigen::Vector2d(hi.x(), lo.y()), hi, Eigen::Vector2d(lo.x(), hi.y())}) {
      const double z = (h.offset - h.normal.x() * c.x() - h.normal.y() * c.y()) / h.normal.z();
      extreme = h.normal.z() > 0 ? std::max(extreme, z) : std::min(extreme, z);
    }
    if (h.normal.z() > 0 && extreme > z0) {
      z0 = extreme;
      limiting = h.name;
    }
    if (h.normal.z() < 0 && extreme < z1) {
      z1 = extreme;
      limiting = h.name;
    }
  }
  if (!(z0 <= z1)) {
    std::ostringstream s;
    s << "the flight band " << given0 << " .. " << given1 << " lies inside the " << limiting << " (its solid reaches "
      << (z0 > given1 ? z0 : z1) << " over the bounds): raise or lower the band";
    throw Error::inParameter("z0/z1", s.str());
  }
  return {z0, z1};
}

bool pointLess(const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
  return std::make_pair(p.x(), p.y()) < std::make_pair(q.x(), q.y());
}

bool siteLess(const SiteRef& s, const SiteRef& t) {
  return std::make_tuple(s.obstacle, s.is_point, s.a.x(), s.a.y(), s.b.x(), s.b.y()) <
         std::make_tuple(t.obstacle, t.is_point, t.a.x(), t.a.y(), t.b.x(), t.b.y());
}

/// Numbers the nodes by position (x, then y) and orders the edges by their nodes (from < to, the
/// polyline and the sites turned with them), then by polyline: the same roadmap, whatever order the
/// SDG gave its faces and edges in.
void canonicalOrder(Roadmap& map) {
  std::vector<int> order(map.nodes.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int i, int j) { return pointLess(map.nodes[i].position, map.nodes[j].position); });
  std::vector<int> rank(order.size());
  std::vector<RoadmapNode> nodes;
  nodes.reserve(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    rank[order[k]] = static_cast<int>(k);
    nodes.push_back(map.nodes[order[k]]);
  }
  map.nodes = std::move(nodes);
  for (RoadmapEdge& e : map.edges) {
    e.from = rank[e.from];
    e.to = rank[e.to];
    if (e.from > e.to) {
      std::swap(e.from, e.to);
      std::reverse(e.polyline.begin(), e.polyline.end());
      std::swap(e.site_a, e.site_b);
    }
  }
  std::sort(map.edges.begin(), map.edges.end(), [](const RoadmapEdge& e, const RoadmapEdge& f) {
    if (e.from != f.from || e.to != f.to) return std::make_pair(e.from, e.to) < std::make_pair(f.from, f.to);
    if (e.polyline.size() != f.polyline.size()) return e.polyline.size() < f.polyline.size();
    if (e.polyline != f.polyline)
      return std::lexicographical_compare(e.polyline.begin(), e.polyline.end(), f.polyline.begin(), f.polyline.end(),
                                          pointLess);
    return siteLess(e.site_a, f.site_a) || (!siteLess(f.site_a, e.site_a) && siteLess(e.site_b, f.site_b));
  });
}

using Ring = std::vector<Eigen::Vector2d>;
using Rings = std::vector<Ring>;  ///< a footprint: its outer ring, then its holes
using Band = std::vector<std::pair<const hulls::Footprint*, int>>;

/// The footprints in the height band [params.z0, params.z1] with their obstacle's id: each convex
/// part's, or the obstacle's own when it has no parts.
Band bandFootprints(const std::vector<hulls::Obstacle>& obstacles, const RoadmapParams& params) {
  Band band;
  auto add = [&](const hulls::Footprint& f, int id) {
    if (f.z_max < params.z0 || f.z_min > params.z1) return;
    if (f.polygon.size() < 3)
      throw Error("obstacle " + std::to_string(id) + ": footprint has " + std::to_string(f.polygon.size()) +
                  " vertices, expected >= 3");
    band.emplace_back(&f, id);
  };
  for (const auto& o : obstacles) {
    if (o.parts.empty()) add(o.footprint, o.id);
    for (const auto& part : o.parts) add(part.footprint, o.id);
  }
  return band;
}

/// params.bounds, else the box of the band's footprints grown by params.margin (0 around the origin
/// when the band is empty). Throws naming `margin` or `bounds`.
Bounds2d roadmapBounds(const Band& band, const RoadmapParams& params) {
  if (params.bounds) return *params.bounds;
  if (!(params.margin > 0)) throw Error::inParameter("margin", "must be > 0");
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  for (const auto& [footprint, id] : band)
    for (const auto& p : footprint->polygon) {
      x0 = std::min(x0, p.x());
      y0 = std::min(y0, p.y());
      x1 = std::max(x1, p.x());
      y1 = std::max(y1, p.y());
    }
  if (band.empty()) x0 = y0 = x1 = y1 = 0.0;
  return {x0 - params.margin, y0 - params.margin, x1 + params.margin, y1 + params.margin};
}

Eigen::AlignedBox<double, 2> boxOf(const Ring& poly) {
  Eigen::AlignedBox<double, 2> b(poly.front(), poly.front());
  for (const auto& p : poly) b.extend(p);
  return b;
}

bool ringLess(const Ring& a, const Ring& b) {
  return std::lexicographical_compare(a.begin(), a.end(), b.begin(), b.end(), pointLess);
}

/// An exact ring of the union rounded to double once, in a canonical form: vertices exactly between
/// their neighbours dropped (the same polygon: chains of collinear sites make degenerate SDG faces
/// whose Voronoi vertex cannot be constructed in double), vertices within `hair` of the one before
/// merged into it, starting at the lexicographically least vertex.
Ring exactRingToDouble(const ExactPolygon& poly, double hair) {
  std::vector<ExactKernel::Point_2> kept;
  for (auto v = poly.vertices_begin(); v != poly.vertices_end(); ++v) kept.push_back(*v);
  for (bool changed = true; changed && kept.size() > 3;) {
    changed = false;
    for (std::size_t i = 0; i < kept.size() && kept.size() > 3; ++i) {
      const auto& prev = kept[(i + kept.size() - 1) % kept.size()];
      const auto& next = kept[(i + 1) % kept.size()];
      if (CGAL::collinear(prev, kept[i], next) && CGAL::collinear_are_ordered_along_line(prev, kept[i], next)) {
        kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(i));
        changed = true;
        --i;
      }
    }
  }
  Ring out;
  for (auto v = kept.begin(); v != kept.end(); ++v) {
    // Rounded from the exact value (the lazy approximation depends on what was evaluated before).
    // Distinct exact vertices a hair apart (the union's intersection points) would leave a site
    // shorter than a hair, around which the double-precision Voronoi vertices go astray (an edge
    // was drawn straight through the footprint): such a vertex merges into the one before.
    const Eigen::Vector2d p(CGAL::to_double(CGAL::exact(v->x())), CGAL::to_double(CGAL::exact(v->y())));
    if (out.empty() || (p - out.back()).cwiseAbs().maxCoeff() > hair) out.push_back(p);
  }
  while (out.size() > 1 && (out.front() - out.back()).cwiseAbs().maxCoeff() <= hair) out.pop_back();
  // Start at the least vertex: CGAL's output order varies from run to run, and the SDG's insertion
  // order decides how degenerate (co-circular) faces are split.
  std::rotate(out.begin(), std::min_element(out.begin(), out.end(), pointLess), out.end());
  return out;
}

/// The band's footprints clipped to the bounds (shrunk by a hair, so none touches them), then every
/// group of footprints that meet (touch, overlap or come within a hair) replaced by the exact union
/// of its members (a polygon with holes: a ring of wall parts keeps the room inside it free). The
/// union is computed with exact constructions and rounded to double once; it leaves CGAL only sites
/// that meet at shared ends. Fills map.footprints, holes and obstacle_groups; returns the same
/// footprints as rings.
std::vector<Rings> mergedFootprints(const Band& band, const Bounds2d& bb, double hair, Roadmap& map) {
  std::vector<Ring> clipped;
  std::vector<int> clipped_id;
  for (const auto& [footprint, id] : band) {
    auto c = clipToBox(footprint->polygon, {bb.x0 + hair, bb.y0 + hair}, {bb.x1 - hair, bb.y1 - hair});
    if (c.empty()) continue;
    clipped.push_back(std::move(c));
    clipped_id.push_back(id);
  }
  std::vector<Eigen::AlignedBox<double, 2>> boxes;
  for (const auto& poly : clipped) boxes.push_back(boxOf(poly));
  UnionFind meeting(clipped.size());
  {
    std::vector<int> by_x(clipped.size());
    std::iota(by_x.begin(), by_x.end(), 0);
    std::sort(by_x.begin(), by_x.end(), [&](int i, int j) { return boxes[i].min().x() < boxes[j].min().x(); });
    for (std::size_t k = 0; k < by_x.size(); ++k)
      for (std::size_t l = k + 1; l < by_x.size() && boxes[by_x[l]].min().x() <= boxes[by_x[k]].max().x() + hair; ++l) {
        const int i = by_x[k], j = by_x[l];
        if (boxes[i].exteriorDistance(boxes[j]) <= hair && polygonsMeet(clipped[i], clipped[j], hair))
          meeting.unite(i, j);
      }
  }
  std::map<int, std::vector<int>> groups;  // root -> members, in input order
  for (std::size_t i = 0; i < clipped.size(); ++i)
    groups[meeting.find(static_cast<int>(i))].push_back(static_cast<int>(i));

  std::vector<Rings> rings;
  for (const auto& [root, members] : groups) {
    std::vector<int> ids;
    for (int m : members) ids.push_back(clipped_id[m]);
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    if (members.size() == 1) {
      map.footprints.push_back(clipped[members.front()]);
      map.holes.emplace_back();
      map.obstacle_groups.push_back(ids);
      rings.push_back({clipped[members.front()]});
      continue;
    }
    ExactPolygonSet set;
    for (int m : members) {
      ExactPolygon poly;
      for (const auto& p : clipped[m]) poly.push_back(ExactKernel::Point_2(p.x(), p.y()));
      if (poly.orientation() == CGAL::CLOCKWISE) poly.reverse_orientation();
      set.join(poly);
    }
    std::vector<ExactPolygonWithHoles> pieces;
    set.polygons_with_holes(std::back_inserter(pieces));
    const std::size_t first = rings.size();
    for (const auto& piece : pieces) {
      if (piece.is_unbounded()) throw Error("roadmap: the union of footprints is unbounded");
      auto outer = exactRingToDouble(piece.outer_boundary(), hair);
      if (outer.size() < 3) continue;
      std::vector<Ring> holes;
      for (auto h = piece.holes_begin(); h != piece.holes_end(); ++h) {
        auto hole = exactRingToDouble(*h, hair);
        if (hole.size() >= 3) holes.push_back(std::move(hole));
      }
      std::sort(holes.begin(), holes.end(), ringLess);
      rings.push_back({outer});
      for (const auto& hole : holes) rings.back().push_back(hole);
    }
    std::sort(rings.begin() + static_cast<std::ptrdiff_t>(first), rings.end(),
              [&](const auto& a, const auto& b) { return ringLess(a.front(), b.front()); });
    for (std::size_t i = first; i < rings.size(); ++i) {
      map.footprints.push_back(rings[i].front());
      map.holes.emplace_back(rings[i].begin() + 1, rings[i].end());
      map.obstacle_groups.push_back(ids);
    }
    std::vector<Ring> all;
    for (std::size_t i = first; i < rings.size(); ++i) all.insert(all.end(), rings[i].begin(), rings[i].end());
    if (selfIntersecting(all)) {
      // Rounding made the union's boundary cross itself: fall back to the convex hull of the group
      // (conservative: it covers the union, holes included).
      std::vector<Eigen::Vector2d> points;
      for (int m : members) points.insert(points.end(), clipped[m].begin(), clipped[m].end());
      const auto at = static_cast<std::ptrdiff_t>(first);
      rings.erase(rings.begin() + at, rings.end());
      map.footprints.erase(map.footprints.begin() + at, map.footprints.end());
      map.holes.erase(map.holes.begin() + at, map.holes.end());
      map.obstacle_groups.erase(map.obstacle_groups.begin() + at, map.obstacle_groups.end());
      map.footprints.push_back(hullmap::core::convexHull2d(points));
      map.holes.emplace_back();
      map.obstacle_groups.push_back(ids);
      rings.push_back({map.footprints.back()});
    }
  }
  return rings;
}

/// The Voronoi vertices of an SDG: one per finite face (face_index), the faces whose vertices
/// coincide merged (co-circular sites, common with boxes: the graph stays connected through them),
/// every vertex snapped to a lattice of 2^-32 of `scale`.
struct VoronoiVertices {
  std::map<Sdg::Face_handle, int> face_index;
  std::vector<Eigen::Vector2d> vertex;  ///< per face; not finite where no construction succeeded
  UnionFind merged{0};                  ///< faces with one vertex
};

VoronoiVertices voronoiVertices(const Sdg& sdg, double scale) {
  VoronoiVertices out;
  auto& vertex = out.vertex;
  const auto construct = DoubleTraits().construct_svd_vertex_2_object();
  for (auto f = sdg.finite_faces_begin(); f != sdg.finite_faces_end(); ++f) {
    out.face_index.emplace(f, static_cast<int>(vertex.size()));
    vertex.push_back(toEigen(construct(f->vertex(0)->site(), f->vertex(1)->site(), f->vertex(2)->site())));
  }
  // A face whose construction failed in double (two parallel segments and a point: the division
  // has no finite result) gets its vertex by Newton's method on the two equal-distance conditions,
  // from the mean of its neighbours' vertices, and keeps it only when the three distances agree.
  // Dropping the face cut the roadmap in two where it is the only link (a build's scene, seed 7).
  const auto distanceToSite = [](const Sdg::Site_2& s, const Eigen::Vector2d& x) {
    return s.is_point() ? (x - toEigen(s.point())).norm()
                        : segmentDistance(toEigen(s.segment().source()), toEigen(s.segment().target()), x);
  };
  for (auto f = sdg.finite_faces_begin(); f != sdg.finite_faces_end(); ++f) {
    Eigen::Vector2d& v = vertex[static_cast<std::size_t>(out.face_index.at(f))];
    if (v.allFinite()) continue;
    Eigen::Vector2d x = Eigen::Vector2d::Zero();
    int from = 0;
    for (int k = 0; k < 3; ++k) {
      const auto g = f->neighbor(k);
      if (sdg.is_infinite(g)) continue;
      const Eigen::Vector2d& w = vertex[static_cast<std::size_t>(out.face_index.at(g))];
      if (w.allFinite()) {
        x += w;
        ++from;
      }
    }
    if (from == 0) continue;
    x /= from;
    const Sdg::Site_2 s0 = f->vertex(0)->site(), s1 = f->vertex(1)->site(), s2 = f->vertex(2)->site();
    const auto residual = [&](const Eigen::Vector2d& p) {
      const double d0 = distanceToSite(s0, p);
      return Eigen::Vector2d(d0 - distanceToSite(s1, p), d0 - distanceToSite(s2, p));
    };
    const double h = 1e-7 * scale;
    for (int iteration = 0; iteration < 50; ++iteration) {
      const Eigen::Vector2d r = residual(x);
      if (r.norm() <= 1e-12 * scale) break;
      Eigen::Matrix2d jacobian;
      jacobian.col(0) = (residual(x + Eigen::Vector2d(h, 0)) - residual(x - Eigen::Vector2d(h, 0))) / (2 * h);
      jacobian.col(1) = (residual(x + Eigen::Vector2d(0, h)) - residual(x - Eigen::Vector2d(0, h))) / (2 * h);
      if (!(std::abs(jacobian.determinant()) > 0)) break;
      x -= jacobian.inverse() * r;
      if (!x.allFinite()) break;
    }
    if (x.allFinite() && residual(x).cwiseAbs().maxCoeff() <= 1e-9 * scale) v = x;
  }
  // Constructions are in double: one vertex computed from different faces differs by ~1e-8 m.
  const double same = 1e-6 * scale;
  out.merged = UnionFind(vertex.size());
  {
    std::vector<int> by_x(vertex.size());
    std::iota(by_x.begin(), by_x.end(), 0);
    std::sort(by_x.begin(), by_x.end(), [&](int i, int j) { return vertex[i].x() < vertex[j].x(); });
    for (std::size_t k = 0; k < by_x.size(); ++k)
      for (std::size_t l = k + 1; l < by_x.size() && vertex[by_x[l]].x() - vertex[by_x[k]].x() <= same; ++l)
        if ((vertex[by_x[k]] - vertex[by_x[l]]).norm() <= same) out.merged.unite(by_x[k], by_x[l]);
  }
  // The SDG splits co-circular sites' faces in an order that follows heap addresses (it varied
  // from run to run), and the same Voronoi vertex constructed from other faces differs in its last
  // bits: snapped to a lattice of 2^-32 of the map's scale (about 1e-10 of it), the nodes are the
  // same on every run; canonicalOrder then numbers them and their edges independently of the SDG.
  const double quantum = std::ldexp(scale, -32);
  for (Eigen::Vector2d& v : vertex)
    if (v.allFinite()) v = (v / quantum).array().round().matrix() * quantum;
  return out;
}

/// A guard on the construction: an edge's polyline chords against every footprint boundary near it.
/// Where a Voronoi vertex constructed in double went astray, the edge may pass closer to a third
/// footprint than to its sites: the clearance then measured, else edge.clearance. (Chords of a
/// parabola lie up to the tolerance nearer its focus, so only a shortfall beyond it counts.)
double guardedClearance(const RoadmapEdge& edge, const std::vector<Rings>& rings,
                        const std::vector<Eigen::AlignedBox<double, 2>>& boxes, const BoxGrid& grid, double tolerance) {
  Eigen::AlignedBox<double, 2> reach(edge.polyline.front(), edge.polyline.front());
  for (const auto& p : edge.polyline) reach.extend(p);
  double measured = edge.clearance;
  const auto near = [&](const Eigen::Vector2d& c, const Eigen::Vector2d& d) {
    return Eigen::AlignedBox<double, 2>(c.cwiseMin(d), c.cwiseMax(d)).exteriorDistance(reach) < measured;
  };
  grid.forEachNear(reach, edge.clearance, [&](std::size_t i) {
    if (boxes[i].exteriorDistance(reach) >= measured) return;
    for (const auto& ring : rings[i])
      for (std::size_t k = 0; k < ring.size(); ++k) {
        const Eigen::Vector2d& c = ring[k];
        const Eigen::Vector2d& d = ring[(k + 1) % ring.size()];
        if (!near(c, d)) continue;
        for (std::size_t q = 1; q < edge.polyline.size(); ++q)
          measured = std::min(measured, segmentsDistance(edge.polyline[q - 1], edge.polyline[q], c, d));
      }
  });
  return measured < edge.clearance - tolerance ? measured : edge.clearance;
}

}  // namespace

double siteDistance(const SiteRef& site, const Eigen::Vector2d& p) {
  return site.is_point ? (p - site.a).norm() : segmentDistance(site.a, site.b, p);
}

Roadmap buildRoadmap(const std::vector<hulls::Obstacle>& obstacles, const RoadmapParams& params,
                     const std::vector<collision::Surface>& surfaces) {
  if (!(params.tolerance > 0) || !std::isfinite(params.tolerance))
    throw Error::inParameter("tolerance", "must be > 0 and finite, got " + std::to_string(params.tolerance));
  if (!(params.z0 <= params.z1)) throw Error::inParameter("z0/z1", "z0 must be <= z1");
  if (!(params.min_clearance >= 0)) throw Error::inParameter("min_clearance", "must be >= 0");

  Roadmap map;
  map.min_clearance = params.min_clearance;
  map.tolerance = params.tolerance;

  // The sites: the footprints of the obstacles' convex parts in the band, within the bounds.
  Band band = bandFootprints(obstacles, params);
  map.bounds = roadmapBounds(band, params);
  const Bounds2d& bb = map.bounds;
  if (!(bb.x0 < bb.x1 && bb.y0 < bb.y1) || !std::isfinite(bb.x0 + bb.x1 + bb.y0 + bb.y1))
    throw Error::inParameter("bounds", "need finite x0 < x1 and y0 < y1");
  // The floor and ceiling bound the band: the roadmap lies above the one and below the other, and
  // only obstacles in what is left of the band count.
  std::tie(map.z0, map.z1) = bandBetweenSurfaces(params.z0, params.z1, surfaces, {bb.x0, bb.y0}, {bb.x1, bb.y1});
  band.erase(
      std::remove_if(band.begin(), band.end(),
                     [&](const auto& entry) { return entry.first->z_max < map.z0 || entry.first->z_min > map.z1; }),
      band.end());
  const double scale = std::max({std::abs(bb.x0), std::abs(bb.x1), std::abs(bb.y0), std::abs(bb.y1), 1.0});
  const std::vector<Rings> rings = mergedFootprints(band, bb, 1e-6 * scale, map);
  std::vector<Eigen::AlignedBox<double, 2>> boxes;
  for (const auto& poly : map.footprints) boxes.push_back(boxOf(poly));

  // The segment Delaunay graph of the footprints' and the bounds' edges.
  const int bounds_owner = static_cast<int>(map.footprints.size());
  Boundaries boundaries;
  boundaries.eps = 1e-9 * scale;
  boundaries.bounds = Eigen::AlignedBox<double, 2>(Eigen::Vector2d(bb.x0, bb.y0), Eigen::Vector2d(bb.x1, bb.y1));
  Sdg sdg;
  auto addSegment = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const Kernel::Point_2 pa(a.x(), a.y()), pb(b.x(), b.y());
    if (pa != pb) sdg.insert(pa, pb);
  };
  for (std::size_t i = 0; i < rings.size(); ++i) {
    boundaries.boxes.push_back(boxes[i]);
    for (const auto& poly : rings[i])
      for (std::size_t k = 0; k < poly.size(); ++k) addSegment(poly[k], poly[(k + 1) % poly.size()]);
  }
  boundaries.polygons = rings;
  const Eigen::Vector2d corners[4] = {{bb.x0, bb.y0}, {bb.x1, bb.y0}, {bb.x1, bb.y1}, {bb.x0, bb.y1}};
  for (int k = 0; k < 4; ++k) addSegment(corners[k], corners[(k + 1) % 4]);
  std::map<Sdg::Vertex_handle, std::vector<int>> owner_cache;
  auto ownersOf = [&](Sdg::Vertex_handle v) -> const std::vector<int>& {
    auto it = owner_cache.find(v);
    if (it != owner_cache.end()) return it->second;
    const Sdg::Site_2 s = v->site();
    const Eigen::Vector2d p =
        s.is_point() ? toEigen(s.point()) : 0.5 * (toEigen(s.segment().source()) + toEigen(s.segment().target()));
    return owner_cache.emplace(v, boundaries.owners(p)).first->second;
  };

  VoronoiVertices voronoi = voronoiVertices(sdg, scale);
  const double same = 1e-6 * scale;
  std::map<int, int> node_of_root;
  auto nodeOf = [&](int face) {
    const int root = voronoi.merged.find(face);
    const auto [it, fresh] = node_of_root.emplace(root, static_cast<int>(map.nodes.size()));
    if (fresh) map.nodes.push_back({voronoi.vertex[root]});
    return it->second;
  };
  auto inBounds = [&](const Eigen::Vector2d& p) {
    return p.x() >= bb.x0 - same && p.x() <= bb.x1 + same && p.y() >= bb.y0 - same && p.y() <= bb.y1 + same;
  };

  // The edges: the Voronoi edges between two footprints (or one and the bounds) that keep the
  // clearance and lie outside every footprint.
  const BoxGrid footprint_grid(
      boxes, Eigen::AlignedBox<double, 2>(Eigen::Vector2d(bb.x0, bb.y0), Eigen::Vector2d(bb.x1, bb.y1)));
  for (auto e = sdg.finite_edges_begin(); e != sdg.finite_edges_end(); ++e) {
    const auto f = e->first;
    const auto g = f->neighbor(e->second);
    if (sdg.is_infinite(f) || sdg.is_infinite(g)) continue;  // reaches infinity: outside the bounds
    const auto va = f->vertex(Sdg::ccw(e->second));
    const auto vb = f->vertex(Sdg::cw(e->second));
    const Sdg::Site_2 sa = va->site(), sb = vb->site();
    const std::vector<int>& oa = ownersOf(va);
    const std::vector<int>& ob = ownersOf(vb);  // both sorted
    std::vector<int> common;
    std::set_intersection(oa.begin(), oa.end(), ob.begin(), ob.end(), std::back_inserter(common));
    if (!common.empty() || oa.empty() || ob.empty()) continue;  // same obstacle (or bounds twice)
    const int fi = voronoi.face_index.at(f), gi = voronoi.face_index.at(g);
    const Eigen::Vector2d a = voronoi.vertex[voronoi.merged.find(fi)], b = voronoi.vertex[voronoi.merged.find(gi)];
    if (!a.allFinite() || !b.allFinite() || !inBounds(a) || !inBounds(b)) continue;
    if (voronoi.merged.find(fi) == voronoi.merged.find(gi)) continue;  // zero length

    RoadmapEdge edge;
    edge.site_a = siteRef(sa, oa, bounds_owner);
    edge.site_b = siteRef(sb, ob, bounds_owner);
    traceBisector(edge, a, b, params.tolerance);
    // The polyline's chords lie up to the tolerance nearer than the arc: an edge is kept only when
    // they keep min_clearance too (the exact check counts touching as a collision).
    const double keep = params.min_clearance + params.tolerance;
    if (edge.clearance < keep) continue;
    edge.clearance = guardedClearance(edge, rings, boxes, footprint_grid, params.tolerance);
    if (edge.clearance < keep) continue;
    const Eigen::Vector2d mid =
        edge.polyline[edge.polyline.size() / 2] * 0.5 + edge.polyline[(edge.polyline.size() - 1) / 2] * 0.5;
    bool inside = false;
    for (std::size_t i = 0; i < map.footprints.size() && !inside; ++i)
      inside = boxes[i].contains(mid) && insideRings(rings[i], mid);
    if (inside) continue;
    for (std::size_t k = 1; k < edge.polyline.size(); ++k)
      edge.length += (edge.polyline[k] - edge.polyline[k - 1]).norm();
    edge.from = nodeOf(fi);
    edge.to = nodeOf(gi);
    edge.polyline.front() = map.nodes[edge.from].position;
    edge.polyline.back() = map.nodes[edge.to].position;
    map.edges.push_back(std::move(edge));
  }
  canonicalOrder(map);
  return map;
}

}  // namespace hullmap::planning

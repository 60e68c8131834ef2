#include "hullmap/planning/roadmap.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <utility>

#include <CGAL/Segment_Delaunay_graph_2.h>
#include <CGAL/Segment_Delaunay_graph_filtered_traits_2.h>
#include <CGAL/Simple_cartesian.h>
#include <nlohmann/json.hpp>

#include "hullmap/mapper/atomic_file.hpp"
#include "hullmap/mapper/error.hpp"

namespace hullmap::planning {
namespace {

// Filtered traits: every predicate is exact (interval arithmetic, falling back to exact numbers);
// Field_with_sqrt_tag lets the constructions (Voronoi vertices) use sqrt in double. The variant
// with intersections accepts footprints that overlap in the ground plane.
using Kernel = CGAL::Simple_cartesian<double>;
using Traits = CGAL::Segment_Delaunay_graph_filtered_traits_2<Kernel, CGAL::Field_with_sqrt_tag>;
using Sdg = CGAL::Segment_Delaunay_graph_2<Traits>;
using Key = std::pair<double, double>;

Eigen::Vector2d toEigen(const Kernel::Point_2& p) { return {CGAL::to_double(p.x()), CGAL::to_double(p.y())}; }
Key keyOf(const Kernel::Point_2& p) { return {CGAL::to_double(p.x()), CGAL::to_double(p.y())}; }

double segmentDistance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

bool insideConvex(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p) {
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    const double cross = (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x());
    if (cross <= 0) return false;  // counter-clockwise: strictly inside is strictly left of every edge
  }
  return true;
}

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void unite(int a, int b) { parent[find(a)] = find(b); }
};

/// Owners of each input point and segment: obstacle indices, `bounds_owner` for the bounds.
struct Owners {
  std::map<Key, std::vector<int>> of_point;
  std::vector<int> ofPoint(const Kernel::Point_2& p) const {
    const auto it = of_point.find(keyOf(p));
    return it == of_point.end() ? std::vector<int>{} : it->second;
  }
  std::vector<int> ofSegment(const Kernel::Point_2& a, const Kernel::Point_2& b) const {
    std::vector<int> oa = ofPoint(a), ob = ofPoint(b), both;
    std::sort(oa.begin(), oa.end());
    std::sort(ob.begin(), ob.end());
    std::set_intersection(oa.begin(), oa.end(), ob.begin(), ob.end(), std::back_inserter(both));
    return both;
  }
};

std::vector<int> ownersOf(const Sdg::Site_2& s, const Owners& owners) {
  if (s.is_segment()) return owners.ofSegment(s.source_of_supporting_site(), s.target_of_supporting_site());
  if (s.is_input()) return owners.ofPoint(s.point());
  // An intersection of two input segments belongs to both.
  std::vector<int> a = owners.ofSegment(s.source_of_supporting_site(0), s.target_of_supporting_site(0));
  const std::vector<int> b = owners.ofSegment(s.source_of_supporting_site(1), s.target_of_supporting_site(1));
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

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

}  // namespace

double siteDistance(const SiteRef& site, const Eigen::Vector2d& p) {
  return site.is_point ? (p - site.a).norm() : segmentDistance(site.a, site.b, p);
}

Roadmap buildRoadmap(const std::vector<clustering::Obstacle>& obstacles, const RoadmapParams& params) {
  if (!(params.tolerance > 0) || !std::isfinite(params.tolerance))
    throw Error("roadmap tolerance: must be > 0, got " + std::to_string(params.tolerance));
  if (!(params.z0 <= params.z1)) throw Error("roadmap band: z0 must be <= z1");
  if (!(params.min_clearance >= 0)) throw Error("roadmap min_clearance: must be >= 0");

  Roadmap map;
  map.z0 = params.z0;
  map.z1 = params.z1;
  map.min_clearance = params.min_clearance;
  map.tolerance = params.tolerance;

  std::vector<const clustering::Obstacle*> band;
  for (const auto& o : obstacles) {
    if (o.footprint.z_max < params.z0 || o.footprint.z_min > params.z1) continue;
    if (o.footprint.polygon.size() < 3)
      throw Error("obstacle " + std::to_string(o.id) + ": footprint has " +
                  std::to_string(o.footprint.polygon.size()) + " vertices, expected >= 3");
    band.push_back(&o);
    map.obstacle_ids.push_back(o.id);
  }

  if (params.bounds) {
    map.bounds = *params.bounds;
  } else {
    if (!(params.margin > 0)) throw Error("roadmap margin: must be > 0");
    double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
    for (const auto* o : band)
      for (const auto& p : o->footprint.polygon) {
        x0 = std::min(x0, p.x()); y0 = std::min(y0, p.y());
        x1 = std::max(x1, p.x()); y1 = std::max(y1, p.y());
      }
    if (band.empty()) x0 = y0 = x1 = y1 = 0.0;
    map.bounds = {x0 - params.margin, y0 - params.margin, x1 + params.margin, y1 + params.margin};
  }
  const Bounds2d& bb = map.bounds;
  if (!(bb.x0 < bb.x1 && bb.y0 < bb.y1) || !std::isfinite(bb.x0 + bb.x1 + bb.y0 + bb.y1))
    throw Error("roadmap bounds: need x0 < x1 and y0 < y1");

  const int bounds_owner = static_cast<int>(band.size());
  Owners owners;
  Sdg sdg;
  auto addSegment = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b, int owner) {
    const Kernel::Point_2 pa(a.x(), a.y()), pb(b.x(), b.y());
    owners.of_point[keyOf(pa)].push_back(owner);
    if (pa != pb) sdg.insert(pa, pb);
  };
  for (std::size_t i = 0; i < band.size(); ++i) {
    const auto& poly = band[i]->footprint.polygon;
    for (std::size_t k = 0; k < poly.size(); ++k) addSegment(poly[k], poly[(k + 1) % poly.size()], static_cast<int>(i));
  }
  const Eigen::Vector2d corners[4] = {{bb.x0, bb.y0}, {bb.x1, bb.y0}, {bb.x1, bb.y1}, {bb.x0, bb.y1}};
  for (int k = 0; k < 4; ++k) addSegment(corners[k], corners[(k + 1) % 4], bounds_owner);

  // Voronoi vertices: one per finite face; faces whose vertices coincide (co-circular sites, common
  // with boxes) are merged into one node so that the graph stays connected through them.
  std::map<Sdg::Face_handle, int> face_index;
  std::vector<Eigen::Vector2d> vertex;
  for (auto f = sdg.finite_faces_begin(); f != sdg.finite_faces_end(); ++f) {
    face_index.emplace(f, static_cast<int>(vertex.size()));
    vertex.push_back(toEigen(sdg.primal(f)));
  }
  const double scale = std::max({std::abs(bb.x0), std::abs(bb.x1), std::abs(bb.y0), std::abs(bb.y1), 1.0});
  const double same = 1e-9 * scale;
  UnionFind merged(vertex.size());
  for (auto e = sdg.finite_edges_begin(); e != sdg.finite_edges_end(); ++e) {
    const auto f = e->first;
    const auto g = f->neighbor(e->second);
    if (sdg.is_infinite(f) || sdg.is_infinite(g)) continue;
    const int i = face_index.at(f), j = face_index.at(g);
    if ((vertex[i] - vertex[j]).norm() <= same) merged.unite(i, j);
  }

  std::map<int, int> node_of_root;
  auto nodeOf = [&](int face) {
    const int root = merged.find(face);
    const auto [it, fresh] = node_of_root.emplace(root, static_cast<int>(map.nodes.size()));
    if (fresh) map.nodes.push_back({vertex[root]});
    return it->second;
  };
  auto inBounds = [&](const Eigen::Vector2d& p) {
    return p.x() >= bb.x0 - same && p.x() <= bb.x1 + same && p.y() >= bb.y0 - same && p.y() <= bb.y1 + same;
  };

  for (auto e = sdg.finite_edges_begin(); e != sdg.finite_edges_end(); ++e) {
    const auto f = e->first;
    const auto g = f->neighbor(e->second);
    if (sdg.is_infinite(f) || sdg.is_infinite(g)) continue;  // reaches infinity: outside the bounds
    const auto va = f->vertex(Sdg::ccw(e->second));
    const auto vb = f->vertex(Sdg::cw(e->second));
    const Sdg::Site_2 sa = va->site(), sb = vb->site();
    std::vector<int> oa = ownersOf(sa, owners), ob = ownersOf(sb, owners);
    std::sort(oa.begin(), oa.end());
    std::sort(ob.begin(), ob.end());
    std::vector<int> common;
    std::set_intersection(oa.begin(), oa.end(), ob.begin(), ob.end(), std::back_inserter(common));
    if (!common.empty() || oa.empty() || ob.empty()) continue;  // same obstacle (or bounds twice)
    const int fi = face_index.at(f), gi = face_index.at(g);
    const Eigen::Vector2d a = vertex[merged.find(fi)], b = vertex[merged.find(gi)];
    if (!inBounds(a) || !inBounds(b)) continue;
    if (merged.find(fi) == merged.find(gi)) continue;  // zero length

    RoadmapEdge edge;
    edge.site_a = siteRef(sa, oa, bounds_owner);
    edge.site_b = siteRef(sb, ob, bounds_owner);
    traceBisector(edge, a, b, params.tolerance);
    if (edge.clearance < params.min_clearance) continue;
    const Eigen::Vector2d mid = edge.polyline[edge.polyline.size() / 2] * 0.5 +
                                edge.polyline[(edge.polyline.size() - 1) / 2] * 0.5;
    bool inside = false;
    for (const auto* o : band) inside = inside || insideConvex(o->footprint.polygon, mid);
    if (inside) continue;
    for (std::size_t k = 1; k < edge.polyline.size(); ++k) edge.length += (edge.polyline[k] - edge.polyline[k - 1]).norm();
    edge.from = nodeOf(fi);
    edge.to = nodeOf(gi);
    edge.polyline.front() = map.nodes[edge.from].position;
    edge.polyline.back() = map.nodes[edge.to].position;
    map.edges.push_back(std::move(edge));
  }
  return map;
}

std::string roadmapJson(const Roadmap& roadmap) {
  using nlohmann::json;
  auto xy = [](const Eigen::Vector2d& p) { return json::array({p.x(), p.y()}); };
  auto site = [&](const SiteRef& s) {
    json j{{"obstacle", s.obstacle >= 0 ? json(s.obstacle) : json(nullptr)}};
    if (s.is_point) j["point"] = xy(s.a);
    else j["segment"] = json::array({xy(s.a), xy(s.b)});
    return j;
  };
  json j;
  j["format"] = "hullmap-roadmap/1";
  j["frame"] = "z-up map";
  j["bounds"] = {roadmap.bounds.x0, roadmap.bounds.y0, roadmap.bounds.x1, roadmap.bounds.y1};
  j["band"] = {roadmap.z0, roadmap.z1};
  j["min_clearance"] = roadmap.min_clearance;
  j["tolerance"] = roadmap.tolerance;
  j["obstacle_ids"] = roadmap.obstacle_ids;
  j["nodes"] = json::array();
  for (const auto& n : roadmap.nodes) j["nodes"].push_back(xy(n.position));
  j["edges"] = json::array();
  for (const auto& e : roadmap.edges) {
    json je{{"from", e.from}, {"to", e.to}, {"length", e.length}, {"clearance", e.clearance}};
    je["sites"] = json::array({site(e.site_a), site(e.site_b)});
    je["polyline"] = json::array();
    for (const auto& p : e.polyline) je["polyline"].push_back(xy(p));
    j["edges"].push_back(std::move(je));
  }
  return j.dump(1) + "\n";
}

void writeRoadmapJson(const std::string& path, const Roadmap& roadmap) {
  const std::string text = roadmapJson(roadmap);
  mapper::writeFileAtomically(path, [&](std::ostream& out) { out << text; });
}

}  // namespace hullmap::planning

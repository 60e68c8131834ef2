#include "hullmap/clustering/convex_parts.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <queue>
#include <set>
#include <string>
#include <tuple>
#include <utility>

#include <Eigen/Eigenvalues>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <tbb/parallel_for.h>

#include "hullmap/core/error.hpp"
#include "lattice_hull.hpp"

namespace hullmap::clustering {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point3>;
using Cell = std::array<std::int64_t, 3>;
using Members = std::vector<std::uint32_t>;  ///< sorted indices into the cluster's cells

/// A facet plane of a lattice hull: n . x <= d inside, x in corner-lattice coordinates (cell (i, j, k)
/// is the cube [i, i+1] x [j, j+1] x [k, k+1]); n primitive.
struct Plane {
  Cell n;
  std::int64_t d;
  bool operator<(const Plane& o) const { return std::tie(n, d) < std::tie(o.n, o.d); }
};

struct LatticeHull {
  std::vector<Plane> planes;  ///< sorted, one per facet
  std::int64_t volume6 = 0;   ///< six times the volume, exact (cells^3)
};

Cell sub(const Cell& a, const Cell& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Cell cross(const Cell& a, const Cell& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
std::int64_t dot(const Cell& a, const Cell& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// Hull of the cells' corners, exact on the lattice: its facet planes and volume do not depend on
/// how CGAL triangulates it, so everything decided from them is deterministic.
LatticeHull latticeHull(const std::vector<Cell>& cells) {
  std::vector<Point3> points;
  for (const auto& c : detail::candidateCorners(cells)) points.emplace_back(double(c[0]), double(c[1]), double(c[2]));
  Mesh mesh;
  CGAL::convex_hull_3(points.begin(), points.end(), mesh);
  LatticeHull hull;
  std::set<Plane> planes;
  bool first = true;
  Cell ref{0, 0, 0};
  const auto lattice = [&](Mesh::Vertex_index v) {
    const Point3& p = mesh.point(v);
    return Cell{std::int64_t(p.x()), std::int64_t(p.y()), std::int64_t(p.z())};
  };
  for (const auto f : mesh.faces()) {
    std::vector<Cell> ring;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) ring.push_back(lattice(v));
    if (first) {
      ref = ring[0];
      first = false;
    }
    for (std::size_t k = 1; k + 1 < ring.size(); ++k) {
      const Cell a = sub(ring[0], ref), b = sub(ring[k], ref), c = sub(ring[k + 1], ref);
      hull.volume6 += dot(a, cross(b, c));
      Cell n = cross(sub(ring[k], ring[0]), sub(ring[k + 1], ring[0]));
      const std::int64_t g = std::gcd(std::gcd(std::abs(n[0]), std::abs(n[1])), std::abs(n[2]));
      if (g == 0) continue;
      for (auto& x : n) x /= g;
      planes.insert({n, dot(n, ring[0])});
    }
  }
  hull.planes.assign(planes.begin(), planes.end());
  return hull;
}

bool inside(const LatticeHull& hull, const Eigen::Vector3d& x) {
  for (const auto& p : hull.planes)
    if (double(p.n[0]) * x.x() + double(p.n[1]) * x.y() + double(p.n[2]) * x.z() > double(p.d) + 1e-9) return false;
  return true;
}

/// Squared Euclidean distance transform along one line (Felzenszwalb and Huttenlocher 2012).
void distanceTransform1d(std::vector<double>& f, std::vector<double>& out, std::vector<int>& v, std::vector<double>& z) {
  const int n = int(f.size());
  v.assign(std::size_t(n), 0);
  z.assign(std::size_t(n) + 1, 0.0);
  int k = 0;
  z[0] = -std::numeric_limits<double>::infinity();
  z[1] = std::numeric_limits<double>::infinity();
  const auto meet = [&](int q, int r) {
    return ((f[std::size_t(q)] + double(q) * q) - (f[std::size_t(r)] + double(r) * r)) / (2.0 * q - 2.0 * r);
  };
  for (int q = 1; q < n; ++q) {
    double s = meet(q, v[std::size_t(k)]);
    while (k > 0 && s <= z[std::size_t(k)]) s = meet(q, v[std::size_t(--k)]);
    ++k;
    v[std::size_t(k)] = q;
    z[std::size_t(k)] = s;
    z[std::size_t(k) + 1] = std::numeric_limits<double>::infinity();
  }
  out.assign(std::size_t(n), 0.0);
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[std::size_t(k) + 1] < q) ++k;
    const double d = q - v[std::size_t(k)];
    out[std::size_t(q)] = d * d + f[std::size_t(v[std::size_t(k)])];
  }
}

/// The check of one part against T (see splitConvexParts).
struct Check {
  bool ok = true;
  bool too_big = false;            ///< box over max_check_cells: not checked
  std::int64_t worst_d2 = 0;       ///< largest squared centre distance (cells^2) over the hull's cells
  Eigen::Vector3d split_point = Eigen::Vector3d::Zero();  ///< where to cut, lattice coordinates
  LatticeHull hull;
  std::size_t keyframes_in_voxels = 0;
};

/// One cluster on its lattice, and the work on it.
class ClusterSplitter {
 public:
  ClusterSplitter(std::vector<Cell> cells, double t_cells, std::size_t max_check_cells,
                  std::vector<Eigen::Vector3d> keyframes)
      : cells_(std::move(cells)),
        t2_(t_cells * t_cells * (1.0 + 1e-12)),
        reach_(std::int64_t(std::floor(t_cells))),
        max_check_cells_(max_check_cells),
        keyframes_(std::move(keyframes)) {}

  /// Final parts with their checks.
  std::vector<std::pair<Members, Check>> run() {
    Members all(cells_.size());
    std::iota(all.begin(), all.end(), 0u);
    std::vector<std::pair<Members, Check>> done;
    std::vector<Members> work{all};
    while (!work.empty()) {
      Members part = std::move(work.back());
      work.pop_back();
      Check check = checkPart(part);
      if (check.ok || part.size() == 1) {
        done.emplace_back(std::move(part), std::move(check));
        continue;
      }
      auto [left, right] = split(part, check);
      work.push_back(std::move(right));
      work.push_back(std::move(left));
    }
    return merge(std::move(done));
  }

 private:
  std::vector<Cell> gather(const Members& part) const {
    std::vector<Cell> out;
    out.reserve(part.size());
    for (const auto i : part) out.push_back(cells_[i]);
    return out;
  }

  void box(const Members& part, Cell& lo, Cell& hi) const {
    lo = cells_[part[0]];
    hi = lo;
    for (const auto i : part)
      for (int a = 0; a < 3; ++a) {
        lo[std::size_t(a)] = std::min(lo[std::size_t(a)], cells_[i][std::size_t(a)]);
        hi[std::size_t(a)] = std::max(hi[std::size_t(a)], cells_[i][std::size_t(a)]);
      }
  }

  Check checkPart(const Members& part) const {
    Check check;
    const std::vector<Cell> cells = gather(part);
    check.hull = latticeHull(cells);
    if (part.size() == 1) return check;
    Cell lo, hi;
    box(part, lo, hi);
    const std::int64_t nx = hi[0] - lo[0] + 1, ny = hi[1] - lo[1] + 1, nz = hi[2] - lo[2] + 1;
    if (double(nx) * double(ny) * double(nz) > double(max_check_cells_)) {
      check.ok = false;
      check.too_big = true;
      return check;
    }
    // Squared distance (cells^2) from each cell centre of the box to the nearest occupied centre.
    constexpr double kFar = 1e20;
    std::vector<float> d2(std::size_t(nx * ny * nz), float(kFar));
    const auto at = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
      return std::size_t(((k - lo[2]) * ny + (j - lo[1])) * nx + (i - lo[0]));
    };
    for (const auto& c : cells) d2[at(c[0], c[1], c[2])] = 0.0f;
    std::vector<double> f, out, z;
    std::vector<int> v;
    const std::array<std::int64_t, 3> dims{nx, ny, nz};
    const std::array<std::int64_t, 3> stride{1, nx, nx * ny};
    for (int axis = 0; axis < 3; ++axis) {
      const std::int64_t n = dims[std::size_t(axis)], s = stride[std::size_t(axis)];
      f.resize(std::size_t(n));
      for (std::int64_t base = 0; base < nx * ny * nz; ++base) {
        if ((base / s) % n != 0) continue;  // only the first cell of each line along `axis`
        for (std::int64_t q = 0; q < n; ++q) f[std::size_t(q)] = d2[std::size_t(base + q * s)];
        distanceTransform1d(f, out, v, z);
        for (std::int64_t q = 0; q < n; ++q) d2[std::size_t(base + q * s)] = float(std::min(out[std::size_t(q)], kFar));
      }
    }
    // Cells whose cube meets the hull: per column, the k range allowed by every facet plane, with
    // the cube's lowest value of n . x (exact integers).
    std::int64_t worst = -1;
    Cell worst_cell{0, 0, 0};
    for (std::int64_t j = lo[1]; j <= hi[1]; ++j) {
      for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
        std::int64_t k0 = lo[2], k1 = hi[2];
        for (const auto& p : check.hull.planes) {
          const std::int64_t rest = p.d - (p.n[0] * i + std::min<std::int64_t>(p.n[0], 0) + p.n[1] * j +
                                           std::min<std::int64_t>(p.n[1], 0) + std::min<std::int64_t>(p.n[2], 0));
          if (p.n[2] > 0) {
            k1 = std::min(k1, floorDiv(rest, p.n[2]));
          } else if (p.n[2] < 0) {
            k0 = std::max(k0, ceilDiv(rest, p.n[2]));
          } else if (rest < 0) {
            k1 = k0 - 1;
          }
          if (k1 < k0) break;
        }
        for (std::int64_t k = k0; k <= k1; ++k) {
          const auto d = std::int64_t(d2[at(i, j, k)]);
          if (d > worst) {
            worst = d;
            worst_cell = {i, j, k};
          }
        }
      }
    }
    check.worst_d2 = std::max<std::int64_t>(worst, 0);
    if (double(check.worst_d2) > t2_) {
      check.ok = false;
      check.split_point = Eigen::Vector3d(double(worst_cell[0]) + 0.5, double(worst_cell[1]) + 0.5,
                                          double(worst_cell[2]) + 0.5);
      return check;
    }
    for (const auto& x : keyframes_) {
      if (!inside(check.hull, x)) continue;
      // In one of the part's voxels (closed cubes): nothing can keep it out of the hull.
      bool in_voxel = false;
      for (int m = 0; m < 8 && !in_voxel; ++m) {
        const std::int64_t i = std::int64_t(std::floor(x.x() + (m & 1 ? 1e-9 : -1e-9)));
        const std::int64_t j = std::int64_t(std::floor(x.y() + (m & 2 ? 1e-9 : -1e-9)));
        const std::int64_t k = std::int64_t(std::floor(x.z() + (m & 4 ? 1e-9 : -1e-9)));
        in_voxel = i >= lo[0] && i <= hi[0] && j >= lo[1] && j <= hi[1] && k >= lo[2] && k <= hi[2] &&
                   d2[at(i, j, k)] == 0.0f;
      }
      if (in_voxel) {
        ++check.keyframes_in_voxels;
        continue;
      }
      check.ok = false;
      check.split_point = x;
      return check;
    }
    return check;
  }

  static std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
    std::int64_t q = a / b;
    if ((a % b != 0) && ((a < 0) != (b < 0))) --q;
    return q;
  }
  static std::int64_t ceilDiv(std::int64_t a, std::int64_t b) { return -floorDiv(-a, b); }

  /// Two non-empty halves of a part that failed its check.
  std::pair<Members, Members> split(const Members& part, const Check& check) const {
    Cell lo, hi;
    box(part, lo, hi);
    if (!check.too_big) {
      // Candidate planes (normal, point): the three axis planes and the three planes normal to the
      // principal axes through the violation, and per axis the cut whose two halves have the
      // smallest summed bounding boxes (it finds an L's junction, which a cut through the violation
      // misses). The one whose halves have the smallest summed hull volume wins.
      std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> planes;
      for (int a = 0; a < 3; ++a) planes.emplace_back(Eigen::Vector3d::Unit(a), check.split_point);
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const auto i : part) mean += centre(i);
      mean /= double(part.size());
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      for (const auto i : part) cov += (centre(i) - mean) * (centre(i) - mean).transpose();
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> pca(cov);
      for (int a = 2; a >= 0; --a) planes.emplace_back(pca.eigenvectors().col(a), check.split_point);
      for (int a = 0; a < 3; ++a)
        if (const auto cut = bestBoxCut(part, a)) planes.emplace_back(Eigen::Vector3d::Unit(a), Eigen::Vector3d::Constant(double(*cut)));
      // Distinct cuts (planes that cut the same way are scored once), scored in parallel; the
      // smallest summed hull volume wins, ties to the first candidate (thread-count independent).
      std::vector<std::pair<Members, Members>> cuts;
      for (const auto& [n, point] : planes) {
        Members left, right;
        for (const auto i : part) (n.dot(centre(i) - point) < 0 ? left : right).push_back(i);
        if (left.empty() || right.empty()) continue;
        if (left.front() != part.front()) std::swap(left, right);
        if (std::any_of(cuts.begin(), cuts.end(), [&](const auto& cut) { return cut.first == left; })) continue;
        cuts.emplace_back(std::move(left), std::move(right));
      }
      std::vector<std::int64_t> side_volumes(2 * cuts.size());
      tbb::parallel_for(std::size_t(0), side_volumes.size(), [&](std::size_t k) {
        side_volumes[k] = latticeHull(gather(k % 2 ? cuts[k / 2].second : cuts[k / 2].first)).volume6;
      });
      std::optional<std::size_t> best;
      for (std::size_t c = 0; c < cuts.size(); ++c)
        if (!best || side_volumes[2 * c] + side_volumes[2 * c + 1] < side_volumes[2 * *best] + side_volumes[2 * *best + 1])
          best = c;
      if (best) return std::move(cuts[*best]);
    }
    // At the median of the longest axis of the box.
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (hi[std::size_t(a)] - lo[std::size_t(a)] > hi[std::size_t(axis)] - lo[std::size_t(axis)]) axis = a;
    std::vector<std::int64_t> values;
    for (const auto i : part) values.push_back(cells_[i][std::size_t(axis)]);
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(values.size() / 2), values.end());
    std::int64_t median = values[values.size() / 2];
    if (median == lo[std::size_t(axis)]) ++median;
    Members left, right;
    for (const auto i : part) (cells_[i][std::size_t(axis)] < median ? left : right).push_back(i);
    return {std::move(left), std::move(right)};
  }

  /// The cell index m along `axis` for which the cells below m and the others have the smallest
  /// summed bounding-box volume (ties: the most even split); none when all share one value.
  std::optional<std::int64_t> bestBoxCut(const Members& part, int axis) const {
    const std::size_t a = std::size_t(axis);
    Members order = part;
    std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) {
      return std::make_pair(cells_[x][a], x) < std::make_pair(cells_[y][a], y);
    });
    const std::size_t n = order.size();
    std::vector<Cell> lo_prefix(n), hi_prefix(n), lo_suffix(n), hi_suffix(n);
    for (std::size_t k = 0; k < n; ++k) {
      const Cell& c = cells_[order[k]];
      lo_prefix[k] = hi_prefix[k] = c;
      if (k > 0)
        for (std::size_t d = 0; d < 3; ++d) {
          lo_prefix[k][d] = std::min(lo_prefix[k - 1][d], c[d]);
          hi_prefix[k][d] = std::max(hi_prefix[k - 1][d], c[d]);
        }
    }
    for (std::size_t k = n; k-- > 0;) {
      const Cell& c = cells_[order[k]];
      lo_suffix[k] = hi_suffix[k] = c;
      if (k + 1 < n)
        for (std::size_t d = 0; d < 3; ++d) {
          lo_suffix[k][d] = std::min(lo_suffix[k + 1][d], c[d]);
          hi_suffix[k][d] = std::max(hi_suffix[k + 1][d], c[d]);
        }
    }
    const auto volume = [](const Cell& lo, const Cell& hi) {
      return (hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
    };
    std::optional<std::int64_t> best;
    std::int64_t best_volume = 0, best_balance = 0;
    for (std::size_t k = 1; k < n; ++k) {
      if (cells_[order[k]][a] == cells_[order[k - 1]][a]) continue;
      const std::int64_t v = volume(lo_prefix[k - 1], hi_prefix[k - 1]) + volume(lo_suffix[k], hi_suffix[k]);
      const std::int64_t balance = std::abs(std::int64_t(2 * k) - std::int64_t(n));
      if (!best || v < best_volume || (v == best_volume && balance < best_balance)) {
        best = cells_[order[k]][a];
        best_volume = v;
        best_balance = balance;
      }
    }
    return best;
  }

  Eigen::Vector3d centre(std::uint32_t i) const {
    return Eigen::Vector3d(double(cells_[i][0]) + 0.5, double(cells_[i][1]) + 0.5, double(cells_[i][2]) + 0.5);
  }

  /// Greedy merge of parts whose boxes come within T, the pair whose union's hull adds the least
  /// volume first, while the union passes the check.
  std::vector<std::pair<Members, Check>> merge(std::vector<std::pair<Members, Check>> parts) const {
    struct Node {
      Members members;
      Check check;
      Cell lo, hi;
      bool alive = true;
    };
    std::vector<Node> nodes;
    for (auto& [members, check] : parts) {
      Node node{std::move(members), std::move(check), {}, {}, true};
      box(node.members, node.lo, node.hi);
      nodes.push_back(std::move(node));
    }
    // Deterministic start: parts ordered by their first cell.
    std::sort(nodes.begin(), nodes.end(), [](const Node& a, const Node& b) { return a.members[0] < b.members[0]; });
    using Candidate = std::tuple<std::int64_t, std::size_t, std::size_t>;  // added volume, a, b
    std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> queue;
    const auto near = [&](const Node& a, const Node& b) {
      for (std::size_t k = 0; k < 3; ++k)
        if (a.lo[k] - b.hi[k] - 1 > reach_ || b.lo[k] - a.hi[k] - 1 > reach_) return false;
      return true;
    };
    const auto unite = [](const Members& a, const Members& b) {
      Members out;
      out.reserve(a.size() + b.size());
      std::merge(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
      return out;
    };
    // The added hull volume of each near pair, computed in parallel, queued in pair order.
    const auto consider = [&](const std::vector<std::pair<std::size_t, std::size_t>>& candidates) {
      std::vector<std::pair<std::size_t, std::size_t>> pairs;
      for (const auto& [a, b] : candidates)
        if (near(nodes[a], nodes[b])) pairs.emplace_back(a, b);
      std::vector<std::int64_t> added(pairs.size());
      tbb::parallel_for(std::size_t(0), pairs.size(), [&](std::size_t k) {
        const auto [a, b] = pairs[k];
        added[k] = latticeHull(gather(unite(nodes[a].members, nodes[b].members))).volume6 -
                   nodes[a].check.hull.volume6 - nodes[b].check.hull.volume6;
      });
      for (std::size_t k = 0; k < pairs.size(); ++k)
        queue.emplace(added[k], std::min(pairs[k].first, pairs[k].second), std::max(pairs[k].first, pairs[k].second));
    };
    std::vector<std::pair<std::size_t, std::size_t>> all_pairs;
    for (std::size_t a = 0; a < nodes.size(); ++a)
      for (std::size_t b = a + 1; b < nodes.size(); ++b) all_pairs.emplace_back(a, b);
    consider(all_pairs);
    while (!queue.empty()) {
      const auto [added, a, b] = queue.top();
      queue.pop();
      if (!nodes[a].alive || !nodes[b].alive) continue;
      Members both = unite(nodes[a].members, nodes[b].members);
      Check check = checkPart(both);
      if (!check.ok) continue;
      nodes[a].alive = nodes[b].alive = false;
      Node node{std::move(both), std::move(check), {}, {}, true};
      box(node.members, node.lo, node.hi);
      nodes.push_back(std::move(node));
      const std::size_t added_node = nodes.size() - 1;
      std::vector<std::pair<std::size_t, std::size_t>> with_new;
      for (std::size_t c = 0; c < added_node; ++c)
        if (nodes[c].alive) with_new.emplace_back(c, added_node);
      consider(with_new);
    }
    std::vector<std::pair<Members, Check>> out;
    for (auto& node : nodes)
      if (node.alive) out.emplace_back(std::move(node.members), std::move(node.check));
    std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first[0] < b.first[0]; });
    return out;
  }

  std::vector<Cell> cells_;
  double t2_;
  std::int64_t reach_;
  std::size_t max_check_cells_;
  std::vector<Eigen::Vector3d> keyframes_;  ///< lattice coordinates
};

/// A cluster on its lattice: cells sorted as the centres are given.
struct ClusterLattice {
  Eigen::Vector3d origin;  ///< corner (0, 0, 0), map frame
  std::vector<Cell> cells;
};

ClusterLattice toLattice(const std::vector<Eigen::Vector3d>& centers, double voxel_size) {
  ClusterLattice lattice;
  // The same origin as buildObstacles: the lower corner of the lexicographically smallest centre.
  const auto anchor = std::min_element(centers.begin(), centers.end(), [](const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
    return std::tie(p.x(), p.y(), p.z()) < std::tie(q.x(), q.y(), q.z());
  });
  lattice.origin = *anchor - Eigen::Vector3d::Constant(0.5 * voxel_size);
  for (const auto& c : centers) {
    const Eigen::Vector3d rel = (c - lattice.origin) / voxel_size - Eigen::Vector3d::Constant(0.5);
    lattice.cells.push_back({std::llround(rel.x()), std::llround(rel.y()), std::llround(rel.z())});
  }
  return lattice;
}

double resolveConcavity(const ConvexPartsParams& params, double voxel_size) {
  if (!(voxel_size > 0) || !std::isfinite(voxel_size))
    throw Error("convex parts: voxel_size must be positive, got " + std::to_string(voxel_size));
  if (!(params.concavity >= 0) || !std::isfinite(params.concavity))
    throw Error("convex parts: concavity must be >= 0 (0: default), got " + std::to_string(params.concavity));
  return params.concavity > 0 ? params.concavity : defaultConcavity(voxel_size);
}

struct SplitResult {
  ClusterLattice lattice;
  std::vector<std::pair<Members, Check>> parts;
};

SplitResult splitCluster(const std::vector<Eigen::Vector3d>& centers, double voxel_size, double t,
                         std::size_t max_check_cells, const std::vector<Eigen::Vector3d>& keyframes) {
  SplitResult result;
  if (centers.empty()) return result;
  for (std::size_t i = 0; i < centers.size(); ++i)
    if (!centers[i].allFinite()) throw Error("convex parts: non-finite voxel centre at index " + std::to_string(i));
  result.lattice = toLattice(centers, voxel_size);
  Eigen::Vector3d lo = centers[0], hi = centers[0];
  for (const auto& c : centers) {
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  std::vector<Eigen::Vector3d> near;
  for (const auto& k : keyframes) {
    if (!k.allFinite()) throw Error("convex parts: non-finite keyframe position");
    if ((k.array() >= lo.array() - voxel_size).all() && (k.array() <= hi.array() + voxel_size).all())
      near.push_back((k - result.lattice.origin) / voxel_size);
  }
  ClusterSplitter splitter(result.lattice.cells, t / voxel_size, max_check_cells, std::move(near));
  result.parts = splitter.run();
  return result;
}

}  // namespace

double defaultConcavity(double voxel_size) { return 3.0 * voxel_size; }

std::vector<std::vector<std::size_t>> splitConvexParts(const std::vector<Eigen::Vector3d>& centers,
                                                       double voxel_size, const ConvexPartsParams& params,
                                                       const std::vector<Eigen::Vector3d>& keyframes) {
  const double t = resolveConcavity(params, voxel_size);
  const SplitResult result = splitCluster(centers, voxel_size, t, params.max_check_cells, keyframes);
  std::vector<std::vector<std::size_t>> out;
  for (const auto& [members, check] : result.parts) out.emplace_back(members.begin(), members.end());
  return out;
}

ConvexPartsSummary addConvexParts(std::vector<Obstacle>& obstacles, const std::vector<Eigen::Vector3d>& centers,
                                  const std::vector<std::uint32_t>& weights,
                                  const std::vector<std::int32_t>& labels, double voxel_size,
                                  const ConvexPartsParams& params, const KnownFreeSpace& known) {
  const double t = resolveConcavity(params, voxel_size);
  if (labels.size() != centers.size())
    throw Error("addConvexParts: " + std::to_string(labels.size()) + " labels for " +
                std::to_string(centers.size()) + " voxels");
  if (!weights.empty() && weights.size() != centers.size())
    throw Error("addConvexParts: " + std::to_string(weights.size()) + " weights for " +
                std::to_string(centers.size()) + " voxels");
  std::map<std::int32_t, std::vector<std::size_t>> clusters;
  for (std::size_t i = 0; i < centers.size(); ++i)
    if (labels[i] >= 0) clusters[labels[i]].push_back(i);
  for (const auto& o : obstacles)
    if (!clusters.count(o.id)) throw Error("addConvexParts: obstacle id " + std::to_string(o.id) + " is no label of the voxels");
  // Free voxel centres sorted by x, for a range per part.
  std::vector<Eigen::Vector3d> free = known.free_voxels;
  std::sort(free.begin(), free.end(), [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::tie(a.x(), a.y(), a.z()) < std::tie(b.x(), b.y(), b.z());
  });
  std::vector<std::size_t> keyframes_in_voxels(obstacles.size(), 0);
  tbb::parallel_for(std::size_t(0), obstacles.size(), [&](std::size_t o) {
    Obstacle& obstacle = obstacles[o];
    const std::vector<std::size_t>& members = clusters.at(obstacle.id);
    std::vector<Eigen::Vector3d> local;
    local.reserve(members.size());
    for (const auto i : members) local.push_back(centers[i]);
    const SplitResult result = splitCluster(local, voxel_size, t, params.max_check_cells, known.keyframes);
    obstacle.parts.clear();
    for (const auto& [part_members, check] : result.parts) {
      std::vector<std::size_t> global;
      global.reserve(part_members.size());
      for (const auto i : part_members) global.push_back(members[i]);
      const Obstacle whole = detail::wrapCluster(obstacle.id, global, centers, weights, voxel_size);
      ObstaclePart part;
      part.voxel_count = whole.voxel_count;
      part.point_weight = whole.point_weight;
      part.aabb_min = whole.aabb_min;
      part.aabb_max = whole.aabb_max;
      part.centroid = whole.centroid;
      part.volume = whole.volume;
      part.hull = whole.hull;
      part.footprint = whole.footprint;
      part.concavity_bound = std::sqrt(double(check.worst_d2)) * voxel_size;
      keyframes_in_voxels[o] += check.keyframes_in_voxels;
      const auto first = std::lower_bound(free.begin(), free.end(), part.aabb_min.x(),
                                          [](const Eigen::Vector3d& p, double x) { return p.x() < x; });
      for (auto it = first; it != free.end() && it->x() <= part.aabb_max.x(); ++it) {
        if ((it->array() < part.aabb_min.array()).any() || (it->array() > part.aabb_max.array()).any()) continue;
        if (inside(check.hull, (*it - result.lattice.origin) / voxel_size)) ++part.free_voxels_inside;
      }
      obstacle.parts.push_back(std::move(part));
    }
  });
  ConvexPartsSummary summary;
  summary.concavity = t;
  for (std::size_t o = 0; o < obstacles.size(); ++o) {
    const auto& obstacle = obstacles[o];
    summary.parts += obstacle.parts.size();
    summary.hull_volume_before += obstacle.volume;
    summary.voxel_volume += double(obstacle.voxel_count) * voxel_size * voxel_size * voxel_size;
    summary.keyframes_in_voxels += keyframes_in_voxels[o];
    for (const auto& part : obstacle.parts) {
      summary.hull_volume_after += part.volume;
      summary.free_voxels_inside += part.free_voxels_inside;
    }
  }
  return summary;
}

}  // namespace hullmap::clustering

// ClusterSplitter's checks: does a part pass the concavity T (its hull's cells within T of the part,
// or a flat part within G), the cells a cluster encloses, and the face-hole rule.
#include "cluster_splitter.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <optional>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/parallel_for_each.h>
#include <Eigen/Eigenvalues>

#include "hullmap/hulls/detail/distance_transform.hpp"
#include "hullmap/hulls/detail/outside_reach.hpp"

namespace hullmap::hulls::detail {
namespace {

/// Per column (i, j) of the box [lo, hi], x fastest: the k range of the cells whose cube meets the
/// hull, from every facet plane with the cube's lowest value of n . x (exact integers); k1 < k0 when
/// none does.
std::vector<std::pair<std::int64_t, std::int64_t>> hullColumns(const FacetHull& hull, const LatticePoint& lo,
                                                               const LatticePoint& hi) {
  const std::int64_t nx = hi[0] - lo[0] + 1, ny = hi[1] - lo[1] + 1;
  std::vector<std::pair<std::int64_t, std::int64_t>> columns(std::size_t(nx * ny));
  // Per plane, d less the cube's lowest offset: a cube (i, j, k) meets the plane's side when
  // n0 i + n1 j + n2 k <= rest0. Vertical planes (n2 = 0) bound each row's i first: the columns
  // outside those bounds are empty without looking at the other planes.
  std::vector<std::pair<const Plane*, std::int64_t>> vertical, others;
  for (const auto& p : hull.planes)
    (p.n[2] == 0 ? vertical : others)
        .emplace_back(&p, p.d - std::min<std::int64_t>(p.n[0], 0) - std::min<std::int64_t>(p.n[1], 0) -
                              std::min<std::int64_t>(p.n[2], 0));
  for (std::int64_t j = lo[1]; j <= hi[1]; ++j) {
    std::int64_t i0 = lo[0], i1 = hi[0];
    for (const auto& [p, rest0] : vertical) {
      const std::int64_t rest = rest0 - p->n[1] * j;  // n0 i <= rest
      if (p->n[0] > 0)
        i1 = std::min(i1, floorDiv(rest, p->n[0]));
      else if (p->n[0] < 0)
        i0 = std::max(i0, ceilDiv(rest, p->n[0]));
      else if (rest < 0)
        i1 = i0 - 1;
    }
    for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
      std::int64_t k0 = lo[2], k1 = hi[2];
      if (i < i0 || i > i1) k1 = k0 - 1;
      for (std::size_t q = 0; q < others.size() && k1 >= k0; ++q) {
        const Plane& p = *others[q].first;
        const std::int64_t rest = others[q].second - (p.n[0] * i + p.n[1] * j);
        // Divide only when the bound tightens: floor(rest / n2) < k1 exactly when rest < k1 n2
        // (n2 > 0), and ceil(rest / n2) > k0 exactly when rest < k0 n2 (n2 < 0).
        if (p.n[2] > 0) {
          if (rest < k1 * p.n[2]) k1 = floorDiv(rest, p.n[2]);
        } else if (rest < k0 * p.n[2]) {
          k0 = ceilDiv(rest, p.n[2]);
        }
      }
      columns[std::size_t((j - lo[1]) * nx + (i - lo[0]))] = {k0, k1};
    }
  }
  return columns;
}

/// True when `x` lies in one of `cells`' closed unit cubes (within 1e-9 of a face counts).
bool inOneOfTheCells(const Eigen::Vector3d& x, const std::vector<LatticePoint>& cells) {
  for (int m = 0; m < 8; ++m) {
    const std::int64_t i = std::int64_t(std::floor(x.x() + (m & 1 ? 1e-9 : -1e-9)));
    const std::int64_t j = std::int64_t(std::floor(x.y() + (m & 2 ? 1e-9 : -1e-9)));
    const std::int64_t k = std::int64_t(std::floor(x.z() + (m & 4 ? 1e-9 : -1e-9)));
    if (std::find(cells.begin(), cells.end(), LatticePoint{i, j, k}) != cells.end()) return true;
  }
  return false;
}

}  // namespace

ClusterSplitter::ClusterSplitter(std::vector<LatticePoint> cells, double t_cells, double g_cells,
                                 std::size_t max_check_cells, std::vector<Eigen::Vector3d> keyframes,
                                 bool fill_enclosed, std::optional<double> floor_k, bool face_holes)
    : cells_(std::move(cells)),
      fill_enclosed_(fill_enclosed),
      face_holes_(face_holes),
      floor_k_(floor_k),
      rho2_(std::max(g_cells, t_cells) * std::max(g_cells, t_cells) * (1.0 + 1e-12)),
      t_(t_cells),
      t2_(t_cells * t_cells * (1.0 + 1e-12)),
      g2_(std::max(g_cells, t_cells) * std::max(g_cells, t_cells) * (1.0 + 1e-12)),
      reach_(std::int64_t(std::floor(std::max(g_cells, t_cells)))),
      cap2_(std::int64_t(std::floor(g2_))),
      max_check_cells_(max_check_cells),
      keyframes_(std::move(keyframes)) {
  // Offsets longer on an axis than the cluster's box is wide lead from any point of the box out of
  // it, where no use of the ball finds anything (enclosedCells' margin takes its own ball): the
  // ball is clipped to the box. With a large concavity (T of hundreds of cells) the whole ball
  // would be tens of millions of offsets.
  std::array<std::int64_t, 3> extent{0, 0, 0};
  if (!cells_.empty()) {
    Members all(cells_.size());
    std::iota(all.begin(), all.end(), 0u);
    LatticePoint lo, hi;
    box(all, lo, hi);
    for (std::size_t a = 0; a < 3; ++a) extent[a] = std::min(reach_, hi[a] - lo[a]);
  }
  ball_ = ballOffsets(g2_, extent);
  // The number of offsets in the whole ball, which `checkPart` weighs against the box it fills.
  for (std::int64_t i = -reach_; i <= reach_; ++i)
    for (std::int64_t j = -reach_; j <= reach_; ++j) {
      const double rest = g2_ - double(i * i + j * j);
      if (rest < 0.0) continue;
      auto k = std::int64_t(std::floor(std::sqrt(rest)));  // the largest k with k^2 <= rest, exactly
      while (double((k + 1) * (k + 1)) <= rest) ++k;
      while (k > 0 && double(k * k) > rest) --k;
      whole_ball_size_ += 2 * std::size_t(k) + 1;
    }
}

std::vector<std::pair<LatticePoint, float>> ClusterSplitter::ballOffsets(double r2,
                                                                         const std::array<std::int64_t, 3>& extent) {
  std::vector<std::pair<LatticePoint, float>> ball;
  for (std::int64_t i = -extent[0]; i <= extent[0]; ++i)
    for (std::int64_t j = -extent[1]; j <= extent[1]; ++j)
      for (std::int64_t k = -extent[2]; k <= extent[2]; ++k)
        if (double(i * i + j * j + k * k) <= r2) ball.push_back({{i, j, k}, float(i * i + j * j + k * k)});
  std::stable_sort(ball.begin(), ball.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  return ball;
}

Check ClusterSplitter::checkPart(const Members& part, bool need_split_point, const FacetHull* hull, bool faces) const {
  auto key = std::make_tuple(part, need_split_point, faces);
  {
    const std::lock_guard<std::mutex> lock(memo_mutex_);
    const auto known = checks_.find(key);
    if (known != checks_.end()) return known->second;
  }
  Check check = checkPartOnce(part, need_split_point, hull, faces);
  const std::lock_guard<std::mutex> lock(memo_mutex_);
  checks_.emplace(std::move(key), check);
  return check;
}

FacetHull ClusterSplitter::hullOf(const Members& part) const {
  {
    const std::lock_guard<std::mutex> lock(memo_mutex_);
    const auto known = hulls_.find(part);
    if (known != hulls_.end()) return known->second;
  }
  FacetHull hull = facetHull(gather(part));
  const std::lock_guard<std::mutex> lock(memo_mutex_);
  hulls_.emplace(part, hull);
  return hull;
}

Check ClusterSplitter::checkPartOnce(const Members& part, bool need_split_point, const FacetHull* hull,
                                     bool faces) const {
  Check check;
  const std::vector<LatticePoint> cells = gather(part);
  check.hull = hull ? *hull : facetHull(cells);
  if (part.size() == 1) return check;
  LatticePoint lo, hi;
  box(part, lo, hi);
  const std::int64_t nx = hi[0] - lo[0] + 1, ny = hi[1] - lo[1] + 1, nz = hi[2] - lo[2] + 1;
  if (double(nx) * double(ny) * double(nz) > double(max_check_cells_)) {
    check.ok = false;
    check.too_big = true;
    return check;
  }
  // The sites: the part's cells, and the cells of its box that its cluster encloses (the inside
  // of a closed shell is no free space for a hull to swallow).
  const auto each_enclosed = [&](auto&& visit) {
    if (enclosed_count_ == 0) return;
    for (std::int64_t k = std::max(lo[2], enc_lo_[2]); k <= std::min(hi[2], enc_hi_[2]); ++k)
      for (std::int64_t j = std::max(lo[1], enc_lo_[1]); j <= std::min(hi[1], enc_hi_[1]); ++j)
        for (std::int64_t i = std::max(lo[0], enc_lo_[0]); i <= std::min(hi[0], enc_hi_[0]); ++i)
          if (enclosed_[encAt(i, j, k)]) visit(i, j, k);
  };
  each_enclosed([&](std::int64_t, std::int64_t, std::int64_t) { check.filled = true; });
  const std::size_t box_cells = std::size_t(nx * ny * nz);
  // Distances up to max(T, G) are all a passing check needs (and a failing one when no split point is
  // wanted): on a sparse part, the ball of radius T around each of its cells costs less than the
  // transform. Values within T are the same exact integers; beyond max(T, G) they stay kFar.
  const bool bounded = !check.filled && part.size() * whole_ball_size_ < 8 * box_cells;
  // Cells whose cube meets the hull.
  const std::vector<std::pair<std::int64_t, std::int64_t>> columns = hullColumns(check.hull, lo, hi);
  // A hull cell farther than max(T, G) from every site fails the check whatever else the distances
  // say: a check that wants no split point then needs no transform, one that does the exact one.
  const bool fails = !bounded && farHullCell(cells, lo, hi, columns);
  if (fails && !need_split_point) {
    check.ok = false;
    return check;
  }
  // Squared distance (cells^2) from each cell centre of the box to the nearest site's centre.
  constexpr double kFar = 1e20;
  std::vector<float> d2(box_cells, float(kFar));
  const auto at = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    return std::size_t(((k - lo[2]) * ny + (j - lo[1])) * nx + (i - lo[0]));
  };
  const auto seed = [&] {
    std::fill(d2.begin(), d2.end(), float(kFar));
    for (const auto& c : cells) d2[at(c[0], c[1], c[2])] = 0.0f;
    each_enclosed([&](std::int64_t i, std::int64_t j, std::int64_t k) { d2[at(i, j, k)] = 0.0f; });
  };
  seed();
  const std::array<std::int64_t, 3> dims{nx, ny, nz};
  // The exact transform over the whole box (Felzenszwalb-Huttenlocher, one pass per axis).
  // After it only the hull's cells are read (the scan), except by the face-hole rule.
  const auto transform = [&] { exactTransform(d2, dims, faces ? nullptr : &columns); };
  if (bounded) {
    for (const auto& c : cells)
      for (const auto& [o, o2] : ball_) {
        const std::int64_t i = c[0] + o[0], j = c[1] + o[1], k = c[2] + o[2];
        if (i < lo[0] || i > hi[0] || j < lo[1] || j > hi[1] || k < lo[2] || k > hi[2]) continue;
        float& d = d2[at(i, j, k)];
        d = std::min(d, o2);
      }
  } else if (fails) {
    transform();
  } else {
    boundedTransform(d2, dims, cap2_);  // the same values, by passes over the box
  }
  constexpr std::int64_t kBeyond = std::numeric_limits<std::int64_t>::max();
  std::int64_t worst = -1;
  LatticePoint worst_cell{0, 0, 0};
  const auto scan = [&] {
    worst = -1;
    for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
      for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
        const auto [k0, k1] = columns[std::size_t((j - lo[1]) * nx + (i - lo[0]))];
        for (std::int64_t k = k0; k <= k1; ++k) {
          const float x = d2[at(i, j, k)];
          const std::int64_t d = x >= float(kFar) ? kBeyond : std::int64_t(x);
          if (d > worst) {
            worst = d;
            worst_cell = {i, j, k};
          }
        }
      }
  };
  scan();
  if (worst == kBeyond) {
    check.ok = false;
    if (!need_split_point) return check;
    seed();
    transform();
    scan();
  }
  check.worst_d2 = std::max<std::int64_t>(worst, 0);
  if (double(check.worst_d2) > t2_ && double(check.worst_d2) <= g2_ && flat(check.hull, cells)) check.flat = true;
  // Holes in a sampled face (the merges' face-hole rule, see faceHoles): a cell farther than T from
  // every site passes when its cube lies within T of a face's plane and a site on that face is
  // within G of it: the flat part's rule, applied to each face of a solid part.
  if (faces && !check.flat && double(check.worst_d2) > t2_ && double(check.worst_d2) <= g2_) {
    const std::int64_t hole = faceHoles(check.hull, lo, hi, d2, columns, worst_cell);
    if (hole < 0) {
      check.faces = true;
    } else {
      check.ok = false;
      check.split_point =
          Eigen::Vector3d(double(worst_cell[0]) + 0.5, double(worst_cell[1]) + 0.5, double(worst_cell[2]) + 0.5);
      return check;
    }
  }
  if (double(check.worst_d2) > (check.flat || check.faces ? g2_ : t2_)) {
    check.ok = false;
    check.split_point =
        Eigen::Vector3d(double(worst_cell[0]) + 0.5, double(worst_cell[1]) + 0.5, double(worst_cell[2]) + 0.5);
    return check;
  }
  checkKeyframes(check, cells);
  return check;
}

void ClusterSplitter::checkKeyframes(Check& check, const std::vector<LatticePoint>& cells) const {
  for (const auto& x : keyframes_) {
    if (!inside(check.hull, x)) continue;
    // In one of the part's voxels (closed cubes): nothing can keep it out of the hull.
    if (inOneOfTheCells(x, cells)) {
      ++check.keyframes_in_voxels;
      continue;
    }
    check.ok = false;
    check.split_point = x;
    return;
  }
}

bool ClusterSplitter::farHullCell(const std::vector<LatticePoint>& cells, const LatticePoint& lo,
                                  const LatticePoint& hi,
                                  const std::vector<std::pair<std::int64_t, std::int64_t>>& columns) const {
  const std::int64_t nx = hi[0] - lo[0] + 1;
  const auto far = [&](const LatticePoint& c) {
    for (const auto& s : cells) {
      const std::int64_t di = s[0] - c[0], dj = s[1] - c[1], dk = s[2] - c[2];
      if (double(di * di + dj * dj + dk * dk) <= rho2_) return false;
    }
    if (enclosed_count_ > 0)
      for (const auto& [o, o2] : ball_) {
        const LatticePoint p{c[0] + o[0], c[1] + o[1], c[2] + o[2]};
        const bool in_box =
            p[0] >= lo[0] && p[0] <= hi[0] && p[1] >= lo[1] && p[1] <= hi[1] && p[2] >= lo[2] && p[2] <= hi[2];
        if (in_box && isEnclosed(p)) return false;
      }
    return true;
  };
  // The probes: the middle hull cell of the box's centre column and of its four quarter columns.
  for (const auto& [qi, qj] : {std::pair{2, 2}, {1, 1}, {3, 1}, {1, 3}, {3, 3}}) {
    const std::int64_t i = lo[0] + (hi[0] - lo[0]) * qi / 4, j = lo[1] + (hi[1] - lo[1]) * qj / 4;
    const auto [k0, k1] = columns[std::size_t((j - lo[1]) * nx + (i - lo[0]))];
    if (k1 >= k0 && far({i, j, k0 + (k1 - k0) / 2})) return true;
  }
  return false;
}

void ClusterSplitter::findEnclosed(const Members& all) {
  LatticePoint lo, hi;
  box(all, lo, hi);
  const std::int64_t m = reach_ + 1;
  const std::int64_t nx = hi[0] - lo[0] + 1, ny = hi[1] - lo[1] + 1, nz = hi[2] - lo[2] + 1;
  if (double(nx + 2 * m) * double(ny + 2 * m) * double(nz + 2 * m) > double(max_check_cells_)) return;
  std::vector<float> d2(std::size_t(nx * ny * nz), 1e20f);
  for (const auto& c : cells_) d2[std::size_t(((c[2] - lo[2]) * ny + (c[1] - lo[1])) * nx + (c[0] - lo[0]))] = 0.0f;
  boundedTransform(d2, {nx, ny, nz}, cap2_);  // only "within rho" is asked of it
  const bool closed_below = floor_k_ && double(lo[2]) <= *floor_k_ + 2.0;
  enclosed_ = enclosedCells(d2, nx, ny, nz, closed_below);
  enclosed_count_ = std::size_t(std::count(enclosed_.begin(), enclosed_.end(), char(1)));
  enc_lo_ = lo;
  enc_hi_ = hi;
}

std::vector<char> ClusterSplitter::enclosedCells(const std::vector<float>& d2, std::int64_t nx, std::int64_t ny,
                                                 std::int64_t nz, bool closed_below) const {
  // A margin wider than rho around the box, so that the outside holds cells beyond rho of the part.
  const std::int64_t m = reach_ + 1;
  const std::int64_t px = nx + 2 * m, py = ny + 2 * m, pz = nz + 2 * m;
  // 0: open, not reached; 1: blocked; 2: reached from outside.
  std::vector<char> state(std::size_t(px * py * pz), 0);
  const auto padded = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    return std::size_t((k * py + j) * px + i);
  };
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i)
        if (double(d2[std::size_t((k * ny + j) * nx + i)]) <= rho2_) state[padded(i + m, j + m, k + m)] = 1;
  // The margin within rho of the part is blocked too: the ball around each cell of the part (the
  // whole ball: the margin lies outside the box, where ball_ is clipped).
  const auto margin_ball = ballOffsets(rho2_, {reach_, reach_, reach_});
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i) {
        if (d2[std::size_t((k * ny + j) * nx + i)] != 0.0f) continue;
        const bool near_face = i < m || j < m || k < m || i >= nx - m || j >= ny - m || k >= nz - m;
        if (!near_face) continue;
        for (const auto& [o, o2] : margin_ball) state[padded(i + m + o[0], j + m + o[1], k + m + o[2])] = 1;
      }
  if (closed_below)  // the floor: everything below the box's lowest layer
    for (std::int64_t k = 0; k < m; ++k)
      for (std::int64_t j = 0; j < py; ++j)
        for (std::int64_t i = 0; i < px; ++i) state[padded(i, j, k)] = 1;
  markReached(state, px, py, pz);
  // Distance to the reached cells (the blocked bottom layer is no reached cell: the floor).
  std::vector<float> outside(state.size());
  for (std::size_t x = 0; x < state.size(); ++x) outside[x] = state[x] == 2 ? 0.0f : 1e20f;
  boundedTransform(outside, {px, py, pz}, cap2_);  // only "farther than rho" is asked of it
  std::vector<char> enclosed(std::size_t(nx * ny * nz), 0);
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i)
        enclosed[std::size_t((k * ny + j) * nx + i)] =
            double(outside[padded(i + m, j + m, k + m)]) > rho2_ && d2[std::size_t((k * ny + j) * nx + i)] > 0.0f;
  return enclosed;
}

std::optional<ClusterSplitter::Slab> ClusterSplitter::thinSlab(const FacetHull& hull,
                                                               const std::vector<LatticePoint>& cells) const {
  for (const auto& p : hull.planes) {
    const double norm = std::sqrt(double(dot(p.n, p.n)));
    const std::int64_t corner =
        std::min<std::int64_t>(p.n[0], 0) + std::min<std::int64_t>(p.n[1], 0) + std::min<std::int64_t>(p.n[2], 0);
    std::int64_t lo = p.d;
    for (const auto& c : cells) lo = std::min(lo, dot(p.n, c) + corner);
    if (double(p.d - lo) <= t_ * norm * (1.0 + 1e-12)) return Slab{p.n, lo, p.d};
  }
  return std::nullopt;
}

std::int64_t ClusterSplitter::faceHoles(const FacetHull& hull, const LatticePoint& lo, const LatticePoint& hi,
                                        const std::vector<float>& d2,
                                        const std::vector<std::pair<std::int64_t, std::int64_t>>& columns,
                                        LatticePoint& worst) const {
  struct FacetSlab {
    LatticePoint n;
    std::int64_t corner;  ///< the lowest n . x over a unit cube at the origin
    double limit;         ///< a cube lies in the slab when n . c + corner >= limit
    double on;            ///< a site's cube lies on the facet when n . c + corner >= on
  };
  std::vector<FacetSlab> slabs;
  slabs.reserve(hull.planes.size());
  for (const auto& p : hull.planes) {
    const double norm = std::sqrt(double(dot(p.n, p.n)));
    slabs.push_back(
        {p.n, std::min<std::int64_t>(p.n[0], 0) + std::min<std::int64_t>(p.n[1], 0) + std::min<std::int64_t>(p.n[2], 0),
         double(p.d) - t_ * norm * (1.0 + 1e-12), double(p.d) - kFaceLayers * norm * (1.0 + 1e-12)});
  }
  const std::int64_t nx = hi[0] - lo[0] + 1, ny = hi[1] - lo[1] + 1;
  const auto at = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    return std::size_t(((k - lo[2]) * ny + (j - lo[1])) * nx + (i - lo[0]));
  };
  // A facet is a face when every cell of its slab that is farther than T from every site has a site
  // of the slab within G (its holes are sampling holes); a facet lifted off the sites (a hull dragged
  // out to a stray) is none. Pass 1 finds the facets that are not faces, pass 2 the cells that no
  // face's slab holds.
  std::vector<std::size_t> holding;
  std::vector<char> found, not_face(slabs.size(), 0);
  std::vector<std::pair<LatticePoint, std::vector<std::size_t>>> far;  // cells beyond T, with their slabs
  for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
    for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
      const auto [k0, k1] = columns[std::size_t((j - lo[1]) * nx + (i - lo[0]))];
      for (std::int64_t k = k0; k <= k1; ++k) {
        if (double(d2[at(i, j, k)]) <= t2_) continue;
        const LatticePoint c{i, j, k};
        holding.clear();
        for (std::size_t s = 0; s < slabs.size(); ++s)
          if (double(dot(slabs[s].n, c) + slabs[s].corner) >= slabs[s].limit) holding.push_back(s);
        found.assign(holding.size(), 0);
        std::size_t missing = holding.size();
        for (const auto& [o, o2] : ball_) {
          if (missing == 0) break;
          const LatticePoint site{i + o[0], j + o[1], k + o[2]};
          if (site[0] < lo[0] || site[0] > hi[0] || site[1] < lo[1] || site[1] > hi[1] || site[2] < lo[2] ||
              site[2] > hi[2] || d2[at(site[0], site[1], site[2])] != 0.0f)
            continue;
          for (std::size_t h = 0; h < holding.size(); ++h)
            if (!found[h] &&
                double(dot(slabs[holding[h]].n, site) + slabs[holding[h]].corner) >= slabs[holding[h]].on) {
              found[h] = 1;
              --missing;
            }
        }
        for (std::size_t h = 0; h < holding.size(); ++h)
          if (!found[h]) not_face[holding[h]] = 1;
        far.emplace_back(c, holding);
      }
    }
  std::int64_t farthest = -1;
  for (const auto& [c, in] : far) {
    if (std::any_of(in.begin(), in.end(), [&](std::size_t s) { return !not_face[s]; })) continue;
    const std::int64_t x = std::int64_t(d2[at(c[0], c[1], c[2])]);
    if (x > farthest) {
      farthest = x;
      worst = c;
    }
  }
  return farthest;
}

bool ClusterSplitter::flat(const FacetHull& hull, const std::vector<LatticePoint>& cells) const {
  for (const auto& p : hull.planes) {
    const double norm = std::sqrt(double(dot(p.n, p.n)));
    // Wider than T once some cube reaches below d - T |n|.
    const double limit = double(p.d) - t_ * norm * (1.0 + 1e-12);
    const std::int64_t corner =
        std::min<std::int64_t>(p.n[0], 0) + std::min<std::int64_t>(p.n[1], 0) + std::min<std::int64_t>(p.n[2], 0);
    bool wide = false;
    for (const auto& c : cells)
      if (double(dot(p.n, c) + corner) < limit) {
        wide = true;
        break;
      }
    if (!wide) return true;
  }
  return false;
}

}  // namespace hullmap::hulls::detail

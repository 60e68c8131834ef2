#include "hullmap/clustering/convex_parts.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <numeric>
#include <optional>
#include <queue>
#include <set>
#include <string>
#include <tuple>
#include <utility>

#include <Eigen/Eigenvalues>
#include <tbb/parallel_for.h>
#include <tbb/parallel_for_each.h>

#include "hullmap/core/error.hpp"
#include "distance_transform.hpp"
#include "lattice_hull.hpp"

namespace hullmap::clustering {
namespace {

using detail::cross;
using detail::dot;
using detail::exactTransform;
using detail::FacetHull;
using detail::facetHull;
using detail::inside;
using detail::LatticePoint;
using detail::Plane;
using detail::sub;

/// Adapted flat gap (ConvexPartsParams::adapt_flat_gap): clusters of fewer voxels keep G; at most
/// this many voxels are sampled for the density; the expected number of empty discs of the adapted
/// radius that chance leaves on the cluster's surface; the cap, a multiple of G.
constexpr std::size_t kAdaptMinVoxels = 16;
constexpr std::size_t kAdaptSamples = 1024;
constexpr double kAdaptVacancies = 0.01;
constexpr double kAdaptMaxFactor = 2.0;
/// absorb(): a non-flat part gives voxels to a flat part only when the flat part has at least this
/// many times its voxels.
constexpr std::size_t kAbsorbRatio = 8;
/// shedStrays(): at most this many stray cells, and at most one in this many of the part; a stray
/// cell's clump (cells linked by steps of at most T) has at most kStrayClump cells.
constexpr std::size_t kShedMax = 8;
constexpr std::size_t kStrayClump = 3;
/// findStrays(): clumps of 2 to kStrayClump cells are strays only when at most this share of the
/// cluster's cells lie in clumps of at most kStrayClump (lone cells are strays always).
constexpr double kStrayShare = 0.1;
constexpr std::size_t kShedShare = 16;
/// The face-hole rule (faceHoles): a site lies on a facet when its cube is within this many voxel
/// edges of the facet's plane (a noisy surface's layer of voxels); merge() applies the rule only to
/// parts of at least kFaceMergeMinVoxels voxels.
constexpr double kFaceLayers = 2.0;
constexpr std::size_t kFaceMergeMinVoxels = 3;
using Members = std::vector<std::uint32_t>;  ///< sorted indices into the cluster's cells

/// The check of one part against T (see splitConvexParts).
struct Check {
  bool ok = true;
  bool too_big = false;       ///< box over max_check_cells: not checked
  std::int64_t worst_d2 = 0;  ///< largest squared centre distance (cells^2) over the hull's cells
  Eigen::Vector3d split_point = Eigen::Vector3d::Zero();  ///< where to cut, lattice coordinates
  FacetHull hull;
  std::size_t keyframes_in_voxels = 0;
  bool flat = false;    ///< passed as a flat part (hull width <= T, distances within G)
  bool filled = false;  ///< enclosed cells counted as the part's own
  bool faces = false;   ///< passed by the face-hole rule (distances within G in a facet's slab)
};

/// One cluster on its lattice, and the work on it.
class ClusterSplitter {
 public:
  /// `t_cells`: T; `g_cells`: G >= T, the distance allowed in a flat part (G = T: no relaxation).
  ClusterSplitter(std::vector<LatticePoint> cells, double t_cells, double g_cells, std::size_t max_check_cells,
                  std::vector<Eigen::Vector3d> keyframes, bool fill_enclosed, std::optional<double> floor_k,
                  bool face_holes)
      : cells_(std::move(cells)),
        fill_enclosed_(fill_enclosed),
        face_holes_(face_holes),
        floor_k_(floor_k),
        rho2_(std::max(g_cells, t_cells) * std::max(g_cells, t_cells) * (1.0 + 1e-12)),
        t_(t_cells),
        t2_(t_cells * t_cells * (1.0 + 1e-12)),
        g2_(std::max(g_cells, t_cells) * std::max(g_cells, t_cells) * (1.0 + 1e-12)),
        reach_(std::int64_t(std::floor(std::max(g_cells, t_cells)))),
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

  /// Lattice offsets within sqrt(r2) and within `extent` on each axis, with their squared lengths,
  /// nearest first (ties in (i, j, k) order).
  static std::vector<std::pair<LatticePoint, float>> ballOffsets(double r2, const std::array<std::int64_t, 3>& extent) {
    std::vector<std::pair<LatticePoint, float>> ball;
    for (std::int64_t i = -extent[0]; i <= extent[0]; ++i)
      for (std::int64_t j = -extent[1]; j <= extent[1]; ++j)
        for (std::int64_t k = -extent[2]; k <= extent[2]; ++k)
          if (double(i * i + j * j + k * k) <= r2) ball.push_back({{i, j, k}, float(i * i + j * j + k * k)});
    std::stable_sort(ball.begin(), ball.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
    return ball;
  }

  /// Final parts with their checks.
  std::vector<std::pair<Members, Check>> run() {
    Members all(cells_.size());
    std::iota(all.begin(), all.end(), 0u);
    if (fill_enclosed_) findEnclosed(all);
    std::vector<std::pair<Members, Check>> done;
    findStrays();
    // Parts to check, with their hulls when the split already built them. The halves of a split
    // are independent, so they are checked in parallel; the order in which parts are done does not
    // matter (merge orders them by their first cell).
    using Work = std::pair<Members, std::optional<FacetHull>>;
    std::vector<Work> start;
    start.emplace_back(std::move(all), std::nullopt);
    std::mutex done_mutex;
    tbb::parallel_for_each(start.begin(), start.end(), [&](Work& work, tbb::feeder<Work>& feeder) {
      Members& part = work.first;
      Check check = checkPart(part, true, work.second ? &*work.second : nullptr);
      // Stray cells are shed before a cut (see shedStrays), each a part of its own for now (the
      // merge below may join them to a part they pass with).
      const auto shed = shedStrays(part, check);
      if (!shed.empty()) {
        const std::lock_guard<std::mutex> lock(done_mutex);
        for (const auto i : shed) {
          Check single;
          single.hull = facetHull({cells_[i]});
          done.emplace_back(Members{i}, std::move(single));
        }
      }
      if (check.ok || part.size() == 1) {
        const std::lock_guard<std::mutex> lock(done_mutex);
        done.emplace_back(std::move(part), std::move(check));
        return;
      }
      Halves halves = split(part, check);
      feeder.add(Work(std::move(halves.left), std::move(halves.left_hull)));
      feeder.add(Work(std::move(halves.right), std::move(halves.right_hull)));
    });
    auto parts = absorb(merge(std::move(done)));
    bool changed = false;
    parts = absorbIntoBoxes(std::move(parts), changed);
    if (changed) parts = absorb(merge(std::move(parts)));
    // Last, with face_holes, the pieces a cut left of a solid part with sparse faces are merged back
    // (parts of at least kFaceMergeMinVoxels voxels: a stray or a clump cut off before stays off).
    return face_holes_ ? absorb(merge(std::move(parts), true)) : parts;
  }

 private:
  std::vector<LatticePoint> gather(const Members& part) const {
    std::vector<LatticePoint> out;
    out.reserve(part.size());
    for (const auto i : part) out.push_back(cells_[i]);
    return out;
  }

  void box(const Members& part, LatticePoint& lo, LatticePoint& hi) const {
    lo = cells_[part[0]];
    hi = lo;
    for (const auto i : part)
      for (int a = 0; a < 3; ++a) {
        lo[std::size_t(a)] = std::min(lo[std::size_t(a)], cells_[i][std::size_t(a)]);
        hi[std::size_t(a)] = std::max(hi[std::size_t(a)], cells_[i][std::size_t(a)]);
      }
  }

  /// `need_split_point`: when false (the merge), a failed check only reports that it failed
  /// (worst_d2 and split_point unset). `hull`: the part's lattice hull when already known.
  Check checkPart(const Members& part, bool need_split_point = true, const FacetHull* hull = nullptr,
                  bool faces = false) const {
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
    // Squared distance (cells^2) from each cell centre of the box to the nearest occupied centre.
    constexpr double kFar = 1e20;
    const std::size_t box_cells = std::size_t(nx * ny * nz);
    std::vector<float> d2(box_cells, float(kFar));
    const auto at = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
      return std::size_t(((k - lo[2]) * ny + (j - lo[1])) * nx + (i - lo[0]));
    };
    // The sites: the part's cells, and the cells of its box that its cluster encloses (the inside
    // of a closed shell is no free space for a hull to swallow).
    const auto seed = [&] {
      std::fill(d2.begin(), d2.end(), float(kFar));
      for (const auto& c : cells) d2[at(c[0], c[1], c[2])] = 0.0f;
      std::size_t filled = 0;
      if (enclosed_count_ == 0) return filled;
      for (std::int64_t k = std::max(lo[2], enc_lo_[2]); k <= std::min(hi[2], enc_hi_[2]); ++k)
        for (std::int64_t j = std::max(lo[1], enc_lo_[1]); j <= std::min(hi[1], enc_hi_[1]); ++j)
          for (std::int64_t i = std::max(lo[0], enc_lo_[0]); i <= std::min(hi[0], enc_hi_[0]); ++i)
            if (enclosed_[encAt(i, j, k)]) {
              d2[at(i, j, k)] = 0.0f;
              ++filled;
            }
      return filled;
    };
    check.filled = seed() > 0;
    const std::array<std::int64_t, 3> dims{nx, ny, nz};
    // The exact transform over the whole box (Felzenszwalb-Huttenlocher, one pass per axis).
    const auto transform = [&] { exactTransform(d2, dims); };
    // Distances up to max(T, G) are all a passing check needs (and a failing one when no split point is
    // wanted): on a sparse part, the ball of radius T around each of its cells costs less than the
    // transform. Values within T are the same exact integers; beyond max(T, G) they stay kFar.
    const bool bounded = !check.filled && part.size() * whole_ball_size_ < 8 * box_cells;
    if (bounded) {
      for (const auto& c : cells)
        for (const auto& [o, o2] : ball_) {
          const std::int64_t i = c[0] + o[0], j = c[1] + o[1], k = c[2] + o[2];
          if (i < lo[0] || i > hi[0] || j < lo[1] || j > hi[1] || k < lo[2] || k > hi[2]) continue;
          float& d = d2[at(i, j, k)];
          d = std::min(d, o2);
        }
    } else {
      transform();
    }
    // Cells whose cube meets the hull: per column, the k range allowed by every facet plane, with
    // the cube's lowest value of n . x (exact integers).
    std::vector<std::pair<std::int64_t, std::int64_t>> columns(std::size_t(nx * ny));
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
        columns[std::size_t((j - lo[1]) * nx + (i - lo[0]))] = {k0, k1};
      }
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
    for (const auto& x : keyframes_) {
      if (!inside(check.hull, x)) continue;
      // In one of the part's voxels (closed cubes): nothing can keep it out of the hull.
      bool in_voxel = false;
      for (int m = 0; m < 8 && !in_voxel; ++m) {
        const std::int64_t i = std::int64_t(std::floor(x.x() + (m & 1 ? 1e-9 : -1e-9)));
        const std::int64_t j = std::int64_t(std::floor(x.y() + (m & 2 ? 1e-9 : -1e-9)));
        const std::int64_t k = std::int64_t(std::floor(x.z() + (m & 4 ? 1e-9 : -1e-9)));
        in_voxel = std::find(cells.begin(), cells.end(), LatticePoint{i, j, k}) != cells.end();
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

  /// The cells the whole cluster encloses (enclosedCells over its box, closed below when its
  /// lowest cell is within two voxels of the floor); none when its box is over max_check_cells.
  void findEnclosed(const Members& all) {
    LatticePoint lo, hi;
    box(all, lo, hi);
    const std::int64_t m = reach_ + 1;
    const std::int64_t nx = hi[0] - lo[0] + 1, ny = hi[1] - lo[1] + 1, nz = hi[2] - lo[2] + 1;
    if (double(nx + 2 * m) * double(ny + 2 * m) * double(nz + 2 * m) > double(max_check_cells_)) return;
    std::vector<float> d2(std::size_t(nx * ny * nz), 1e20f);
    for (const auto& c : cells_) d2[std::size_t(((c[2] - lo[2]) * ny + (c[1] - lo[1])) * nx + (c[0] - lo[0]))] = 0.0f;
    exactTransform(d2, {nx, ny, nz});
    const bool closed_below = floor_k_ && double(lo[2]) <= *floor_k_ + 2.0;
    enclosed_ = enclosedCells(d2, nx, ny, nz, closed_below);
    enclosed_count_ = std::size_t(std::count(enclosed_.begin(), enclosed_.end(), char(1)));
    enc_lo_ = lo;
    enc_hi_ = hi;
  }

  /// Whether the cluster encloses the cell (see findEnclosed).
  bool isEnclosed(const LatticePoint& c) const {
    if (enclosed_count_ == 0) return false;
    for (std::size_t a = 0; a < 3; ++a)
      if (c[a] < enc_lo_[a] || c[a] > enc_hi_[a]) return false;
    return enclosed_[encAt(c[0], c[1], c[2])] != 0;
  }

  std::size_t encAt(std::int64_t i, std::int64_t j, std::int64_t k) const {
    const std::int64_t nx = enc_hi_[0] - enc_lo_[0] + 1, ny = enc_hi_[1] - enc_lo_[1] + 1;
    return std::size_t(((k - enc_lo_[2]) * ny + (j - enc_lo_[1])) * nx + (i - enc_lo_[0]));
  }

  /// Cells of the box (nx * ny * nz, as `d2`) enclosed by the part: farther than rho from every cell
  /// that the outside reaches, where the outside spreads from around the box through the cells
  /// farther than rho from the part's cells (6-connected), so holes narrower than about 2 rho do not
  /// let it in. A closing of the part's shell: its inside is filled, and a concave corner only within
  /// about 0.3 rho of its apex. `closed_below`: nothing enters through the box's bottom face (the
  /// floor closes it).
  std::vector<char> enclosedCells(const std::vector<float>& d2, std::int64_t nx, std::int64_t ny, std::int64_t nz,
                                  bool closed_below) const {
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
    std::vector<std::size_t> queue;
    for (std::int64_t k = 0; k < pz; ++k)
      for (std::int64_t j = 0; j < py; ++j)
        for (std::int64_t i = 0; i < px; ++i) {
          const bool border = i == 0 || j == 0 || k == 0 || i == px - 1 || j == py - 1 || k == pz - 1;
          if (border && state[padded(i, j, k)] == 0) {
            state[padded(i, j, k)] = 2;
            queue.push_back(padded(i, j, k));
          }
        }
    const std::array<std::int64_t, 6> steps{1, -1, px, -px, px * py, -px * py};
    while (!queue.empty()) {
      const std::size_t x = queue.back();
      queue.pop_back();
      for (const auto step : steps) {
        const std::int64_t y = std::int64_t(x) + step;
        if (y < 0 || y >= std::int64_t(state.size()) || state[std::size_t(y)] != 0) continue;
        state[std::size_t(y)] = 2;
        queue.push_back(std::size_t(y));
      }
    }
    // Distance to the reached cells (the blocked bottom layer is no reached cell: the floor).
    std::vector<float> outside(state.size());
    for (std::size_t x = 0; x < state.size(); ++x) outside[x] = state[x] == 2 ? 0.0f : 1e20f;
    exactTransform(outside, {px, py, pz});
    std::vector<char> enclosed(std::size_t(nx * ny * nz), 0);
    for (std::int64_t k = 0; k < nz; ++k)
      for (std::int64_t j = 0; j < ny; ++j)
        for (std::int64_t i = 0; i < nx; ++i)
          enclosed[std::size_t((k * ny + j) * nx + i)] =
              double(outside[padded(i + m, j + m, k + m)]) > rho2_ && d2[std::size_t((k * ny + j) * nx + i)] > 0.0f;
    return enclosed;
  }

  /// A flat part's slab: a facet normal n (corner-lattice units) along which the hull is at most T
  /// wide, and the range [lo, hi] of n . x over the hull (hi the facet plane's value). The first such
  /// facet in the hull's plane order; none when the hull is wider than T along every facet normal.
  struct Slab {
    LatticePoint n;
    std::int64_t lo, hi;
  };
  std::optional<Slab> thinSlab(const FacetHull& hull, const std::vector<LatticePoint>& cells) const {
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

  /// The parts that still hold cells, in order of their first cell (after hand-overs emptied some).
  static std::vector<std::pair<Members, Check>> withoutEmpty(std::vector<std::pair<Members, Check>> parts) {
    std::vector<std::pair<Members, Check>> kept;
    for (auto& part : parts)
      if (!part.first.empty()) kept.push_back(std::move(part));
    std::sort(kept.begin(), kept.end(), [](const auto& a, const auto& b) { return a.first[0] < b.first[0]; });
    return kept;
  }

  /// Moves the cells `in` of part q into part f when f with them and what is left of q (`out`, which
  /// lost sites) each pass the check; true when they moved. Nothing changes otherwise.
  bool handOver(std::vector<std::pair<Members, Check>>& parts, std::size_t f, std::size_t q, const Members& in,
                Members out) const {
    if (in.empty()) return false;
    Members both;
    both.reserve(parts[f].first.size() + in.size());
    std::merge(parts[f].first.begin(), parts[f].first.end(), in.begin(), in.end(), std::back_inserter(both));
    Check check = checkPart(both, false);
    if (!check.ok) return false;
    Check rest;
    if (!out.empty()) {
      rest = checkPart(out, false);
      if (!rest.ok) return false;
    }
    parts[f] = {std::move(both), std::move(check)};
    parts[q] = {std::move(out), std::move(rest)};
    return true;
  }

  /// Hands the voxels of the non-flat parts that lie in a flat part's slab to that flat part, when
  /// the flat part with them still passes its check (so every part keeps its guarantee) and the
  /// non-flat part is a fragment (the flat part has at least kAbsorbRatio times its voxels). Where two
  /// walls meet, or a voxel of noise sits off a wall, the merge leaves a small non-flat part (the
  /// corner's voxels of both walls together are thicker than T, and its hull over the walls' holes is
  /// farther than T from them): its voxels in each wall's slab go to that wall, and what is left (if
  /// anything) stays a part. Then the flat fragments do the same with the other flat parts. Flat
  /// parts in order of size (largest first, ties by first cell), the non-flat parts in order of their
  /// first cell before them; deterministic.
  std::vector<std::pair<Members, Check>> absorb(std::vector<std::pair<Members, Check>> parts) const {
    std::vector<std::size_t> flats, others;
    for (std::size_t p = 0; p < parts.size(); ++p) (parts[p].second.flat ? flats : others).push_back(p);
    if (flats.empty()) return parts;
    std::stable_sort(flats.begin(), flats.end(),
                     [&](std::size_t a, std::size_t b) { return parts[a].first.size() > parts[b].first.size(); });
    // Then the flat fragments: a few voxels of a wall's foot or top edge that the split cut off
    // together with a stray in line with them (a part thin too, at right angles to the wall) give
    // their voxels in the wall's slab back to it, and the stray is left a part of its own.
    for (const auto f : flats) others.push_back(f);
    bool changed = false;
    for (const auto q : others) {
      LatticePoint qlo, qhi;
      box(parts[q].first, qlo, qhi);
      for (const auto f : flats) {
        if (parts[q].first.empty()) break;
        if (f == q) continue;
        // Fragments only: a part at least 1/kAbsorbRatio of the flat part's size stays as it is (a
        // slanted slab through a 3D cluster would otherwise gather its voxels into a wide thin hull).
        if (parts[q].first.size() * kAbsorbRatio > parts[f].first.size()) continue;
        LatticePoint flo, fhi;
        box(parts[f].first, flo, fhi);
        bool near = true;
        for (std::size_t k = 0; k < 3; ++k)
          near = near && qlo[k] - fhi[k] - 1 <= reach_ && flo[k] - qhi[k] - 1 <= reach_;
        if (!near) continue;
        const auto slab = thinSlab(parts[f].second.hull, gather(parts[f].first));
        if (!slab) continue;
        // The voxels of q whose cube lies in the slab.
        const std::int64_t low_corner = std::min<std::int64_t>(slab->n[0], 0) + std::min<std::int64_t>(slab->n[1], 0) +
                                        std::min<std::int64_t>(slab->n[2], 0);
        const std::int64_t high_corner = std::max<std::int64_t>(slab->n[0], 0) + std::max<std::int64_t>(slab->n[1], 0) +
                                         std::max<std::int64_t>(slab->n[2], 0);
        Members in, out;
        for (const auto i : parts[q].first) {
          const std::int64_t v = dot(slab->n, cells_[i]);
          (v + low_corner >= slab->lo && v + high_corner <= slab->hi ? in : out).push_back(i);
        }
        if (!handOver(parts, f, q, in, std::move(out))) continue;
        changed = true;
        if (!parts[q].first.empty()) box(parts[q].first, qlo, qhi);
      }
    }
    if (!changed) return parts;
    return withoutEmpty(std::move(parts));
  }

  /// Marks the stray cells: those whose clump (the cells linked to it by steps of at most T) has at
  /// most kStrayClump cells, with the clump's id (its smallest cell index) in clump_; none when the
  /// cluster is too wide for the packed keys (21 bits per axis). A lone cell (no other cell within T)
  /// is a clump of one.
  void findStrays() {
    clump_.assign(cells_.size(), kNoClump);
    for (const auto& c : cells_)
      for (const auto x : c)
        if (x < -(std::int64_t(1) << 19) || x >= (std::int64_t(1) << 19)) return;
    const auto pack = [](const LatticePoint& c) {
      return (std::uint64_t(c[0] + (1 << 20)) << 42) | (std::uint64_t(c[1] + (1 << 20)) << 21) |
             std::uint64_t(c[2] + (1 << 20));
    };
    std::vector<std::pair<std::uint64_t, std::uint32_t>> occupied;
    occupied.reserve(cells_.size());
    for (std::uint32_t i = 0; i < cells_.size(); ++i) occupied.emplace_back(pack(cells_[i]), i);
    std::sort(occupied.begin(), occupied.end());
    // The cells within T of cell i, into `out`; false (out incomplete) once more than kStrayClump.
    const auto neighbours = [&](std::uint32_t i, std::vector<std::uint32_t>& out) {
      out.clear();
      const LatticePoint& c = cells_[i];
      for (const auto& [o, o2] : ball_) {
        if (double(o2) > t2_) break;  // ball_ is sorted by distance
        if (o2 == 0.0f) continue;
        const std::uint64_t key = pack({c[0] + o[0], c[1] + o[1], c[2] + o[2]});
        const auto it = std::lower_bound(occupied.begin(), occupied.end(), std::make_pair(key, std::uint32_t(0)));
        if (it == occupied.end() || it->first != key) continue;
        out.push_back(it->second);
        if (out.size() >= kStrayClump) return false;
      }
      return true;
    };
    std::vector<std::uint32_t> clump, around;
    std::size_t in_small = 0;  // cells in clumps of at most kStrayClump
    std::vector<char> in_pair_or_more(cells_.size(), 0);
    std::vector<char> big(cells_.size(), 0);  // known to lie in a clump of more than kStrayClump
    for (std::uint32_t i = 0; i < cells_.size(); ++i) {
      if (clump_[i] != kNoClump || big[i]) continue;
      // Grow i's clump breadth first; give up once it holds more than kStrayClump cells.
      clump.assign(1, i);
      bool small = true;
      for (std::size_t next = 0; next < clump.size() && small; ++next) {
        small = neighbours(clump[next], around);
        for (const auto n : around)
          if (std::find(clump.begin(), clump.end(), n) == clump.end()) clump.push_back(n);
        small = small && clump.size() <= kStrayClump;
      }
      if (!small) {
        // Every cell reached is linked to i, so its clump is the same big one: no search from it.
        for (const auto m : clump) big[m] = 1;
        continue;
      }
      const std::uint32_t id = *std::min_element(clump.begin(), clump.end());
      for (const auto m : clump) clump_[m] = id;
      in_small += clump.size();
      if (clump.size() > 1)
        for (const auto m : clump) in_pair_or_more[m] = 1;
    }
    // Where small clumps are the surface's own sampling (a sparse map: a fifth of the cells or more
    // lie in them) rather than noise off it (a dense one: 2 % or less), only lone cells are strays.
    if (double(in_small) <= kStrayShare * double(cells_.size())) return;
    for (std::size_t i = 0; i < cells_.size(); ++i)
      if (in_pair_or_more[i]) clump_[i] = kNoClump;
  }

  /// Sheds the stray cells that alone keep a part from passing (`check`: its failed check, with the
  /// split point): while it fails, the stray cell (findStrays: its clump, the cells linked to it by
  /// steps of at most T, has at most kStrayClump cells) nearest the deepest uncovered cell is taken
  /// out with the rest of its clump in the part, if it lies within 2 rho (rho = max(T, G)) of that
  /// cell and the deepest distance did not grow; when what is left passes after at most kShedMax such
  /// cells (and at most 1/kShedShare of the part), they are removed from `part`, `check` becomes the
  /// rest's and they are returned (each becomes a part of one voxel, which the merge may join to a
  /// part it passes with); otherwise nothing changes. A stray voxel, or two or three together, a few
  /// cells off a box's face (noise, outliers DBSCAN took in) drags a wedge of hull out to it that is
  /// farther than T from everything, and the cut that removed it also took a slice of the box. A part
  /// whose deepest uncovered cell has no stray cell within 2 rho (a room's middle) costs one scan of
  /// its cells.
  std::vector<std::uint32_t> shedStrays(Members& part, Check& check) const {
    if (check.ok || check.too_big || part.size() < 2 * kShedShare) return {};
    std::vector<std::uint32_t> shed;
    Members rest = part;
    Check now = check;
    const std::size_t most = std::min<std::size_t>(kShedMax, part.size() / kShedShare);
    while (!now.ok && !now.too_big && shed.size() < most) {
      // The stray cell nearest the deepest uncovered cell (ties: the first), within 2 rho of it.
      double best = 4.0 * rho2_;
      std::optional<std::uint32_t> pick;
      for (const auto i : rest) {
        if (clump_[i] == kNoClump) continue;
        const Eigen::Vector3d d =
            Eigen::Vector3d(double(cells_[i][0]) + 0.5, double(cells_[i][1]) + 0.5, double(cells_[i][2]) + 0.5) -
            now.split_point;
        if (d.squaredNorm() <= best) {
          if (!pick || d.squaredNorm() < best) pick = i;
          best = d.squaredNorm();
        }
      }
      if (!pick) return {};
      const std::uint32_t id = clump_[*pick];
      Members kept;
      kept.reserve(rest.size());
      for (const auto i : rest) (clump_[i] == id ? shed : kept).push_back(i);
      if (shed.size() > most || kept.empty()) return {};
      rest = std::move(kept);
      const std::int64_t before = now.worst_d2;
      now = checkPart(rest, true);
      if (!now.ok && now.worst_d2 > before) return {};
    }
    if (!now.ok) return {};
    part = std::move(rest);
    check = std::move(now);
    return shed;
  }

  /// Hands the voxels of a non-flat fragment lying in the bounding box of a larger non-flat part (at
  /// least kAbsorbRatio times its voxels) to that part, when the part with them and what is left of
  /// the fragment (if anything) each pass the check. A stray voxel off a box's face drags a wedge of
  /// hull out to it, so the split cuts it off together with some of the face's voxels around it, and
  /// the face is left with a hole the rest of the box cannot merge across: this gives the face's
  /// voxels back, leaving the stray (and whatever else lies outside the box) a part of its own.
  /// Larger parts first (ties by first cell), fragments in order of their first cell; deterministic.
  /// `changed`: set when a voxel moved (the parts are then merged again).
  std::vector<std::pair<Members, Check>> absorbIntoBoxes(std::vector<std::pair<Members, Check>> parts,
                                                         bool& changed) const {
    std::vector<std::size_t> order;
    for (std::size_t p = 0; p < parts.size(); ++p)
      if (!parts[p].second.flat) order.push_back(p);
    if (order.size() < 2) return parts;
    std::vector<std::size_t> targets = order;
    std::stable_sort(targets.begin(), targets.end(),
                     [&](std::size_t a, std::size_t b) { return parts[a].first.size() > parts[b].first.size(); });
    for (const auto q : order) {
      for (const auto f : targets) {
        if (f == q || parts[q].first.empty()) continue;
        if (parts[q].first.size() * kAbsorbRatio > parts[f].first.size()) continue;
        LatticePoint flo, fhi;
        box(parts[f].first, flo, fhi);
        Members in, out;
        for (const auto i : parts[q].first) {
          const LatticePoint& c = cells_[i];
          bool inside_box = true;
          for (std::size_t a = 0; a < 3; ++a) inside_box = inside_box && c[a] >= flo[a] && c[a] <= fhi[a];
          (inside_box ? in : out).push_back(i);
        }
        if (handOver(parts, f, q, in, std::move(out))) changed = true;
      }
    }
    if (!changed) return parts;
    return withoutEmpty(std::move(parts));
  }

  /// The face-hole rule of checkPart over the cells whose cube meets the hull (`columns`: per column
  /// of the box lo..hi, the k range), with `d2` the squared distances to the sites (exact up to
  /// max(T, G); 0 at the sites): the squared distance of the farthest cell that is farther than T
  /// from every site and not within G of a site in the slab of a facet whose slab holds it, that
  /// cell in `worst`; -1 when there is none.
  std::int64_t faceHoles(const FacetHull& hull, const LatticePoint& lo, const LatticePoint& hi,
                         const std::vector<float>& d2,
                         const std::vector<std::pair<std::int64_t, std::int64_t>>& columns, LatticePoint& worst) const {
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
          {p.n,
           std::min<std::int64_t>(p.n[0], 0) + std::min<std::int64_t>(p.n[1], 0) + std::min<std::int64_t>(p.n[2], 0),
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

  /// Whether the hull is at most T wide along one of its facet normals (so it is at most T thick:
  /// the width along a facet normal bounds the hull's least width from above). A facet's width is
  /// its plane's value minus the least value of n . x over the cells' cubes (exact integers).
  bool flat(const FacetHull& hull, const std::vector<LatticePoint>& cells) const {
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

  static std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
    std::int64_t q = a / b;
    if ((a % b != 0) && ((a < 0) != (b < 0))) --q;
    return q;
  }
  static std::int64_t ceilDiv(std::int64_t a, std::int64_t b) { return -floorDiv(-a, b); }

  /// Two non-empty halves of a part that failed its check.
  struct Halves {
    Members left, right;
    std::optional<FacetHull> left_hull, right_hull;
  };
  Halves split(const Members& part, const Check& check) const {
    LatticePoint lo, hi;
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
        if (const auto cut = bestBoxCut(part, a))
          planes.emplace_back(Eigen::Vector3d::Unit(a), Eigen::Vector3d::Constant(double(*cut)));
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
      std::vector<FacetHull> sides(2 * cuts.size());
      tbb::parallel_for(std::size_t(0), sides.size(), [&](std::size_t k) {
        sides[k] = facetHull(gather(k % 2 ? cuts[k / 2].second : cuts[k / 2].first));
      });
      const auto volume = [&](std::size_t c) { return sides[2 * c].volume6 + sides[2 * c + 1].volume6; };
      std::optional<std::size_t> best;
      for (std::size_t c = 0; c < cuts.size(); ++c)
        if (!best || volume(c) < volume(*best)) best = c;
      if (best)
        return {std::move(cuts[*best].first), std::move(cuts[*best].second), std::move(sides[2 * *best]),
                std::move(sides[2 * *best + 1])};
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
    return {std::move(left), std::move(right), std::nullopt, std::nullopt};
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
    std::vector<LatticePoint> lo_prefix(n), hi_prefix(n), lo_suffix(n), hi_suffix(n);
    for (std::size_t k = 0; k < n; ++k) {
      const LatticePoint& c = cells_[order[k]];
      lo_prefix[k] = hi_prefix[k] = c;
      if (k > 0)
        for (std::size_t d = 0; d < 3; ++d) {
          lo_prefix[k][d] = std::min(lo_prefix[k - 1][d], c[d]);
          hi_prefix[k][d] = std::max(hi_prefix[k - 1][d], c[d]);
        }
    }
    for (std::size_t k = n; k-- > 0;) {
      const LatticePoint& c = cells_[order[k]];
      lo_suffix[k] = hi_suffix[k] = c;
      if (k + 1 < n)
        for (std::size_t d = 0; d < 3; ++d) {
          lo_suffix[k][d] = std::min(lo_suffix[k + 1][d], c[d]);
          hi_suffix[k][d] = std::max(hi_suffix[k + 1][d], c[d]);
        }
    }
    const auto volume = [](const LatticePoint& lo, const LatticePoint& hi) {
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

  /// Greedy merge of parts whose boxes come within max(T, G), the pair whose union's hull adds the least
  /// volume first, while the union passes the check (`faces`: with the face-hole rule, parts of at
  /// least kFaceMergeMinVoxels voxels only).
  std::vector<std::pair<Members, Check>> merge(std::vector<std::pair<Members, Check>> parts, bool faces = false) const {
    struct Node {
      Members members;
      Check check;
      LatticePoint lo, hi;
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
    std::map<std::pair<std::size_t, std::size_t>, FacetHull> union_hulls;  ///< of the queued pairs
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
    // Which node owns each cell, on a grid over the cluster's box (none when the box is too big;
    // then no pair is ruled out early).
    constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
    LatticePoint grid_lo{0, 0, 0}, grid_hi{0, 0, 0};
    std::vector<std::uint32_t> owner;
    {
      Members all(cells_.size());
      std::iota(all.begin(), all.end(), 0u);
      box(all, grid_lo, grid_hi);
      const double grid_cells = double(grid_hi[0] - grid_lo[0] + 1) * double(grid_hi[1] - grid_lo[1] + 1) *
                                double(grid_hi[2] - grid_lo[2] + 1);
      if (grid_cells <= double(max_check_cells_)) owner.assign(std::size_t(grid_cells), kNone);
    }
    const auto ownerAt = [&](const LatticePoint& c) -> std::uint32_t {
      for (std::size_t k = 0; k < 3; ++k)
        if (c[k] < grid_lo[k] || c[k] > grid_hi[k]) return kNone;
      return owner[std::size_t(((c[2] - grid_lo[2]) * (grid_hi[1] - grid_lo[1] + 1) + (c[1] - grid_lo[1])) *
                                   (grid_hi[0] - grid_lo[0] + 1) +
                               (c[0] - grid_lo[0]))];
    };
    const auto own = [&](std::size_t node) {
      if (owner.empty()) return;
      for (const auto i : nodes[node].members) {
        const LatticePoint& c = cells_[i];
        owner[std::size_t(((c[2] - grid_lo[2]) * (grid_hi[1] - grid_lo[1] + 1) + (c[1] - grid_lo[1])) *
                              (grid_hi[0] - grid_lo[0] + 1) +
                          (c[0] - grid_lo[0]))] = std::uint32_t(node);
      }
    };
    for (std::size_t node = 0; node < nodes.size(); ++node) own(node);
    // A pair whose union surely fails its check: the midpoint of the centres of a cell of each lies
    // in the union's hull, so the cell holding it is one the check scans; when no site of the union
    // (a cell of it, or a cell its cluster encloses: the check counts those inside the union's box)
    // is within max(T, G) of it, the check fails. Such a pair would be popped and rejected, so leaving it
    // out of the queue changes nothing but the time.
    const auto surelyFails = [&](std::size_t a, std::size_t b) {
      if (owner.empty()) return false;
      const Members& ma = nodes[a].members;
      const Members& mb = nodes[b].members;
      for (const std::size_t pa : {std::size_t(0), ma.size() / 2, ma.size() - 1})
        for (const std::size_t pb : {std::size_t(0), mb.size() / 2, mb.size() - 1}) {
          const LatticePoint& p = cells_[ma[pa]];
          const LatticePoint& q = cells_[mb[pb]];
          const LatticePoint m{floorDiv(p[0] + q[0] + 1, 2), floorDiv(p[1] + q[1] + 1, 2),
                               floorDiv(p[2] + q[2] + 1, 2)};
          const bool covered = std::any_of(ball_.begin(), ball_.end(), [&](const auto& offset) {
            const LatticePoint x{m[0] + offset.first[0], m[1] + offset.first[1], m[2] + offset.first[2]};
            const std::uint32_t o = ownerAt(x);
            return o == a || o == b || isEnclosed(x);
          });
          if (!covered) return true;
        }
      return false;
    };
    // The added hull volume of each near pair, computed in parallel, queued in pair order.
    const auto consider = [&](const std::vector<std::pair<std::size_t, std::size_t>>& candidates) {
      std::vector<std::pair<std::size_t, std::size_t>> pairs;
      for (const auto& [a, b] : candidates)
        if (near(nodes[a], nodes[b]) &&
            (!faces || std::min(nodes[a].members.size(), nodes[b].members.size()) >= kFaceMergeMinVoxels))
          pairs.emplace_back(a, b);
      std::vector<char> fails(pairs.size());
      std::vector<FacetHull> hulls(pairs.size());
      tbb::parallel_for(std::size_t(0), pairs.size(), [&](std::size_t k) {
        const auto [a, b] = pairs[k];
        fails[k] = surelyFails(a, b);
        if (!fails[k]) hulls[k] = facetHull(gather(unite(nodes[a].members, nodes[b].members)));
      });
      for (std::size_t k = 0; k < pairs.size(); ++k) {
        if (fails[k]) continue;
        const auto [a, b] = pairs[k];
        const std::int64_t added = hulls[k].volume6 - nodes[a].check.hull.volume6 - nodes[b].check.hull.volume6;
        queue.emplace(added, std::min(a, b), std::max(a, b));
        union_hulls[{std::min(a, b), std::max(a, b)}] = std::move(hulls[k]);
      }
    };
    std::vector<std::pair<std::size_t, std::size_t>> all_pairs;
    for (std::size_t a = 0; a < nodes.size(); ++a)
      for (std::size_t b = a + 1; b < nodes.size(); ++b) all_pairs.emplace_back(a, b);
    consider(all_pairs);
    while (!queue.empty()) {
      const auto [added, a, b] = queue.top();
      queue.pop();
      const auto hull = union_hulls.find({a, b});
      const FacetHull union_hull = std::move(hull->second);
      union_hulls.erase(hull);
      if (!nodes[a].alive || !nodes[b].alive) continue;
      Members both = unite(nodes[a].members, nodes[b].members);
      Check check = checkPart(both, false, &union_hull, faces);
      if (!check.ok) continue;
      nodes[a].alive = nodes[b].alive = false;
      Node node{std::move(both), std::move(check), {}, {}, true};
      box(node.members, node.lo, node.hi);
      nodes.push_back(std::move(node));
      const std::size_t added_node = nodes.size() - 1;
      own(added_node);
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

  std::vector<LatticePoint> cells_;
  bool fill_enclosed_;
  bool face_holes_;                ///< merges also use the face-hole rule (ConvexPartsParams::face_holes)
  std::optional<double> floor_k_;  ///< the floor's height, lattice units (k of the corner lattice)
  double rho2_;                    ///< max(T, G)^2, cells^2: the closing radius when finding enclosed cells
  static constexpr std::uint32_t kNoClump = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> clump_;  ///< per cell: its stray clump's id, kNoClump when none (findStrays)
  std::vector<char> enclosed_;        ///< over the cluster's box [enc_lo_, enc_hi_], x fastest
  std::size_t enclosed_count_ = 0;
  LatticePoint enc_lo_{0, 0, 0}, enc_hi_{0, 0, 0};
  double t_;            ///< T, cells
  double t2_;           ///< T^2, cells^2 (with a relative 1e-12 for rounding)
  double g2_;           ///< G^2 >= T^2: the bound of a flat part
  std::int64_t reach_;  ///< floor(max(T, G))
  std::vector<std::pair<LatticePoint, float>>
      ball_;  ///< offsets within max(T, G) and the cluster's box (squared length, cells^2), nearest first
  std::size_t whole_ball_size_ = 0;  ///< offsets within max(T, G), unclipped
  std::size_t max_check_cells_;
  std::vector<Eigen::Vector3d> keyframes_;  ///< lattice coordinates
};

/// A cluster on its lattice: cells sorted as the centres are given.
struct ClusterLattice {
  Eigen::Vector3d origin;  ///< corner (0, 0, 0), map frame
  std::vector<LatticePoint> cells;
};

ClusterLattice toLattice(const std::vector<Eigen::Vector3d>& centers, double voxel_size) {
  ClusterLattice lattice;
  // The same origin as buildObstacles: the lower corner of the lexicographically smallest centre.
  const auto anchor =
      std::min_element(centers.begin(), centers.end(), [](const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
        return std::tie(p.x(), p.y(), p.z()) < std::tie(q.x(), q.y(), q.z());
      });
  lattice.origin = *anchor - Eigen::Vector3d::Constant(0.5 * voxel_size);
  for (const auto& c : centers) lattice.cells.push_back(detail::latticeIndex(c, lattice.origin, voxel_size));
  return lattice;
}

double resolveConcavity(const ConvexPartsParams& params, double voxel_size) {
  if (!(voxel_size > 0) || !std::isfinite(voxel_size))
    throw Error("convex parts: voxel_size must be positive, got " + std::to_string(voxel_size));
  if (!(params.concavity >= 0) || !std::isfinite(params.concavity))
    throw Error("convex parts: concavity must be >= 0 (0: default), got " + std::to_string(params.concavity));
  return params.concavity > 0 ? params.concavity : defaultConcavity(voxel_size);
}

/// G: the flat parts' bound, at least T (T when unset: no relaxation).
double resolveFlatGap(const ConvexPartsParams& params, double t) {
  if (params.flat_gap && (!(*params.flat_gap >= 0) || !std::isfinite(*params.flat_gap)))
    throw Error("convex parts: flat_gap must be >= 0, got " + std::to_string(*params.flat_gap));
  return std::max(t, params.flat_gap.value_or(t));
}

void checkFloor(const ConvexPartsParams& params) {
  if (params.floor_z && !std::isfinite(*params.floor_z))
    throw Error("convex parts: floor_z must be finite, got " + std::to_string(*params.floor_z));
}

struct SplitResult {
  ClusterLattice lattice;
  std::vector<std::pair<Members, Check>> parts;
  double flat_gap = 0.0;  ///< the G used for this cluster, map units
};

/// x = pi lambda R^2 (the expected number of sites in a disc of radius R) at which N sites spread
/// uniformly over an area leave, in expectation, `vacancies` empty discs of radius R (Hall 1988: about
/// N x e^-x of them): the root x >= 1 of x - ln x = ln N - ln vacancies.
double chanceDiscSites(double sites, double vacancies) {
  const double target = std::log(std::max(sites, 3.0)) - std::log(vacancies);
  double x = std::max(target, 1.0);
  for (int i = 0; i < 64; ++i) x = target + std::log(x);
  return x;
}

}  // namespace

double adaptedFlatGap(const std::vector<Eigen::Vector3d>& centers, double voxel_size, const ConvexPartsParams& params) {
  const double t = resolveConcavity(params, voxel_size);
  const double g = resolveFlatGap(params, t);
  if (!params.adapt_flat_gap || !(g > t) || centers.size() < kAdaptMinVoxels) return g;
  for (std::size_t i = 0; i < centers.size(); ++i)
    if (!centers[i].allFinite()) throw Error("convex parts: non-finite voxel centre at index " + std::to_string(i));
  const ClusterLattice lattice = toLattice(centers, voxel_size);
  // The cells as sorted packed keys (21 bits per axis, offset so that a ball around any cell stays
  // non-negative), for the counts below.
  // G in cells, with a relative 1e-9 so that G = 6 voxels in map units counts the cells 6 away.
  const double r_cells = g / voxel_size;
  const double r2_cells = r_cells * r_cells * (1.0 + 1e-9);
  const std::int64_t reach = std::int64_t(std::floor(std::sqrt(r2_cells)));
  const auto key = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    return (std::uint64_t(i + reach + 1) << 42) | (std::uint64_t(j + reach + 1) << 21) | std::uint64_t(k + reach + 1);
  };
  std::int64_t span = 0;
  for (const auto& c : lattice.cells) span = std::max({span, c[0], c[1], c[2]});
  if (span + 2 * reach + 2 >= (std::int64_t(1) << 21)) return g;  // too wide to pack: no adaptation
  std::vector<std::uint64_t> keys;
  keys.reserve(lattice.cells.size());
  for (const auto& c : lattice.cells) keys.push_back(key(c[0], c[1], c[2]));
  std::sort(keys.begin(), keys.end());
  std::vector<LatticePoint> ball;
  for (std::int64_t i = -reach; i <= reach; ++i)
    for (std::int64_t j = -reach; j <= reach; ++j)
      for (std::int64_t k = -reach; k <= reach; ++k)
        if ((i != 0 || j != 0 || k != 0) && double(i * i + j * j + k * k) <= r2_cells) ball.push_back({i, j, k});
  // Neighbours within G of every stride-th cell (at most kAdaptSamples of them, deterministic).
  const std::size_t stride = (lattice.cells.size() + kAdaptSamples - 1) / kAdaptSamples;
  std::vector<std::size_t> counts;
  for (std::size_t s = 0; s < lattice.cells.size(); s += stride) {
    const LatticePoint& c = lattice.cells[s];
    std::size_t count = 0;
    for (const auto& o : ball)
      count += std::binary_search(keys.begin(), keys.end(), key(c[0] + o[0], c[1] + o[1], c[2] + o[2]));
    counts.push_back(count);
  }
  // The lower quartile: the sparser stretches of the surface, not its dense edges.
  std::nth_element(counts.begin(), counts.begin() + std::ptrdiff_t(counts.size() / 4), counts.end());
  const double neighbours = std::max(1.0, double(counts[counts.size() / 4]));
  const double lambda_pi = neighbours / (r_cells * r_cells);  // pi lambda, sites per cell^2 times pi
  const double x = chanceDiscSites(double(lattice.cells.size()), kAdaptVacancies);
  const double r_chance = std::sqrt(x / lambda_pi);  // cells
  const double t_cells = t / voxel_size;
  const double adapted = std::sqrt(r_chance * r_chance + t_cells * t_cells) * voxel_size;
  return std::clamp(adapted, g, kAdaptMaxFactor * g);
}

namespace {

SplitResult splitCluster(const std::vector<Eigen::Vector3d>& centers, double voxel_size, double t,
                         const ConvexPartsParams& params, const std::vector<Eigen::Vector3d>& keyframes) {
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
  std::optional<double> floor_k;
  if (params.floor_z) floor_k = (*params.floor_z - result.lattice.origin.z()) / voxel_size;
  result.flat_gap = adaptedFlatGap(centers, voxel_size, params);
  ClusterSplitter splitter(result.lattice.cells, t / voxel_size, result.flat_gap / voxel_size, params.max_check_cells,
                           std::move(near), params.fill_enclosed, floor_k, params.face_holes);
  result.parts = splitter.run();
  return result;
}

}  // namespace

double defaultConcavity(double voxel_size) { return 3.0 * voxel_size; }

std::vector<std::vector<std::size_t>> splitConvexParts(const std::vector<Eigen::Vector3d>& centers, double voxel_size,
                                                       const ConvexPartsParams& params,
                                                       const std::vector<Eigen::Vector3d>& keyframes) {
  const double t = resolveConcavity(params, voxel_size);
  resolveFlatGap(params, t);  // throws on a bad flat_gap
  checkFloor(params);
  const SplitResult result = splitCluster(centers, voxel_size, t, params, keyframes);
  std::vector<std::vector<std::size_t>> out;
  for (const auto& [members, check] : result.parts) out.emplace_back(members.begin(), members.end());
  return out;
}

ConvexPartsSummary addConvexParts(std::vector<Obstacle>& obstacles, const std::vector<Eigen::Vector3d>& centers,
                                  const std::vector<std::uint32_t>& weights, const std::vector<std::int32_t>& labels,
                                  double voxel_size, const ConvexPartsParams& params, const KnownFreeSpace& known) {
  const double t = resolveConcavity(params, voxel_size);
  const double g = resolveFlatGap(params, t);
  checkFloor(params);
  if (labels.size() != centers.size())
    throw Error("addConvexParts: " + std::to_string(labels.size()) + " labels for " + std::to_string(centers.size()) +
                " voxels");
  if (!weights.empty() && weights.size() != centers.size())
    throw Error("addConvexParts: " + std::to_string(weights.size()) + " weights for " + std::to_string(centers.size()) +
                " voxels");
  std::map<std::int32_t, std::vector<std::size_t>> clusters;
  for (std::size_t i = 0; i < centers.size(); ++i)
    if (labels[i] >= 0) clusters[labels[i]].push_back(i);
  for (const auto& o : obstacles)
    if (!clusters.count(o.id))
      throw Error("addConvexParts: obstacle id " + std::to_string(o.id) + " is no label of the voxels");
  // Free voxel centres sorted by x, for a range per part.
  std::vector<Eigen::Vector3d> free = known.free_voxels;
  std::sort(free.begin(), free.end(), [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::tie(a.x(), a.y(), a.z()) < std::tie(b.x(), b.y(), b.z());
  });
  std::vector<std::size_t> keyframes_in_voxels(obstacles.size(), 0), flat_parts(obstacles.size(), 0),
      face_parts(obstacles.size(), 0);
  std::vector<double> flat_gaps(obstacles.size(), g);
  tbb::parallel_for(std::size_t(0), obstacles.size(), [&](std::size_t o) {
    Obstacle& obstacle = obstacles[o];
    const std::vector<std::size_t>& members = clusters.at(obstacle.id);
    std::vector<Eigen::Vector3d> local;
    local.reserve(members.size());
    for (const auto i : members) local.push_back(centers[i]);
    const SplitResult result = splitCluster(local, voxel_size, t, params, known.keyframes);
    flat_gaps[o] = result.flat_gap;
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
      part.flat = check.flat;
      part.filled = check.filled;
      part.faces = check.faces;
      if (check.flat) ++flat_parts[o];
      if (check.faces) ++face_parts[o];
      keyframes_in_voxels[o] += check.keyframes_in_voxels;
      const auto first = std::lower_bound(free.begin(), free.end(), part.aabb_min.x(),
                                          [](const Eigen::Vector3d& p, double x) { return p.x() < x; });
      // The part's own voxels on the lattice, for the surface band (26 neighbours).
      const auto cellOf = [&](const Eigen::Vector3d& p) {
        const Eigen::Vector3d c = ((p - result.lattice.origin) / voxel_size).array().round();
        return std::array<std::int64_t, 3>{std::int64_t(c.x()), std::int64_t(c.y()), std::int64_t(c.z())};
      };
      std::set<std::array<std::int64_t, 3>> own;
      for (const auto i : global) own.insert(cellOf(centers[i]));
      const auto nearOwn = [&](const Eigen::Vector3d& p) {
        const auto c = cellOf(p);
        for (std::int64_t dx = -1; dx <= 1; ++dx)
          for (std::int64_t dy = -1; dy <= 1; ++dy)
            for (std::int64_t dz = -1; dz <= 1; ++dz)
              if (own.count({c[0] + dx, c[1] + dy, c[2] + dz})) return true;
        return false;
      };
      for (auto it = first; it != free.end() && it->x() <= part.aabb_max.x(); ++it) {
        if ((it->array() < part.aabb_min.array()).any() || (it->array() > part.aabb_max.array()).any()) continue;
        if (!inside(check.hull, (*it - result.lattice.origin) / voxel_size)) continue;
        ++part.free_voxels_inside;
        if (!nearOwn(*it)) ++part.free_voxels_off_surface;
      }
      obstacle.parts.push_back(std::move(part));
    }
  });
  ConvexPartsSummary summary;
  summary.concavity = t;
  summary.flat_gap = g;
  summary.flat_gap_max = g;
  for (const double used : flat_gaps) summary.flat_gap_max = std::max(summary.flat_gap_max, used);
  for (std::size_t o = 0; o < obstacles.size(); ++o) {
    const auto& obstacle = obstacles[o];
    summary.parts += obstacle.parts.size();
    summary.hull_volume_before += obstacle.volume;
    summary.voxel_volume += double(obstacle.voxel_count) * voxel_size * voxel_size * voxel_size;
    summary.keyframes_in_voxels += keyframes_in_voxels[o];
    summary.flat_parts += flat_parts[o];
    summary.face_parts += face_parts[o];
    for (const auto& part : obstacle.parts) {
      summary.hull_volume_after += part.volume;
      summary.free_voxels_inside += part.free_voxels_inside;
      summary.free_voxels_off_surface += part.free_voxels_off_surface;
    }
  }
  return summary;
}

}  // namespace hullmap::clustering

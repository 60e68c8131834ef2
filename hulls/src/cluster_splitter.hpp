// The convex split of one cluster on its voxel lattice (splitConvexParts): ClusterSplitter checks a
// part against the concavity T (splitter_checks.cpp), cuts a part that fails (splitter_split.cpp) and
// merges parts back while they still pass (splitter_merge.cpp). Internal to the clustering library.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "hullmap/hulls/detail/lattice_hull.hpp"

namespace hullmap::hulls::detail {

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
/// a / b rounded down (b != 0).
inline std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
  std::int64_t q = a / b;
  if ((a % b != 0) && ((a < 0) != (b < 0))) --q;
  return q;
}
/// a / b rounded up (b != 0).
inline std::int64_t ceilDiv(std::int64_t a, std::int64_t b) { return -floorDiv(-a, b); }

class ClusterSplitter {
 public:
  /// `t_cells`: T; `g_cells`: G >= T, the distance allowed in a flat part (G = T: no relaxation).
  ClusterSplitter(std::vector<LatticePoint> cells, double t_cells, double g_cells, std::size_t max_check_cells,
                  std::vector<Eigen::Vector3d> keyframes, bool fill_enclosed, std::optional<double> floor_k,
                  bool face_holes);

  /// Lattice offsets within sqrt(r2) and within `extent` on each axis, with their squared lengths,
  /// nearest first (ties in (i, j, k) order).
  static std::vector<std::pair<LatticePoint, float>> ballOffsets(double r2, const std::array<std::int64_t, 3>& extent);

  /// Final parts with their checks.
  std::vector<std::pair<Members, Check>> run();

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
  /// (worst_d2 and split_point unset). `hull`: the part's lattice hull when already known. A check
  /// is a function of the part and the two flags: each is made once (checkPartOnce) and remembered,
  /// since the merges meet the same unions again.
  Check checkPart(const Members& part, bool need_split_point = true, const FacetHull* hull = nullptr,
                  bool faces = false) const;
  Check checkPartOnce(const Members& part, bool need_split_point, const FacetHull* hull, bool faces) const;

  /// The lattice hull of a part, remembered likewise (the merges' unions).
  FacetHull hullOf(const Members& part) const;

  /// The keyframe rule of checkPart on a check that passed the distances: the check fails, with the
  /// keyframe as its split point, at the first keyframe inside the hull and in none of the cells'
  /// closed cubes; those in a cell's cube are counted (keyframes_in_voxels).
  void checkKeyframes(Check& check, const std::vector<LatticePoint>& cells) const;

  /// Whether one of a few probe cells of the hull (`columns`: per column of the box lo..hi, the k
  /// range whose cubes meet it) is farther than max(T, G) from every site (the cells, and the
  /// enclosed cells of the box): then the check fails for certain. False says nothing.
  bool farHullCell(const std::vector<LatticePoint>& cells, const LatticePoint& lo, const LatticePoint& hi,
                   const std::vector<std::pair<std::int64_t, std::int64_t>>& columns) const;

  /// The cells the whole cluster encloses (enclosedCells over its box, closed below when its
  /// lowest cell is within two voxels of the floor); none when its box is over max_check_cells.
  void findEnclosed(const Members& all);

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
                                  bool closed_below) const;

  /// A flat part's slab: a facet normal n (corner-lattice units) along which the hull is at most T
  /// wide, and the range [lo, hi] of n . x over the hull (hi the facet plane's value). The first such
  /// facet in the hull's plane order; none when the hull is wider than T along every facet normal.
  struct Slab {
    LatticePoint n;
    std::int64_t lo, hi;
  };
  std::optional<Slab> thinSlab(const FacetHull& hull, const std::vector<LatticePoint>& cells) const;

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
                Members out) const;

  /// Hands the voxels of the non-flat parts that lie in a flat part's slab to that flat part, when
  /// the flat part with them still passes its check (so every part keeps its guarantee) and the
  /// non-flat part is a fragment (the flat part has at least kAbsorbRatio times its voxels). Where two
  /// walls meet, or a voxel of noise sits off a wall, the merge leaves a small non-flat part (the
  /// corner's voxels of both walls together are thicker than T, and its hull over the walls' holes is
  /// farther than T from them): its voxels in each wall's slab go to that wall, and what is left (if
  /// anything) stays a part. Then the flat fragments do the same with the other flat parts. Flat
  /// parts in order of size (largest first, ties by first cell), the non-flat parts in order of their
  /// first cell before them; deterministic.
  std::vector<std::pair<Members, Check>> absorb(std::vector<std::pair<Members, Check>> parts) const;

  /// Marks the stray cells: those whose clump (the cells linked to it by steps of at most T) has at
  /// most kStrayClump cells, with the clump's id (its smallest cell index) in clump_; none when the
  /// cluster is too wide for the packed keys (21 bits per axis). A lone cell (no other cell within T)
  /// is a clump of one.
  void findStrays();

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
  std::vector<std::uint32_t> shedStrays(Members& part, Check& check) const;

  /// Hands the voxels of a non-flat fragment lying in the bounding box of a larger non-flat part (at
  /// least kAbsorbRatio times its voxels) to that part, when the part with them and what is left of
  /// the fragment (if anything) each pass the check. A stray voxel off a box's face drags a wedge of
  /// hull out to it, so the split cuts it off together with some of the face's voxels around it, and
  /// the face is left with a hole the rest of the box cannot merge across: this gives the face's
  /// voxels back, leaving the stray (and whatever else lies outside the box) a part of its own.
  /// Larger parts first (ties by first cell), fragments in order of their first cell; deterministic.
  /// `changed`: set when a voxel moved (the parts are then merged again).
  std::vector<std::pair<Members, Check>> absorbIntoBoxes(std::vector<std::pair<Members, Check>> parts,
                                                         bool& changed) const;

  /// The face-hole rule of checkPart over the cells whose cube meets the hull (`columns`: per column
  /// of the box lo..hi, the k range), with `d2` the squared distances to the sites (exact up to
  /// max(T, G); 0 at the sites): the squared distance of the farthest cell that is farther than T
  /// from every site and not within G of a site in the slab of a facet whose slab holds it, that
  /// cell in `worst`; -1 when there is none.
  std::int64_t faceHoles(const FacetHull& hull, const LatticePoint& lo, const LatticePoint& hi,
                         const std::vector<float>& d2,
                         const std::vector<std::pair<std::int64_t, std::int64_t>>& columns, LatticePoint& worst) const;

  /// Whether the hull is at most T wide along one of its facet normals (so it is at most T thick:
  /// the width along a facet normal bounds the hull's least width from above). A facet's width is
  /// its plane's value minus the least value of n . x over the cells' cubes (exact integers).
  bool flat(const FacetHull& hull, const std::vector<LatticePoint>& cells) const;

  /// Two non-empty halves of a part that failed its check.
  struct Halves {
    Members left, right;
    std::optional<FacetHull> left_hull, right_hull;
  };
  Halves split(const Members& part, const Check& check) const;

  /// The cell index m along `axis` for which the cells below m and the others have the smallest
  /// summed bounding-box volume (ties: the most even split); none when all share one value.
  std::optional<std::int64_t> bestBoxCut(const Members& part, int axis) const;

  Eigen::Vector3d centre(std::uint32_t i) const {
    return Eigen::Vector3d(double(cells_[i][0]) + 0.5, double(cells_[i][1]) + 0.5, double(cells_[i][2]) + 0.5);
  }

  /// Greedy merge of parts whose boxes come within max(T, G), the pair whose union's hull adds the least
  /// volume first, while the union passes the check (`faces`: with the face-hole rule, parts of at
  /// least kFaceMergeMinVoxels voxels only).
  std::vector<std::pair<Members, Check>> merge(std::vector<std::pair<Members, Check>> parts, bool faces = false) const;

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
  std::int64_t cap2_;   ///< floor(max(T, G)^2): the largest integer squared distance within max(T, G)
  std::vector<std::pair<LatticePoint, float>>
      ball_;  ///< offsets within max(T, G) and the cluster's box (squared length, cells^2), nearest first
  std::size_t whole_ball_size_ = 0;  ///< offsets within max(T, G), unclipped
  std::size_t max_check_cells_;
  std::vector<Eigen::Vector3d> keyframes_;  ///< lattice coordinates
  mutable std::mutex memo_mutex_;           ///< guards checks_ and hulls_ (checks run in parallel)
  mutable std::map<std::tuple<Members, bool, bool>, Check> checks_;  ///< checkPart's, by its arguments
  mutable std::map<Members, FacetHull> hulls_;                       ///< hullOf's
};

}  // namespace hullmap::hulls::detail

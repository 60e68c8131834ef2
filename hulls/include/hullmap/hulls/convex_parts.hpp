#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/hulls/sparse_edges.hpp"

namespace hullmap::hulls {

/// Settings of the split of clusters into convex parts.
struct ConvexPartsParams {
  /// T, map units: no point of a part's hull may be farther than T from the part's own occupied voxel
  /// cubes, so T bounds the free space a hull may swallow. 0 means the default, defaultConcavity().
  double concavity = 0.0;
  /// G, map units: the bound for flat parts (hull at most T thick) instead of T. Unset or below T:
  /// G = T. hullmap build sets it to the DBSCAN eps (docs/CONVEX_PARTS.md, "Flat gap").
  std::optional<double> flat_gap;
  /// Adapt G to each cluster's sampling (adaptedFlatGap): sparse clusters get up to 2 G. Off: G for all.
  bool adapt_flat_gap = false;
  /// Count the space a cluster's closed shell encloses as its parts' own voxels in the bound; no fill
  /// for a box over max_check_cells (docs/CONVEX_PARTS.md, "Enclosed space"). Off: voxels only.
  bool fill_enclosed = true;
  /// Face-hole rule for merges: holes up to G in a solid part's faces pass, as in a flat part (parts of
  /// >= 3 voxels; docs/CONVEX_PARTS.md, "Face holes"). No effect when G = T. Off: T and G only.
  bool face_holes = true;
  /// Map-frame z of the floor's top, when known: a part within two voxels of it is closed below by it.
  /// Unset: shells must be closed on every side.
  std::optional<double> floor_z;
  /// Cells (of a part's box) above which the part is split at its longest axis's median unchecked
  /// (4 bytes a cell: 2^23 is 32 MiB). Parts merge only when their union is checked.
  std::size_t max_check_cells = std::size_t(1) << 23;
  /// Grow each sparse part in its own plane after its check (sparse_edges.hpp). Unset: no growth.
  /// hullmap build sets it (BuildParams::sparse_edges).
  std::optional<SparseEdges> sparse_edges;
};

/// What is known to be free: nothing of it should be inside a hull.
struct KnownFreeSpace {
  /// Camera positions (keyframes), map frame: no part's hull may contain one, unless it lies in an
  /// occupied voxel of that part (nothing can then keep it out; such keyframes are counted).
  std::vector<Eigen::Vector3d> keyframes;
  /// Centres of observed-free voxels (ray-cast), map frame: counted per part (free_voxels_inside).
  std::vector<Eigen::Vector3d> free_voxels;
};

/// The stray-part rule of addConvexParts (off unless given). A part of at most `max_voxels` voxels,
/// at most `max_core_voxels` of them DBSCAN core voxels, of an obstacle that has other parts, and
/// with no `support` voxel within `support_reach` of any of its voxels, is dropped, and its voxels
/// leave the obstacle.
/// Why the rule exists: docs/CONVEX_PARTS.md, "Stray parts".
struct StrayParts {
  std::size_t max_voxels = 3;
  std::size_t max_core_voxels = 1;
  std::vector<std::uint8_t> core;        ///< per voxel of addConvexParts' `centers`: 1 when DBSCAN core
  std::vector<Eigen::Vector3d> support;  ///< voxels that hold structure up: the floor's, ceiling's, ground's
  double support_reach = 0.0;            ///< map units; 0: 2 T
};

/// The default T: 3 voxel edges (0.15 m at 5 cm voxels); it scales with the voxel size, so it means
/// the same at any monocular scale. Why 3: docs/CONVEX_PARTS.md, "The default T".
double defaultConcavity(double voxel_size);

/// The flat gap G used for one cluster (voxel centres `centers`, as splitConvexParts takes them), map
/// units. Without adapt_flat_gap, when G <= T, or for fewer than 16 voxels: G itself. Otherwise G
/// adapted to the cluster's sampling (the largest hole chance explains in a surface that sparse, made
/// T-thick), clamped to [G, 2 G], so that chance holes do not split it. Relative to the data, so it
/// means the same at any monocular scale. The derivation: docs/CONVEX_PARTS.md, "Adapted flat gap".
double adaptedFlatGap(const std::vector<Eigen::Vector3d>& centers, double voxel_size, const ConvexPartsParams& params);

/// Splits one cluster's voxels into convex parts; returns the parts as sorted lists of indices into
/// `centers` (a partition of 0..n-1), ordered by their first index. Deterministic (the same parts on
/// every run, with any number of threads).
///
/// Guarantee: every point of each part's hull (of its voxels' corners, as buildObstacles makes it) is
/// within T of the part's own voxel cubes, unless the part is one voxel. The check is certified on
/// the voxel lattice and conservative by at most sqrt(3)/2 voxel edge. No part's hull contains a
/// keyframe (strictly or on its boundary) unless the keyframe lies in one of that part's voxels.
/// Method (top-down cuts, then bottom-up merges) and proof: docs/CONVEX_PARTS.md, "splitConvexParts".
///
/// `centers`: voxel centres of one cluster on a lattice of edge `voxel_size` (map units). Throws
/// hullmap::Error on voxel_size <= 0, a negative or non-finite concavity, or non-finite input.
std::vector<std::vector<std::size_t>> splitConvexParts(const std::vector<Eigen::Vector3d>& centers, double voxel_size,
                                                       const ConvexPartsParams& params,
                                                       const std::vector<Eigen::Vector3d>& keyframes = {});

/// Totals of addConvexParts over all obstacles.
struct ConvexPartsSummary {
  std::size_t parts = 0;
  double concavity = 0.0;                   ///< the T used, map units
  double flat_gap = 0.0;                    ///< the G asked for (>= T), map units
  double flat_gap_max = 0.0;                ///< the largest G used for a cluster (adaptedFlatGap)
  std::size_t flat_parts = 0;               ///< parts that passed as flat (bound G)
  std::size_t face_parts = 0;               ///< parts that passed by the face-hole rule (bound G)
  double hull_volume_before = 0.0;          ///< summed whole-cluster hull volume, map units^3
  double hull_volume_after = 0.0;           ///< summed part hull volume
  double voxel_volume = 0.0;                ///< clustered voxels times voxel_size^3
  std::size_t keyframes_in_voxels = 0;      ///< keyframes in an occupied voxel of a part (kept inside)
  std::size_t free_voxels_inside = 0;       ///< observed-free voxel centres inside some part's hull
  std::size_t free_voxels_off_surface = 0;  ///< of those, none of the part's voxels among their 26 neighbours
  std::size_t stray_parts = 0;              ///< parts dropped by the stray-part rule
  std::vector<std::size_t> stray_voxels;    ///< their voxels (indices into centers, ascending): no obstacle's now
  std::vector<int> stray_obstacles;         ///< per stray voxel: the id of the obstacle it left
  std::size_t sparse_edge_parts = 0;        ///< parts grown by sparse_edges
  double sparse_edge_growth_max = 0.0;      ///< the most one grew, map units
};

/// Fills `parts` of every obstacle made by buildObstacles from the same centres/weights/labels:
/// splitConvexParts on each cluster (in parallel over clusters, TBB), each part wrapped as the
/// whole is (hull, footprint, volume, ...; candidate cuts and merges are also scored in parallel, with
/// results independent of the thread count), with its certified concavity bound and the count of
/// `known.free_voxels` inside its hull. A cluster that needs no split gets one part equal to the whole.
/// With `strays`, the stray parts (StrayParts) are dropped: the obstacle keeps its other parts, and
/// its whole hull, footprint, counts and box are made again from the voxels it keeps; the dropped
/// voxels are listed in the summary, for the caller to relabel as noise.
/// Throws hullmap::Error as buildObstacles and splitConvexParts do, when an obstacle's id is not a
/// label of the voxels, and when strays->core does not hold one flag per voxel.
ConvexPartsSummary addConvexParts(std::vector<Obstacle>& obstacles, const std::vector<Eigen::Vector3d>& centers,
                                  const std::vector<std::uint32_t>& weights, const std::vector<std::int32_t>& labels,
                                  double voxel_size, const ConvexPartsParams& params, const KnownFreeSpace& known = {},
                                  const StrayParts* strays = nullptr);

}  // namespace hullmap::hulls

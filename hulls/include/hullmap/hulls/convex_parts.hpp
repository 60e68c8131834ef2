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
  /// G, map units: a part whose hull is at most T thick (along one of its facet normals) is flat, a
  /// patch of surface, and for it the bound is G instead of T: a sparse wall or table top, whose map
  /// points leave holes wider than T in it, stays one part, while its hull still swallows no more
  /// than a slab T thick. Unset (or below T): G = T, no relaxation. hullmap build sets it to the
  /// DBSCAN eps, the distance at which the map's sampling connects a surface (and adapts it).
  std::optional<double> flat_gap;
  /// Adapt G to each cluster's own sampling (see adaptedFlatGap): a sparse cluster, whose map points
  /// leave wider holes by chance alone, gets a larger G (at most 2 G), a dense one keeps G. Off: G for
  /// every cluster. hullmap build turns it on when G is auto (the eps used), off for --flat-gap G.
  bool adapt_flat_gap = false;
  /// Count the space a cluster encloses as its parts' own voxels in the bound (a part's check uses
  /// the enclosed cells inside its box): computed once per cluster, the cells of the cluster's box
  /// farther than rho = max(T, G) (G this cluster's, adapted or not) from all space reached from outside the box, where
  /// the outside spreads (6-connected) only through cells farther than rho from the cluster's voxels, so holes narrower
  /// than about 2 rho do not let it in. It is a closing of the shell: a concave corner is filled only within about 0.3
  /// rho of its apex. A box or a cylinder sampled only on its surface (its inside is never observed) stays one part; a
  /// ring of walls, open at the top, does not enclose the room. A cluster whose box (with a margin of rho) holds more
  /// than max_check_cells cells gets no fill. Off: only the voxels count.
  bool fill_enclosed = true;
  /// Holes in the faces of a solid part (the face-hole rule), used when parts are merged: a cell of the
  /// union's hull farther than T from every site passes when its cube lies within T of the plane of
  /// one of the hull's facets that is a face, and a site on that facet (its cube within 2 voxels of the
  /// plane) is within G of it. A facet is a face when every such cell of its slab has one: a facet
  /// lifted off the sites, as one dragged out to a stray voxel, is none. It is the flat part's rule
  /// applied to each face of a box or a cylinder whose sparse faces and edges leave holes wider than T
  /// (the pieces a cut left of it are merged back); only parts of at least 3 voxels are merged under
  /// it. A part that passed by it says so (ObstaclePart::faces); its bound is at most G. No effect
  /// when G = T. Off: merges use T (and G for flat parts) only.
  bool face_holes = true;
  /// The floor's height (map frame z of its top), when known: a part whose lowest voxel is within two
  /// voxels of it is closed below by it (nothing enters the shell through its bottom face, which
  /// stands on the floor and is never seen). Unset: shells must be closed on every side.
  std::optional<double> floor_z;
  /// A part whose bounding box holds more voxel cells than this is split in two at the median of
  /// its longest axis without being checked (the check holds one 4-byte distance per cell of the
  /// box: 2^23 cells is 32 MiB). Parts are merged back only when their union is checked.
  std::size_t max_check_cells = std::size_t(1) << 23;
  /// Grow each sparse part in its own plane by a share of its point spacing (sparse_edges.hpp),
  /// after its check: its hull reaches the surface's edges its last points stop short of. Unset: no
  /// growth. hullmap build sets it (BuildParams::sparse_edges).
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
/// Why: the eps that connects a sparse map's surfaces also makes a stray map point (or a small clump
/// of them) up to 1.5 eps in front of a wall a border point of the wall's cluster; the outlier trim
/// (clustering/outlier_trim.hpp) takes back the lone ones off a flat patch, but not those by a corner,
/// by furniture against the wall, or in a clump the extension chained to it. Split off the surface
/// (they lie farther than T from it), each became a part of its own in the room. One core voxel is
/// no dense evidence at a sparse map's eps: a stray point by a wall's edge reaches enough of the
/// wall's points to be core itself, and chains two more strays to it (on generated rooms, a
/// three-point sliver 0.8 m tall above a cylinder gave half of a room's false alarms). A part with
/// two core voxels is kept; so is a part near the floor (a leg's foot, a step).
struct StrayParts {
  std::size_t max_voxels = 3;
  std::size_t max_core_voxels = 1;
  std::vector<std::uint8_t> core;        ///< per voxel of addConvexParts' `centers`: 1 when DBSCAN core
  std::vector<Eigen::Vector3d> support;  ///< voxels that hold structure up: the floor's, ceiling's, ground's
  double support_reach = 0.0;            ///< map units; 0: 2 T
};

/// The default T: 3 voxel edges (0.15 m at 5 cm voxels). Why 3:
/// - the check is certified but conservative by up to sqrt(3)/2 voxel (see splitConvexParts), and
///   the hull of a wall that is not axis-aligned covers the staircase of its cubes' corners, about
///   one voxel away from them: T must be well above one voxel or every slanted wall shatters;
/// - sparse SLAM surfaces have one or two map points per occupied 5 cm voxel and holes of one or
///   two voxels between them: a flat patch with such holes must stay one part;
/// - with the half-voxel overshoot every conservative hull has anyway, 3 voxels keeps swallowed
///   space within about 0.1 m of the surfaces (the margin issue 13's evaluation uses) at 5 cm voxels.
/// It scales with the voxel size, so it means the same on a map of arbitrary monocular scale.
double defaultConcavity(double voxel_size);

/// The flat gap G used for one cluster (voxel centres `centers`, as splitConvexParts takes them), map
/// units. Without adapt_flat_gap, when G <= T, or for fewer than 16 voxels: G itself. Otherwise G
/// adapted to the cluster's sampling, so that chance holes in a sparse surface do not split it:
/// - the density: lambda = q / (pi G^2), q the lower quartile, over up to 1024 voxels (every k-th),
///   of the count of the cluster's other voxels within G (a surface meets a ball of radius G in a
///   disc of area about pi G^2; the lower quartile measures its sparser stretches, not its dense
///   edges; a surface several voxels thick counts more, which only lowers the result);
/// - the largest hole chance explains: N voxels spread uniformly at density lambda leave about
///   N x e^-x empty discs of radius R, x = pi lambda R^2 (Hall 1988); R is where that expectation
///   is 0.01;
/// - a flat part is up to T thick, so a cell of its hull over such a hole lies within
///   sqrt(R^2 + T^2) of a voxel centre: the result is that, clamped to [G, 2 G].
/// Relative to the data (G is the eps, the voxel lattice is the map's), so it means the same at any
/// monocular scale. An opening wider than twice the result (a doorway, a window) is still split.
double adaptedFlatGap(const std::vector<Eigen::Vector3d>& centers, double voxel_size, const ConvexPartsParams& params);

/// Splits one cluster's voxels into convex parts; returns the parts as sorted lists of indices into
/// `centers` (a partition of 0..n-1), ordered by their first index. Deterministic (the same parts on
/// every run, with any number of threads).
///
/// Guarantee: for every part, every point of the hull of its voxels' corners (the hull
/// buildObstacles makes) is within T of the part's own voxel cubes, unless the part is one voxel
/// (whose hull is its cube). The check is on the voxel lattice: for each cell whose cube meets the
/// hull (a test on the hull's facet planes, exact in integers, that may also admit a few cells
/// touching it only near an edge, which only makes the check stricter), the bound is the distance
/// from the cell's centre to the nearest occupied cell's centre. That bounds the distance from every
/// point of the cell's cube to that occupied cube (the largest distance from a cube's points to
/// another cube is at a corner, and equals the centre distance), so it is an upper bound (certified),
/// and it exceeds the true largest distance by at most sqrt(3)/2 voxel edge.
///
/// Also, no part's hull contains a keyframe position (strictly or on its boundary), unless the
/// keyframe lies in one of that part's voxels.
///
/// Method: top-down, a part that violates T (or contains a keyframe) first sheds stray cells: while
/// it fails, its lone cell (no other cell of the cluster within T) nearest the deepest uncovered cell
/// (within 2 max(T, G) of it) is taken out; when the rest passes after at most 8 such cells (and at
/// most 1/16 of the part), they become one-voxel parts, otherwise none is shed and the part is cut in two by a plane,
/// and the halves recursively. The candidate planes: through its deepest uncovered cell (or the keyframe), the three
/// axis planes and the three normal to the principal axes of its voxel centres; and per axis the cut whose halves have
/// the smallest summed bounding boxes. The one whose halves have the smallest summed hull volume (exact, on the
/// lattice) wins. Then bottom-up, adjacent parts (boxes within T) are merged while the union still passes the check,
/// the pair adding the least hull volume first: a box stays one part, an L becomes its two arms, a ring of walls its
/// walls. Last, a non-flat fragment (a part with at most 1/8 of a nearby flat part's voxels, such as a room's corner)
/// hands its voxels lying in the flat part's slab to it, when both still pass the check; likewise a non-flat fragment
/// hands its voxels lying in the bounding box of a non-flat part with at least 8 times its voxels to that part (a stray
/// clump's slice of a box's face goes back to the box), and then the parts are merged again.
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

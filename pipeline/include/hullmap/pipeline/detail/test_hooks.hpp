#pragma once

// White-box entry points for the tests and the CLI's test switch; not installed.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace hullmap::pipeline::detail {

/// Test-only: when set, build() and write() call it at the start of each stage with the stage's
/// name: "read", "frame_and_filters", "octree", "dbscan", "obstacles", then write()'s "write" (staging
/// directory made and locked), "wrote_map", "wrote_voxels", "wrote_obstacles" (called one after the
/// other once map.bt, voxels.csv and the obstacle files, written side by side, are all written) and
/// "move_into_place" (every file written, the directory not yet in place); a test stops the run there (throw, or kill
/// the process) to see what a run interrupted at that stage leaves behind. Not thread-safe; nullptr (the default) does
/// nothing.
extern void (*stage_hook)(const char* stage);

/// The build's rims step, exposed for its tests. After DBSCAN, each floor voxel (kFloorLabel) joins
/// a cluster (labels >= 0 on entry) it stands under, by the first of two rules that finds one;
/// "above" is "at its layer or above", and for a ceiling voxel (kCeilingLabel) "below" likewise;
/// `layers` = max(2, `reach` / `resolution`) (floor, + 1e-9):
///  1. the nearest clustered voxel (squared lattice distance, ties to the lower label) in its
///     column neighbourhood (|di|, |dj| <= 1 cell) at most `layers` above;
///  2. else the nearest such voxel up to 2 * `layers` above that is the lower end of a face of its
///     cluster: two voxels of its cluster within `reach` of it (centre distance) lie at least 2
///     layers higher (a wall, a box's side or a table leg goes on up; a table top, flat, does not,
///     so the floor under a top more than `layers` up stays floor).
/// The foot of a wall or box lies in the floor's band, and on a sparse map the voxels above a foot
/// voxel are often empty for more than `reach`. `centers` are voxel centres on the lattice of
/// `resolution` (map frame, z up); `reach` (map units): build passes the DBSCAN eps used, at most the auto rule's upper
/// clamp (max_eps_voxels voxels: 0.4 m at 5 cm), so that a large eps given by hand does not join most of the floor.
/// Voxels join clusters as they were on entry (no chains). Throws hullmap::Error when the sizes differ.
void attachSurfaceRims(const std::vector<Eigen::Vector3d>& centers, double resolution, double reach,
                       std::vector<std::int32_t>& labels);

}  // namespace hullmap::pipeline::detail

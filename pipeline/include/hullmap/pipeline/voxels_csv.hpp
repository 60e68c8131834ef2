#pragma once
// voxels.csv: one line per occupied voxel (centre, weight, DBSCAN label, core flag).

#include <cstdint>
#include <filesystem>
#include <vector>

#include <Eigen/Core>

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/mapper/occupancy_map.hpp"

namespace hullmap::pipeline {

/// One row of voxels.csv.
struct VoxelRow {
  Eigen::Vector3d center;    ///< map frame, map units
  std::uint32_t weight = 1;  ///< map points in the voxel
  std::int32_t label = clustering::kNoise;
  bool core = false;
};

/// Writes voxels.csv atomically: header `x,y,z,weight,label,core`, one voxel a line (9 significant
/// digits). `clusters` holds one label and core flag per voxel. Throws hullmap::Error naming `path`.
void writeVoxelsCsv(const std::filesystem::path& path, const std::vector<mapper::OccupiedVoxel>& voxels,
                    const clustering::DbscanResult& clusters);

/// Reads a voxels.csv written by writeVoxelsCsv; throws hullmap::Error "<path>:<line>: <what>".
std::vector<VoxelRow> readVoxelsCsv(const std::filesystem::path& path);

}  // namespace hullmap::pipeline

#pragma once
// Private to hullmap_pipeline: the surface steps of build() (surfaces.cpp).

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/mapper/floor.hpp"
#include "hullmap/mapper/occupancy_map.hpp"
#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::pipeline {

/// Centres of the observed-free leaves of the map (each pruned leaf once).
std::vector<Eigen::Vector3d> freeVoxelCentres(const mapper::OccupancyMap& map);

/// The floor and ceiling as solid half-spaces: up to the plane, or to the far face of the highest
/// voxel set aside as that surface when it lies beyond (the voxels lie inside completely).
std::vector<collision::Surface> boundingSurfaces(const BuildReport& report, const std::vector<Eigen::Vector3d>& centers,
                                                 const std::vector<std::int32_t>& labels, double resolution);

/// The floor's height for closing shells from below, when one height serves the whole map, or none.
std::optional<double> levelFloorHeight(const mapper::Plane& floor, const std::vector<Eigen::Vector3d>& centers,
                                       double resolution);

}  // namespace hullmap::pipeline

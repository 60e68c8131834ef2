#pragma once
// Private to hullmap_pipeline: the build's stages after the octree, as one list (cluster_stages.cpp).

#include "hullmap/pipeline/pipeline.hpp"
#include "stage_timer.hpp"

namespace hullmap::pipeline {

/// Runs the stages from the octree's voxels to the obstacles, in order, each timed and announced to
/// the stage hook: surfaces, auto_params, dbscan, extension (when on), obstacles, convex_parts (when
/// on); then the warnings. Reads result.map, result.params and result.keyframes; fills result.voxels,
/// clusters, obstacles, surfaces and the report's cluster parameters, surfaces, parts and warnings.
void clusterInto(BuildResult& result, StageTimer& timer);

}  // namespace hullmap::pipeline

// What `hullmap build` prints after a build: the stages, then the clustering (build_summary.hpp).
#include "build_summary.hpp"

#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>

namespace hullmap::cli {
namespace {

std::string planeText(const pipeline::PlaneReport& r, const char* what, bool aligned) {
  std::ostringstream s;
  s << what << ": ";
  using Mode = mapper::PlaneSetting::Mode;
  if (r.setting.mode == Mode::kNone) return s.str() + "none (not searched)";
  if (!r.plane) return s.str() + "none found (" + r.fit.reason + ")";
  const auto& p = *r.plane;
  s << std::setprecision(4);
  if (r.setting.mode == Mode::kHeight) {
    s << "z = " << r.setting.height << " (given)";
  } else if (r.levelled) {
    s << "found, tilt " << r.fit.tilt_deg << " deg, " << 100.0 * r.fit.inlier_share
      << "% of the points; levelled to z = 0";
  } else if (aligned) {
    s << "found at " << p.offset / p.normal.z() << " (normal " << p.normal.x() << ' ' << p.normal.y() << ' '
      << p.normal.z() << "), " << 100.0 * r.fit.inlier_share << "% of the points";
  } else {
    s << "found at " << p.offset / p.normal.z() << " (normal " << p.normal.x() << ' ' << p.normal.y() << ' '
      << p.normal.z() << ", tilt " << r.fit.tilt_deg << " deg), " << 100.0 * r.fit.inlier_share << "% of the points";
    if (std::string(what) == "floor") s << "; map kept in its frame";
  }
  s << "; " << r.voxels << " voxels not clustered";
  return s.str();
}

}  // namespace

void printStages(const pipeline::BuildResult& result) {
  const auto& report = result.report;
  if (report.alignment) {
    const auto& a = *report.alignment;
    const Eigen::Vector3d& t = a.transform.translation;
    std::cout << std::setprecision(6) << "align: scale " << a.transform.scale << ", rotation "
              << Eigen::AngleAxisd(a.transform.rotation).angle() * 180.0 / M_PI << " deg, translation " << t.x() << ' '
              << t.y() << ' ' << t.z() << "; RMSE " << a.rmse << " (max " << a.max_error << "), " << a.matched
              << " keyframes matched, " << a.unmatched << " unmatched\n";
    if (a.roll_from_cameras)
      std::cout << "align: the reference is nearly a line and leaves the roll about it undetermined (+-"
                << a.roll_sigma * 180.0 / M_PI << " deg): the cameras' level x axes set it, turning the fit by "
                << a.roll_turn * 180.0 / M_PI << " deg\n";
    if (a.drift) {
      const auto [low, high] = std::minmax_element(a.drift->scales.begin(), a.drift->scales.end());
      std::cout << "align: scale drift undone along the path (scale " << *low << " to " << *high << "): RMSE " << a.rmse
                << " where one similarity gives " << a.similarity_rmse << "\n";
    }
  }
  if (pipeline::readsOctree(result.params)) return;
  const bool aligned = report.alignment.has_value();
  std::cout << planeText(report.floor, "floor", aligned) << "\n"
            << planeText(report.ceiling, "ceiling", aligned) << "\n";
}

void printClustering(const pipeline::BuildResult& result) {
  const auto& report = result.report;
  const auto& cp = report.cluster_params;
  std::cout << std::setprecision(4) << "eps: " << cp.used.eps << (cp.eps_auto ? " (auto)" : " (given)")
            << ", min-pts: " << cp.used.min_pts << (cp.min_pts_auto ? " (auto)" : " (given)");
  if (cp.extension_params) {
    std::cout << "; extension: min-pts " << cp.extension_params->min_pts << " within reach "
              << cp.extension_params->reach << ", " << cp.extension.joined << " noise voxel"
              << (cp.extension.joined == 1 ? "" : "s") << " joined";
    if (cp.trim.dropped > 0)
      std::cout << ", " << cp.trim.dropped << " outlier voxel" << (cp.trim.dropped == 1 ? "" : "s") << " dropped";
    if (cp.coplanar.merged > 0)
      std::cout << ", " << cp.coplanar.merged << " flat cluster" << (cp.coplanar.merged == 1 ? "" : "s")
                << " joined to the surface around " << (cp.coplanar.merged == 1 ? "it" : "them");
  }
  std::cout << "\n";
  std::cout << "obstacles: " << result.obstacles.size();
  if (report.parts) {
    const auto& p = *report.parts;
    std::cout << " in " << p.parts << " convex parts (concavity " << p.concavity;
    // G <= T: no relaxation, no part passes as flat; an auto G (the eps) may land there too.
    const double asked = result.params.convex_parts->flat_gap.value_or(cp.used.eps);
    if (p.flat_gap > p.concavity) {
      std::cout << ", flat gap " << p.flat_gap << ": " << p.flat_parts << " flat part"
                << (p.flat_parts == 1 ? "" : "s");
    } else if (asked > 0.0) {
      std::cout << ", flat gap " << asked << " <= T: off";
    } else {
      std::cout << ", flat gap off";
    }
    if (p.stray_parts > 0)
      std::cout << "; " << p.stray_parts << " stray part" << (p.stray_parts == 1 ? "" : "s") << " of "
                << p.stray_voxels.size() << " voxel" << (p.stray_voxels.size() == 1 ? "" : "s") << " dropped";
    if (p.sparse_edge_parts > 0)
      std::cout << "; " << p.sparse_edge_parts << " sparse part" << (p.sparse_edge_parts == 1 ? "" : "s")
                << " grown to their edges, by up to " << p.sparse_edge_growth_max;
    std::cout << "); observed-free voxels inside hulls: " << p.free_voxels_inside << " (" << p.free_voxels_off_surface
              << " off the surface band), keyframes inside hulls: " << report.keyframes_inside_hulls;
  }
  std::cout << "\n";
}

}  // namespace hullmap::cli

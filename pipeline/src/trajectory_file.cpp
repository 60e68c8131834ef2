#include "hullmap/pipeline/trajectory_file.hpp"

#include <system_error>

#include "hullmap/core/atomic_file.hpp"
#include "hullmap/core/number_text.hpp"

namespace hullmap::pipeline {

void writeTumTrajectory(const std::filesystem::path& path, const std::vector<io::Keyframe>& keyframes) {
  core::writeFileAtomically(path.string(), [&](std::ostream& os) {
    os << "# t tx ty tz qx qy qz qw (TUM; camera-to-map, the build's output frame)\n";
    char buffer[core::kShortestTextMax];
    const auto put = [&](double v, char after) {
      os.write(buffer, core::writeShortest(buffer, v) - buffer);
      os.put(after);
    };
    for (const auto& k : keyframes) {
      const Eigen::Quaterniond& q = k.orientation;
      put(k.stamp, ' ');
      put(k.position.x(), ' ');
      put(k.position.y(), ' ');
      put(k.position.z(), ' ');
      put(q.x(), ' ');
      put(q.y(), ' ');
      put(q.z(), ' ');
      put(q.w(), '\n');
    }
  });
}

std::optional<std::vector<io::Keyframe>> readBuildTrajectory(const std::filesystem::path& build_dir) {
  const std::filesystem::path path = build_dir / kTrajectoryFile;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
  return io::readTumTrajectory(path.string());
}

}  // namespace hullmap::pipeline

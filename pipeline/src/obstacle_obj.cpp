// obstacles.obj: one object per convex part (obstacle_io.hpp).
#include <charconv>
#include <limits>
#include <ostream>
#include <string>

#include "hullmap/core/atomic_file.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"

namespace hullmap::pipeline {

void writeObstaclesObj(std::ostream& out, const std::vector<hulls::Obstacle>& obstacles) {
  // Numbers as `out << std::setprecision(max_digits10) << v` writes them (printf's %.17g, which
  // to_chars' general format with that precision is), without the stream's per-number cost.
  std::string text = "# hullmap obstacles: convex hulls (one object per convex part), z-up map frame\n";
  char number[64];
  const auto put_real = [&](double v) {
    text.append(number, std::to_chars(number, number + sizeof number, v, std::chars_format::general,
                                      std::numeric_limits<double>::max_digits10)
                            .ptr);
  };
  const auto put_index = [&](std::size_t v) {
    text.append(number, std::to_chars(number, number + sizeof number, v).ptr);
  };
  std::size_t base = 1;
  const auto write = [&](const std::string& name, const hulls::ConvexHull& hull) {
    text += "o " + name + '\n';
    for (const auto& v : hull.vertices) {
      text += "v ";
      put_real(v.x());
      text += ' ';
      put_real(v.y());
      text += ' ';
      put_real(v.z());
      text += '\n';
    }
    for (const auto& t : hull.triangles) {
      text += "f ";
      put_index(base + t[0]);
      text += ' ';
      put_index(base + t[1]);
      text += ' ';
      put_index(base + t[2]);
      text += '\n';
    }
    base += hull.vertices.size();
  };
  for (const auto& o : obstacles) {
    if (o.parts.empty()) write("obstacle_" + std::to_string(o.id), o.hull);
    for (std::size_t k = 0; k < o.parts.size(); ++k)
      write("obstacle_" + std::to_string(o.id) + "_part_" + std::to_string(k), o.parts[k].hull);
  }
  out.write(text.data(), std::streamsize(text.size()));
}

void writeObstaclesObj(const std::string& path, const std::vector<hulls::Obstacle>& obstacles) {
  core::writeFileAtomically(path, [&](std::ostream& out) { writeObstaclesObj(out, obstacles); });
}

}  // namespace hullmap::pipeline

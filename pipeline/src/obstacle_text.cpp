// obstacles.json's obstacles as text without building their document (obstacle_text.hpp).
#include "obstacle_text.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

namespace hullmap::pipeline {
namespace {

/// JSON text as nlohmann's dump(1) writes it (one space an indent level, ", " and ": " spelled
/// ",\n" and ": ", empty containers as [] and {}, floats through its own to_chars, non-finite as
/// null), written straight into a string: most of obstacles.json is numbers, and building the
/// document for them cost more than writing them. The caller gives keys in sorted order, as the
/// document's std::map has them.
class DumpText {
 public:
  DumpText(std::string& out, int depth) : out_(out), depth_(depth) {}

  void real(double v) {
    if (!std::isfinite(v)) {
      out_ += "null";
      return;
    }
    char text[64];
    out_.append(text, nlohmann::detail::to_chars(text, text + sizeof text, v));
  }
  template <class Integer>
  void integer(Integer v) {
    char text[24];
    out_.append(text, std::to_chars(text, text + sizeof text, v).ptr);
  }
  void boolean(bool v) { out_ += v ? "true" : "false"; }
  void vec3(const Eigen::Vector3d& v) {
    open('[');
    for (int i = 0; i < 3; ++i) {
      item();
      real(v[i]);
    }
    close(']');
  }

  void open(char bracket) {
    out_ += bracket;
    empty_.push_back(true);
    ++depth_;
  }
  void close(char bracket) {
    --depth_;
    if (!empty_.back()) {
      out_ += '\n';
      out_.append(std::size_t(depth_), ' ');
    }
    empty_.pop_back();
    out_ += bracket;
  }
  /// Before an array's element.
  void item() {
    if (!empty_.back()) out_ += ',';
    empty_.back() = false;
    out_ += '\n';
    out_.append(std::size_t(depth_), ' ');
  }
  /// Before an object's member.
  void key(const char* name) {
    item();
    out_ += '"';
    out_ += name;
    out_ += "\": ";
  }

 private:
  std::string& out_;
  int depth_;
  std::vector<bool> empty_;
};

void dumpHull(DumpText& d, const hulls::ConvexHull& hull) {
  d.open('{');
  d.key("triangles");
  d.open('[');
  for (const auto& t : hull.triangles) {
    d.item();
    d.open('[');
    for (const int i : t) {
      d.item();
      d.integer(i);
    }
    d.close(']');
  }
  d.close(']');
  d.key("vertices");
  d.open('[');
  for (const auto& v : hull.vertices) {
    d.item();
    d.vec3(v);
  }
  d.close(']');
  d.close('}');
}

void dumpFootprint(DumpText& d, const hulls::Footprint& footprint) {
  d.open('{');
  d.key("polygon");
  d.open('[');
  for (const auto& p : footprint.polygon) {
    d.item();
    d.open('[');
    d.item();
    d.real(p.x());
    d.item();
    d.real(p.y());
    d.close(']');
  }
  d.close(']');
  d.key("z_max");
  d.real(footprint.z_max);
  d.key("z_min");
  d.real(footprint.z_min);
  d.close('}');
}

/// commonJson's members from "aabb" to "centroid", and from "hull" to the end: a part's own members
/// fall between them in sorted order.
template <class T>
void dumpCommonHead(DumpText& d, const T& o) {
  d.key("aabb");
  d.open('{');
  d.key("max");
  d.vec3(o.aabb_max);
  d.key("min");
  d.vec3(o.aabb_min);
  d.close('}');
  d.key("centroid");
  d.vec3(o.centroid);
}

}  // namespace

void dumpObstacleText(std::string& out, const hulls::Obstacle& o, int depth) {
  DumpText d(out, depth);
  d.open('{');
  dumpCommonHead(d, o);
  d.key("footprint");
  dumpFootprint(d, o.footprint);
  d.key("hull");
  dumpHull(d, o.hull);
  d.key("id");
  d.integer(o.id);
  d.key("parts");
  d.open('[');
  for (const auto& p : o.parts) {
    d.item();
    d.open('{');
    dumpCommonHead(d, p);
    d.key("concavity_bound");
    d.real(p.concavity_bound);
    d.key("faces");
    d.boolean(p.faces);
    d.key("filled");
    d.boolean(p.filled);
    d.key("flat");
    d.boolean(p.flat);
    d.key("footprint");
    dumpFootprint(d, p.footprint);
    d.key("free_voxels_inside");
    d.integer(p.free_voxels_inside);
    d.key("free_voxels_off_surface");
    d.integer(p.free_voxels_off_surface);
    d.key("hull");
    dumpHull(d, p.hull);
    d.key("point_weight");
    d.integer(p.point_weight);
    d.key("volume");
    d.real(p.volume);
    d.key("voxel_count");
    d.integer(p.voxel_count);
    d.close('}');
  }
  d.close(']');
  d.key("point_weight");
  d.integer(o.point_weight);
  d.key("volume");
  d.real(o.volume);
  d.key("voxel_count");
  d.integer(o.voxel_count);
  d.close('}');
}

}  // namespace hullmap::pipeline

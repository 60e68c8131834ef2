#include "hullmap/live/map_messages.hpp"

#include <cstring>

namespace hullmap::live {
namespace {

constexpr int kAllPointsId = 0;
constexpr int kReferencePointsId = 6;

struct Field {
  std::size_t offset = 0;
  std::uint8_t datatype = 0;
};

Field findField(const CloudLayout& cloud, const char* name) {
  for (const auto& f : cloud.fields) {
    if (f.name != name) continue;
    if (f.datatype != kFloat32 && f.datatype != kFloat64) {
      throw Error(std::string("PointCloud2: field ") + name + " is of datatype " + std::to_string(f.datatype) +
                  ", expected FLOAT32 (7) or FLOAT64 (8)");
    }
    const std::size_t size = f.datatype == kFloat32 ? 4 : 8;
    if (f.offset + size > cloud.point_step) {
      throw Error(std::string("PointCloud2: field ") + name + " at offset " + std::to_string(f.offset) +
                  " lies beyond point_step " + std::to_string(cloud.point_step));
    }
    return {f.offset, f.datatype};
  }
  throw Error(std::string("PointCloud2: no field ") + name);
}

double readField(const std::uint8_t* point, const Field& field) {
  if (field.datatype == kFloat32) {
    float v;
    std::memcpy(&v, point + field.offset, sizeof v);
    return v;
  }
  double v;
  std::memcpy(&v, point + field.offset, sizeof v);
  return v;
}

}  // namespace

io::Points cloudPoints(const CloudLayout& cloud, const std::uint8_t* data, std::size_t size, std::size_t* non_finite) {
  if (cloud.is_bigendian) throw Error("PointCloud2: big-endian data is not read");
  const Field x = findField(cloud, "x");
  const Field y = findField(cloud, "y");
  const Field z = findField(cloud, "z");
  const std::uint64_t count = std::uint64_t{cloud.width} * cloud.height;
  if (cloud.height > 0 && std::uint64_t{cloud.row_step} < std::uint64_t{cloud.width} * cloud.point_step) {
    throw Error("PointCloud2: row_step " + std::to_string(cloud.row_step) + " < width * point_step");
  }
  if (std::uint64_t{cloud.row_step} * cloud.height > size) {
    throw Error("PointCloud2: data holds " + std::to_string(size) + " bytes, its header says " +
                std::to_string(std::uint64_t{cloud.row_step} * cloud.height));
  }
  io::Points points;
  points.reserve(count);
  std::size_t skipped = 0;
  for (std::uint32_t row = 0; row < cloud.height; ++row) {
    const std::uint8_t* base = data + std::size_t{row} * cloud.row_step;
    for (std::uint32_t col = 0; col < cloud.width; ++col) {
      const std::uint8_t* p = base + std::size_t{col} * cloud.point_step;
      const Eigen::Vector3d v(readField(p, x), readField(p, y), readField(p, z));
      if (!v.allFinite()) {
        ++skipped;
        continue;
      }
      points.push_back(v);
    }
  }
  if (non_finite) *non_finite = skipped;
  return points;
}

std::optional<bool> OrbSlamMapMarkers::decide(const MarkerKey& key, std::optional<io::Points>** slot) {
  if (key.ns != "MapPoints") return false;
  if (key.action == marker::kDeleteAll) {
    const bool changed = !empty();
    clear();
    return changed;
  }
  *slot = key.id == kAllPointsId ? &all_ : key.id == kReferencePointsId ? &reference_ : nullptr;
  if (!*slot) return false;
  if (key.action == marker::kDelete) {
    const bool changed = (*slot)->has_value();
    (*slot)->reset();
    return changed;
  }
  if (key.type != marker::kPoints) return false;
  return std::nullopt;
}

io::Points OrbSlamMapMarkers::points() const {
  io::Points points;
  points.reserve((all_ ? all_->size() : 0) + (reference_ ? reference_->size() : 0));
  if (all_) points.insert(points.end(), all_->begin(), all_->end());
  if (reference_) points.insert(points.end(), reference_->begin(), reference_->end());
  return points;
}

void OrbSlamMapMarkers::clear() {
  all_.reset();
  reference_.reset();
}

void TopicMap::count(const std::string& type) {
  ++map_.messages;
  map_.type = type;
}

void TopicMap::addCloud(const std::string& type, const CloudLayout& layout, const std::uint8_t* data,
                        std::size_t size) {
  count(type);
  clouds_ = true;
  try {
    map_.points = cloudPoints(layout, data, size);  // each cloud is the whole map: the last good one stays
  } catch (const Error&) {
    ++map_.skipped;
  }
}

BagMap TopicMap::result() const {
  BagMap map = map_;
  if (!clouds_) map.points = markers_.points();
  return map;
}

bool normaliseKeyframes(std::vector<io::Keyframe>& keyframes) {
  for (const auto& k : keyframes) {
    if (!k.position.allFinite() || !k.orientation.coeffs().allFinite() || k.orientation.norm() < 1e-9) return false;
  }
  for (auto& k : keyframes) k.orientation.normalize();
  return true;
}

std::uint64_t SequenceGaps::missed(const std::string& publisher, std::uint64_t sequence) {
  auto [it, first] = last_.emplace(publisher, sequence);
  if (first) return 0;
  const std::uint64_t last = it->second;
  if (sequence <= last) return 0;
  it->second = sequence;
  return sequence - last - 1;
}

}  // namespace hullmap::live

#include "hullmap/mapper/frame.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string_view>
#include <vector>

#include "hullmap/core/error.hpp"
#include "hullmap/core/number_text.hpp"

namespace hullmap::mapper {
namespace {

std::string_view trimmed(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

}  // namespace

UpAxis parseUpAxis(const std::string& text) {
  std::string t;
  for (char c : text) {
    if (!std::isspace(static_cast<unsigned char>(c)))
      t += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  if (t == "x" || t == "+x") return UpAxis::kPosX;
  if (t == "-x") return UpAxis::kNegX;
  if (t == "y" || t == "+y") return UpAxis::kPosY;
  if (t == "-y") return UpAxis::kNegY;
  if (t == "z" || t == "+z") return UpAxis::kPosZ;
  if (t == "-z") return UpAxis::kNegZ;
  throw Error::inParameter("up", "expected one of x, -x, y, -y, z, -z, got '" + text + "'");
}

std::string toString(UpAxis up) {
  switch (up) {
    case UpAxis::kPosX:
      return "+x";
    case UpAxis::kNegX:
      return "-x";
    case UpAxis::kPosY:
      return "+y";
    case UpAxis::kNegY:
      return "-y";
    case UpAxis::kPosZ:
      return "+z";
    case UpAxis::kNegZ:
      return "-z";
  }
  return "?";
}

Eigen::Matrix3d upRotation(UpAxis up) {
  Eigen::Matrix3d r;
  switch (up) {
    case UpAxis::kPosZ:
      r.setIdentity();
      break;
    case UpAxis::kNegZ:  // 180 deg about x
      r << 1, 0, 0, 0, -1, 0, 0, 0, -1;
      break;
    case UpAxis::kPosY:  // +90 deg about x
      r << 1, 0, 0, 0, 0, -1, 0, 1, 0;
      break;
    case UpAxis::kNegY:  // -90 deg about x
      r << 1, 0, 0, 0, 0, 1, 0, -1, 0;
      break;
    case UpAxis::kPosX:  // -90 deg about y
      r << 0, 0, -1, 0, 1, 0, 1, 0, 0;
      break;
    case UpAxis::kNegX:  // +90 deg about y
      r << 0, 0, 1, 0, 1, 0, -1, 0, 0;
      break;
  }
  return r;
}

namespace {

void checkScale(double scale) {
  if (!(std::isfinite(scale) && scale > 0)) {
    throw Error::inParameter("scale", "must be a finite number > 0, got " + std::to_string(scale));
  }
}

}  // namespace

void toMapFrame(const FrameParams& frame, io::Points& points) {
  checkScale(frame.scale);
  const Eigen::Matrix3d m = upRotation(frame.up) * frame.scale;
  for (io::Point& p : points) p = m * p;
}

void toMapFrame(const FrameParams& frame, std::vector<io::Keyframe>& keyframes) {
  checkScale(frame.scale);
  const Eigen::Matrix3d r = upRotation(frame.up);
  const Eigen::Quaterniond q(r);
  for (io::Keyframe& k : keyframes) {
    k.position = r * (frame.scale * k.position);
    k.orientation = (q * k.orientation).normalized();
  }
}

void applyFilters(const FilterParams& filters, io::Points& points, io::InputStats& stats) {
  std::size_t outside = 0;
  std::size_t below = 0;
  std::size_t above = 0;
  const auto keep = [&](const io::Point& p) {
    if (filters.crop) {
      const Box& b = *filters.crop;
      if ((p.array() < b.min.array()).any() || (p.array() > b.max.array()).any()) {
        ++outside;
        return false;
      }
    }
    if (filters.z_min && p.z() < *filters.z_min) {
      ++below;
      return false;
    }
    if (filters.z_max && p.z() > *filters.z_max) {
      ++above;
      return false;
    }
    return true;
  };
  points.erase(std::remove_if(points.begin(), points.end(), [&](const io::Point& p) { return !keep(p); }),
               points.end());
  if (outside) stats.dropped["outside_crop"] += outside;
  if (below) stats.dropped["below_z_min"] += below;
  if (above) stats.dropped["above_z_max"] += above;
}

namespace {

std::vector<double> parseNumbers(const std::string& option, const std::string& text, std::size_t expected,
                                 const char* form) {
  std::vector<double> values;
  const std::string_view view(text);
  bool bad = false;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = view.find(',', start);
    const std::string_view token =
        trimmed(view.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
    double v = 0;
    if (!core::parseDouble(token, v) || !std::isfinite(v)) bad = true;
    values.push_back(v);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  if (bad || values.size() != expected) {
    throw Error(option + ": expected " + form + " (" + std::to_string(expected) + " finite numbers), got '" + text +
                "'");
  }
  return values;
}

}  // namespace

Eigen::Vector3d parseVector3(const std::string& option, const std::string& text) {
  const auto v = parseNumbers(option, text, 3, "x,y,z");
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

Box parseBox(const std::string& option, const std::string& text) {
  const auto v = parseNumbers(option, text, 6, "x0,y0,z0,x1,y1,z1");
  Box box{Eigen::Vector3d(v[0], v[1], v[2]), Eigen::Vector3d(v[3], v[4], v[5])};
  for (int i = 0; i < 3; ++i) {
    if (box.min[i] > box.max[i]) {
      throw Error(option + ": min corner exceeds max corner on " + std::string(1, "xyz"[i]) + " in '" + text + "'");
    }
  }
  return box;
}

}  // namespace hullmap::mapper

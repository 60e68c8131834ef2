#include "hullmap/io/readers.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>

#include "read_detail.hpp"

namespace hullmap::io {
namespace {

constexpr std::size_t kSniffBytes = 64 * 1024;

std::string lowerExtension(const std::string& name) {
  std::string ext = std::filesystem::path(name).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

PointFormat formatFromExtension(const std::string& name) {
  const std::string ext = lowerExtension(name);
  if (ext == ".pcd") return PointFormat::kPcd;
  if (ext == ".ply") return PointFormat::kPly;
  return PointFormat::kText;
}

bool startsWith(std::string_view s, std::string_view prefix) {
  return s.size() >= prefix.size() && s.compare(0, prefix.size(), prefix) == 0;
}

void checkStreamParams(const PointStreamParams& params) {
  if (params.batch_points == 0) throw Error("PointStreamParams::batch_points must be at least 1");
  if (params.read_bytes == 0) throw Error("PointStreamParams::read_bytes must be at least 1");
}

// First bytes, after a UTF-8 byte-order mark, that tell the format.
PointFormat detectFromHead(std::string_view bytes, bool blank, const std::string& name) {
  if (blank) return formatFromExtension(name);
  if (startsWith(bytes, "ply\n") || startsWith(bytes, "ply\r\n")) return PointFormat::kPly;

  // The first meaningful line tells PCD ("# .PCD" comment, VERSION or FIELDS) and rostopic echo
  // ("header:" of the first message, or a "---" separator).
  const std::string_view sniff = bytes.substr(0, kSniffBytes);
  detail::ByteSource source(sniff);
  detail::LineCursor cursor(source);
  std::string_view line;
  while (cursor.next(line)) {
    const std::string_view t = detail::trim(line);
    if (t.empty()) continue;
    if (startsWith(t, "# .PCD")) return PointFormat::kPcd;
    if (t.front() == '#') continue;
    if (startsWith(t, "VERSION") || startsWith(t, "FIELDS")) return PointFormat::kPcd;
    if (startsWith(line, "header:") || t == "---") return PointFormat::kOrbSlamEcho;
    break;
  }
  for (std::size_t i = 0; i < sniff.size(); ++i) {
    const auto c = static_cast<unsigned char>(sniff[i]);
    if ((c < 0x20 && c != '\n' && c != '\t' && c != '\r' && c != '\f' && c != '\v') || c == 0x7f) {
      throw Error(name + ": not a point file (binary byte 0x" + "0123456789abcdef"[c >> 4] +
                  "0123456789abcdef"[c & 15] + " at offset " + std::to_string(i) +
                  "); expected ORB-SLAM text or echo dump, PCD, PLY or x y z text");
    }
  }
  return PointFormat::kText;
}

InputStats streamSource(detail::ByteSource& source, const std::string& name, const PointStreamParams& params,
                        const PointBatchConsumer& consume) {
  InputStats stats;
  stats.path = name;
  bool blank = false;
  const PointFormat format = detail::detectPointFormat(source, name, blank);
  stats.format = toString(format);
  if (!blank) {
    detail::PointSink sink(params.batch_points, consume);
    switch (format) {
      case PointFormat::kOrbSlamEcho:
        detail::parseOrbSlamEcho(source, name, sink, stats);
        break;
      case PointFormat::kText:
        detail::parseText(source, name, sink, stats);
        break;
      case PointFormat::kPcd:
        detail::parsePcd(source, name, sink, stats);
        break;
      case PointFormat::kPly:
        detail::parsePly(source, name, sink, stats);
        break;
    }
    sink.flush();
  }
  return stats;
}

// The whole-input readers: one batch per file, appended to `points`.
PointStreamParams wholeFile() {
  PointStreamParams params;
  params.batch_points = std::numeric_limits<std::size_t>::max();
  return params;
}

PointBatchConsumer appendTo(Points& points) {
  return [&points](Points& batch) {
    if (points.empty()) {
      points.swap(batch);
    } else {
      points.insert(points.end(), batch.begin(), batch.end());
    }
  };
}

}  // namespace

std::string toString(PointFormat format) {
  switch (format) {
    case PointFormat::kOrbSlamEcho:
      return "orbslam_echo";
    case PointFormat::kText:
      return "text";
    case PointFormat::kPcd:
      return "pcd";
    case PointFormat::kPly:
      return "ply";
  }
  return "unknown";
}

namespace detail {

PointFormat detectPointFormat(ByteSource& source, const std::string& name, bool& blank) {
  const std::size_t bom = 3;
  source.ensure(0, bom + kSniffBytes);
  std::string_view head = source.view(0, std::min(source.end(), bom + kSniffBytes));
  std::size_t first = 0;
  if (startsWith(head, "\xEF\xBB\xBF")) first = bom;  // UTF-8 byte-order mark
  // Blank unless a byte that is not whitespace comes, however far into the input.
  blank = true;
  for (std::size_t pos = first; blank && (pos < source.end() || source.more()); ++pos) {
    const char c = *source.at(pos);
    blank = isSpace(c) || c == '\n';
  }
  head = source.view(0, std::min(source.end(), bom + kSniffBytes)).substr(first);
  return detectFromHead(head, blank, name);
}

}  // namespace detail

PointFormat detectPointFormat(std::string_view bytes, const std::string& name) {
  detail::ByteSource source(bytes);
  bool blank = false;
  return detail::detectPointFormat(source, name, blank);
}

PointFormat detectPointFormat(const std::string& path) {
  detail::ByteSource source(path, kSniffBytes);
  source.ensure(0, kSniffBytes);
  return detectPointFormat(source.view(0, std::min(source.end(), kSniffBytes)), path);
}

InputStats streamPoints(std::string_view bytes, const std::string& name, const PointStreamParams& params,
                        const PointBatchConsumer& consume) {
  checkStreamParams(params);
  detail::ByteSource source(bytes);
  return streamSource(source, name, params, consume);
}

InputStats streamPointFile(const std::string& path, const PointStreamParams& params,
                           const PointBatchConsumer& consume) {
  checkStreamParams(params);
  detail::ByteSource source(path, params.read_bytes);
  return streamSource(source, path, params, consume);
}

std::vector<InputStats> streamPointFiles(const std::vector<std::string>& paths, const PointStreamParams& params,
                                         const PointBatchConsumer& consume) {
  std::vector<InputStats> inputs;
  for (const std::string& path : paths) inputs.push_back(streamPointFile(path, params, consume));
  return inputs;
}

PointSet parsePoints(std::string_view bytes, const std::string& name) {
  PointSet set;
  set.inputs.push_back(streamPoints(bytes, name, wholeFile(), appendTo(set.points)));
  return set;
}

PointSet readPointFile(const std::string& path) {
  PointSet set;
  set.inputs.push_back(streamPointFile(path, wholeFile(), appendTo(set.points)));
  return set;
}

PointSet readPointFiles(const std::vector<std::string>& paths) {
  PointSet all;
  all.inputs = streamPointFiles(paths, wholeFile(), appendTo(all.points));
  return all;
}

std::vector<Keyframe> parseTumTrajectory(std::string_view bytes, const std::string& name) {
  std::vector<Keyframe> keyframes;
  detail::forEachNumberRow(bytes, name, [&](const double* v, std::size_t count, std::size_t line) {
    if (count != 8) {
      detail::failAt(name, line, "expected 8 numbers (t tx ty tz qx qy qz qw), got " + std::to_string(count));
    }
    for (std::size_t i = 0; i < 8; ++i) {
      if (!std::isfinite(v[i])) detail::failAt(name, line, "non-finite value in pose");
    }
    Keyframe k;
    k.stamp = v[0] > kNanosecondStampThreshold ? v[0] * 1e-9 : v[0];
    k.position = Eigen::Vector3d(v[1], v[2], v[3]);
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);  // Eigen's constructor takes w first
    // stableNorm: the squares of components near 1e200 overflow (norm() = inf normalised
    // (1e200, 0, 0, 0) to all zeros).
    const double norm = q.coeffs().stableNorm();
    if (!(norm > 1e-12)) detail::failAt(name, line, "zero quaternion");
    k.orientation = Eigen::Quaterniond(q.coeffs() / norm);
    keyframes.push_back(k);
  });
  return keyframes;
}

std::vector<Keyframe> readTumTrajectory(const std::string& path) {
  detail::ByteSource source(path, PointStreamParams{}.read_bytes);
  source.loadAll();
  return parseTumTrajectory(source.view(0, source.end()), path);
}

}  // namespace hullmap::io

#include "hullmap/mapper/readers.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <limits>
#include <cstring>
#include <filesystem>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "read_detail.hpp"

namespace hullmap::mapper {
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

// The bytes of a file: mapped when it is a regular file (no copy, no zero-fill of a buffer: a
// 300 MB text map parses at the speed of the parser), read into memory otherwise (pipes).
class FileBytes {
 public:
  FileBytes(const std::string& path, std::size_t limit) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw Error(path + ": is a directory, not a point file");
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw Error(path + ": cannot open (" + std::strerror(errno) + ")");
    struct stat st {};
    if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) {
      const auto size = std::min<std::size_t>(static_cast<std::size_t>(st.st_size), limit);
      if (size > 0) {
        void* p = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
        if (p != MAP_FAILED) {
          ::madvise(p, size, MADV_SEQUENTIAL);
          map_ = p;
          map_size_ = size;
          view_ = std::string_view(static_cast<const char*>(p), size);
          ::close(fd);
          return;
        }
      }
    }
    char buffer[65536];
    while (copy_.size() < limit) {
      const ssize_t n = ::read(fd, buffer, sizeof buffer);
      if (n < 0) {
        const int err = errno;
        ::close(fd);
        throw Error(path + ": read error (" + std::strerror(err) + ")");
      }
      if (n == 0) break;
      copy_.append(buffer, static_cast<std::size_t>(n));
    }
    ::close(fd);
    if (copy_.size() > limit) copy_.resize(limit);
    view_ = copy_;
  }
  ~FileBytes() {
    if (map_) ::munmap(map_, map_size_);
  }
  FileBytes(const FileBytes&) = delete;
  FileBytes& operator=(const FileBytes&) = delete;

  std::string_view view() const { return view_; }

 private:
  void* map_ = nullptr;
  std::size_t map_size_ = 0;
  std::string copy_;
  std::string_view view_;
};

}  // namespace

std::string toString(PointFormat format) {
  switch (format) {
    case PointFormat::kOrbSlamEcho: return "orbslam_echo";
    case PointFormat::kText: return "text";
    case PointFormat::kPcd: return "pcd";
    case PointFormat::kPly: return "ply";
  }
  return "unknown";
}

PointFormat detectPointFormat(std::string_view bytes, const std::string& name) {
  if (startsWith(bytes, "\xEF\xBB\xBF")) bytes.remove_prefix(3);  // UTF-8 byte-order mark
  if (detail::isBlank(bytes)) {
    return formatFromExtension(name);
  }
  if (startsWith(bytes, "ply\n") || startsWith(bytes, "ply\r\n")) return PointFormat::kPly;

  // The first meaningful line tells PCD ("# .PCD" comment, VERSION or FIELDS) and rostopic echo
  // ("header:" of the first message, or a "---" separator).
  detail::LineCursor cursor(bytes.substr(0, kSniffBytes));
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
  const std::string_view sniff = bytes.substr(0, kSniffBytes);
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

PointFormat detectPointFormat(const std::string& path) {
  const FileBytes bytes(path, kSniffBytes);
  return detectPointFormat(bytes.view(), path);
}

PointSet parsePoints(std::string_view bytes, const std::string& name) {
  PointSet set;
  InputStats stats;
  stats.path = name;
  const PointFormat format = detectPointFormat(bytes, name);
  stats.format = toString(format);
  if (!detail::isBlank(bytes)) {
    switch (format) {
      case PointFormat::kOrbSlamEcho: detail::parseOrbSlamEcho(bytes, name, set.points, stats); break;
      case PointFormat::kText: detail::parseText(bytes, name, set.points, stats); break;
      case PointFormat::kPcd: detail::parsePcd(bytes, name, set.points, stats); break;
      case PointFormat::kPly: detail::parsePly(bytes, name, set.points, stats); break;
    }
  }
  set.inputs.push_back(std::move(stats));
  return set;
}

PointSet readPointFile(const std::string& path) {
  const FileBytes bytes(path, std::numeric_limits<std::size_t>::max());
  return parsePoints(bytes.view(), path);
}

PointSet readPointFiles(const std::vector<std::string>& paths) {
  PointSet all;
  for (const std::string& path : paths) {
    PointSet one = readPointFile(path);
    if (all.points.empty()) {
      all.points = std::move(one.points);
    } else {
      all.points.insert(all.points.end(), one.points.begin(), one.points.end());
    }
    all.inputs.push_back(std::move(one.inputs.front()));
  }
  return all;
}

std::vector<Keyframe> parseTumTrajectory(std::string_view bytes, const std::string& name) {
  std::vector<Keyframe> keyframes;
  detail::LineCursor cursor(bytes);
  std::string_view line;
  while (cursor.next(line)) {
    const std::size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    if (detail::trim(line).empty()) continue;
    double v[8];
    std::size_t count = 0;
    detail::forEachToken(line, [&](std::string_view token) {
      double value = 0;
      if (!detail::parseDouble(token, value)) {
        detail::failAt(name, cursor.lineNumber(),
                       token.empty() ? std::string("empty field") : detail::quoted(token) + " is not a number");
      }
      if (count < 8) v[count] = value;
      ++count;
    });
    if (count != 8) {
      detail::failAt(name, cursor.lineNumber(),
                     "expected 8 numbers (t tx ty tz qx qy qz qw), got " + std::to_string(count));
    }
    for (double x : v) {
      if (!std::isfinite(x)) detail::failAt(name, cursor.lineNumber(), "non-finite value in pose");
    }
    Keyframe k;
    k.stamp = v[0] > kNanosecondStampThreshold ? v[0] * 1e-9 : v[0];
    k.position = Eigen::Vector3d(v[1], v[2], v[3]);
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);  // Eigen's constructor takes w first
    // stableNorm: the squares of components near 1e200 overflow (norm() = inf normalised
    // (1e200, 0, 0, 0) to all zeros).
    const double norm = q.coeffs().stableNorm();
    if (!(norm > 1e-12)) detail::failAt(name, cursor.lineNumber(), "zero quaternion");
    k.orientation = Eigen::Quaterniond(q.coeffs() / norm);
    keyframes.push_back(k);
  }
  return keyframes;
}

std::vector<Keyframe> readTumTrajectory(const std::string& path) {
  const FileBytes bytes(path, std::numeric_limits<std::size_t>::max());
  return parseTumTrajectory(bytes.view(), path);
}

}  // namespace hullmap::mapper

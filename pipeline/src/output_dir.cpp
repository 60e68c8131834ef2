#include "hullmap/pipeline/output_dir.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>

#include <unistd.h>

#include "hullmap/core/atomic_file.hpp"
#include "hullmap/core/error.hpp"

namespace hullmap::pipeline {
namespace {

namespace fs = std::filesystem;
using Reason = OutputDirRefusal::Reason;

/// Absolute, normalised, without a trailing separator ("out/" and "out" are one directory).
fs::path normalised(const std::string& path) {
  fs::path p = fs::absolute(path).lexically_normal();
  if (p.filename().empty() && p.has_parent_path()) p = p.parent_path();
  return p;
}

/// Symbolic links resolved as far as the path exists.
fs::path resolved(const fs::path& path) {
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(path, ec);
  return ec ? path : p;
}

/// True when `inner` is `outer` or lies below it (both resolved, normalised).
bool within(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
    if (o->empty()) continue;
    if (i == inner.end() || *i != *o) return false;
  }
  return true;
}

/// "a, b, c and 4 more" from sorted names.
std::string someNames(const std::vector<std::string>& names) {
  std::string text;
  const std::size_t shown = std::min<std::size_t>(names.size(), 3);
  for (std::size_t i = 0; i < shown; ++i) text += (i ? ", " : "") + names[i];
  if (names.size() > shown) text += " and " + std::to_string(names.size() - shown) + " more";
  return text;
}

/// The names a marker lists, or nullopt when `path` is no marker.
std::optional<std::set<std::string>> markerFiles(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line) || line != kOutputMarkerFormat) return std::nullopt;
  std::set<std::string> files;
  while (std::getline(in, line)) {
    if (!line.empty() && line.find('/') == std::string::npos && line != "." && line != "..") files.insert(line);
  }
  return files;
}

OutputDirRefusal refusal(Reason reason, const std::string& dir, const std::string& why) {
  return OutputDirRefusal{reason, dir + ": " + why};
}

}  // namespace

std::optional<OutputDirRefusal> outputDirRefusal(const std::string& dir, const OutputDirPolicy& policy) {
  if (dir.empty()) return OutputDirRefusal{Reason::kEmptyName, "output directory: empty name"};
  const fs::path out = normalised(dir);
  const fs::path real = resolved(out);
  std::error_code ec;
  const fs::path cwd = resolved(fs::current_path(ec));
  if (!ec && within(cwd, real)) {
    return refusal(Reason::kCurrentDirectory, dir,
                   real == cwd ? "is the current directory; a run replaces its output directory whole, so give "
                                 "a new directory for it (e.g. out)"
                               : "contains the current directory; a run replaces its output directory whole, so "
                                 "give a new directory for it (e.g. out)");
  }

  const fs::file_status status = fs::status(out, ec);
  if (fs::exists(status) && !fs::is_directory(status)) {
    return refusal(Reason::kNotADirectory, dir, "exists and is not a directory");
  }

  for (const auto& input : policy.inputs) {
    if (input.empty() || !fs::exists(input, ec)) continue;
    if (within(resolved(normalised(input)), real)) {
      return refusal(Reason::kHoldsInput, dir,
                     "holds the input " + input +
                         "; a run replaces its output directory whole, so write "
                         "the output elsewhere");
    }
  }

  if (!fs::exists(status)) {
    const fs::path parent = out.parent_path();
    fs::path ancestor = parent;
    while (!fs::exists(ancestor, ec) && ancestor.has_parent_path() && ancestor != ancestor.parent_path()) {
      ancestor = ancestor.parent_path();
    }
    if (!fs::is_directory(ancestor, ec)) {
      return refusal(Reason::kNotADirectory, dir, "cannot create it: " + ancestor.string() + " is not a directory");
    }
    if (ancestor != parent && !policy.make_parents) {
      return refusal(Reason::kMissingParent, dir, "its parent directory " + parent.string() + " does not exist");
    }
    if (::access(ancestor.c_str(), W_OK | X_OK) != 0) {
      return refusal(Reason::kNotWritable, dir,
                     "cannot create it in " + ancestor.string() + ": " + std::strerror(errno));
    }
    return std::nullopt;
  }

  std::vector<std::string> entries;
  for (const auto& entry : fs::directory_iterator(out, ec)) entries.push_back(entry.path().filename().string());
  if (ec) return refusal(Reason::kNotWritable, dir, "cannot list it: " + ec.message());
  if (entries.empty()) return std::nullopt;
  std::sort(entries.begin(), entries.end());

  const auto listed = markerFiles(out / kOutputMarker);
  if (!listed) {
    return refusal(Reason::kForeign, dir,
                   "not empty and not a hullmap output (holds " + someNames(entries) + "; no " + kOutputMarker +
                       " marker); refusing to replace it: give a new or empty directory");
  }
  std::vector<std::string> foreign;
  for (const auto& name : entries) {
    if (name == kOutputMarker) continue;
    const fs::file_status s = fs::symlink_status(out / name, ec);
    if (!listed->count(name) || !fs::is_regular_file(s)) foreign.push_back(name);
  }
  if (!foreign.empty()) {
    return refusal(Reason::kForeignFiles, dir,
                   "a hullmap output that also holds files hullmap did not write (" + someNames(foreign) +
                       "); refusing to replace it: move them out first");
  }
  if (::access(out.parent_path().c_str(), W_OK | X_OK) != 0) {
    return refusal(Reason::kNotWritable, dir,
                   "cannot replace it in " + out.parent_path().string() + ": " + std::strerror(errno));
  }
  return std::nullopt;
}

void checkOutputDir(const std::string& dir, const OutputDirPolicy& policy) {
  if (const auto refused = outputDirRefusal(dir, policy)) throw Error(refused->message);
}

void checkOutputFile(const std::string& path) {
  if (path == "-") return;
  if (path.empty()) throw Error("output file: empty name");
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw Error(path + ": is a directory");
  fs::path parent = fs::path(path).parent_path();
  if (parent.empty()) parent = ".";
  if (::access(parent.c_str(), W_OK | X_OK) != 0) {
    throw Error(path + ": cannot write there: " + parent.string() + ": " + std::strerror(errno));
  }
  if (!fs::is_directory(parent, ec))
    throw Error(path + ": cannot write there: " + parent.string() + " is not a directory");
}

void writeOutputMarker(const std::string& dir, const std::vector<std::string>& files) {
  core::writeFileAtomically((fs::path(dir) / kOutputMarker).string(), [&](std::ostream& out) {
    out << kOutputMarkerFormat << '\n';
    for (const auto& name : files) out << name << '\n';
  });
}

}  // namespace hullmap::pipeline

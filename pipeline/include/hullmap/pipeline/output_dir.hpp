#pragma once

#include <optional>
#include <string>
#include <vector>

namespace hullmap::pipeline {

/// The marker file hullmap writes into every output directory it makes. Its first line is
/// kOutputMarkerFormat, then the names of the files the run wrote, one a line. A directory holding
/// this marker and nothing but the files it lists is "a previous hullmap output" and may be
/// replaced by a new run; any other non-empty directory is the user's and is never replaced.
inline constexpr const char* kOutputMarker = ".hullmap-output";
inline constexpr const char* kOutputMarkerFormat = "hullmap-output/1";

/// What a run that replaces an output directory whole needs to know about it.
struct OutputDirPolicy {
  /// Files the run reads (map points, trajectory, ...): none may lie inside the output directory,
  /// since replacing the directory would remove them. Names that do not exist (e.g. "-") are skipped.
  std::vector<std::string> inputs;
  /// Like `mkdir -p`: missing parent directories are created. When false a missing parent is refused.
  bool make_parents = false;
};

/// Why an output directory may not be written.
struct OutputDirRefusal {
  enum class Reason {
    kEmptyName,         ///< "" given
    kCurrentDirectory,  ///< the working directory, or one of its ancestors (`-o .`, `-o ..`)
    kNotADirectory,     ///< exists and is a file (or a path below a file)
    kMissingParent,     ///< the parent directory does not exist and make_parents is false
    kNotWritable,       ///< the nearest existing ancestor cannot be written
    kHoldsInput,        ///< one of policy.inputs lies inside
    kForeign,           ///< not empty and not a hullmap output (no marker)
    kForeignFiles,      ///< a hullmap output, but also holding files hullmap did not write
  };
  Reason reason;
  /// One line naming the directory as given and saying why: "mydata: not empty and not a hullmap
  /// output (holds important.txt, map_points.txt); refusing to replace it".
  std::string message;
};

/// The reason a run may not replace `dir` whole with its output, or nullopt when it may: `dir` is
/// absent (its parent existing, or policy.make_parents), an empty directory, or a previous hullmap
/// output (kOutputMarker present, every entry a regular file the marker lists). Reads the file
/// system only; thread-safe. The answer can change if another process changes `dir` meanwhile: a
/// writer checks again just before it replaces the directory.
std::optional<OutputDirRefusal> outputDirRefusal(const std::string& dir, const OutputDirPolicy& policy = {});

/// Throws hullmap::Error with the refusal's message when outputDirRefusal finds one.
void checkOutputDir(const std::string& dir, const OutputDirPolicy& policy = {});

/// Throws hullmap::Error "<path>: <why>" when a single output file (a CSV, a picture) plainly cannot
/// be written: it is a directory, or its directory is missing or not writable (the OS's reason:
/// "out/missing/labels.csv: cannot write there: out/missing: No such file or directory"). Meant to be
/// called before the work that produces it. "-" (standard output) always passes.
void checkOutputFile(const std::string& path);

/// Writes kOutputMarker into `dir` (normally a staging directory, before it is moved into place),
/// listing `files`, the names of the files the run wrote there. Throws hullmap::Error naming it.
void writeOutputMarker(const std::string& dir, const std::vector<std::string>& files);

}  // namespace hullmap::pipeline

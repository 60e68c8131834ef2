#pragma once

#include <optional>
#include <string>
#include <vector>

namespace hullmap::plot {

/// Debian package that provides rsvg-convert, named in errors and output.
inline constexpr const char* kPngConverterPackage = "librsvg2-bin";

/// Full path of the executable `name` in the ':'-separated directory list `search_path` (the value
/// of PATH), or nullopt.
std::optional<std::string> findProgram(const std::string& name, const std::string& search_path);

/// rsvg-convert found on the process's PATH, or nullopt.
std::optional<std::string> findPngConverter();

/// Where a picture goes. `path` ending in ".png" (any case) means PNG only; otherwise the SVG is
/// written to `path`, and with `also_png` a PNG beside it (extension replaced by .png).
struct PictureOutput {
  std::string path;
  bool also_png = false;
  std::string option = "-o";  ///< the option that named `path`, for error messages
};

/// Throws the hullmap::Error writePicture would throw before writing anything: no file name, a
/// directory that does not exist, a PNG asked without a converter. Lets a command fail before its work.
void checkPictureOutput(const PictureOutput& output, const std::optional<std::string>& converter);

/// Writes `svg` as asked, each file atomically (temporary file + rename). PNGs are rendered by
/// `converter` (rsvg-convert). Returns the files written. Throws hullmap::Error naming the file or
/// the option: when a PNG is asked and `converter` is nullopt the message names the package to
/// install (librsvg2-bin); when the converter fails, its exit status.
std::vector<std::string> writePicture(const std::string& svg, const PictureOutput& output,
                                      const std::optional<std::string>& converter);

}  // namespace hullmap::plot

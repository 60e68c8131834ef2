#include "hullmap/plot/picture_output.hpp"

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "hullmap/core/atomic_file.hpp"
#include "hullmap/core/error.hpp"

extern char** environ;

namespace hullmap::plot {

std::optional<std::string> findProgram(const std::string& name, const std::string& search_path) {
  std::size_t start = 0;
  while (start <= search_path.size()) {
    std::size_t end = search_path.find(':', start);
    if (end == std::string::npos) end = search_path.size();
    const std::string dir = search_path.substr(start, end - start);
    if (!dir.empty()) {
      const std::filesystem::path candidate = std::filesystem::path(dir) / name;
      std::error_code ec;
      if (std::filesystem::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0) {
        return candidate.string();
      }
    }
    start = end + 1;
  }
  return std::nullopt;
}

std::optional<std::string> findPngConverter() {
  const char* path = std::getenv("PATH");
  return findProgram("rsvg-convert", path ? path : "");
}

namespace {

// ".svg" for "Map.SVG".
std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

bool endsWithPng(const std::string& path) { return lowerExtension(path) == ".png"; }

std::string tempBeside(const std::filesystem::path& target, const std::string& suffix) {
  return (target.parent_path() / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()) + suffix))
      .string();
}

// rsvg-convert -f png -o png svg, without a shell; throws naming `target` on failure.
void runConverter(const std::string& converter, const std::string& svg_file, const std::string& png_file,
                  const std::string& target) {
  std::vector<std::string> args = {converter, "-f", "png", "-b", "white", "-o", png_file, svg_file};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (::posix_spawn(&pid, converter.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
    throw Error(target + ": cannot run " + converter);
  }
  int raw = 0;
  if (::waitpid(pid, &raw, 0) < 0 || !WIFEXITED(raw) || WEXITSTATUS(raw) != 0) {
    throw Error(target + ": " + converter + " failed (exit status " +
                std::to_string(WIFEXITED(raw) ? WEXITSTATUS(raw) : -1) + ")");
  }
}

// Renders `svg` to the PNG `target` atomically.
void writePng(const std::string& svg, const std::string& target, const std::string& converter) {
  const std::filesystem::path t(target);
  const std::string svg_tmp = tempBeside(t, ".svg");
  const std::string png_tmp = tempBeside(t, ".png");
  const auto cleanup = [&] {
    std::error_code ignored;
    std::filesystem::remove(svg_tmp, ignored);
    std::filesystem::remove(png_tmp, ignored);
  };
  try {
    core::writeFileAtomically(svg_tmp, [&](std::ostream& out) { out << svg; });
    runConverter(converter, svg_tmp, png_tmp, target);
    std::error_code ec;
    std::filesystem::rename(png_tmp, t, ec);
    if (ec) throw Error(target + ": cannot rename into place: " + ec.message());
  } catch (...) {
    cleanup();
    throw;
  }
  cleanup();
}

}  // namespace

void checkPictureOutput(const PictureOutput& output, const std::optional<std::string>& converter) {
  if (output.path.empty()) throw Error(output.option + ": no output file given");
  const bool png_only = endsWithPng(output.path);
  if (!png_only && lowerExtension(output.path) != ".svg") {
    throw Error(output.option + " " + output.path + ": expected a .svg or .png file name");
  }
  const auto dir = std::filesystem::path(output.path).parent_path();
  std::error_code ec;
  if (!dir.empty() && !std::filesystem::is_directory(dir, ec)) {
    throw Error(output.option + " " + output.path + ": directory " + dir.string() + " does not exist");
  }
  if ((png_only || output.also_png) && !converter) {
    throw Error((png_only ? output.option + " " + output.path : std::string("--png")) +
                ": PNG output needs rsvg-convert, which is not on PATH; install the Debian package " +
                kPngConverterPackage + " (apt-get install " + kPngConverterPackage + ") or write an .svg");
  }
}

std::vector<std::string> writePicture(const std::string& svg, const PictureOutput& output,
                                      const std::optional<std::string>& converter) {
  checkPictureOutput(output, converter);
  const bool png_only = endsWithPng(output.path);
  std::vector<std::string> written;
  if (png_only) {
    writePng(svg, output.path, *converter);
    written.push_back(output.path);
    return written;
  }
  core::writeFileAtomically(output.path, [&](std::ostream& out) { out << svg; });
  written.push_back(output.path);
  if (output.also_png) {
    const std::string png = std::filesystem::path(output.path).replace_extension(".png").string();
    writePng(svg, png, *converter);
    written.push_back(png);
  }
  return written;
}

}  // namespace hullmap::plot

#pragma once

#include <stdexcept>
#include <string>

namespace hullmap {

/// The one exception hullmap's public API throws. Its message names the file and line, or the
/// parameter, at fault: "maps/a.pcd:12: expected 3 numbers, got 2", "eps: must be > 0, got 0".
///
/// An error about parameters also carries their names (the fields of the params structs, as
/// "min_pts" or "crop/z_min/z_max"), so a front end can name them its own way: the command line
/// says "--min-pts" where the library says "min_pts".
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;

  /// An error about `parameter` (one name, or several joined by '/'): what() is
  /// "<parameter>: <detail>".
  static Error inParameter(const std::string& parameter, const std::string& detail) {
    Error e(parameter + ": " + detail);
    e.parameter_ = parameter;
    return e;
  }

  /// The parameter(s) at fault as given to inParameter, or "" for any other error.
  const std::string& parameter() const noexcept { return parameter_; }

  /// what() without the leading "<parameter>: ".
  std::string detail() const {
    const std::string all = what();
    return parameter_.empty() ? all : all.substr(parameter_.size() + 2);
  }

 private:
  std::string parameter_;
};

}  // namespace hullmap

// HeightField's interpolation (height_field.hpp).
#include "hullmap/core/height_field.hpp"

#include <algorithm>
#include <cmath>

namespace hullmap {

double HeightField::height(double x, double y) const {
  const double u = std::clamp((x - origin.x()) / step - 0.5, 0.0, double(nx - 1));
  const double v = std::clamp((y - origin.y()) / step - 0.5, 0.0, double(ny - 1));
  const std::size_t i = std::min(std::size_t(u), nx > 1 ? nx - 2 : 0);
  const std::size_t j = std::min(std::size_t(v), ny > 1 ? ny - 2 : 0);
  const double fu = nx > 1 ? u - double(i) : 0.0, fv = ny > 1 ? v - double(j) : 0.0;
  const auto h = [&](std::size_t a, std::size_t b) { return at(std::min(a, nx - 1), std::min(b, ny - 1)); };
  const double h00 = h(i, j), h11 = h(i + 1, j + 1);
  // The triangle below the diagonal (fu >= fv) has nodes (i, j), (i + 1, j), (i + 1, j + 1); the
  // other (i, j), (i, j + 1), (i + 1, j + 1).
  if (fu >= fv) return h00 + fu * (h(i + 1, j) - h00) + fv * (h11 - h(i + 1, j));
  return h00 + fv * (h(i, j + 1) - h00) + fu * (h11 - h(i, j + 1));
}

double HeightField::lowest() const { return *std::min_element(heights.begin(), heights.end()); }
double HeightField::highest() const { return *std::max_element(heights.begin(), heights.end()); }

bool HeightField::valid() const {
  if (!(step > 0) || !std::isfinite(step) || !origin.allFinite() || nx == 0 || ny == 0) return false;
  if (heights.size() != nx * ny) return false;
  return std::all_of(heights.begin(), heights.end(), [](double z) { return std::isfinite(z); });
}

}  // namespace hullmap

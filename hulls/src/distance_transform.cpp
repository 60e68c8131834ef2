// Felzenszwalb and Huttenlocher's exact squared Euclidean distance transform (Theory of Computing
// 8, 2012), one pass per axis.
#include "distance_transform.hpp"

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

namespace hullmap::hulls::detail {
namespace {

/// Squared Euclidean distance transform along one line (Felzenszwalb and Huttenlocher 2012).
void distanceTransform1d(std::vector<double>& f, std::vector<double>& out, std::vector<int>& v,
                         std::vector<double>& z) {
  const int n = int(f.size());
  v.resize(std::size_t(n));
  z.resize(std::size_t(n) + 1);
  int k = 0;
  v[0] = 0;
  z[0] = -std::numeric_limits<double>::infinity();
  z[1] = std::numeric_limits<double>::infinity();
  const auto meet = [&](int q, int r) {
    return ((f[std::size_t(q)] + double(q) * q) - (f[std::size_t(r)] + double(r) * r)) / (2.0 * q - 2.0 * r);
  };
  for (int q = 1; q < n; ++q) {
    double s = meet(q, v[std::size_t(k)]);
    while (k > 0 && s <= z[std::size_t(k)]) s = meet(q, v[std::size_t(--k)]);
    ++k;
    v[std::size_t(k)] = q;
    z[std::size_t(k)] = s;
    z[std::size_t(k) + 1] = std::numeric_limits<double>::infinity();
  }
  out.resize(std::size_t(n));
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[std::size_t(k) + 1] < q) ++k;
    const double d = q - v[std::size_t(k)];
    out[std::size_t(q)] = d * d + f[std::size_t(v[std::size_t(k)])];
  }
}

}  // namespace

/// Exact squared Euclidean distance transform in place (Felzenszwalb-Huttenlocher, one pass per
/// axis) over a box of `dims` cells stored x fastest: `d2` holds 0 at the sites and a large value
/// elsewhere (kept below 1e20; lines holding only 0 and 1e20 take a faster, exactly equal path).
void exactTransform(std::vector<float>& d2, const std::array<std::int64_t, 3>& dims) {
  constexpr double kFar = 1e20;
  const std::array<std::int64_t, 3> stride{1, dims[0], dims[0] * dims[1]};
  std::vector<double> f, out, z;
  std::vector<int> v;
  for (int axis = 0; axis < 3; ++axis) {
    const std::size_t a = std::size_t(axis), b = std::size_t((axis + 1) % 3), c = std::size_t((axis + 2) % 3);
    const std::int64_t n = dims[a], s = stride[a];
    f.resize(std::size_t(n));
    // Every line along `axis`: its first cell runs over the other two axes.
    for (std::int64_t ib = 0; ib < dims[b]; ++ib)
      for (std::int64_t ic = 0; ic < dims[c]; ++ic) {
        const std::int64_t base = ib * stride[b] + ic * stride[c];
        // A line holding no finite value stays as it is (every value kFar after the transform too),
        // and on the first pass, where the values are 0 (sites) or kFar, the transform is the
        // squared distance to the nearest site along the line: two sweeps give the same exact
        // integers as the lower envelope of parabolas.
        bool any = false, binary = true;
        for (std::int64_t q = 0; q < n; ++q) {
          const float x = d2[std::size_t(base + q * s)];
          any = any || x < float(kFar);
          binary = binary && (x == 0.0f || x >= float(kFar));
        }
        if (!any) continue;
        if (axis == 0 && binary) {
          std::int64_t last = -1;  // the nearest site at or before q
          for (std::int64_t q = 0; q < n; ++q) {
            if (d2[std::size_t(base + q * s)] == 0.0f) last = q;
            f[std::size_t(q)] = last < 0 ? kFar : double(q - last) * double(q - last);
          }
          last = -1;  // the nearest site at or after q
          for (std::int64_t q = n - 1; q >= 0; --q) {
            if (d2[std::size_t(base + q * s)] == 0.0f) last = q;
            const double after = last < 0 ? kFar : double(last - q) * double(last - q);
            d2[std::size_t(base + q * s)] = float(std::min(std::min(f[std::size_t(q)], after), kFar));
          }
          continue;
        }
        for (std::int64_t q = 0; q < n; ++q) f[std::size_t(q)] = d2[std::size_t(base + q * s)];
        distanceTransform1d(f, out, v, z);
        for (std::int64_t q = 0; q < n; ++q) d2[std::size_t(base + q * s)] = float(std::min(out[std::size_t(q)], kFar));
      }
  }
}

}  // namespace hullmap::hulls::detail

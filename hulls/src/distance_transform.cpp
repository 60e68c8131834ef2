// Felzenszwalb and Huttenlocher's exact squared Euclidean distance transform (Theory of Computing
// 8, 2012), one pass per axis.
#include "hullmap/hulls/detail/distance_transform.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "hullmap/core/detail/cpu_clones.hpp"

namespace hullmap::hulls::detail {
namespace {

/// Squared Euclidean distance transform along one line (Felzenszwalb and Huttenlocher 2012) in
/// integers: `f` holds squared distances (integers) or kFar, at least one of them finite; `out`
/// gets the lower envelope of the parabolas (q - r)^2 + f[r] of the finite ones. The parabolas'
/// crossings are kept as fractions num / den (den > 0) and compared by cross-multiplication in
/// `Wide` (128 bits in general; 64 when the box is narrower than 2^14 cells on every axis, so that
/// heights stay below 2^30 and denominators below 2^15), so no division rounds; the envelope, and its
/// values at the integers, are exact.
template <class Wide>
void distanceTransform1d(const std::vector<double>& f, std::vector<double>& out, std::vector<std::int64_t>& v,
                         std::vector<std::int64_t>& num, std::vector<std::int64_t>& den) {
  constexpr double kFar = 1e20;
  const std::int64_t n = std::int64_t(f.size());
  v.resize(std::size_t(n));
  num.resize(std::size_t(n));
  den.resize(std::size_t(n));
  // The crossing of the parabolas from q and r (r < q): ((f[q] + q^2) - (f[r] + r^2)) / (2q - 2r).
  const auto height = [&](std::int64_t q) { return std::int64_t(f[std::size_t(q)]) + q * q; };
  std::int64_t k = -1;  // the envelope's parabolas v[0..k]; parabola k starts at num[k] / den[k] (k > 0)
  for (std::int64_t q = 0; q < n; ++q) {
    if (f[std::size_t(q)] >= kFar) continue;
    std::int64_t a = 0, b = 1;
    while (k >= 0) {
      const std::int64_t r = v[std::size_t(k)];
      a = height(q) - height(r);
      b = 2 * (q - r);
      // Parabola k is hidden when the new one crosses it at or before where k starts.
      if (k > 0 && Wide(a) * den[std::size_t(k)] <= Wide(num[std::size_t(k)]) * b) {
        --k;
        continue;
      }
      break;
    }
    ++k;
    v[std::size_t(k)] = q;
    num[std::size_t(k)] = a;
    den[std::size_t(k)] = b;
  }
  out.resize(std::size_t(n));
  std::int64_t j = 0;
  for (std::int64_t q = 0; q < n; ++q) {
    // The next parabola starts before q: num / den < q.
    while (j < k && num[std::size_t(j) + 1] < Wide(q) * den[std::size_t(j) + 1]) ++j;
    const std::int64_t r = v[std::size_t(j)], d = q - r;
    out[std::size_t(q)] = double(d * d) + f[std::size_t(r)];
  }
}

}  // namespace

/// Exact squared Euclidean distance transform in place (Felzenszwalb-Huttenlocher, one pass per
/// axis) over a box of `dims` cells stored x fastest: `d2` holds 0 at the sites and a large value
/// elsewhere (kept below 1e20; lines holding only 0 and 1e20 take a faster, exactly equal path).
void exactTransform(std::vector<float>& d2, const std::array<std::int64_t, 3>& dims,
                    const std::vector<std::pair<std::int64_t, std::int64_t>>* wanted) {
  constexpr double kFar = 1e20;
  const std::array<std::int64_t, 3> stride{1, dims[0], dims[0] * dims[1]};
  std::vector<double> f, out;
  std::vector<std::int64_t> v, num, den;
  constexpr std::int64_t kNarrow = std::int64_t(1) << 14;
  const bool narrow = dims[0] < kNarrow && dims[1] < kNarrow && dims[2] < kNarrow;
  for (int axis = 0; axis < 3; ++axis) {
    const std::size_t a = std::size_t(axis), b = std::size_t((axis + 1) % 3), c = std::size_t((axis + 2) % 3);
    const std::int64_t n = dims[a], s = stride[a];
    f.resize(std::size_t(n));
    // Every line along `axis`: its first cell runs over the other two axes.
    for (std::int64_t ib = 0; ib < dims[b]; ++ib)
      for (std::int64_t ic = 0; ic < dims[c]; ++ic) {
        const std::int64_t base = ib * stride[b] + ic * stride[c];
        // The last pass runs along z over the columns (i, j) = (ib, ic): one with no wanted cell is
        // left as it is.
        if (axis == 2 && wanted) {
          const auto& range = (*wanted)[std::size_t(ic * dims[0] + ib)];
          if (range.second < range.first) continue;
        }
        // A line holding no finite value stays as it is (every value kFar after the transform too),
        // and on the first pass, where the values are 0 (sites) or kFar, the transform is the
        // squared distance to the nearest site along the line: two sweeps give the same exact
        // integers as the lower envelope of parabolas. Later passes copy the line as they look.
        bool any = false;
        if (axis == 0) {
          bool binary = true;
          for (std::int64_t q = 0; q < n; ++q) {
            const float x = d2[std::size_t(base + q * s)];
            any = any || x < float(kFar);
            binary = binary && (x == 0.0f || x >= float(kFar));
          }
          if (!any) continue;
          if (binary) {
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
        } else {
          for (std::int64_t q = 0; q < n; ++q) {
            const float x = d2[std::size_t(base + q * s)];
            any = any || x < float(kFar);
            f[std::size_t(q)] = x;
          }
          if (!any) continue;
        }
        if (narrow)
          distanceTransform1d<std::int64_t>(f, out, v, num, den);
        else
          distanceTransform1d<__int128>(f, out, v, num, den);
        for (std::int64_t q = 0; q < n; ++q) d2[std::size_t(base + q * s)] = float(std::min(out[std::size_t(q)], kFar));
      }
  }
}

// Its passes are min-plus sweeps over whole rows, which AVX2 does eight floats at a time.
HULLMAP_AVX2_CLONES void boundedTransform(std::vector<float>& d2, const std::array<std::int64_t, 3>& dims,
                                          std::int64_t cap2) {
  constexpr float kFar = 1e20f;
  std::int64_t reach = 0;
  while ((reach + 1) * (reach + 1) <= cap2) ++reach;
  const std::int64_t nx = dims[0], ny = dims[1], nz = dims[2];
  // x: the squared distance to the nearest site of the row, when it is at most `reach` cells away
  // (the input is 0 at the sites and kFar elsewhere, so the sites stay recognisable in place).
  for (std::int64_t row = 0; row < ny * nz; ++row) {
    float* line = d2.data() + row * nx;
    std::int64_t site = -reach - 1;  // the nearest site at or before i
    for (std::int64_t i = 0; i < nx; ++i) {
      if (line[i] == 0.0f) {
        site = i;
      } else if (i - site <= reach) {
        line[i] = float((i - site) * (i - site));
      }
    }
    if (site < 0) continue;  // no site in the row
    site = nx + reach + 1;   // the nearest site at or after i
    for (std::int64_t i = nx - 1; i >= 0; --i) {
      if (line[i] == 0.0f) {
        site = i;
      } else if (site - i <= reach) {
        line[i] = std::min(line[i], float((site - i) * (site - i)));
      }
    }
  }
  // y, then z: the least over the rows `o` cells away of their value plus o^2 (kFar + o^2 is kFar).
  const auto pass = [&](std::int64_t lines, std::int64_t count, std::int64_t stride, std::int64_t blocks,
                        std::int64_t block_stride) {
    std::vector<float> in(std::size_t(lines * stride));
    for (std::int64_t b = 0; b < blocks; ++b) {
      float* base = d2.data() + b * block_stride;
      std::copy(base, base + lines * stride, in.begin());
      for (std::int64_t q = 0; q < lines; ++q) {
        float* out = base + q * stride;
        for (std::int64_t o = 1; o <= reach; ++o) {
          const float w = float(o * o);
          for (const std::int64_t from : {q - o, q + o}) {
            if (from < 0 || from >= lines) continue;
            const float* src = in.data() + from * stride;
            for (std::int64_t x = 0; x < count; ++x) out[x] = std::min(out[x], src[x] + w);
          }
        }
      }
    }
  };
  pass(ny, nx, nx, nz, nx * ny);     // per z plane: its ny rows of nx cells
  pass(nz, nx * ny, nx * ny, 1, 0);  // the whole box: nz planes of nx * ny cells
  const float cap = float(cap2);
  for (float& x : d2)
    if (x > cap) x = kFar;
}

}  // namespace hullmap::hulls::detail

// The ray walk of insertScan (scan_insertion.cpp): each thread walks its share of the rays with
// octomap's computeRayKeys arithmetic, four rays at a time in SSE2 lanes, and sets the keys' bits in
// its own 8x8x8 bit bricks (BrickSet: allocated when first marked, found through a grid over the
// scan's box, or an open-addressing index outside it).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#if defined(__SSE2__) && defined(__x86_64__)
#include <emmintrin.h>
#endif

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "hullmap/mapper/detail/octree_keys.hpp"

namespace hullmap::mapper {
namespace detail {

namespace {

std::uint64_t spreadBits(std::uint64_t v) {
  v &= 0xFFFF;
  v = (v | (v << 16)) & 0x0000FF0000FFull;
  v = (v | (v << 8)) & 0x00F00F00F00Full;
  v = (v | (v << 4)) & 0x0C30C30C30C3ull;
  v = (v | (v << 2)) & 0x249249249249ull;
  return v;
}

std::uint64_t compactBits(std::uint64_t v) {
  v &= 0x249249249249ull;
  v = (v | (v >> 2)) & 0x0C30C30C30C3ull;
  v = (v | (v >> 4)) & 0x00F00F00F00Full;
  v = (v | (v >> 8)) & 0x0000FF0000FFull;
  v = (v | (v >> 16)) & 0xFFFF;
  return v;
}

}  // namespace

std::uint64_t mortonCode(std::uint64_t packed) {
  return spreadBits(packed) | (spreadBits(packed >> 16) << 1) | (spreadBits(packed >> 32) << 2);
}

octomap::OcTreeKey mortonKey(std::uint64_t morton) {
  return octomap::OcTreeKey(static_cast<octomap::key_type>(compactBits(morton)),
                            static_cast<octomap::key_type>(compactBits(morton >> 1)),
                            static_cast<octomap::key_type>(compactBits(morton >> 2)));
}

BrickSet::BrickSet(const int lo[3], const int dims[3], bool allocate_grid) {
  for (int i = 0; i < 3; ++i) {
    lo_[i] = lo[i];
    dims_[i] = dims[i];
    grid_lo_[i] = static_cast<unsigned>(lo[i]) * 8;
    grid_extent_[i] = static_cast<unsigned>(dims[i]) * 8;
  }
  grid_.assign(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2], kNoBrick);
  // Cell (bx, by, bz) of the grid is (bz * dims1 + by) * dims0 + bx; inside a brick, key bits
  // interleave (kSpread).
  const std::uint32_t stride[3] = {512, 512 * static_cast<std::uint32_t>(dims[0]),
                                   512 * static_cast<std::uint32_t>(dims[0]) * static_cast<std::uint32_t>(dims[1])};
  for (int a = 0; a < 3; ++a) {
    axis_code_[a].resize(grid_extent_[a]);
    for (std::uint32_t r = 0; r < grid_extent_[a]; ++r) axis_code_[a][r] = (r >> 3) * stride[a] + (kSpread[r & 7] << a);
  }
  if (allocate_grid) {
    free_.resize(grid_.size() * kWords);
    occupied_.resize(grid_.size() * kWords);
    coords_.reserve(grid_.size());
    for (std::size_t cell = 0; cell < grid_.size(); ++cell) {
      const std::uint64_t x = lo_[0] + cell % dims_[0];
      const std::uint64_t y = lo_[1] + (cell / dims_[0]) % dims_[1];
      const std::uint64_t z = lo_[2] + cell / (static_cast<std::size_t>(dims_[0]) * dims_[1]);
      grid_[cell] = static_cast<std::uint32_t>(cell * kWords);
      coords_.push_back(x | y << 13 | z << 26);
    }
    grid_allocated_ = true;
  }
}

std::uint32_t BrickSet::addBrick(std::uint64_t coord) {
  const std::uint32_t index = static_cast<std::uint32_t>(coords_.size());
  free_.resize(free_.size() + kWords);
  occupied_.resize(occupied_.size() + kWords);
  coords_.push_back(coord);
  return index;
}

std::uint32_t BrickSet::gridBrick(std::size_t cell) {
  if (grid_[cell] == kNoBrick) {
    const std::uint64_t x = lo_[0] + cell % dims_[0];
    const std::uint64_t y = lo_[1] + (cell / dims_[0]) % dims_[1];
    const std::uint64_t z = lo_[2] + cell / (static_cast<std::size_t>(dims_[0]) * dims_[1]);
    grid_[cell] = addBrick(x | y << 13 | z << 26) * kWords;
  }
  return grid_[cell] / kWords;
}

std::uint32_t BrickSet::find(std::uint64_t coord) {
  const unsigned x = static_cast<unsigned>(coord & 0x1FFF) - lo_[0];
  const unsigned y = static_cast<unsigned>((coord >> 13) & 0x1FFF) - lo_[1];
  const unsigned z = static_cast<unsigned>(coord >> 26) - lo_[2];
  if (x < static_cast<unsigned>(dims_[0]) && y < static_cast<unsigned>(dims_[1]) &&
      z < static_cast<unsigned>(dims_[2])) {
    return gridBrick((static_cast<std::size_t>(z) * dims_[1] + y) * dims_[0] + x);
  }
  if (2 * (hashed_ + 1) > slots_.size()) {
    const std::size_t capacity = std::max<std::size_t>(4096, 2 * slots_.size());
    std::vector<std::uint64_t> old_slots;
    std::vector<std::uint32_t> old_index;
    old_slots.swap(slots_);
    old_index.swap(slot_index_);
    slots_.assign(capacity, 0);
    slot_index_.assign(capacity, 0);
    shift_ = 64 - static_cast<unsigned>(std::log2(static_cast<double>(capacity)) + 0.5);
    for (std::size_t i = 0; i < old_slots.size(); ++i) {
      if (old_slots[i] == 0) continue;
      std::size_t s = static_cast<std::size_t>(((old_slots[i] - 1) * 0x9E3779B97F4A7C15ull) >> shift_);
      while (slots_[s] != 0) s = (s + 1) & (capacity - 1);
      slots_[s] = old_slots[i];
      slot_index_[s] = old_index[i];
    }
  }
  std::size_t s = static_cast<std::size_t>((coord * 0x9E3779B97F4A7C15ull) >> shift_);
  while (slots_[s] != 0) {
    if (slots_[s] == coord + 1) return slot_index_[s];
    s = (s + 1) & (slots_.size() - 1);
  }
  slots_[s] = coord + 1;
  slot_index_[s] = addBrick(coord);
  ++hashed_;
  return slot_index_[s];
}

void BrickSet::markFree(const std::uint64_t* keys, std::size_t count) {
  const std::uint32_t* code0 = axis_code_[0].data();
  const std::uint32_t* code1 = axis_code_[1].data();
  const std::uint32_t* code2 = axis_code_[2].data();
  std::uint64_t* free = free_.data();
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint64_t packed = keys[i];
    const unsigned r0 = static_cast<unsigned>(packed & 0xFFFF);
    const unsigned r1 = static_cast<unsigned>((packed >> 16) & 0xFFFF);
    const unsigned r2 = static_cast<unsigned>(packed >> 32);
    if ((r0 < grid_extent_[0]) & (r1 < grid_extent_[1]) & (r2 < grid_extent_[2])) {
      const std::uint32_t code = code0[r0] + code1[r1] + code2[r2];
      if (grid_allocated_) {
        free[code >> 6] |= std::uint64_t{1} << (code & 63);
        continue;
      }
      std::uint32_t word = grid_[code >> 9];
      if (word == kNoBrick) {
        word = gridBrick(code >> 9) * kWords;
        free = free_.data();
      }
      free[word + ((code >> 6) & 7)] |= std::uint64_t{1} << (code & 63);
    } else if ((packed >> 48) == 0) {
      const int k[3] = {static_cast<int>((r0 + grid_lo_[0]) & 0xFFFF), static_cast<int>((r1 + grid_lo_[1]) & 0xFFFF),
                        static_cast<int>((r2 + grid_lo_[2]) & 0xFFFF)};
      mark(k, false);
      free = free_.data();
    }
  }
}

bool KeyCaster::startRay(const octomap::point3d& origin, const int key_origin[3], const octomap::point3d& end,
                         const int key_end[3], RayStart& start) const {
  // OcTreeBaseImpl::computeRayKeys (octomap 1.9) up to its loop, statement for statement.
  if (key_origin[0] == key_end[0] && key_origin[1] == key_end[1] && key_origin[2] == key_end[2]) return false;

  octomap::point3d direction = (end - origin);
  const float length = static_cast<float>(direction.norm());
  direction /= length;

  for (int i = 0; i < 3; ++i) {
    if (direction(i) > 0.0)
      start.step[i] = 1;
    else if (direction(i) < 0.0)
      start.step[i] = -1;
    else
      start.step[i] = 0;

    if (start.step[i] != 0) {
      double voxel_border = (static_cast<double>(key_origin[i] - max_val_) + 0.5) * resolution_;
      voxel_border += static_cast<float>(start.step[i] * resolution_ * 0.5);
      start.t_max[i] = (voxel_border - origin(i)) / direction(i);
      start.t_delta[i] = resolution_ / std::fabs(direction(i));
    } else {
      start.t_max[i] = std::numeric_limits<double>::max();
      start.t_delta[i] = std::numeric_limits<double>::max();
    }
  }
  start.length = length;
  return true;
}

namespace {

// Steps walked between two passes marking their keys (16 KiB of keys: stays in L1).
constexpr int kSteps = 512;

}  // namespace

#if defined(__SSE2__) && defined(__x86_64__)

namespace {

// Two rays per SSE2 register. Keys are packed k0 | k1 << 16 | k2 << 32 in 16-bit lanes, so that
// stepping past the edge of octomap's 16-bit keys wraps as octomap's does. A lane without a ray
// never steps or stops and holds a key with bits 48-63 set (no key).
struct LaneGroup {
  __m128d t0, t1, t2, d0, d1, d2, limit;
  __m128i key, key_end, step0, step1, step2;  // step_i: step[i] in key i's 16-bit lane
};

// One lane's ray, or an idle lane's values.
struct LaneRay {
  double t[3] = {0.0, 0.0, 0.0};
  double delta[3] = {0.0, 0.0, 0.0};
  double limit = std::numeric_limits<double>::infinity();
  std::uint64_t key = std::uint64_t{0xFFFF} << 48;
  std::uint64_t key_end = 0;
  std::uint64_t step[3] = {0, 0, 0};
};

inline __m128d withLane(__m128d v, int lane, double x) {
  return lane == 0 ? _mm_move_sd(v, _mm_set_sd(x)) : _mm_unpacklo_pd(v, _mm_set_sd(x));
}

inline __m128i withLane(__m128i v, int lane, std::uint64_t x) {
  const __m128i s = _mm_cvtsi64_si128(static_cast<long long>(x));
  return lane == 0 ? _mm_castpd_si128(_mm_move_sd(_mm_castsi128_pd(v), _mm_castsi128_pd(s))) : _mm_unpacklo_epi64(v, s);
}

inline void setLane(LaneGroup& g, int lane, const LaneRay& r) {
  g.t0 = withLane(g.t0, lane, r.t[0]);
  g.t1 = withLane(g.t1, lane, r.t[1]);
  g.t2 = withLane(g.t2, lane, r.t[2]);
  g.d0 = withLane(g.d0, lane, r.delta[0]);
  g.d1 = withLane(g.d1, lane, r.delta[1]);
  g.d2 = withLane(g.d2, lane, r.delta[2]);
  g.limit = withLane(g.limit, lane, r.limit);
  g.key = withLane(g.key, lane, r.key);
  g.key_end = withLane(g.key_end, lane, r.key_end);
  g.step0 = withLane(g.step0, lane, r.step[0]);
  g.step1 = withLane(g.step1, lane, r.step[1]);
  g.step2 = withLane(g.step2, lane, r.step[2]);
}

// One step of both lanes: the stepped keys, less `lo`, go to keys[0..1] (all ones where a ray
// stopped). Returns the lanes whose ray stopped (movemask bits).
inline int stepLanes(LaneGroup& g, __m128i lo, std::uint64_t* keys) {
  const __m128d lt01 = _mm_cmplt_pd(g.t0, g.t1);
  const __m128d x = _mm_and_pd(lt01, _mm_cmplt_pd(g.t0, g.t2));
  const __m128d y = _mm_andnot_pd(lt01, _mm_cmplt_pd(g.t1, g.t2));
  const __m128d z = _mm_andnot_pd(_mm_or_pd(x, y), _mm_castsi128_pd(_mm_set1_epi32(-1)));
  g.t0 = _mm_add_pd(g.t0, _mm_and_pd(g.d0, x));
  g.t1 = _mm_add_pd(g.t1, _mm_and_pd(g.d1, y));
  g.t2 = _mm_add_pd(g.t2, _mm_and_pd(g.d2, z));
  const __m128i steps = _mm_or_si128(
      _mm_or_si128(_mm_and_si128(g.step0, _mm_castpd_si128(x)), _mm_and_si128(g.step1, _mm_castpd_si128(y))),
      _mm_and_si128(g.step2, _mm_castpd_si128(z)));
  g.key = _mm_add_epi16(g.key, steps);
  const __m128i same = _mm_cmpeq_epi32(g.key, g.key_end);
  const __m128i at_end = _mm_and_si128(same, _mm_shuffle_epi32(same, _MM_SHUFFLE(2, 3, 0, 1)));
  const __m128d past = _mm_cmpgt_pd(_mm_min_pd(_mm_min_pd(g.t0, g.t1), g.t2), g.limit);
  const __m128i stop = _mm_or_si128(at_end, _mm_castpd_si128(past));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(keys), _mm_or_si128(_mm_sub_epi16(g.key, lo), stop));
  return _mm_movemask_pd(_mm_castsi128_pd(stop));
}

}  // namespace

// The walk of computeRayKeys, four rays at a time and without branches: which axis steps next is
// as unpredictable as a ray's direction, and one ray's walk is a chain of dependent additions;
// four independent chains in vector lanes keep the core busy. Each step is octomap's:
//   dim = t0 < t1 ? (t0 < t2 ? 0 : 2) : (t1 < t2 ? 1 : 2); key[dim] += step[dim]; t[dim] += delta[dim];
//   stop if key == key_end, or if min(t) > length; else the key is free.
// An axis that does not step adds +0.0, which leaves its t unchanged. The keys go to a buffer that
// a scalar pass then marks.
void KeyCaster::castRays(const octomap::point3d& origin, const int key_origin[3], const Ray* rays, std::size_t count,
                         BrickSet& out) const {
  std::size_t next = 0;
  bool any_cast = false;
  int active = 0;
  const std::uint64_t packed_origin = pack(key_origin);
  // The next ray that has free keys, or an idle lane.
  auto nextRay = [&] {
    LaneRay lane;
    RayStart start;
    while (next < count) {
      const Ray& ray = rays[next++];
      if (!ray.casts || !startRay(origin, key_origin, ray.end, ray.key_end, start)) continue;
      for (int a = 0; a < 3; ++a) {
        lane.t[a] = start.t_max[a];
        lane.delta[a] = start.t_delta[a];
        lane.step[a] = static_cast<std::uint64_t>(start.step[a] & 0xFFFF) << (16 * a);
      }
      lane.limit = start.length;
      lane.key = packed_origin;
      lane.key_end = pack(ray.key_end);
      any_cast = true;
      ++active;
      break;
    }
    return lane;
  };
  LaneGroup g0, g1;
  const LaneRay r00 = nextRay(), r01 = nextRay(), r10 = nextRay(), r11 = nextRay();
  g0.t0 = _mm_set_pd(r01.t[0], r00.t[0]);
  g0.t1 = _mm_set_pd(r01.t[1], r00.t[1]);
  g0.t2 = _mm_set_pd(r01.t[2], r00.t[2]);
  g0.d0 = _mm_set_pd(r01.delta[0], r00.delta[0]);
  g0.d1 = _mm_set_pd(r01.delta[1], r00.delta[1]);
  g0.d2 = _mm_set_pd(r01.delta[2], r00.delta[2]);
  g0.limit = _mm_set_pd(r01.limit, r00.limit);
  g0.key = _mm_set_epi64x(static_cast<long long>(r01.key), static_cast<long long>(r00.key));
  g0.key_end = _mm_set_epi64x(static_cast<long long>(r01.key_end), static_cast<long long>(r00.key_end));
  g0.step0 = _mm_set_epi64x(static_cast<long long>(r01.step[0]), static_cast<long long>(r00.step[0]));
  g0.step1 = _mm_set_epi64x(static_cast<long long>(r01.step[1]), static_cast<long long>(r00.step[1]));
  g0.step2 = _mm_set_epi64x(static_cast<long long>(r01.step[2]), static_cast<long long>(r00.step[2]));
  g1 = g0;
  setLane(g1, 0, r10);
  setLane(g1, 1, r11);

  const unsigned* grid_lo = out.gridLo();
  const __m128i lo = _mm_set1_epi64x(static_cast<long long>(grid_lo[0] | static_cast<std::uint64_t>(grid_lo[1]) << 16 |
                                                            static_cast<std::uint64_t>(grid_lo[2]) << 32));
  alignas(16) std::uint64_t keys[kSteps * 4];
  while (active > 0) {
    int steps = kSteps;
    for (int n = 0; n < kSteps; ++n) {
      const int stop0 = stepLanes(g0, lo, &keys[4 * n]);
      const int stop1 = stepLanes(g1, lo, &keys[4 * n + 2]);
      if ((stop0 | stop1) != 0) {
        active -= static_cast<int>(bitCount(static_cast<unsigned>(stop0 | stop1 << 2)));
        if (stop0 & 1) setLane(g0, 0, nextRay());
        if (stop0 & 2) setLane(g0, 1, nextRay());
        if (stop1 & 1) setLane(g1, 0, nextRay());
        if (stop1 & 2) setLane(g1, 1, nextRay());
        if (active == 0) {
          steps = n + 1;
          break;
        }
      }
    }
    out.markFree(keys, static_cast<std::size_t>(steps) * 4);
  }
  if (any_cast) out.mark(key_origin, false);
}

#else

// computeRayKeys' walk, one ray at a time.
void KeyCaster::castRays(const octomap::point3d& origin, const int key_origin[3], const Ray* rays, std::size_t count,
                         BrickSet& out) const {
  const int lo[3] = {static_cast<int>(out.gridLo()[0]), static_cast<int>(out.gridLo()[1]),
                     static_cast<int>(out.gridLo()[2])};
  std::uint64_t keys[kSteps] = {};
  int n = 0;
  bool any_cast = false;
  for (std::size_t r = 0; r < count; ++r) {
    RayStart start;
    if (!rays[r].casts || !startRay(origin, key_origin, rays[r].end, rays[r].key_end, start)) continue;
    any_cast = true;
    double t[3] = {start.t_max[0], start.t_max[1], start.t_max[2]};
    int key[3] = {key_origin[0], key_origin[1], key_origin[2]};
    const int* key_end = rays[r].key_end;
    for (;;) {
      const int dim = t[0] < t[1] ? (t[0] < t[2] ? 0 : 2) : (t[1] < t[2] ? 1 : 2);
      key[dim] = (key[dim] + start.step[dim]) & 0xFFFF;
      t[dim] += start.t_delta[dim];
      if (key[0] == key_end[0] && key[1] == key_end[1] && key[2] == key_end[2]) break;
      if (std::min(std::min(t[0], t[1]), t[2]) > start.length) break;
      const int rel[3] = {(key[0] - lo[0]) & 0xFFFF, (key[1] - lo[1]) & 0xFFFF, (key[2] - lo[2]) & 0xFFFF};
      keys[n++] = pack(rel);
      if (n == kSteps) {
        out.markFree(keys, kSteps);
        n = 0;
      }
    }
  }
  out.markFree(keys, static_cast<std::size_t>(n));
  if (any_cast) out.mark(key_origin, false);
}

#endif

namespace {

// Each thread's grid costs 4 bytes a cell to clear: only for boxes of at most 16 MiB that are
// not much larger than the work.
constexpr std::size_t kMaxGridCells = std::size_t{1} << 22;
// A brick costs 128 bytes: boxes allocated whole up to 8 MiB, and 32 bytes a point.
constexpr std::size_t kMaxAllocatedCells = std::size_t{1} << 16;

}  // namespace

// The rays from origin to each point, walked into one BrickSet per thread.
ScanUpdate computeScanUpdate(const octomap::OcTree& tree, const io::Points& points, const io::Point& origin_d,
                             double max_range) {
  const KeyCaster caster(tree);
  const octomap::point3d origin(static_cast<float>(origin_d.x()), static_cast<float>(origin_d.y()),
                                static_cast<float>(origin_d.z()));
  auto toPoint3d = [](const io::Point& q) {
    return octomap::point3d(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()));
  };
  // Where each ray ends, as insertPointCloud decides (the measured point, or cut at max_range).
  auto rayEnd = [&](const octomap::point3d& p, bool& endpoint) {
    endpoint = max_range < 0.0 || (p - origin).norm() <= max_range;
    if (endpoint) return p;
    const octomap::point3d direction = (p - origin).normalized();
    return origin + direction * static_cast<float>(max_range);
  };

  // Each ray's end and its key, and the box of the ends' bricks: the grid's box (a walk stays
  // between its ends' keys, give or take a voxel; a key outside the grid goes to the hash).
  struct Box {
    int lo[3] = {1 << 30, 1 << 30, 1 << 30};
    int hi[3] = {-1, -1, -1};
  };
  tbb::enumerable_thread_specific<Box> boxes;
  int origin_key[3] = {0, 0, 0};
  const bool origin_ok = caster.coordToKeyChecked(origin, origin_key);
  std::vector<KeyCaster::Ray> rays(points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 4096),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      Box& box = boxes.local();
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        bool endpoint;
                        KeyCaster::Ray& ray = rays[i];
                        ray.end = rayEnd(toPoint3d(points[i]), endpoint);
                        // When `endpoint`, the end is the point itself: its key is the occupied one.
                        if (!caster.coordToKeyChecked(ray.end, ray.key_end)) continue;
                        ray.casts = origin_ok;
                        ray.occupied = endpoint;
                        for (int a = 0; a < 3; ++a) {
                          box.lo[a] = std::min(box.lo[a], ray.key_end[a] >> 3);
                          box.hi[a] = std::max(box.hi[a], ray.key_end[a] >> 3);
                        }
                      }
                    });
  int lo[3] = {0, 0, 0}, dims[3] = {0, 0, 0};
  if (origin_ok) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = origin_key[a] >> 3;
      int hi = lo[a];
      for (const Box& box : boxes) {
        lo[a] = std::min(lo[a], box.lo[a]);
        hi = std::max(hi, box.hi[a]);
      }
      lo[a] = std::max(0, lo[a] - 1);
      dims[a] = std::min(8191, hi + 1) - lo[a] + 1;
    }
    const std::size_t box_cells = static_cast<std::size_t>(dims[0]) * dims[1] * dims[2];
    if (box_cells > kMaxGridCells || box_cells > 1024 * points.size() + 65536) dims[0] = dims[1] = dims[2] = 0;
  }

  // Small boxes are allocated whole: no lookup of the grid per key.
  const std::size_t cells = static_cast<std::size_t>(dims[0]) * dims[1] * dims[2];
  const bool allocate_grid = cells > 0 && cells <= std::min(kMaxAllocatedCells, points.size() / 4);
  tbb::enumerable_thread_specific<BrickSet> local([&] { return BrickSet(lo, dims, allocate_grid); });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 1024),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      BrickSet& set = local.local();
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        if (rays[i].occupied) set.mark(rays[i].key_end, true);
                      }
                      caster.castRays(origin, origin_key, rays.data() + range.begin(), range.size(), set);
                    });

  std::vector<BrickSet> sets;
  for (BrickSet& set : local) sets.push_back(std::move(set));
  return ScanUpdate(std::move(sets));
}

}  // namespace detail
}  // namespace hullmap::mapper

// ClusterSplitter's split: parts that fail their check are cut in two (at the worst cell, or the
// best cut of the box), stray cells shed first, until every part passes; then the merge.
#include "cluster_splitter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <numeric>
#include <optional>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/parallel_for_each.h>
#include <Eigen/Eigenvalues>

#include "hullmap/hulls/detail/distance_transform.hpp"

namespace hullmap::hulls::detail {

std::vector<std::pair<Members, Check>> ClusterSplitter::run() {
  Members all(cells_.size());
  std::iota(all.begin(), all.end(), 0u);
  if (fill_enclosed_) findEnclosed(all);
  std::vector<std::pair<Members, Check>> done;
  findStrays();
  // Parts to check, with their hulls when the split already built them. The halves of a split
  // are independent, so they are checked in parallel; the order in which parts are done does not
  // matter (merge orders them by their first cell).
  using Work = std::pair<Members, std::optional<FacetHull>>;
  std::vector<Work> start;
  start.emplace_back(std::move(all), std::nullopt);
  std::mutex done_mutex;
  tbb::parallel_for_each(start.begin(), start.end(), [&](Work& work, tbb::feeder<Work>& feeder) {
    Members& part = work.first;
    Check check = checkPart(part, true, work.second ? &*work.second : nullptr);
    // Stray cells are shed before a cut (see shedStrays), each a part of its own for now (the
    // merge below may join them to a part they pass with).
    const auto shed = shedStrays(part, check);
    if (!shed.empty()) {
      const std::lock_guard<std::mutex> lock(done_mutex);
      for (const auto i : shed) {
        Check single;
        single.hull = facetHull({cells_[i]});
        done.emplace_back(Members{i}, std::move(single));
      }
    }
    if (check.ok || part.size() == 1) {
      const std::lock_guard<std::mutex> lock(done_mutex);
      done.emplace_back(std::move(part), std::move(check));
      return;
    }
    Halves halves = split(part, check);
    feeder.add(Work(std::move(halves.left), std::move(halves.left_hull)));
    feeder.add(Work(std::move(halves.right), std::move(halves.right_hull)));
  });
  auto parts = absorb(merge(std::move(done)));
  bool changed = false;
  parts = absorbIntoBoxes(std::move(parts), changed);
  if (changed) parts = absorb(merge(std::move(parts)));
  // Last, with face_holes, the pieces a cut left of a solid part with sparse faces are merged back
  // (parts of at least kFaceMergeMinVoxels voxels: a stray or a clump cut off before stays off).
  return face_holes_ ? absorb(merge(std::move(parts), true)) : parts;
}

void ClusterSplitter::findStrays() {
  clump_.assign(cells_.size(), kNoClump);
  for (const auto& c : cells_)
    for (const auto x : c)
      if (x < -(std::int64_t(1) << 19) || x >= (std::int64_t(1) << 19)) return;
  const auto pack = [](const LatticePoint& c) {
    return (std::uint64_t(c[0] + (1 << 20)) << 42) | (std::uint64_t(c[1] + (1 << 20)) << 21) |
           std::uint64_t(c[2] + (1 << 20));
  };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> occupied;
  occupied.reserve(cells_.size());
  for (std::uint32_t i = 0; i < cells_.size(); ++i) occupied.emplace_back(pack(cells_[i]), i);
  std::sort(occupied.begin(), occupied.end());
  // The cells within T of cell i, into `out`; false (out incomplete) once more than kStrayClump.
  const auto neighbours = [&](std::uint32_t i, std::vector<std::uint32_t>& out) {
    out.clear();
    const LatticePoint& c = cells_[i];
    for (const auto& [o, o2] : ball_) {
      if (double(o2) > t2_) break;  // ball_ is sorted by distance
      if (o2 == 0.0f) continue;
      const std::uint64_t key = pack({c[0] + o[0], c[1] + o[1], c[2] + o[2]});
      const auto it = std::lower_bound(occupied.begin(), occupied.end(), std::make_pair(key, std::uint32_t(0)));
      if (it == occupied.end() || it->first != key) continue;
      out.push_back(it->second);
      if (out.size() >= kStrayClump) return false;
    }
    return true;
  };
  std::vector<std::uint32_t> clump, around;
  std::size_t in_small = 0;  // cells in clumps of at most kStrayClump
  std::vector<char> in_pair_or_more(cells_.size(), 0);
  std::vector<char> big(cells_.size(), 0);  // known to lie in a clump of more than kStrayClump
  for (std::uint32_t i = 0; i < cells_.size(); ++i) {
    if (clump_[i] != kNoClump || big[i]) continue;
    // Grow i's clump breadth first; give up once it holds more than kStrayClump cells.
    clump.assign(1, i);
    bool small = true;
    for (std::size_t next = 0; next < clump.size() && small; ++next) {
      small = neighbours(clump[next], around);
      for (const auto n : around)
        if (std::find(clump.begin(), clump.end(), n) == clump.end()) clump.push_back(n);
      small = small && clump.size() <= kStrayClump;
    }
    if (!small) {
      // Every cell reached is linked to i, so its clump is the same big one: no search from it.
      for (const auto m : clump) big[m] = 1;
      continue;
    }
    const std::uint32_t id = *std::min_element(clump.begin(), clump.end());
    for (const auto m : clump) clump_[m] = id;
    in_small += clump.size();
    if (clump.size() > 1)
      for (const auto m : clump) in_pair_or_more[m] = 1;
  }
  // Where small clumps are the surface's own sampling (a sparse map: a fifth of the cells or more
  // lie in them) rather than noise off it (a dense one: 2 % or less), only lone cells are strays.
  if (double(in_small) <= kStrayShare * double(cells_.size())) return;
  for (std::size_t i = 0; i < cells_.size(); ++i)
    if (in_pair_or_more[i]) clump_[i] = kNoClump;
}

std::vector<std::uint32_t> ClusterSplitter::shedStrays(Members& part, Check& check) const {
  if (check.ok || check.too_big || part.size() < 2 * kShedShare) return {};
  std::vector<std::uint32_t> shed;
  Members rest = part;
  Check now = check;
  const std::size_t most = std::min<std::size_t>(kShedMax, part.size() / kShedShare);
  while (!now.ok && !now.too_big && shed.size() < most) {
    // The stray cell nearest the deepest uncovered cell (ties: the first), within 2 rho of it.
    double best = 4.0 * rho2_;
    std::optional<std::uint32_t> pick;
    for (const auto i : rest) {
      if (clump_[i] == kNoClump) continue;
      const Eigen::Vector3d d =
          Eigen::Vector3d(double(cells_[i][0]) + 0.5, double(cells_[i][1]) + 0.5, double(cells_[i][2]) + 0.5) -
          now.split_point;
      if (d.squaredNorm() <= best) {
        if (!pick || d.squaredNorm() < best) pick = i;
        best = d.squaredNorm();
      }
    }
    if (!pick) return {};
    const std::uint32_t id = clump_[*pick];
    Members kept;
    kept.reserve(rest.size());
    for (const auto i : rest) (clump_[i] == id ? shed : kept).push_back(i);
    if (shed.size() > most || kept.empty()) return {};
    rest = std::move(kept);
    const std::int64_t before = now.worst_d2;
    now = checkPart(rest, true);
    if (!now.ok && now.worst_d2 > before) return {};
  }
  if (!now.ok) return {};
  part = std::move(rest);
  check = std::move(now);
  return shed;
}

ClusterSplitter::Halves ClusterSplitter::split(const Members& part, const Check& check) const {
  LatticePoint lo, hi;
  box(part, lo, hi);
  if (!check.too_big) {
    // Candidate planes (normal, point): the three axis planes and the three planes normal to the
    // principal axes through the violation, and per axis the cut whose two halves have the
    // smallest summed bounding boxes (it finds an L's junction, which a cut through the violation
    // misses). The one whose halves have the smallest summed hull volume wins.
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> planes;
    for (int a = 0; a < 3; ++a) planes.emplace_back(Eigen::Vector3d::Unit(a), check.split_point);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto i : part) mean += centre(i);
    mean /= double(part.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const auto i : part) cov += (centre(i) - mean) * (centre(i) - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> pca(cov);
    for (int a = 2; a >= 0; --a) planes.emplace_back(pca.eigenvectors().col(a), check.split_point);
    for (int a = 0; a < 3; ++a)
      if (const auto cut = bestBoxCut(part, a))
        planes.emplace_back(Eigen::Vector3d::Unit(a), Eigen::Vector3d::Constant(double(*cut)));
    // Distinct cuts (planes that cut the same way are scored once), scored in parallel; the
    // smallest summed hull volume wins, ties to the first candidate (thread-count independent).
    std::vector<std::pair<Members, Members>> cuts;
    for (const auto& [n, point] : planes) {
      Members left, right;
      for (const auto i : part) (n.dot(centre(i) - point) < 0 ? left : right).push_back(i);
      if (left.empty() || right.empty()) continue;
      if (left.front() != part.front()) std::swap(left, right);
      if (std::any_of(cuts.begin(), cuts.end(), [&](const auto& cut) { return cut.first == left; })) continue;
      cuts.emplace_back(std::move(left), std::move(right));
    }
    std::vector<FacetHull> sides(2 * cuts.size());
    tbb::parallel_for(std::size_t(0), sides.size(), [&](std::size_t k) {
      sides[k] = facetHull(gather(k % 2 ? cuts[k / 2].second : cuts[k / 2].first));
    });
    const auto volume = [&](std::size_t c) { return sides[2 * c].volume6 + sides[2 * c + 1].volume6; };
    std::optional<std::size_t> best;
    for (std::size_t c = 0; c < cuts.size(); ++c)
      if (!best || volume(c) < volume(*best)) best = c;
    if (best)
      return {std::move(cuts[*best].first), std::move(cuts[*best].second), std::move(sides[2 * *best]),
              std::move(sides[2 * *best + 1])};
  }
  // At the median of the longest axis of the box.
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (hi[std::size_t(a)] - lo[std::size_t(a)] > hi[std::size_t(axis)] - lo[std::size_t(axis)]) axis = a;
  std::vector<std::int64_t> values;
  for (const auto i : part) values.push_back(cells_[i][std::size_t(axis)]);
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(values.size() / 2), values.end());
  std::int64_t median = values[values.size() / 2];
  if (median == lo[std::size_t(axis)]) ++median;
  Members left, right;
  for (const auto i : part) (cells_[i][std::size_t(axis)] < median ? left : right).push_back(i);
  return {std::move(left), std::move(right), std::nullopt, std::nullopt};
}

std::optional<std::int64_t> ClusterSplitter::bestBoxCut(const Members& part, int axis) const {
  const std::size_t a = std::size_t(axis);
  // The part's cells by (coordinate on the axis, index): the part is sorted by index, so a stable
  // counting sort by the coordinate gives that order when the box is not much longer than the part.
  std::int64_t lo = cells_[part[0]][a], hi = lo;
  for (const auto i : part) {
    lo = std::min(lo, cells_[i][a]);
    hi = std::max(hi, cells_[i][a]);
  }
  Members order(part.size());
  if (std::uint64_t(hi - lo) < 4 * std::uint64_t(part.size())) {
    std::vector<std::uint32_t> start(std::size_t(hi - lo) + 2, 0);
    for (const auto i : part) ++start[std::size_t(cells_[i][a] - lo) + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    for (const auto i : part) order[start[std::size_t(cells_[i][a] - lo)]++] = i;
  } else {
    order = part;
    std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) {
      return std::make_pair(cells_[x][a], x) < std::make_pair(cells_[y][a], y);
    });
  }
  const std::size_t n = order.size();
  std::vector<LatticePoint> lo_prefix(n), hi_prefix(n), lo_suffix(n), hi_suffix(n);
  for (std::size_t k = 0; k < n; ++k) {
    const LatticePoint& c = cells_[order[k]];
    lo_prefix[k] = hi_prefix[k] = c;
    if (k > 0)
      for (std::size_t d = 0; d < 3; ++d) {
        lo_prefix[k][d] = std::min(lo_prefix[k - 1][d], c[d]);
        hi_prefix[k][d] = std::max(hi_prefix[k - 1][d], c[d]);
      }
  }
  for (std::size_t k = n; k-- > 0;) {
    const LatticePoint& c = cells_[order[k]];
    lo_suffix[k] = hi_suffix[k] = c;
    if (k + 1 < n)
      for (std::size_t d = 0; d < 3; ++d) {
        lo_suffix[k][d] = std::min(lo_suffix[k + 1][d], c[d]);
        hi_suffix[k][d] = std::max(hi_suffix[k + 1][d], c[d]);
      }
  }
  const auto volume = [](const LatticePoint& lo, const LatticePoint& hi) {
    return (hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
  };
  std::optional<std::int64_t> best;
  std::int64_t best_volume = 0, best_balance = 0;
  for (std::size_t k = 1; k < n; ++k) {
    if (cells_[order[k]][a] == cells_[order[k - 1]][a]) continue;
    const std::int64_t v = volume(lo_prefix[k - 1], hi_prefix[k - 1]) + volume(lo_suffix[k], hi_suffix[k]);
    const std::int64_t balance = std::abs(std::int64_t(2 * k) - std::int64_t(n));
    if (!best || v < best_volume || (v == best_volume && balance < best_balance)) {
      best = cells_[order[k]][a];
      best_volume = v;
      best_balance = balance;
    }
  }
  return best;
}

}  // namespace hullmap::hulls::detail

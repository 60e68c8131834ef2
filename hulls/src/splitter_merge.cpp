// ClusterSplitter's merge: parts are joined back, cheapest added hull volume first, while the
// union still passes its check; flat parts absorb the voxels that the cuts left beside them.
#include "cluster_splitter.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <queue>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/parallel_for_each.h>
#include <Eigen/Eigenvalues>

#include "hullmap/hulls/detail/distance_transform.hpp"

namespace hullmap::hulls::detail {
namespace {

/// Which merge node owns each cell of a box [lo, hi] (x fastest); no cells when the box holds more
/// than the limit given to allocate.
struct OwnerGrid {
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  LatticePoint lo{0, 0, 0}, hi{0, 0, 0};
  std::vector<std::uint32_t> cells;

  void allocate(std::size_t max_cells) {
    const double n = double(hi[0] - lo[0] + 1) * double(hi[1] - lo[1] + 1) * double(hi[2] - lo[2] + 1);
    if (n <= double(max_cells)) cells.assign(std::size_t(n), kNone);
  }
  std::size_t index(const LatticePoint& c) const {
    return std::size_t(((c[2] - lo[2]) * (hi[1] - lo[1] + 1) + (c[1] - lo[1])) * (hi[0] - lo[0] + 1) + (c[0] - lo[0]));
  }
  /// The owner of cell `c`; kNone outside the box.
  std::uint32_t at(const LatticePoint& c) const {
    for (std::size_t k = 0; k < 3; ++k)
      if (c[k] < lo[k] || c[k] > hi[k]) return kNone;
    return cells[index(c)];
  }
  void own(const std::vector<std::uint32_t>& members, const std::vector<LatticePoint>& all, std::uint32_t node) {
    if (cells.empty()) return;
    for (const auto i : members) cells[index(all[i])] = node;
  }
};

}  // namespace

bool ClusterSplitter::handOver(std::vector<std::pair<Members, Check>>& parts, std::size_t f, std::size_t q,
                               const Members& in, Members out) const {
  if (in.empty()) return false;
  Members both;
  both.reserve(parts[f].first.size() + in.size());
  std::merge(parts[f].first.begin(), parts[f].first.end(), in.begin(), in.end(), std::back_inserter(both));
  Check check = checkPart(both, false);
  if (!check.ok) return false;
  Check rest;
  if (!out.empty()) {
    rest = checkPart(out, false);
    if (!rest.ok) return false;
  }
  parts[f] = {std::move(both), std::move(check)};
  parts[q] = {std::move(out), std::move(rest)};
  return true;
}

std::vector<std::pair<Members, Check>> ClusterSplitter::absorb(std::vector<std::pair<Members, Check>> parts) const {
  std::vector<std::size_t> flats, others;
  for (std::size_t p = 0; p < parts.size(); ++p) (parts[p].second.flat ? flats : others).push_back(p);
  if (flats.empty()) return parts;
  std::stable_sort(flats.begin(), flats.end(),
                   [&](std::size_t a, std::size_t b) { return parts[a].first.size() > parts[b].first.size(); });
  // Then the flat fragments: a few voxels of a wall's foot or top edge that the split cut off
  // together with a stray in line with them (a part thin too, at right angles to the wall) give
  // their voxels in the wall's slab back to it, and the stray is left a part of its own.
  for (const auto f : flats) others.push_back(f);
  bool changed = false;
  for (const auto q : others) {
    LatticePoint qlo, qhi;
    box(parts[q].first, qlo, qhi);
    for (const auto f : flats) {
      if (parts[q].first.empty()) break;
      if (f == q) continue;
      // Fragments only: a part at least 1/kAbsorbRatio of the flat part's size stays as it is (a
      // slanted slab through a 3D cluster would otherwise gather its voxels into a wide thin hull).
      if (parts[q].first.size() * kAbsorbRatio > parts[f].first.size()) continue;
      LatticePoint flo, fhi;
      box(parts[f].first, flo, fhi);
      bool near = true;
      for (std::size_t k = 0; k < 3; ++k) near = near && qlo[k] - fhi[k] - 1 <= reach_ && flo[k] - qhi[k] - 1 <= reach_;
      if (!near) continue;
      const auto slab = thinSlab(parts[f].second.hull, gather(parts[f].first));
      if (!slab) continue;
      // The voxels of q whose cube lies in the slab.
      const std::int64_t low_corner = std::min<std::int64_t>(slab->n[0], 0) + std::min<std::int64_t>(slab->n[1], 0) +
                                      std::min<std::int64_t>(slab->n[2], 0);
      const std::int64_t high_corner = std::max<std::int64_t>(slab->n[0], 0) + std::max<std::int64_t>(slab->n[1], 0) +
                                       std::max<std::int64_t>(slab->n[2], 0);
      Members in, out;
      for (const auto i : parts[q].first) {
        const std::int64_t v = dot(slab->n, cells_[i]);
        (v + low_corner >= slab->lo && v + high_corner <= slab->hi ? in : out).push_back(i);
      }
      if (!handOver(parts, f, q, in, std::move(out))) continue;
      changed = true;
      if (!parts[q].first.empty()) box(parts[q].first, qlo, qhi);
    }
  }
  if (!changed) return parts;
  return withoutEmpty(std::move(parts));
}

std::vector<std::pair<Members, Check>> ClusterSplitter::absorbIntoBoxes(std::vector<std::pair<Members, Check>> parts,
                                                                        bool& changed) const {
  std::vector<std::size_t> order;
  for (std::size_t p = 0; p < parts.size(); ++p)
    if (!parts[p].second.flat) order.push_back(p);
  if (order.size() < 2) return parts;
  std::vector<std::size_t> targets = order;
  std::stable_sort(targets.begin(), targets.end(),
                   [&](std::size_t a, std::size_t b) { return parts[a].first.size() > parts[b].first.size(); });
  for (const auto q : order) {
    for (const auto f : targets) {
      if (f == q || parts[q].first.empty()) continue;
      if (parts[q].first.size() * kAbsorbRatio > parts[f].first.size()) continue;
      LatticePoint flo, fhi;
      box(parts[f].first, flo, fhi);
      Members in, out;
      for (const auto i : parts[q].first) {
        const LatticePoint& c = cells_[i];
        bool inside_box = true;
        for (std::size_t a = 0; a < 3; ++a) inside_box = inside_box && c[a] >= flo[a] && c[a] <= fhi[a];
        (inside_box ? in : out).push_back(i);
      }
      if (handOver(parts, f, q, in, std::move(out))) changed = true;
    }
  }
  if (!changed) return parts;
  return withoutEmpty(std::move(parts));
}

std::vector<std::pair<Members, Check>> ClusterSplitter::merge(std::vector<std::pair<Members, Check>> parts,
                                                              bool faces) const {
  struct Node {
    Members members;
    Check check;
    LatticePoint lo, hi;
    bool alive = true;
  };
  std::vector<Node> nodes;
  for (auto& [members, check] : parts) {
    Node node{std::move(members), std::move(check), {}, {}, true};
    box(node.members, node.lo, node.hi);
    nodes.push_back(std::move(node));
  }
  // Deterministic start: parts ordered by their first cell.
  std::sort(nodes.begin(), nodes.end(), [](const Node& a, const Node& b) { return a.members[0] < b.members[0]; });
  using Candidate = std::tuple<std::int64_t, std::size_t, std::size_t>;  // added volume, a, b
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> queue;
  std::map<std::pair<std::size_t, std::size_t>, FacetHull> union_hulls;  ///< of the queued pairs
  const auto near = [&](const Node& a, const Node& b) {
    for (std::size_t k = 0; k < 3; ++k)
      if (a.lo[k] - b.hi[k] - 1 > reach_ || b.lo[k] - a.hi[k] - 1 > reach_) return false;
    return true;
  };
  const auto unite = [](const Members& a, const Members& b) {
    Members out;
    out.reserve(a.size() + b.size());
    std::merge(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
    return out;
  };
  // Which node owns each cell, on a grid over the cluster's box (none when the box is too big;
  // then no pair is ruled out early).
  OwnerGrid owner;
  {
    Members all(cells_.size());
    std::iota(all.begin(), all.end(), 0u);
    box(all, owner.lo, owner.hi);
    owner.allocate(max_check_cells_);
  }
  const auto own = [&](std::size_t node) { owner.own(nodes[node].members, cells_, std::uint32_t(node)); };
  for (std::size_t node = 0; node < nodes.size(); ++node) own(node);
  // A pair whose union surely fails its check: the midpoint of the centres of a cell of each lies
  // in the union's hull, so the cell holding it is one the check scans; when no site of the union
  // (a cell of it, or a cell its cluster encloses: the check counts those inside the union's box)
  // is within max(T, G) of it, the check fails. Such a pair would be popped and rejected, so leaving it
  // out of the queue changes nothing but the time.
  const auto surelyFails = [&](std::size_t a, std::size_t b) {
    if (owner.cells.empty()) return false;
    const Members& ma = nodes[a].members;
    const Members& mb = nodes[b].members;
    for (const std::size_t pa : {std::size_t(0), ma.size() / 2, ma.size() - 1})
      for (const std::size_t pb : {std::size_t(0), mb.size() / 2, mb.size() - 1}) {
        const LatticePoint& p = cells_[ma[pa]];
        const LatticePoint& q = cells_[mb[pb]];
        const LatticePoint m{floorDiv(p[0] + q[0] + 1, 2), floorDiv(p[1] + q[1] + 1, 2), floorDiv(p[2] + q[2] + 1, 2)};
        const bool covered = std::any_of(ball_.begin(), ball_.end(), [&](const auto& offset) {
          const LatticePoint x{m[0] + offset.first[0], m[1] + offset.first[1], m[2] + offset.first[2]};
          const std::uint32_t o = owner.at(x);
          return o == a || o == b || isEnclosed(x);
        });
        if (!covered) return true;
      }
    return false;
  };
  // The added hull volume of each near pair, computed in parallel, queued in pair order.
  const auto consider = [&](const std::vector<std::pair<std::size_t, std::size_t>>& candidates) {
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (const auto& [a, b] : candidates)
      if (near(nodes[a], nodes[b]) &&
          (!faces || std::min(nodes[a].members.size(), nodes[b].members.size()) >= kFaceMergeMinVoxels))
        pairs.emplace_back(a, b);
    std::vector<char> fails(pairs.size());
    std::vector<FacetHull> hulls(pairs.size());
    tbb::parallel_for(std::size_t(0), pairs.size(), [&](std::size_t k) {
      const auto [a, b] = pairs[k];
      fails[k] = surelyFails(a, b);
      if (!fails[k]) hulls[k] = hullOf(unite(nodes[a].members, nodes[b].members));
    });
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      if (fails[k]) continue;
      const auto [a, b] = pairs[k];
      const std::int64_t added = hulls[k].volume6 - nodes[a].check.hull.volume6 - nodes[b].check.hull.volume6;
      queue.emplace(added, std::min(a, b), std::max(a, b));
      union_hulls[{std::min(a, b), std::max(a, b)}] = std::move(hulls[k]);
    }
  };
  std::vector<std::pair<std::size_t, std::size_t>> all_pairs;
  for (std::size_t a = 0; a < nodes.size(); ++a)
    for (std::size_t b = a + 1; b < nodes.size(); ++b) all_pairs.emplace_back(a, b);
  consider(all_pairs);
  while (!queue.empty()) {
    const auto [added, a, b] = queue.top();
    queue.pop();
    const auto hull = union_hulls.find({a, b});
    const FacetHull union_hull = std::move(hull->second);
    union_hulls.erase(hull);
    if (!nodes[a].alive || !nodes[b].alive) continue;
    Members both = unite(nodes[a].members, nodes[b].members);
    Check check = checkPart(both, false, &union_hull, faces);
    if (!check.ok) continue;
    nodes[a].alive = nodes[b].alive = false;
    Node node{std::move(both), std::move(check), {}, {}, true};
    box(node.members, node.lo, node.hi);
    nodes.push_back(std::move(node));
    const std::size_t added_node = nodes.size() - 1;
    own(added_node);
    std::vector<std::pair<std::size_t, std::size_t>> with_new;
    for (std::size_t c = 0; c < added_node; ++c)
      if (nodes[c].alive) with_new.emplace_back(c, added_node);
    consider(with_new);
  }
  std::vector<std::pair<Members, Check>> out;
  for (auto& node : nodes)
    if (node.alive) out.emplace_back(std::move(node.members), std::move(node.check));
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first[0] < b.first[0]; });
  return out;
}

}  // namespace hullmap::hulls::detail

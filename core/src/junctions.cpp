#include "mbest/core/junctions.h"

#include "mbest/core/bending.h"
#include "mbest/core/median.h"
#include "mbest/core/union_find.h"

#include <algorithm>
#include <functional>
#include <limits>

namespace mbest {
namespace {

// The cost of pairing a set of exits too large to pair exactly (bending.h, kMaxExactExits):
// a greedy pairing's cost is no fair comparison.
constexpr double kUnknownCost = std::numeric_limits<double>::infinity();

// Can branch `b` join the crossings at its two ends into one: does it join two junctions,
// and carry one strand (not one of two side-by-side twins, each a strand of its own)?
bool joins_junctions(const SkeletonGraph& g, const Branch& b) {
  return b.twin < 0 && g.nodes[b.node[0]].kind == Node::Kind::junction &&
         g.nodes[b.node[1]].kind == Node::Kind::junction;
}


}  // namespace

bool wider_than_neighbours(const SkeletonGraph& g, int i, double reach) {
  const Branch& mid = g.branches[i];
  if (mid.radius.empty()) return false;
  double mean = 0;
  for (float r : mid.radius) mean += r;
  mean /= static_cast<double>(mid.radius.size());
  std::vector<float> around;
  for (int s = 0; s < 2; ++s)
    for (const BranchEnd& e : g.nodes[mid.node[s]].branch_ends) {
      const Branch& b = g.branches[e.branch];
      if (e.branch == i || !b.alive) continue;
      const int n = static_cast<int>(b.radius.size());
      for (int k = 0; k < std::min(n, static_cast<int>(reach)); ++k)
        around.push_back(e.side == 0 ? b.radius[k] : b.radius[n - 1 - k]);
    }
  const float typical = middle_value(around);
  return typical > 0 && mean >= kTwoStrandWidth * typical;
}

namespace {

// Ys still unpaired after Y-pair matching whose joining path runs through other crossings:
// a loop or a third strand lying across a shallow crossing splits one topological crossing
// into a Y, an X and a Y. Each Y alone would end a strand in the middle of the mask. The
// crossings along the shortest such path through even crossings, up to `through_length`
// long, are one crossing. Unlike a single joining branch (two Ys 10-30 r apart may be two
// T-junctions), a crossing in between is itself evidence of one cluster: on 400 dev scenes
// the 30 r limit beat 10 r, and 10 r plus 30 r along wide branches, on every preset (and
// 40 r did worse than 30 r on 1600 fresh ones).
// Closest pairs first, each Y once. `degree` is kept up to date for the union-find roots.
void pair_ys_through_crossings(SkeletonGraph& g, UnionFind& uf, std::vector<int>& degree,
                               double epsilon, double through_length) {
  const int n_nodes = static_cast<int>(g.nodes.size());
  // Junction-to-junction branches between different crossings, by crossing (root).
  std::vector<std::vector<int>> incident(n_nodes);
  for (int i = 0; i < static_cast<int>(g.branches.size()); ++i) {
    const Branch& b = g.branches[i];
    if (!b.alive || !joins_junctions(g, b)) continue;
    const int r0 = uf.find(b.node[0]), r1 = uf.find(b.node[1]);
    if (r0 == r1) continue;
    incident[r0].push_back(i);
    incident[r1].push_back(i);
  }
  struct Path {
    double length;
    int from, to;
    std::vector<int> branches;
  };
  std::vector<Path> paths;
  std::vector<double> dist(n_nodes);
  std::vector<int> via(n_nodes);
  const auto other_end = [&](const Branch& b, int root) {
    return uf.find(b.node[0]) == root ? uf.find(b.node[1]) : uf.find(b.node[0]);
  };
  // Dijkstra over crossings from `start`, paths no longer than `limit` in all, entering odd
  // crossings but not passing them.
  const auto search = [&](int start, double limit) {
    std::fill(dist.begin(), dist.end(), limit + 1);
    std::fill(via.begin(), via.end(), -1);
    dist[start] = 0;
    std::vector<std::pair<double, int>> heap{{0.0, start}};
    while (!heap.empty()) {
      std::pop_heap(heap.begin(), heap.end(), std::greater<>());
      const auto [d, r] = heap.back();
      heap.pop_back();
      if (d > dist[r]) continue;
      if (r != start && degree[r] % 2 == 1) {
        if (r > start) {  // each pair once
          Path p{d, start, r, {}};
          for (int at = r; at != start; at = other_end(g.branches[via[at]], at))
            p.branches.push_back(via[at]);
          // A single joining branch was Y-pair matching's to take.
          if (p.branches.size() > 1) paths.push_back(std::move(p));
        }
        continue;
      }
      for (int i : incident[r]) {
        const int next = other_end(g.branches[i], r);
        const double nd = d + g.branches[i].length;
        if (nd <= limit && nd < dist[next]) {
          dist[next] = nd;
          via[next] = i;
          heap.push_back({nd, next});
          std::push_heap(heap.begin(), heap.end(), std::greater<>());
        }
      }
    }
  };
  for (int start = 0; start < n_nodes; ++start) {
    if (uf.find(start) != start || degree[start] % 2 == 0 || incident[start].empty()) continue;
    search(start, std::max(epsilon, through_length));
  }
  std::stable_sort(paths.begin(), paths.end(),
                   [](const Path& a, const Path& b) { return a.length < b.length; });
  for (const Path& p : paths) {
    const int a = uf.find(p.from), b = uf.find(p.to);
    if (a == b || degree[a] % 2 == 0 || degree[b] % 2 == 0) continue;
    bool intact = true;  // every branch still joins two different crossings
    for (int i : p.branches) {
      const Branch& br = g.branches[i];
      intact = intact && br.alive && uf.find(br.node[0]) != uf.find(br.node[1]);
    }
    if (!intact) continue;
    std::vector<int> roots;
    for (int i : p.branches)
      for (int s = 0; s < 2; ++s) roots.push_back(uf.find(g.branches[i].node[s]));
    std::sort(roots.begin(), roots.end());
    roots.erase(std::unique(roots.begin(), roots.end()), roots.end());
    int total = 0;
    for (int r : roots) total += degree[r];
    for (int i : p.branches) {
      uf.unite(g.branches[i].node[0], g.branches[i].node[1]);
      g.branches[i].alive = false;
    }
    degree[uf.find(p.from)] = total - 2 * static_cast<int>(p.branches.size());
  }
}

// `loop`, a branch leaving and re-entering one crossing whose other exits are `others`, is a
// rod's small self-loop rather than a strip round a hole in the mask: those exits are two
// (the rod's way in and out), the loop is about as wide as they are (a hole splits a rod
// into two strips each narrower than it), and it is at least `min_length_radii` of its own
// radius long (a loop round a hole the mask shows).
bool small_self_loop(const SkeletonGraph& g, const Branch& loop, const std::vector<BranchEnd>& others,
                     double min_length_radii) {
  if (loop.radius.empty() || others.size() != 2) return false;
  const float own = middle_value(loop.radius);
  const float narrower = std::min(middle_value(g.branches[others[0].branch].radius),
                                  middle_value(g.branches[others[1].branch].radius));
  return narrower > 0 && own >= kLoopWidthShare * narrower && loop.length >= min_length_radii * own;
}

}  // namespace

std::vector<CrossingRegion> group_junctions(SkeletonGraph& g, double merge_length, double epsilon,
                                            double wide_length, double through_length,
                                            const ExitsCost& pairing_cost,
                                            double small_loop_radii) {
  const int n_nodes = static_cast<int>(g.nodes.size());
  UnionFind uf(n_nodes);
  auto make_inner = [&](Branch& b) { b.alive = false; };

  for (Branch& b : g.branches)
    if (b.alive && joins_junctions(g, b) && b.length <= merge_length) {
      uf.unite(b.node[0], b.node[1]);
      make_inner(b);
    }

  // The exits of the crossings `roots` as they stand, less branch `skip`.
  const auto exits_of = [&](std::initializer_list<int> roots, int skip) {
    std::vector<BranchEnd> exits;
    for (int k = 0; k < static_cast<int>(g.branches.size()); ++k) {
      const Branch& b = g.branches[k];
      if (!b.alive || k == skip) continue;
      for (int s = 0; s < 2; ++s)
        if (g.nodes[b.node[s]].kind == Node::Kind::junction &&
            std::find(roots.begin(), roots.end(), uf.find(b.node[s])) != roots.end())
          exits.push_back({k, s});
    }
    return exits;
  };
  // Exits per crossing, with small cycles folded in.
  auto degree_of = [&](std::vector<int>& degree) {
    degree.assign(n_nodes, 0);
    for (Branch& b : g.branches) {
      if (!b.alive || !joins_junctions(g, b)) {
        if (b.alive)
          for (int s = 0; s < 2; ++s)
            if (g.nodes[b.node[s]].kind == Node::Kind::junction) ++degree[uf.find(b.node[s])];
        continue;
      }
      const int r0 = uf.find(b.node[0]), r1 = uf.find(b.node[1]);
      if (r0 == r1 && b.length <= 4 * merge_length) {
        const int i = static_cast<int>(&b - g.branches.data());
        if (!(small_loop_radii > 0 && small_self_loop(g, b, exits_of({r0}, i), small_loop_radii))) {
          make_inner(b);
          continue;
        }
      }
      ++degree[r0];
      ++degree[r1];
    }
  };
  std::vector<int> degree;
  degree_of(degree);

  // Y-pair matching: odd crossings joined by one branch, each paired once: cheapest first by
  // what joining adds to the cost of pairing their exits, given a cost; shortest first
  // otherwise and among pairs with a crossing too large to pair exactly.
  std::vector<int> order;
  for (int i = 0; i < static_cast<int>(g.branches.size()); ++i) {
    const Branch& b = g.branches[i];
    if (!b.alive || !joins_junctions(g, b)) continue;
    if (b.length <= epsilon ||
        (b.length <= wide_length && wider_than_neighbours(g, i, 3 * merge_length)))
      order.push_back(i);
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return g.branches[a].length < g.branches[b].length; });
  if (pairing_cost) {
    const auto cost_of = [&](const std::vector<BranchEnd>& exits) {
      return exits.size() <= static_cast<size_t>(kMaxExactExits) ? pairing_cost(exits) : kUnknownCost;
    };
    std::vector<double> added(g.branches.size(), kUnknownCost);
    for (int i : order) {
      const int r0 = uf.find(g.branches[i].node[0]), r1 = uf.find(g.branches[i].node[1]);
      if (r0 == r1 || degree[r0] % 2 == 0 || degree[r1] % 2 == 0) continue;
      const double joined = cost_of(exits_of({r0, r1}, i)), a = cost_of(exits_of({r0}, -1)),
                   c = cost_of(exits_of({r1}, -1));
      if (joined < kUnknownCost && a < kUnknownCost && c < kUnknownCost) added[i] = joined - a - c;
    }
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return added[a] < added[b]; });
  }
  std::vector<bool> paired(n_nodes, false);
  for (int i : order) {
    Branch& b = g.branches[i];
    const int r0 = uf.find(b.node[0]), r1 = uf.find(b.node[1]);
    if (r0 == r1 || paired[r0] || paired[r1] || degree[r0] % 2 == 0 || degree[r1] % 2 == 0) continue;
    uf.unite(r0, r1);
    const int r = uf.find(r0);
    paired[r] = true;
    degree[r] = degree[r0] + degree[r1] - 2;
    make_inner(b);
  }
  degree_of(degree);
  pair_ys_through_crossings(g, uf, degree, epsilon, through_length);

  std::vector<int> region_of(n_nodes, -1);
  std::vector<CrossingRegion> regions;
  for (int n = 0; n < n_nodes; ++n) {
    if (g.nodes[n].kind != Node::Kind::junction || !g.nodes[n].alive) continue;
    const int root = uf.find(n);
    if (region_of[root] < 0) {
      region_of[root] = static_cast<int>(regions.size());
      regions.emplace_back();
    }
    regions[region_of[root]].nodes.push_back(n);
  }
  for (int i = 0; i < static_cast<int>(g.branches.size()); ++i) {
    const Branch& b = g.branches[i];
    for (int s = 0; s < 2; ++s) {
      const Node& node = g.nodes[b.node[s]];
      if (node.kind != Node::Kind::junction || !node.alive) continue;
      CrossingRegion& r = regions[region_of[uf.find(b.node[s])]];
      if (b.alive) {
        r.exits.push_back({i, s});
      } else if (s == 0 || uf.find(b.node[0]) != uf.find(b.node[1])) {
        // A dead branch touching this crossing: an inner one unless it was a pruned spur.
        const bool spur = g.nodes[b.node[1 - s]].kind == Node::Kind::end;
        if (!spur) r.inner_branches.push_back(i);
      }
    }
  }
  for (CrossingRegion& r : regions) {
    cv::Point2f c(0, 0);
    for (int n : r.nodes) c += g.nodes[n].centre;
    r.centre = c * (1.0f / static_cast<float>(r.nodes.size()));
    std::sort(r.inner_branches.begin(), r.inner_branches.end());
    r.inner_branches.erase(std::unique(r.inner_branches.begin(), r.inner_branches.end()),
                           r.inner_branches.end());
  }
  return regions;
}

}  // namespace mbest

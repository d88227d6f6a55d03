#include "mbest/core/traverse.h"

#include "mbest/core/geometry.h"

namespace mbest {
namespace {

struct Builder {
  const SkeletonGraph& g;
  const std::vector<Passage>& passages;
  std::vector<int> passage_at;  // per branch end (2 * branch + side): passage index or -1
  std::vector<bool> visited;    // per branch

  Builder(const SkeletonGraph& graph, const std::vector<Passage>& ps)
      : g(graph), passages(ps), passage_at(2 * graph.branches.size(), -1),
        visited(graph.branches.size(), false) {
    for (int i = 0; i < static_cast<int>(ps.size()); ++i) {
      passage_at[2 * ps[i].from.branch + ps[i].from.side] = i;
      passage_at[2 * ps[i].to.branch + ps[i].to.side] = i;
    }
  }

  int passage_of(BranchEnd e) const { return passage_at[2 * e.branch + e.side]; }

  int cut_of(BranchEnd e) const {
    const int p = passage_of(e);
    if (p < 0) return 0;
    return passages[p].from == e ? passages[p].from_tangent.cut : passages[p].to_tangent.cut;
  }

  static void append(Dlo& dlo, cv::Point p, float r) {
    const size_t before = dlo.centerline.size();
    append_connected(dlo.centerline, p);
    const float r0 = dlo.radius.empty() ? r : dlo.radius.back();
    const size_t added = dlo.centerline.size() - before;
    for (size_t k = 1; k <= added; ++k)
      dlo.radius.push_back(r0 + (r - r0) * static_cast<float>(k) / static_cast<float>(added));
  }

  // Walks from `start` (entering its branch there) until a true end or back to the start.
  void walk(BranchEnd start, Dlo& dlo, std::vector<int>& dlo_passages) {
    BranchEnd cur = start;
    for (;;) {
      visited[cur.branch] = true;
      const Branch& b = g.branches[cur.branch];
      const int n = static_cast<int>(b.pixels.size());
      const BranchEnd exit{cur.branch, 1 - cur.side};
      const int first = cut_of(cur), last = n - 1 - cut_of(exit);
      for (int i = first; i <= last; ++i) {
        const int k = cur.side == 0 ? i : n - 1 - i;
        append(dlo, b.pixels[k], b.radius[k]);
      }
      const int p = passage_of(exit);
      if (p < 0) return;
      const Passage& ps = passages[p];
      const bool forward = ps.from == exit;
      dlo_passages.push_back(p);
      const size_t m = ps.path.size();
      for (size_t i = 0; i < m; ++i) {
        const size_t k = forward ? i : m - 1 - i;
        append(dlo, ps.path[k], ps.radius[k]);
      }
      const BranchEnd next = forward ? ps.to : ps.from;
      if (visited[next.branch]) {  // back where it started: a closed DLO
        dlo.closed = true;
        return;
      }
      cur = next;
    }
  }
};

}  // namespace

Traversal traverse(const SkeletonGraph& g, const std::vector<Passage>& passages, double min_length) {
  Builder builder(g, passages);
  Traversal t;
  t.passage_dlo.assign(passages.size(), -1);

  auto keep = [&](Dlo&& dlo, const std::vector<int>& dps) {
    if (dlo.closed && dlo.centerline.size() > 2) {
      // The walk ends where it began: close the gap to the first pixel, without repeating it.
      if (dlo.centerline.back() != dlo.centerline.front())
        Builder::append(dlo, dlo.centerline.front(), dlo.radius.front());
      dlo.centerline.pop_back();
      dlo.radius.pop_back();
    }
    if (chain_length(dlo.centerline) < min_length) return;
    const int id = static_cast<int>(t.dlos.size());
    for (int p : dps) t.passage_dlo[p] = id;
    t.dlo_passages.push_back(dps);
    t.dlos.push_back(std::move(dlo));
  };

  // Open DLOs start at true ends: end nodes, and exits a crossing left unpaired.
  for (int i = 0; i < static_cast<int>(g.branches.size()); ++i) {
    for (int s = 0; s < 2; ++s) {
      const Branch& b = g.branches[i];
      if (!b.alive || builder.visited[i] || builder.passage_of({i, s}) >= 0) continue;
      Dlo dlo;
      std::vector<int> dps;
      builder.walk({i, s}, dlo, dps);
      keep(std::move(dlo), dps);
    }
  }
  // Closed DLOs through crossings: every branch end is paired.
  for (int i = 0; i < static_cast<int>(g.branches.size()); ++i) {
    if (!g.branches[i].alive || builder.visited[i]) continue;
    Dlo dlo;
    std::vector<int> dps;
    builder.walk({i, 0}, dlo, dps);
    dlo.closed = true;
    keep(std::move(dlo), dps);
  }
  // Rings: closed chains that never met a junction.
  for (size_t k = 0; k < g.rings.size(); ++k) {
    Dlo dlo;
    dlo.centerline = g.rings[k];
    dlo.radius = g.ring_radius[k];
    dlo.closed = true;
    keep(std::move(dlo), {});
  }
  return t;
}

}  // namespace mbest

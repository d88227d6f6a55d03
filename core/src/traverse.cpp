#include "mbest/core/traverse.h"

#include <algorithm>
#include <cmath>

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

namespace {

// Extends `line` (and `radius`) beyond its last pixel; see extend_ends.
void extend_tail(std::vector<cv::Point>& line, std::vector<float>& radius, const cv::Mat& mask, float r) {
  // Direction from the chord 3 r .. r before the end: the last r px bend towards a corner
  // of a flat tip.
  const int n = static_cast<int>(line.size());
  const int back = std::min(n - 1, std::max(2, static_cast<int>(std::lround(3 * r))));
  const int skip = std::min(back - 2, static_cast<int>(std::lround(r)));
  if (back < 2) return;
  cv::Point2f dir = cv::Point2f(line[n - 1 - skip]) - cv::Point2f(line[n - 1 - back]);
  const float len = std::hypot(dir.x, dir.y);
  if (len < 1) return;
  dir *= 1.0f / len;
  // The bent tip is replaced: extend straight on from where the chord ends.
  const cv::Point2f start(line[n - 1 - skip]);
  const float tip_radius = radius.back();
  line.resize(n - skip);
  radius.resize(n - skip);
  const int max_steps = static_cast<int>(std::ceil(2 * r)) + 2 + skip;
  auto inside = [&](cv::Point p) { return p.x >= 0 && p.y >= 0 && p.x < mask.cols && p.y < mask.rows; };
  std::vector<cv::Point> ext;
  bool reached_border = false;
  for (int k = 1; k <= max_steps; ++k) {
    const cv::Point p(start + dir * static_cast<float>(k));  // rounds to the nearest pixel
    if (!inside(p)) {
      reached_border = true;
      break;
    }
    if (!mask.ptr<uint8_t>(p.y)[p.x]) break;
    ext.push_back(p);
  }
  if (!reached_border) {  // stop half a radius inside the edge
    const size_t keep = ext.size() - std::min(ext.size(), static_cast<size_t>(std::lround(tip_radius / 2)));
    ext.resize(keep);
  }
  for (const cv::Point& p : ext) append_connected(line, p);
  radius.resize(line.size(), tip_radius);
}

}  // namespace

void extend_ends(std::vector<Dlo>& dlos, const cv::Mat& mask, float r) {
  for (Dlo& dlo : dlos) {
    if (dlo.closed || dlo.centerline.size() < 3) continue;
    extend_tail(dlo.centerline, dlo.radius, mask, r);
    std::reverse(dlo.centerline.begin(), dlo.centerline.end());
    std::reverse(dlo.radius.begin(), dlo.radius.end());
    extend_tail(dlo.centerline, dlo.radius, mask, r);
    std::reverse(dlo.centerline.begin(), dlo.centerline.end());
    std::reverse(dlo.radius.begin(), dlo.radius.end());
  }
}

}  // namespace mbest

#include "mbest/core/prune.h"

#include <algorithm>
#include <cmath>

#include "mbest/core/bending.h"

namespace mbest {

namespace {

// Does the branch end at `side` run out of the image: is the image border no farther from
// the end pixel than the mask's edge (the radius measured there, plus a pixel)?
bool leaves_image(const SkeletonGraph& g, const Branch& b, int side, cv::Size image) {
  const cv::Point e = g.nodes[b.node[side]].pixels.front();
  const int to_border = 1 + std::min({e.x, e.y, image.width - 1 - e.x, image.height - 1 - e.y});
  const float r = b.radius.empty() ? 1.0f : (side == 0 ? b.radius.front() : b.radius.back());
  return to_border <= r + 1.5f;
}

cv::Point2f unit(cv::Point2f v) {
  const float n = std::hypot(v.x, v.y);
  return n > 0 ? v * (1.0f / n) : v;
}

// The pixel `reach` px along branch end `e` from its node (or the branch's far end).
cv::Point2f along(const Branch& b, int side, double reach) {
  const int n = static_cast<int>(b.pixels.size());
  const int k = std::min(n - 1, static_cast<int>(reach));
  return cv::Point2f(side == 0 ? b.pixels[k] : b.pixels[n - 1 - k]);
}

// Is the short branch `i` (end side `end_side`) the stub of a DLO that ends just past a
// crossing rather than a split end? Then its junction is a crossing (four or more
// branches) and the stub runs straight on from another branch there; split ends sprout
// sideways from a DLO's body or fork at its end.
bool is_stub_past_crossing(const SkeletonGraph& g, int i, int end_side, double reach) {
  const Branch& b = g.branches[i];
  const Node& junction = g.nodes[b.node[1 - end_side]];
  if (junction.degree() < 4 || b.pixels.empty()) return false;
  const cv::Point2f c = junction.centre;
  const cv::Point2f stub = unit(cv::Point2f(g.nodes[b.node[end_side]].pixels.front()) - c);
  for (const BranchEnd& e : junction.branch_ends) {
    const Branch& other = g.branches[e.branch];
    if (e.branch == i || !other.alive || other.pixels.empty()) continue;
    const cv::Point2f out = unit(along(other, e.side, reach) - c);
    if (stub.dot(-out) > std::cos(35.0 * M_PI / 180)) return true;
  }
  return false;
}

// Is the short branch `i` where two DLOs meet rather than a split end? A split end forks
// off one DLO, so every branch at its junction has that DLO's colour. Where two of them
// differ (colour_penalty > 0) the short branch is a real end: of a DLO lying on another
// (the others differ), or of one ending just past a crossing (the branch itself differs;
// sampled over its outer half, away from the DLO it crosses).
bool joins_two_colours(const SkeletonGraph& g, int i, int end_side, const ColourSource& colour) {
  if (colour.bgr.empty()) return false;
  const Branch& spur = g.branches[i];
  const Node& junction = g.nodes[spur.node[1 - end_side]];
  std::vector<BranchTangent> sampled;
  const BranchEnd tip{i, end_side};
  sampled.push_back(fit_branch_tangent(g, tip, 0, 3 * colour.radius, false));
  sample_branch_colour(g, tip, colour.bgr, &sampled.back(),
                       std::max(1, static_cast<int>(spur.pixels.size()) / 2));
  for (const BranchEnd& e : junction.branch_ends) {
    const Branch& other = g.branches[e.branch];
    if (e.branch == i || !other.alive) continue;
    const bool shared = g.nodes[other.node[1 - e.side]].kind == Node::Kind::junction;
    sampled.push_back(fit_branch_tangent(g, e, colour.radius, 3 * colour.radius, shared));
    sample_branch_colour(g, e, colour.bgr, &sampled.back(),
                         static_cast<int>(std::lround(kColourStretchFits * 3 * colour.radius)));
  }
  // A thin prong of a forked tip is mostly the tip's shaded edge: its own colour counts
  // only when it is about as wide as the branches it leaves.
  float widest = 0;
  for (size_t k = 1; k < sampled.size(); ++k) widest = std::max(widest, sampled[k].radius);
  const size_t from = sampled[0].radius >= 0.6f * widest ? 0 : 1;
  for (size_t a = from; a < sampled.size(); ++a)
    for (size_t b = a + 1; b < sampled.size(); ++b)
      if (colour_penalty(sampled[a], sampled[b]) > 0) return true;
  return false;
}

}  // namespace

int prune_split_ends(SkeletonGraph& g, double delta, cv::Size image, const ColourSource& colour) {
  std::vector<int> spurs;
  for (int i = 0; i < static_cast<int>(g.branches.size()); ++i) {
    const Branch& b = g.branches[i];
    if (!b.alive || b.length >= delta) continue;
    const Node::Kind k0 = g.nodes[b.node[0]].kind, k1 = g.nodes[b.node[1]].kind;
    if ((k0 == Node::Kind::end) != (k1 == Node::Kind::end)) spurs.push_back(i);
  }
  std::stable_sort(spurs.begin(), spurs.end(),
                   [&](int a, int b) { return g.branches[a].length < g.branches[b].length; });

  int removed = 0;
  for (int i : spurs) {
    Branch& b = g.branches[i];
    const int end_side = g.nodes[b.node[0]].kind == Node::Kind::end ? 0 : 1;
    if (leaves_image(g, b, end_side, image) || is_stub_past_crossing(g, i, end_side, delta) ||
        joins_two_colours(g, i, end_side, colour))
      continue;
    Node& junction = g.nodes[b.node[1 - end_side]];
    if (junction.degree() < 3) continue;  // would cut a line in two
    b.alive = false;
    g.nodes[b.node[end_side]].alive = false;
    auto& ends = junction.branch_ends;
    ends.erase(std::remove(ends.begin(), ends.end(), BranchEnd{i, 1 - end_side}), ends.end());
    ++removed;
  }
  return removed;
}

}  // namespace mbest

#include "mbest/core/prune.h"

#include <algorithm>

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

}  // namespace

int prune_split_ends(SkeletonGraph& g, double delta, cv::Size image) {
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
    if (leaves_image(g, b, end_side, image)) continue;
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

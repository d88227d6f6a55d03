#include "mbest/core/prune.h"

#include <algorithm>

namespace mbest {

int prune_split_ends(SkeletonGraph& g, double delta) {
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

// Split-end pruning: a jagged mask makes the skeleton sprout short spurs that end near a
// junction they created. A branch from an end that reaches a junction within `delta` px
// (the paper's delta = 2 r, the widest DLO's diameter) is such a split end.
#pragma once

#include "mbest/core/keypoints.h"

namespace mbest {

// Removes split ends from `graph`, shortest first; a junction keeps at least two branches
// (of two spurs at a real end, the longer one stays as the DLO's end). Branches joining two
// ends (short isolated pieces) are left alone. Returns the number of branches removed.
int prune_split_ends(SkeletonGraph& graph, double delta);

}  // namespace mbest

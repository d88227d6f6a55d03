// Split-end pruning: a jagged mask makes the skeleton sprout short spurs that end near a
// junction they created. A branch from an end that reaches a junction within `delta` px
// (the paper's delta = 2 r, the widest DLO's diameter) is such a split end.
#pragma once

#include "mbest/core/keypoints.h"

namespace mbest {

// The colour image for colour-aware decisions: `bgr` (empty = none), `radius` = the widest
// DLO's radius in pixels.
struct ColourSource {
  cv::Mat bgr;
  double radius = 1;
};

// Removes split ends from `graph`, shortest first; a junction keeps at least two branches
// (of two spurs at a real end, the longer one stays as the DLO's end). Left alone: branches
// joining two ends (short isolated pieces); branches whose end is as close to the border
// of an image of size `image` as to the mask's edge (a DLO leaving the image, whose stub
// beyond a crossing near the border may be short); and the stub of a DLO ending just past
// a crossing: a branch from a junction of four or more branches that runs straight on
// (within 35 degrees) from another branch there. With a colour image (`colour`), also the
// end of a DLO lying on another: a short branch at a junction whose other branches differ
// in colour. Returns the number removed.
int prune_split_ends(SkeletonGraph& graph, double delta, cv::Size image,
                     const ColourSource& colour = ColourSource());

}  // namespace mbest

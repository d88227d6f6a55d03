// Traversal: following the skeleton from each end, through crossings along the paired
// passages, into ordered centerlines; what is left after all ends are used is closed loops.
#pragma once

#include <vector>

#include "mbest/core/bending.h"
#include "mbest/core/detector.h"
#include "mbest/core/keypoints.h"

namespace mbest {

struct Traversal {
  std::vector<Dlo> dlos;  // centerline and radius filled; crossings empty
  // For each passage: the DLO that runs through it (-1 if that DLO was dropped as too short).
  std::vector<int> passage_dlo;
  std::vector<std::vector<int>> dlo_passages;  // per DLO, its passages in traversal order
};

// Builds the DLOs. DLOs whose centerline is shorter than `min_length` px are dropped.
Traversal traverse(const SkeletonGraph& graph, const std::vector<Passage>& passages,
                   double min_length);

}  // namespace mbest

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

// Thinning leaves a skeleton end about a radius short of the DLO's tip, and bent towards a
// corner of a flat tip over its last r px. Replaces those r px of each end of an open DLO
// by a straight run along the chord from 3 r to r px before the end, through `mask`, at
// most 2 r + 2 px beyond the old end: to the image border if it gets there, else to half a
// radius short of the mask's edge, between where a flat and a round tip end.
void extend_ends(std::vector<Dlo>& dlos, const cv::Mat& mask, float r);

}  // namespace mbest

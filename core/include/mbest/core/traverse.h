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
  std::vector<int> branch_dlo;  // per skeleton branch: the DLO that runs along it, or -1
};

// Builds the DLOs. DLOs whose centerline is shorter than `min_length` px are dropped.
Traversal traverse(const SkeletonGraph& graph, const std::vector<Passage>& passages,
                   double min_length);

// A rod's self-loop that crosses the rod (or other DLOs) may be closed into a ring at one
// of those crossings, the rod running on beside it: each crossing's pairing alone cannot
// tell (add_loop_closing_costs covers a loop of one branch). For each closed DLO of `t`
// that runs through a crossing region, finds the least costly re-pairing of one of its
// passages there with one of an open DLO's (either way round, by pair_cost under
// `weights` without the loop cost) that makes the loop part of that DLO. Makes the
// cheapest, if it costs at most `max_cost` more than the two passages did (or at most
// `own_colour_cost`, if larger, where all four exits are of one colour, within half
// kColourTolerance: a rod's own loop) and the loop's colour is not that of a ring of its own
// (its exit's colour further than kColourTolerance from both of the open DLO's exits). One
// loop at a time: returns true when `passages` changed (traverse again). `max_cost` 0 turns
// it off.
bool open_closed_loops(std::vector<Passage>& passages, const Traversal& t, PairWeights weights,
                       double max_cost, double own_colour_cost = 0);

// Thinning leaves a skeleton end about a radius short of the DLO's tip, and bent towards a
// corner of a flat tip over its last r px. Replaces those r px of each end of an open DLO
// by a straight run along the chord from 3 r to r px before the end, through `mask`, at
// most 2 r + 2 px beyond the old end: to the image border if it gets there, else to half a
// radius short of the mask's edge, between where a flat and a round tip end.
void extend_ends(std::vector<Dlo>& dlos, const cv::Mat& mask, float r);

// A DLO that ends where it meets another strand most often runs on under it and ends just
// past it, in a stub too short to keep a skeleton branch of its own (pruned as a split end,
// or folded into the crossing): the stub's pixels went to the strand it passes under.
// After extend_ends, casts rays from each open end, along the chord of its last 3 r px and
// fanned out up to 30 degrees either side (stubs bend), through `mask`. A ray makes a stub
// when the end runs into another DLO's body (within its median radius + 1 px of its
// centerline) at 10 degrees or more to that DLO's axis, then on through mask no DLO covers
// reaching at least max(3, half the end's radius) px from every body, before the mask ends,
// the image ends (where the stub's length along the ray counts) or a third body begins; all
// within 6 r + 2 px. The end is extended straight along the ray reaching furthest into its
// stub, up to half a radius short of the stub's tip. Returns the number of ends extended.
int reach_past_crossings(std::vector<Dlo>& dlos, const cv::Mat& mask, float r);

}  // namespace mbest

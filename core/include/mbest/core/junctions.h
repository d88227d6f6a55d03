// Junction clustering, Y-pair matching and X replacement: the junction nodes of a skeleton
// are grouped into crossings, each the meeting point of the branches of one topological
// crossing, whatever shape the skeleton gave it (one X, two Ys, or several small nodes).
#pragma once

#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "mbest/core/keypoints.h"

namespace mbest {

struct CrossingRegion {
  std::vector<int> nodes;           // junction nodes merged into this crossing
  std::vector<int> inner_branches;  // branches inside it (the segment joining two Ys, ...)
  std::vector<BranchEnd> exits;     // the branches that leave it
  cv::Point2f centre;               // mean of the merged junctions' centres
};

// Groups the junction nodes of `graph`:
// 1. junctions joined by a branch no longer than `merge_length` (the detector passes 2 r) are one
//    crossing (three DLOs through one point give several such small junctions);
// 2. a branch that leaves and re-enters the same crossing within 4 `merge_length` is inside
//    it (a hole in the mask makes such a small cycle), unless it is a rod's small self-loop:
//    the crossing's only other exits are two, the loop is at least kLoopWidthShare as wide
//    as the narrower of them (the strips round a hole are each narrower than the rod), and
//    it is at least `small_loop_radii` times its own radius long (0: never);
// 3. crossings with an odd number of exits (Ys) are paired, while the branch joining them is
//    no longer than `epsilon` (the paper's 10 r), or, up to `wide_length`, while it is wider
//    than the DLOs around it (mean radius at least 1.25 times theirs): two strands crossing at a shallow angle theta overlap over about
//    2 r / sin(theta / 2), where the mask is wider than one DLO; a branch between two
//    separate T-junctions is not. The pair is one X-crossing, its joining branch inside it.
//    Each Y a Y-pair once: with `pairing_cost`, cheapest first by how much joining two adds
//    to the cost of pairing their exits (a Y alone leaves one strand ending, free; joined,
//    the two such strands must pair): of two Ys a Y could be paired with, the one whose
//    strands continue its own. Closest first without it, as the paper (and among pairs
//    where a crossing has more exits than bending.h pairs exactly).
// 4. Ys still unpaired whose joining path runs through other crossings (a third strand
//    across a shallow crossing makes a Y, an X and a Y) are one crossing with those between
//    them, when the path is no longer than `through_length`.
// Branches made inner are marked dead in `graph`.
// How wide a small cycle at a crossing must be, against the crossing's other exits, to be
// taken for a rod's own loop (step 2).
inline constexpr double kLoopWidthShare = 0.75;

// Where two strands overlap or lie side by side, the mask is wider than either: a branch
// whose radius is at least this many times that of the branches around it carries two.
inline constexpr double kTwoStrandWidth = 1.25;

// Is branch `i`, joining two junctions, wider than the other branches at those junctions
// (their first `reach` pixels): its mean radius at least kTwoStrandWidth times their median?
bool wider_than_neighbours(const SkeletonGraph& graph, int i, double reach);

// The least cost of pairing a set of exits (bending.h: bending energy and colour).
using ExitsCost = std::function<double(const std::vector<BranchEnd>& exits)>;

std::vector<CrossingRegion> group_junctions(SkeletonGraph& graph, double merge_length,
                                            double epsilon, double wide_length,
                                            double through_length,
                                            const ExitsCost& pairing_cost = {},
                                            double small_loop_radii = 0);

}  // namespace mbest

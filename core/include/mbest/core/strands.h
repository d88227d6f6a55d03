// Side-by-side strands. Where two DLOs lie side by side, or one ends lying along another,
// the mask shows one band wider than either and the skeleton one branch down its middle:
// a Y where the two come together, and at the band's far end another junction, the image
// border, or the point where it narrows to one DLO. A pairing of exits cannot express a
// branch that carries two strands: each would be paired once, and one DLO would end at the
// Y, or both would be drawn crossing. So such a branch is split in two, one per strand,
// each offset from the middle towards its own side.
#pragma once

#include <opencv2/core.hpp>

#include "mbest/core/keypoints.h"

namespace mbest {

// How much wider than one strand a branch must be to carry two: where strands of radii
// r1 <= r2 lie side by side the band's half width is up to r1 + r2, where they overlap fully
// it is r2. A stretch of branch is taken for two strands where its radius is at least
// r2 + kSideBySideShare * r1, for one where it is below.
inline constexpr double kSideBySideShare = 0.4;

// Splits every branch that carries two strands side by side out of a Y (a junction of three
// branches whose two narrow branches both run on into the wide one, within 60 degrees):
// - when the band stays two strands wide up to a Y where the two part again, or to the
//   image border, the branch becomes two, side by side, between the same two nodes (a new
//   end node at the border); each is marked as the other's `twin`;
// - when it narrows to one strand and stays so well past that (6 strand radii) up to a node
//   other than such a Y, one strand ends there: the branch becomes the strand running on
//   (moved to its side up to the narrowing, then the old pixels) and a new branch runs from
//   the Y to a new end node at the narrowing;
// - otherwise it is left as it is: narrowing and widening again is where the two strands
//   cross (two Ys joined by a branch, which junctions.h pairs), and a band that runs into a
//   larger crossing or ends in the mask is not told apart from one wide DLO.
// The band must be two strands wide over at least `min_length` px past the Y's bulge. A
// strand's pixels are the middle ones moved sideways by the band's half width less the
// strand's radius (that of its branch next to the Y), within `mask` (CV_8UC1); its radius
// is the strand's own. Returns the branches split.
int split_side_by_side(SkeletonGraph& graph, const cv::Mat& mask, double min_length);

}  // namespace mbest

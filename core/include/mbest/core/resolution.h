// Working resolution. Thinning costs about (pixels of the mask) x (iterations), both
// growing with the DLO radius r, so it dominates for wide DLOs. Such masks are traced at
// half resolution, where r is still several pixels, and the results are mapped back: the
// crossing order and the instance masks are always made at full resolution.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "mbest/core/bending.h"
#include "mbest/core/junctions.h"
#include "mbest/core/traverse.h"

namespace mbest {

// Half-resolution mask: pixel (x, y) is set when at least half of the full-resolution
// pixels (2x..2x+1, 2y..2y+1) inside the image are set. Size ((cols+1)/2, (rows+1)/2).
cv::Mat half_resolution(const cv::Mat& mask);

// Maps the traced DLOs, passages and crossing regions from half to full resolution: pixel
// p becomes 2p + (1, 1) clamped to the image, chains are reconnected 8-connectedly, and
// radii are measured again on the full-resolution `mask`.
void to_full_resolution(Traversal& traversal, std::vector<Passage>& passages,
                        std::vector<CrossingRegion>& regions, const cv::Mat& mask);

}  // namespace mbest

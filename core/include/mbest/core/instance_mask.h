// Instance masks. The mask already holds the exact DLO pixels, so instead of drawing discs
// along each centerline, every mask pixel is given to the DLO whose centerline is nearest
// inside the mask (a multi-source breadth-first search from all centerlines), after the
// band of each top strand through a crossing has been given to that strand.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "mbest/core/detector.h"

namespace mbest {

// A strand drawn over the others at a crossing.
struct TopStrand {
  int dlo = -1;
  std::vector<cv::Point> path;
  std::vector<float> radius;  // per path pixel
};

// mask: CV_8UC1 (non-zero = DLO). `tops` are painted in order, so later ones cover earlier
// ones (give them bottom to top). Returns CV_16UC1: 0 outside the mask and on mask pixels no
// centerline reaches, otherwise DLO index + 1. The result is a view into a buffer with a
// one-pixel border (so not continuous; rows are reached with ptr()), which saves a copy.
cv::Mat instance_labels(const cv::Mat& mask, const std::vector<Dlo>& dlos,
                        const std::vector<TopStrand>& tops);

}  // namespace mbest

// A picture a person can check at a glance: each DLO's pixels tinted with its own colour,
// its centerline drawn, its start marked, and each crossing circled in the colour of the
// DLO on top.
#pragma once

#include <opencv2/core.hpp>

#include "mbest/core/detector.h"

namespace mbest {

// A distinct, stable colour (BGR) for DLO index `i`.
cv::Scalar dlo_colour(int i);

// background: CV_8UC3 image or CV_8UC1 mask of the detection's size. Returns CV_8UC3.
cv::Mat draw_overlay(const cv::Mat& background, const Detection& detection);

}  // namespace mbest

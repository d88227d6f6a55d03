// Crossing order: which strand lies on top at each crossing. Along the strand on top the
// colour is that of one DLO; along the one below it changes where the top one covers it.
// So the strand whose path has the lower colour spread (sum over R, G, B of the standard
// deviation along the path, on a box-blurred image to ignore glare: the paper's 5x5 box,
// smaller for thin DLOs) is on top.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "mbest/core/bending.h"

namespace mbest {

// Colour spread along `path` in `bgr` (CV_8UC3), each pixel the mean of its (2 half + 1)^2
// neighbourhood (clipped at the image border). Only the blurred values at path pixels are
// computed, never the whole blurred image.
double colour_spread(const cv::Mat& bgr, const std::vector<cv::Point>& path, int half = 2);

// The blur's half size for a strand of radius r: the paper's 5x5 box where it fits inside
// the strand, smaller for thin DLOs, whose 5x5 box would take in the background.
int blur_half_size(float radius);

// For each crossing region with two or more passages, its passages ordered top first.
// Without a colour image (`bgr` empty) the straighter strand is taken as on top.
std::vector<std::vector<int>> order_crossings(const std::vector<Passage>& passages,
                                              int region_count, const cv::Mat& bgr);

}  // namespace mbest

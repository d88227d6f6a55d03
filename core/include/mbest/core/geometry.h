// Small pixel-geometry helpers shared by the pipeline stages.
#pragma once

#include <cmath>
#include <vector>

#include <opencv2/core.hpp>

namespace mbest {

// Appends `p` to the 8-connected chain `line`, first filling any gap from the chain's last
// pixel with a straight digital line; a repeat of the last pixel is skipped.
void append_connected(std::vector<cv::Point>& line, cv::Point p);

// Cubic Hermite curve from `a` (leaving along unit `ta`) to `b` (arriving along unit `tb`),
// tangents scaled by the chord length, rasterised as an 8-connected chain from a to b.
std::vector<cv::Point> hermite_path(cv::Point2f a, cv::Point2f ta, cv::Point2f b, cv::Point2f tb);

// `v` scaled to length 1; the zero vector stays zero.
inline cv::Point2f unit(cv::Point2f v) {
  const float n = std::hypot(v.x, v.y);
  return n > 0 ? v * (1.0f / n) : cv::Point2f(0, 0);
}

// True when the two pixels are 8-neighbours (and not the same pixel).
inline bool eight_adjacent(cv::Point a, cv::Point b) {
  return a != b && std::abs(a.x - b.x) <= 1 && std::abs(a.y - b.y) <= 1;
}

}  // namespace mbest

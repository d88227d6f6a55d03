// Small pixel-geometry helpers shared by the pipeline stages.
#pragma once

#include <algorithm>
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

// The cheapest 8-connected chain of pixels of `mask` (CV_8UC1, non-zero = on) from `a` to
// `b`, both ends included, searched inside `roi` (clipped to the image). A step costs its
// length times 1 + centre_weight * (1 - min(inside, depth) / depth), `inside` being the
// pixel's distance to the background, so the chain keeps to the middle of the strands it
// runs along rather than hugging their edges. With a `guide` (a chain of pixels, e.g. the
// curve the path replaces) and guide_weight > 0, a step costs guide_weight *
// min(g, 2 * depth) / depth times its length more, g being the pixel's distance to the
// guide, so the chain keeps near the guide where the mask lets it. Empty when `a` or `b`
// lies off the mask or outside `roi`, or no chain joins them there.
std::vector<cv::Point> path_through_mask(const cv::Mat& mask, cv::Point a, cv::Point b,
                                         cv::Rect roi, float depth, float centre_weight,
                                         const std::vector<cv::Point>* guide = nullptr,
                                         float guide_weight = 0);

// `v` scaled to length 1; the zero vector stays zero.
inline cv::Point2f unit(cv::Point2f v) {
  const float n = std::hypot(v.x, v.y);
  return n > 0 ? v * (1.0f / n) : cv::Point2f(0, 0);
}

// Pixels over which a direction of travel along a path is taken where no fit is needed
// (a routed loop's halves and joins, a crossing's strands).
constexpr size_t kDirectionSpan = 6;

// The unit direction of travel along the pixel chain `path` (not empty) at its start,
// towards the pixel `span` on, and at its end, from the pixel `span` before; zero for a
// single pixel.
inline cv::Point2f start_direction(const std::vector<cv::Point>& path, size_t span) {
  return unit(cv::Point2f(path[std::min(span, path.size() - 1)] - path.front()));
}
inline cv::Point2f end_direction(const std::vector<cv::Point>& path, size_t span) {
  const size_t last = path.size() - 1;
  return unit(cv::Point2f(path[last] - path[last >= span ? last - span : 0]));
}

// True when the two pixels are 8-neighbours (and not the same pixel).
inline bool eight_adjacent(cv::Point a, cv::Point b) {
  return a != b && std::abs(a.x - b.x) <= 1 && std::abs(a.y - b.y) <= 1;
}

}  // namespace mbest

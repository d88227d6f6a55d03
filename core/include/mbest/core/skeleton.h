// Skeletonisation: Zhang-Suen thinning visiting only pixels on the current boundary,
// followed by removal of staircase corners so that every line pixel has two neighbours.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace mbest {

// A skeleton image that carries a one-pixel zero border: `image` is a view into `buffer`,
// so reading the 8 neighbours of any pixel of `image` is always valid.
struct Skeleton {
  cv::Mat buffer;                 // (rows + 2) x (cols + 2), CV_8UC1
  cv::Mat image;                  // rows x cols view into buffer: 1 = skeleton, 0 = not
  std::vector<cv::Point> pixels;  // every skeleton pixel, in raster order
};

// mask: CV_8UC1, non-zero = foreground. The result is 8-connected, one pixel thin and
// has the topology of the mask (holes and components are kept).
Skeleton skeletonize(const cv::Mat& mask);

// 8-neighbourhood code of the pixel at p: bit 0 = N, 1 = NE, 2 = E, 3 = SE, 4 = S, 5 = SW,
// 6 = W, 7 = NW (clockwise from north). `p` must have valid memory around it.
inline int neighbour_code(const uint8_t* p, size_t step) {
  const ptrdiff_t s = static_cast<ptrdiff_t>(step);
  return (p[-s] != 0) | (p[-s + 1] != 0) << 1 | (p[1] != 0) << 2 | (p[s + 1] != 0) << 3 |
         (p[s] != 0) << 4 | (p[s - 1] != 0) << 5 | (p[-1] != 0) << 6 | (p[-s - 1] != 0) << 7;
}

// Offsets (dx, dy) of the 8 neighbours in the bit order of neighbour_code.
constexpr int kNeighbourDx[8] = {0, 1, 1, 1, 0, -1, -1, -1};
constexpr int kNeighbourDy[8] = {-1, -1, 0, 1, 1, 1, 0, -1};

}  // namespace mbest

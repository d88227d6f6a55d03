#include "mbest/core/geometry.h"

#include <cmath>
#include <cstdlib>

namespace mbest {

void append_connected(std::vector<cv::Point>& line, cv::Point p) {
  if (line.empty()) {
    line.push_back(p);
    return;
  }
  const cv::Point a = line.back();
  if (a == p) return;
  // Bresenham from a (exclusive) to p (inclusive).
  const int dx = std::abs(p.x - a.x), dy = -std::abs(p.y - a.y);
  const int sx = a.x < p.x ? 1 : -1, sy = a.y < p.y ? 1 : -1;
  int err = dx + dy, x = a.x, y = a.y;
  while (x != p.x || y != p.y) {
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      x += sx;
    }
    if (e2 <= dx) {
      err += dx;
      y += sy;
    }
    line.emplace_back(x, y);
  }
}

std::vector<cv::Point> hermite_path(cv::Point2f a, cv::Point2f ta, cv::Point2f b, cv::Point2f tb) {
  const cv::Point2f d = b - a;
  const float len = std::hypot(d.x, d.y);
  std::vector<cv::Point> out;
  const int n = std::max(2, static_cast<int>(std::ceil(2 * len)) + 1);
  for (int i = 0; i <= n; ++i) {
    const float s = static_cast<float>(i) / static_cast<float>(n);
    const float s2 = s * s, s3 = s2 * s;
    const float h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2,
                h11 = s3 - s2;
    const cv::Point2f q = h00 * a + h10 * len * ta + h01 * b + h11 * len * tb;
    append_connected(out, cv::Point(static_cast<int>(std::lround(q.x)), static_cast<int>(std::lround(q.y))));
  }
  return out;
}

}  // namespace mbest

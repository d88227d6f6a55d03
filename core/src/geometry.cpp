#include "mbest/core/geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

#include <opencv2/imgproc.hpp>

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

std::vector<cv::Point> path_through_mask(const cv::Mat& inside, cv::Point a, cv::Point b,
                                         cv::Rect roi, float depth, float centre_weight,
                                         const std::vector<cv::Point>* guide, float guide_weight) {
  CV_Assert(inside.type() == CV_32FC1);
  roi &= cv::Rect(0, 0, inside.cols, inside.rows);
  if (!roi.contains(a) || !roi.contains(b) || !(inside.at<float>(a) > 0) ||
      !(inside.at<float>(b) > 0) || !(depth > 0))
    return {};
  const int w = roi.width, n = roi.width * roi.height;
  cv::Mat off_guide;  // per ROI pixel, its distance to the guide
  if (guide && guide_weight > 0) {
    cv::Mat g(roi.size(), CV_8UC1, cv::Scalar(255));
    for (const cv::Point& p : *guide)
      if (roi.contains(p)) g.at<uchar>(p - roi.tl()) = 0;
    cv::distanceTransform(g, off_guide, cv::DIST_L2, cv::DIST_MASK_3);
  }
  const auto index = [&](cv::Point p) { return (p.y - roi.y) * w + (p.x - roi.x); };
  const auto point = [&](int i) { return cv::Point(roi.x + i % w, roi.y + i / w); };
  std::vector<float> cost(static_cast<size_t>(n), std::numeric_limits<float>::infinity());
  std::vector<int> from(static_cast<size_t>(n), -1);
  using Item = std::pair<float, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  const int start = index(a), goal = index(b);
  cost[start] = 0;
  open.push({0.f, start});
  constexpr float kDiagonal = 1.41421356f;
  while (!open.empty()) {
    const auto [c, i] = open.top();
    open.pop();
    if (c > cost[i]) continue;
    if (i == goal) break;
    const cv::Point p = point(i);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (dx == 0 && dy == 0) continue;
        const cv::Point q(p.x + dx, p.y + dy);
        if (!roi.contains(q)) continue;
        const float d = inside.at<float>(q);
        if (!(d > 0)) continue;
        float weight = 1 + centre_weight * (1 - std::min(d, depth) / depth);
        if (!off_guide.empty())
          weight += guide_weight * std::min(off_guide.at<float>(q - roi.tl()), 2 * depth) / depth;
        const float step = (dx && dy ? kDiagonal : 1.f) * weight;
        const int j = index(q);
        if (c + step < cost[j]) {
          cost[j] = c + step;
          from[j] = i;
          open.push({cost[j], j});
        }
      }
  }
  if (start != goal && from[goal] < 0) return {};
  std::vector<cv::Point> out;
  for (int i = goal; i != -1; i = i == start ? -1 : from[i]) out.push_back(point(i));
  std::reverse(out.begin(), out.end());
  return out;
}

}  // namespace mbest

#include "mbest/core/geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
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

std::vector<cv::Point> path_through_mask(const cv::Mat& mask, cv::Point a, cv::Point b,
                                         cv::Rect roi, float depth, float centre_weight,
                                         const std::vector<cv::Point>* guide, float guide_weight) {
  CV_Assert(mask.type() == CV_8UC1);
  const cv::Rect image(0, 0, mask.cols, mask.rows);
  roi &= image;
  if (!roi.contains(a) || !roi.contains(b) || !mask.at<uint8_t>(a) || !mask.at<uint8_t>(b) ||
      !(depth > 0))
    return {};
  // Each pixel's depth in the mask, exact up to `depth` inside roi: the distance transform
  // of roi grown by more than that.
  const int grow = static_cast<int>(std::ceil(depth)) + 2;
  const cv::Rect grown =
      cv::Rect(roi.x - grow, roi.y - grow, roi.width + 2 * grow, roi.height + 2 * grow) & image;
  cv::Mat inside;
  cv::distanceTransform(mask(grown), inside, cv::DIST_L2, cv::DIST_MASK_3);
  cv::Mat off_guide;  // per roi pixel, its distance to the guide
  if (guide && guide_weight > 0) {
    cv::Mat g(roi.size(), CV_8UC1, cv::Scalar(255));
    for (const cv::Point& p : *guide)
      if (roi.contains(p)) g.at<uint8_t>(p - roi.tl()) = 0;
    cv::distanceTransform(g, off_guide, cv::DIST_L2, cv::DIST_MASK_3);
  }
  // Cost per unit length of each pixel of roi framed by one blocked pixel (0: off the mask),
  // so the search needs no bounds checks.
  const int w = roi.width + 2, h = roi.height + 2;
  std::vector<float> weight(static_cast<size_t>(w) * h, 0.f);
  for (int y = 0; y < roi.height; ++y) {
    const uint8_t* m = mask.ptr<uint8_t>(roi.y + y) + roi.x;
    const float* d = inside.ptr<float>(roi.y + y - grown.y) + (roi.x - grown.x);
    const float* g = off_guide.empty() ? nullptr : off_guide.ptr<float>(y);
    float* out = weight.data() + static_cast<size_t>(y + 1) * w + 1;
    for (int x = 0; x < roi.width; ++x) {
      if (!m[x]) continue;
      out[x] = 1 + centre_weight * (1 - std::min(d[x], depth) / depth);
      if (g) out[x] += guide_weight * std::min(g[x], 2 * depth) / depth;
    }
  }
  const auto index = [&](cv::Point p) { return (p.y - roi.y + 1) * w + (p.x - roi.x + 1); };
  const int start = index(a), goal = index(b);
  const float bx = static_cast<float>(b.x - roi.x + 1), by = static_cast<float>(b.y - roi.y + 1);
  // A*: every step costs at least its length, so the straight distance left to b never
  // overestimates, and b is settled optimally after far fewer pixels than by Dijkstra.
  const auto ahead = [&](int i) {
    return std::hypot(static_cast<float>(i % w) - bx, static_cast<float>(i / w) - by);
  };
  constexpr float kDiagonal = 1.41421356f;
  const int step[8] = {-w - 1, -w, -w + 1, -1, 1, w - 1, w, w + 1};
  const float length[8] = {kDiagonal, 1, kDiagonal, 1, 1, kDiagonal, 1, kDiagonal};
  std::vector<float> cost(weight.size(), std::numeric_limits<float>::infinity());
  std::vector<int> from(weight.size(), -1);
  using Item = std::pair<float, int>;  // cost so far + ahead, pixel
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  cost[start] = 0;
  open.push({ahead(start), start});
  while (!open.empty()) {
    const auto [f, i] = open.top();
    open.pop();
    const float c = cost[i];
    if (f > c + ahead(i) + 1e-3f) continue;  // a stale entry
    if (i == goal) break;
    for (int k = 0; k < 8; ++k) {
      const int j = i + step[k];
      if (weight[j] == 0) continue;
      const float next = c + length[k] * weight[j];
      if (next < cost[j]) {
        cost[j] = next;
        from[j] = i;
        open.push({next + ahead(j), j});
      }
    }
  }
  if (start != goal && from[goal] < 0) return {};
  std::vector<cv::Point> out;
  for (int i = goal; i != -1; i = i == start ? -1 : from[i])
    out.emplace_back(roi.x + i % w - 1, roi.y + i / w - 1);
  std::reverse(out.begin(), out.end());
  return out;
}

}  // namespace mbest

#include "mbest/core/crossing_order.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mbest {

int blur_half_size(float radius) {
  return std::clamp(static_cast<int>(std::floor(radius - 1.5f)), 0, 2);
}

double colour_spread(const cv::Mat& bgr, const std::vector<cv::Point>& path, int half) {
  if (path.empty() || bgr.empty()) return 0;
  double sum[3] = {0, 0, 0}, sq[3] = {0, 0, 0};
  int n = 0;
  for (const cv::Point& p : path) {
    if (p.x < 0 || p.y < 0 || p.x >= bgr.cols || p.y >= bgr.rows) continue;
    double acc[3] = {0, 0, 0};
    int count = 0;
    for (int y = std::max(0, p.y - half); y <= std::min(bgr.rows - 1, p.y + half); ++y) {
      const cv::Vec3b* row = bgr.ptr<cv::Vec3b>(y);
      for (int x = std::max(0, p.x - half); x <= std::min(bgr.cols - 1, p.x + half); ++x) {
        for (int c = 0; c < 3; ++c) acc[c] += row[x][c];
        ++count;
      }
    }
    for (int c = 0; c < 3; ++c) {
      const double v = acc[c] / count;
      sum[c] += v;
      sq[c] += v * v;
    }
    ++n;
  }
  if (n == 0) return 0;
  double spread = 0;
  for (int c = 0; c < 3; ++c) {
    const double mean = sum[c] / n;
    spread += std::sqrt(std::max(0.0, sq[c] / n - mean * mean));
  }
  return spread;
}

std::vector<std::vector<int>> order_crossings(const std::vector<Passage>& passages, int region_count,
                                              const cv::Mat& bgr) {
  std::vector<std::vector<int>> by_region(region_count);
  for (int i = 0; i < static_cast<int>(passages.size()); ++i) by_region[passages[i].region].push_back(i);
  std::vector<std::vector<int>> ordered;
  std::vector<double> score(passages.size(), 0);
  for (auto& list : by_region) {
    if (list.size() < 2) continue;
    // One blur for all strands of a crossing, sized to the thinnest of them.
    float thinnest = std::numeric_limits<float>::max();
    for (int i : list)
      for (float r : {passages[i].from_tangent.radius, passages[i].to_tangent.radius}) thinnest = std::min(thinnest, r);
    const int half = blur_half_size(thinnest);
    for (int i : list) score[i] = bgr.empty() ? passages[i].energy : colour_spread(bgr, passages[i].path, half);
    std::stable_sort(list.begin(), list.end(), [&](int a, int b) { return score[a] < score[b]; });
    ordered.push_back(list);
  }
  return ordered;
}

}  // namespace mbest

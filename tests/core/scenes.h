// Masks drawn in the tests: rods as thick polylines, so each test states its scene in a
// few lines, and a small strict matched DICE to score labels against drawn instances.
#pragma once

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace mbest::test {

// Points of a circular arc, centre c, radius r, from angle a0 to a1 (radians).
inline std::vector<cv::Point> arc(cv::Point2d c, double r, double a0, double a1, int n = 90) {
  std::vector<cv::Point> pts;
  for (int i = 0; i <= n; ++i) {
    const double a = a0 + (a1 - a0) * i / n;
    pts.emplace_back(static_cast<int>(std::lround(c.x + r * std::cos(a))),
                     static_cast<int>(std::lround(c.y + r * std::sin(a))));
  }
  return pts;
}

// Draws the polyline `pts` `width` px wide with value `value` into `img`.
inline void draw_rod(cv::Mat& img, const std::vector<cv::Point>& pts, int width, int value = 255) {
  cv::polylines(img, std::vector<std::vector<cv::Point>>{pts}, false, cv::Scalar::all(value), width,
                cv::LINE_8);
  for (const cv::Point& p : {pts.front(), pts.back()})
    cv::circle(img, p, width / 2, cv::Scalar::all(value), -1);
}

// A straight rod through `c` at `angle_deg`, `length` long.
inline std::vector<cv::Point> line_through(cv::Point2d c, double angle_deg, double length) {
  const double a = angle_deg * M_PI / 180;
  const cv::Point2d d(std::cos(a) * length / 2, std::sin(a) * length / 2);
  return {cv::Point(cv::Point2d(c - d)), cv::Point(cv::Point2d(c + d))};
}

// Strict matched DICE of `pred` (CV_16U labels) against instance masks `gt` (CV_8U, non-zero
// = the instance), by trying every assignment (fine for the few instances of a test).
inline double strict_dice(const std::vector<cv::Mat>& gt, const cv::Mat& pred) {
  double max_label = 0;
  cv::minMaxLoc(pred, nullptr, &max_label);
  const int n = static_cast<int>(gt.size()), m = static_cast<int>(max_label);
  if (n == 0) return m == 0 ? 1 : 0;
  if (m == 0) return 0;
  std::vector<std::vector<double>> d(n, std::vector<double>(m));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const cv::Mat p = pred == (j + 1), g = gt[i] != 0;
      d[i][j] = 2.0 * cv::countNonZero(p & g) / (cv::countNonZero(p) + cv::countNonZero(g));
    }
  const int k = std::max(n, m);
  std::vector<int> perm(k);
  std::iota(perm.begin(), perm.end(), 0);
  double best = 0;
  do {
    double s = 0;
    for (int i = 0; i < n; ++i)
      if (perm[i] < m) s += d[i][perm[i]];
    best = std::max(best, s);
  } while (std::next_permutation(perm.begin(), perm.end()));
  return best / k;
}

// Number of 8-neighbours of p that are in `pixels` (an 8-connectivity check helper).
inline bool eight_connected_chain(const std::vector<cv::Point>& line) {
  for (size_t i = 1; i < line.size(); ++i)
    if (std::abs(line[i].x - line[i - 1].x) > 1 || std::abs(line[i].y - line[i - 1].y) > 1 ||
        line[i] == line[i - 1])
      return false;
  return true;
}

}  // namespace mbest::test

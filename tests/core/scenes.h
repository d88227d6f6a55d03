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

// Two rods `wa` and `wb` px wide along a gentle arc across a 420 x 300 picture, from x = 20 to
// `b_to_x` (rod b) and 400 (rod a): apart at both ends, lying side by side, touching, from
// x = 120 to 300, rod a above. Rod b ends lying along rod a when `b_to_x` is inside that.
struct SideBySide {
  std::vector<cv::Point> a, b;
};
inline SideBySide side_by_side(int wa, int wb, int b_to_x = 400) {
  SideBySide s;
  for (int x = 20; x <= 400; x += 4) {
    const double arc = 150 + 40 * std::sin((x - 20) * M_PI / 380);
    const double apart = x < 120 ? (120 - x) * 0.5 : x > 300 ? (x - 300) * 0.5 : 0;
    s.a.emplace_back(x, static_cast<int>(std::lround(arc - wa / 2.0 - apart)));
    if (x <= b_to_x) s.b.emplace_back(x, static_cast<int>(std::lround(arc + wb / 2.0 + apart)));
  }
  return s;
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

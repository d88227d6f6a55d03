#include "mbest/core/overlay.h"

#include <opencv2/imgproc.hpp>

namespace mbest {

cv::Scalar dlo_colour(int i) {
  static const cv::Scalar kPalette[] = {
      {60, 180, 255}, {255, 120, 40}, {80, 220, 80},  {230, 80, 230}, {40, 230, 230},
      {255, 200, 80}, {120, 80, 255}, {160, 255, 160}, {200, 160, 255}, {80, 160, 200}};
  return kPalette[i % 10];
}

cv::Mat draw_overlay(const cv::Mat& background, const Detection& det) {
  cv::Mat out;
  if (background.channels() == 1)
    cv::cvtColor(background, out, cv::COLOR_GRAY2BGR);
  else
    out = background.clone();
  out *= 0.45;
  for (int y = 0; y < det.labels.rows; ++y) {
    const uint16_t* l = det.labels.ptr<uint16_t>(y);
    cv::Vec3b* o = out.ptr<cv::Vec3b>(y);
    for (int x = 0; x < det.labels.cols; ++x) {
      if (!l[x]) continue;
      const cv::Scalar c = dlo_colour(l[x] - 1);
      for (int k = 0; k < 3; ++k) o[x][k] = cv::saturate_cast<uint8_t>(0.35 * o[x][k] + 0.65 * c[k]);
    }
  }
  for (size_t i = 0; i < det.dlos.size(); ++i) {
    const Dlo& d = det.dlos[i];
    for (const cv::Point& p : d.centerline)
      if (p.inside(cv::Rect(0, 0, out.cols, out.rows))) out.at<cv::Vec3b>(p) = cv::Vec3b(255, 255, 255);
    if (!d.centerline.empty() && !d.closed) cv::circle(out, d.centerline.front(), 4, {255, 255, 255}, -1);
  }
  for (const Crossing& c : det.crossings)
    cv::circle(out, c.location, 7, c.dlos.empty() ? cv::Scalar(255, 255, 255) : dlo_colour(c.dlos[0]), 2);
  return out;
}

}  // namespace mbest

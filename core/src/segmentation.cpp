#include "mbest/core/segmentation.h"

#include <filesystem>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace mbest {

Result<cv::Mat> colour_filter(const cv::Mat& bgr) {
  if (bgr.empty()) return Error{"colour filter: the image is empty"};
  if (bgr.type() != CV_8UC3) return Error{"colour filter: the image must be 8-bit BGR (CV_8UC3)"};
  cv::Mat hsv;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  // Hue bands (OpenCV hue, 0-180) of the tubes of the mbest-real set: red/pink wraps around
  // 0, yellow-green, and green-teal-blue, which is also found at low brightness.
  struct Band {
    int h_lo, h_hi, v_lo;
  };
  static const Band kBands[] = {{0, 20, 75}, {160, 180, 75}, {25, 50, 75}, {50, 120, 20}};
  cv::Mat mask = cv::Mat::zeros(bgr.size(), CV_8UC1), band;
  for (const Band& b : kBands) {
    cv::inRange(hsv, cv::Scalar(b.h_lo, 20, b.v_lo), cv::Scalar(b.h_hi, 255, 255), band);
    mask |= band;
  }
  // Close pin-holes, then open away isolated specks.
  const cv::Mat k = cv::Mat::ones(3, 3, CV_8UC1);
  cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, k);
  cv::morphologyEx(mask, mask, cv::MORPH_OPEN, k);
  return mask;
}

Result<cv::Mat> read_image(const std::string& path) {
  if (!std::filesystem::exists(path)) return Error{path + ": no such file"};
  cv::Mat img = cv::imread(path, cv::IMREAD_COLOR);
  if (img.empty()) return Error{path + ": not a readable image (unknown format or corrupt)"};
  return img;
}

std::string sibling_mask_path(const std::string& image_path, const std::string& folder) {
  const std::filesystem::path image(image_path);
  return (image.parent_path().parent_path() / folder / (image.stem().string() + ".png")).string();
}

Result<cv::Mat> read_mask(const std::string& path, cv::Size expected) {
  if (!std::filesystem::exists(path)) return Error{path + ": no such file"};
  cv::Mat m = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (m.empty()) return Error{path + ": not a readable image (unknown format or corrupt)"};
  if (m.depth() != CV_8U && m.depth() != CV_16U)
    return Error{path + ": mask must be 8- or 16-bit"};
  if (m.channels() > 1) {
    std::vector<cv::Mat> ch;
    cv::split(m, ch);
    cv::Mat any = ch[0] != 0;
    for (size_t i = 1; i < ch.size() && i < 3; ++i) any |= ch[i] != 0;
    m = any;
  } else {
    m = m != 0;
  }
  if (!expected.empty() && m.size() != expected)
    return Error{path + ": mask is " + std::to_string(m.cols) + "x" + std::to_string(m.rows) +
                 " but the image is " + std::to_string(expected.width) + "x" +
                 std::to_string(expected.height)};
  return m;
}

}  // namespace mbest

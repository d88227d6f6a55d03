#include "mbest/core/instance_mask.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "scenes.h"

namespace mbest {
namespace {

TEST(InstanceMask, EveryReachableMaskPixelGoesToTheNearestCenterline) {
  cv::Mat mask = cv::Mat::zeros(100, 100, CV_8UC1);
  cv::rectangle(mask, {10, 10}, {89, 89}, 255, -1);
  std::vector<Dlo> dlos(2);
  for (int y = 10; y < 90; ++y) {
    dlos[0].centerline.emplace_back(30, y);
    dlos[1].centerline.emplace_back(70, y);
  }
  const cv::Mat labels = instance_labels(mask, dlos, {});
  EXPECT_EQ(labels.type(), CV_16UC1);
  EXPECT_EQ(cv::countNonZero(labels), cv::countNonZero(mask));
  EXPECT_EQ(labels.at<uint16_t>(50, 12), 1);
  EXPECT_EQ(labels.at<uint16_t>(50, 45), 1);
  EXPECT_EQ(labels.at<uint16_t>(50, 55), 2);
  EXPECT_EQ(labels.at<uint16_t>(50, 88), 2);
  EXPECT_EQ(labels.at<uint16_t>(5, 5), 0);
}

TEST(InstanceMask, TopBandBelongsToTheTopStrandButNotItsSurroundings) {
  cv::Mat mask = cv::Mat::zeros(100, 100, CV_8UC1);
  cv::rectangle(mask, {0, 40}, {99, 59}, 255, -1);  // horizontal rod, radius 10
  cv::rectangle(mask, {40, 0}, {59, 99}, 255, -1);  // vertical rod
  std::vector<Dlo> dlos(2);
  for (int x = 0; x < 100; ++x) dlos[0].centerline.emplace_back(x, 50);
  for (int y = 0; y < 100; ++y) dlos[1].centerline.emplace_back(50, y);
  TopStrand top{1, {}, {}};
  for (int y = 30; y < 70; ++y) {
    top.path.emplace_back(50, y);
    top.radius.push_back(9.5f);
  }
  const cv::Mat labels = instance_labels(mask, dlos, {top});
  EXPECT_EQ(labels.at<uint16_t>(50, 50), 2);  // the crossing goes to the top strand
  EXPECT_EQ(labels.at<uint16_t>(45, 41), 2);
  EXPECT_EQ(labels.at<uint16_t>(50, 20), 1);  // the horizontal rod away from the crossing
  EXPECT_EQ(labels.at<uint16_t>(50, 80), 1);
  EXPECT_EQ(cv::countNonZero(labels), cv::countNonZero(mask));
}

TEST(InstanceMask, MaskPartsNoCenterlineReachesStayBackground) {
  cv::Mat mask = cv::Mat::zeros(50, 50, CV_8UC1);
  cv::rectangle(mask, {5, 5}, {20, 20}, 255, -1);
  cv::rectangle(mask, {30, 30}, {45, 45}, 255, -1);
  std::vector<Dlo> dlos(1);
  dlos[0].centerline = {{10, 10}, {11, 11}};
  const cv::Mat labels = instance_labels(mask, dlos, {});
  EXPECT_EQ(labels.at<uint16_t>(20, 20), 1);
  EXPECT_EQ(labels.at<uint16_t>(40, 40), 0);
}

}  // namespace
}  // namespace mbest

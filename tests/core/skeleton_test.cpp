#include "mbest/core/skeleton.h"

#include <bitset>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "mbest/core/keypoints.h"
#include "scenes.h"

namespace mbest {
namespace {

int neighbours(const Skeleton& s, cv::Point p) {
  return static_cast<int>(std::bitset<8>(neighbour_code(s.image.ptr<uint8_t>(p.y) + p.x, s.image.step)).count());
}

TEST(Skeleton, StraightRodBecomesOneThinLineInsideTheMask) {
  cv::Mat mask = cv::Mat::zeros(100, 200, CV_8UC1);
  test::draw_rod(mask, {{30, 50}, {170, 50}}, 15);
  const Skeleton s = skeletonize(mask);
  ASSERT_GT(s.pixels.size(), 100u);
  int ends = 0;
  for (const cv::Point& p : s.pixels) {
    EXPECT_TRUE(mask.at<uint8_t>(p)) << p;
    const int n = neighbours(s, p);
    EXPECT_LE(n, 2) << "line pixel with " << n << " neighbours at " << p;
    ends += n == 1;
  }
  EXPECT_EQ(ends, 2);
}

TEST(Skeleton, DiagonalRodHasNoStaircaseJunctions) {
  cv::Mat mask = cv::Mat::zeros(200, 200, CV_8UC1);
  test::draw_rod(mask, {{20, 30}, {180, 170}}, 11);
  const Skeleton s = skeletonize(mask);
  const Keypoints kp = detect_keypoints(s);
  EXPECT_TRUE(kp.junction_pixels.empty()) << kp.junction_pixels.size() << " junction pixels";
  EXPECT_EQ(kp.ends.size(), 2u);
}

TEST(Skeleton, AnnulusKeepsItsHole) {
  cv::Mat mask = cv::Mat::zeros(200, 200, CV_8UC1);
  cv::circle(mask, {100, 100}, 67, 255, -1);  // a thick cv::circle has pinholes: cut the hole
  cv::circle(mask, {100, 100}, 53, 0, -1);
  const Skeleton s = skeletonize(mask);
  const Keypoints kp = detect_keypoints(s);
  EXPECT_TRUE(kp.ends.empty());
  EXPECT_TRUE(kp.junction_pixels.empty());
  EXPECT_GT(s.pixels.size(), 300u);  // about 2 pi 60
}

TEST(Skeleton, SkeletonPixelsAreSortedAndMarkedInTheImage) {
  cv::Mat mask = cv::Mat::zeros(60, 60, CV_8UC1);
  cv::rectangle(mask, {5, 5}, {50, 20}, 255, -1);
  const Skeleton s = skeletonize(mask);
  EXPECT_EQ(static_cast<int>(s.pixels.size()), cv::countNonZero(s.image));
  for (size_t i = 1; i < s.pixels.size(); ++i)
    EXPECT_TRUE(s.pixels[i - 1].y < s.pixels[i].y ||
                (s.pixels[i - 1].y == s.pixels[i].y && s.pixels[i - 1].x < s.pixels[i].x));
}

TEST(Skeleton, EmptyFullAndTinyMasks) {
  EXPECT_TRUE(skeletonize(cv::Mat::zeros(30, 40, CV_8UC1)).pixels.empty());
  const Skeleton full = skeletonize(cv::Mat(30, 40, CV_8UC1, cv::Scalar(255)));
  EXPECT_FALSE(full.pixels.empty());
  EXPECT_EQ(skeletonize(cv::Mat(1, 1, CV_8UC1, cv::Scalar(1))).pixels.size(), 1u);
  EXPECT_EQ(skeletonize(cv::Mat(1, 50, CV_8UC1, cv::Scalar(1))).pixels.size(), 50u);
}

}  // namespace
}  // namespace mbest

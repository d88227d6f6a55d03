#include "mbest/core/geometry.h"

#include <cstdlib>

#include <gtest/gtest.h>

namespace mbest {
namespace {

void expect_chain_on_mask(const std::vector<cv::Point>& path, const cv::Mat& mask) {
  for (size_t k = 0; k < path.size(); ++k) {
    EXPECT_NE(mask.at<uchar>(path[k]), 0) << "pixel " << k << " " << path[k] << " is off the mask";
    if (k > 0) {
      EXPECT_TRUE(eight_adjacent(path[k - 1], path[k])) << "gap before pixel " << k;
    }
  }
}

TEST(Geometry, PathThroughMaskGoesRoundACornerOnTheMask) {
  // An L: a band along the top, then down the right.
  cv::Mat mask = cv::Mat::zeros(100, 100, CV_8UC1);
  mask(cv::Rect(10, 10, 80, 10)).setTo(255);
  mask(cv::Rect(80, 10, 10, 80)).setTo(255);
  const cv::Rect image(0, 0, 100, 100);
  const std::vector<cv::Point> path =
      path_through_mask(mask, {14, 15}, {85, 85}, image, 5, 1);
  ASSERT_GE(path.size(), 2u);
  EXPECT_EQ(path.front(), cv::Point(14, 15));
  EXPECT_EQ(path.back(), cv::Point(85, 85));
  expect_chain_on_mask(path, mask);
}

TEST(Geometry, PathThroughMaskKeepsToTheMiddleOfAWideBand) {
  // A band 21 px wide (rows 10-30); both ends 2 px inside its top edge. The shortest chain
  // runs straight along that edge; weighted to the middle it dips to the centre row.
  cv::Mat mask = cv::Mat::zeros(41, 120, CV_8UC1);
  mask(cv::Rect(0, 10, 120, 21)).setTo(255);
  const cv::Rect image(0, 0, 120, 41);
  const auto row_at_middle = [](const std::vector<cv::Point>& path) {
    for (const cv::Point& p : path)
      if (p.x == 60) return p.y;
    return -1;
  };
  const std::vector<cv::Point> edge = path_through_mask(mask, {2, 12}, {117, 12}, image, 10, 0);
  EXPECT_EQ(row_at_middle(edge), 12);
  const std::vector<cv::Point> middle = path_through_mask(mask, {2, 12}, {117, 12}, image, 10, 1);
  EXPECT_NEAR(row_at_middle(middle), 20, 2);
  expect_chain_on_mask(middle, mask);
}

TEST(Geometry, PathThroughMaskKeepsNearItsGuideWhereTheMaskAllows) {
  // A frame round a hole: from the middle of its left side to the middle of its right side,
  // over the top or under the bottom, both as long. A guide over the top (a curve cutting
  // over the background above the hole) picks the top; one under the bottom, the bottom.
  cv::Mat mask = cv::Mat::zeros(100, 100, CV_8UC1);
  mask(cv::Rect(10, 10, 80, 80)).setTo(255);
  mask(cv::Rect(20, 20, 60, 60)).setTo(0);
  const cv::Rect image(0, 0, 100, 100);
  for (const int side : {-1, 1}) {
    std::vector<cv::Point> guide;
    for (int x = 15; x <= 85; ++x) guide.emplace_back(x, 50 + side * 25);
    const std::vector<cv::Point> path =
        path_through_mask(mask, {15, 50}, {85, 50}, image, 5, 1, &guide, 0.25f);
    ASSERT_FALSE(path.empty());
    expect_chain_on_mask(path, mask);
    for (const cv::Point& p : path) {
      if (p.x == 50) {
        EXPECT_EQ(p.y < 50 ? -1 : 1, side) << "went round the other side";
      }
    }
  }
}

TEST(Geometry, PathThroughMaskIsEmptyWhenNoChainJoinsTheEnds) {
  cv::Mat mask = cv::Mat::zeros(50, 100, CV_8UC1);
  mask(cv::Rect(5, 20, 30, 10)).setTo(255);
  mask(cv::Rect(60, 20, 30, 10)).setTo(255);
  const cv::Rect image(0, 0, 100, 50);
  EXPECT_TRUE(path_through_mask(mask, {10, 25}, {80, 25}, image, 5, 1).empty());  // two pieces
  EXPECT_TRUE(path_through_mask(mask, {10, 25}, {10, 5}, image, 5, 1).empty());   // end off the mask
  // Joined, but only outside the search window.
  mask(cv::Rect(30, 40, 40, 5)).setTo(255);
  mask(cv::Rect(30, 20, 5, 25)).setTo(255);
  mask(cv::Rect(65, 20, 5, 25)).setTo(255);
  EXPECT_FALSE(path_through_mask(mask, {10, 25}, {80, 25}, image, 5, 1).empty());
  EXPECT_TRUE(path_through_mask(mask, {10, 25}, {80, 25}, cv::Rect(0, 15, 100, 20), 5, 1).empty());
}

}  // namespace
}  // namespace mbest

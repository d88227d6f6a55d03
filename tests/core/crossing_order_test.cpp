#include "mbest/core/crossing_order.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "mbest/core/detector.h"
#include "scenes.h"

namespace mbest {
namespace {

TEST(CrossingOrder, UniformPathHasNoSpread) {
  cv::Mat img(50, 50, CV_8UC3, cv::Scalar(30, 200, 90));
  EXPECT_NEAR(colour_spread(img, {{10, 10}, {20, 20}, {49, 49}, {0, 0}}), 0, 1e-9);
  EXPECT_EQ(colour_spread(img, {}), 0);
}

TEST(CrossingOrder, BlurFitsInsideTheStrand) {
  EXPECT_EQ(blur_half_size(9.0f), 2);  // the paper's 5x5 box
  EXPECT_EQ(blur_half_size(3.5f), 2);
  EXPECT_EQ(blur_half_size(3.0f), 1);  // a 6 px cable: 3x3
  EXPECT_EQ(blur_half_size(1.5f), 0);  // hairline: no blur
}

TEST(CrossingOrder, SpreadSumsChannelsOfTheBlurredImage) {
  cv::Mat img = cv::Mat::zeros(60, 60, CV_8UC3);
  img(cv::Rect(30, 0, 30, 60)).setTo(cv::Scalar(0, 0, 100));
  // Far from the edge: blurred values are exactly 0 and 100 in the red channel.
  EXPECT_NEAR(colour_spread(img, {{10, 30}, {50, 30}}), 50, 1e-9);
}

// Two coloured rods; `second_on_top` decides which is drawn last.
void expect_top(bool second_on_top, double angle) {
  cv::Mat img = cv::Mat::zeros(300, 300, CV_8UC3), mask = cv::Mat::zeros(300, 300, CV_8UC1);
  const auto a = test::line_through({150, 150}, 20, 260), b = test::line_through({150, 150}, 20 + angle, 260);
  const cv::Scalar ca(60, 200, 60), cb(200, 80, 220);
  for (int k = 0; k < 2; ++k) {
    const bool draw_b = (k == 1) == second_on_top;
    cv::Mat m = cv::Mat::zeros(300, 300, CV_8UC1);
    test::draw_rod(m, draw_b ? b : a, 15);
    img.setTo(draw_b ? cb : ca, m);
    mask |= m;
  }
  auto r = detect(mask, img);
  ASSERT_TRUE(r.ok());
  const Detection& d = r.value();
  ASSERT_EQ(d.crossings.size(), 1u);
  // The DLO on top owns the crossing centre in the labels and has the top colour there.
  const int top = d.crossings[0].dlos[0];
  const cv::Point c(150, 150);
  EXPECT_EQ(d.labels.at<uint16_t>(c), top + 1);
  const cv::Point probe = d.dlos[top].centerline[d.dlos[top].centerline.size() / 5];
  const cv::Vec3b colour = img.at<cv::Vec3b>(probe);
  EXPECT_EQ(colour, second_on_top ? cv::Vec3b(200, 80, 220) : cv::Vec3b(60, 200, 60));
}

TEST(CrossingOrder, StrandDrawnLastIsOnTop) {
  for (double angle : {30.0, 70.0}) {
    expect_top(true, angle);
    expect_top(false, angle);
  }
}

}  // namespace
}  // namespace mbest

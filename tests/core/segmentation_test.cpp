#include "mbest/core/segmentation.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace mbest {
namespace {

namespace fs = std::filesystem;

TEST(Segmentation, ColourFilterKeepsColouredTubesOnBlack) {
  cv::Mat img = cv::Mat::zeros(100, 100, CV_8UC3);
  cv::line(img, {10, 20}, {90, 20}, cv::Scalar(140, 130, 230), 9);  // pink (BGR)
  cv::line(img, {10, 50}, {90, 50}, cv::Scalar(90, 170, 60), 9);    // green
  cv::line(img, {10, 80}, {90, 80}, cv::Scalar(20, 20, 20), 9);     // dark grey: background
  auto m = colour_filter(img);
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m.value().at<uint8_t>(20, 50), 255);
  EXPECT_EQ(m.value().at<uint8_t>(50, 50), 255);
  EXPECT_EQ(m.value().at<uint8_t>(80, 50), 0);
  EXPECT_EQ(m.value().at<uint8_t>(35, 50), 0);
}

TEST(Segmentation, ColourFilterRejectsWrongInput) {
  EXPECT_FALSE(colour_filter(cv::Mat()).ok());
  EXPECT_FALSE(colour_filter(cv::Mat::zeros(5, 5, CV_8UC1)).ok());
}

TEST(Segmentation, ReadErrorsNameTheFile) {
  const fs::path dir = fs::temp_directory_path() / "mbest_segmentation_test";
  fs::create_directories(dir);
  const std::string corrupt = (dir / "corrupt.png").string();
  std::ofstream(corrupt) << "not a png";
  auto a = read_image(corrupt);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.error().message.find("corrupt.png"), std::string::npos);
  auto b = read_image((dir / "missing.jpg").string());
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().message.find("no such file"), std::string::npos);

  const std::string mask = (dir / "mask.png").string();
  cv::Mat m = cv::Mat::zeros(20, 30, CV_16UC1);
  m.at<uint16_t>(3, 4) = 900;
  cv::imwrite(mask, m);
  auto wrong = read_mask(mask, cv::Size(40, 20));
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.error().message.find("30x20"), std::string::npos);
  auto ok = read_mask(mask, cv::Size(30, 20));
  ASSERT_TRUE(ok.ok());
  EXPECT_EQ(ok.value().type(), CV_8UC1);
  EXPECT_EQ(cv::countNonZero(ok.value()), 1);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mbest

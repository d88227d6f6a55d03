#include "mbest/core/resolution.h"

#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "mbest/core/detector.h"
#include "mbest/core/segmentation.h"
#include "scenes.h"

namespace mbest {
namespace {

TEST(Resolution, HalfResolutionKeepsBlocksAtLeastHalfSet) {
  cv::Mat m = cv::Mat::zeros(5, 5, CV_8UC1);  // odd size: last row and column are 1 px blocks
  m.at<uint8_t>(0, 0) = m.at<uint8_t>(1, 1) = 255;  // block (0,0): 2 of 4 -> set
  m.at<uint8_t>(0, 2) = 255;                        // block (1,0): 1 of 4 -> clear
  m.at<uint8_t>(4, 4) = 9;                          // block (2,2): 1 of 1 -> set
  const cv::Mat h = half_resolution(m);
  ASSERT_EQ(h.size(), cv::Size(3, 3));
  EXPECT_EQ(h.at<uint8_t>(0, 0), 1);
  EXPECT_EQ(h.at<uint8_t>(0, 1), 0);
  EXPECT_EQ(h.at<uint8_t>(2, 2), 1);
  EXPECT_EQ(cv::countNonZero(h), 2);
}

DetectorConfig speed_mode() {
  DetectorConfig c;
  c.half_resolution_radius = 6;
  return c;
}

bool ran_stage(const Detection& d, const std::string& stage) {
  for (const StageTime& s : d.timings)
    if (s.stage == stage) return true;
  return false;
}

TEST(Resolution, SpeedModeGivesFullResolutionCenterlinesAndRadii) {
  cv::Mat mask = cv::Mat::zeros(120, 300, CV_8UC1);
  test::draw_rod(mask, {{20, 60}, {280, 60}}, 15);
  auto r = detect(mask, cv::Mat(), speed_mode());
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(ran_stage(r.value(), "half_resolution"));
  ASSERT_EQ(r.value().dlos.size(), 1u);
  const Dlo& d = r.value().dlos[0];
  EXPECT_TRUE(test::eight_connected_chain(d.centerline));
  EXPECT_EQ(d.radius.size(), d.centerline.size());
  EXPECT_NEAR(d.radius[d.radius.size() / 2], (15 + 3) / 2.0, 0.5);
  for (const cv::Point& p : d.centerline) EXPECT_NEAR(p.y, 60, 1) << p;
}

TEST(Resolution, ThinDlosFallBackToFullResolution) {
  cv::Mat mask = cv::Mat::zeros(120, 300, CV_8UC1);
  test::draw_rod(mask, {{20, 60}, {280, 60}}, 5);
  auto r = detect(mask, cv::Mat(), speed_mode());
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(ran_stage(r.value(), "skeleton_full_resolution"));
  EXPECT_EQ(r.value().dlos.size(), 1u);
}

TEST(Resolution, SpeedModeOnDevPhotos) {
  namespace fs = std::filesystem;
  for (const char* tier : {"S2", "S3"}) {
    const fs::path root = fs::path(MBEST_SHARED_DIR) / "datasets/mbest-real" / tier;
    if (!fs::exists(root)) GTEST_SKIP() << root << " not found";
    for (int i : {0, 7, 22}) {
      auto img = read_image((root / "images" / ("img" + std::to_string(i) + ".jpg")).string());
      ASSERT_TRUE(img.ok());
      auto det = detect(colour_filter(img.value()).value(), img.value(), speed_mode());
      ASSERT_TRUE(det.ok());
      const cv::Mat labels =
          cv::imread((root / "labels" / ("img" + std::to_string(i) + ".png")).string(), cv::IMREAD_UNCHANGED);
      const int n = tier[1] - '0';
      std::vector<cv::Mat> gt;
      for (int id = 1; id <= n; ++id) gt.push_back(labels == id);
      EXPECT_EQ(static_cast<int>(det.value().dlos.size()), n) << tier << " img" << i;
      EXPECT_GT(test::strict_dice(gt, det.value().labels), 0.98) << tier << " img" << i;
    }
  }
}

}  // namespace
}  // namespace mbest

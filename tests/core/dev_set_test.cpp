// End-to-end on a few photos of ../shared/datasets/mbest-real (skipped where it is absent).
#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "mbest/core/detector.h"
#include "mbest/core/segmentation.h"
#include "scenes.h"

namespace mbest {
namespace {

namespace fs = std::filesystem;

struct Case {
  const char* tier;
  int image;
  int dlos;
};

class DevSet : public ::testing::TestWithParam<Case> {};

TEST_P(DevSet, MatchesTheLabelsClosely) {
  const Case c = GetParam();
  const fs::path root = fs::path(MBEST_SHARED_DIR) / "datasets/mbest-real" / c.tier;
  const fs::path image = root / "images" / ("img" + std::to_string(c.image) + ".jpg");
  if (!fs::exists(image)) GTEST_SKIP() << image << " not found";
  auto img = read_image(image.string());
  ASSERT_TRUE(img.ok());
  auto mask = colour_filter(img.value());
  ASSERT_TRUE(mask.ok());
  auto det = detect(mask.value(), img.value());
  ASSERT_TRUE(det.ok());
  EXPECT_EQ(static_cast<int>(det.value().dlos.size()), c.dlos);

  const cv::Mat labels = cv::imread((root / "labels" / ("img" + std::to_string(c.image) + ".png")).string(),
                                    cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(labels.empty());
  std::vector<cv::Mat> gt;
  for (int id = 1; id <= c.dlos; ++id) gt.push_back(labels == id);
  EXPECT_GT(test::strict_dice(gt, det.value().labels), 0.98);
}

// img24 of S1 is a self-loop whose crossing is shallow (its two Ys are 117 px apart);
// S3 img0 and img22 have self-loops and six crossings.
INSTANTIATE_TEST_SUITE_P(Photos, DevSet,
                         ::testing::Values(Case{"S1", 24, 1}, Case{"S2", 5, 2}, Case{"S3", 0, 3},
                                           Case{"S3", 22, 3}),
                         [](const auto& info) {
                           return std::string(info.param.tier) + "_img" + std::to_string(info.param.image);
                         });

}  // namespace
}  // namespace mbest

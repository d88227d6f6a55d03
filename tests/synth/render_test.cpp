#include "mbest/synth/render.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "mbest/synth/config.h"

namespace mbest::synth {
namespace {

// Flat pure colours (rod k in channel k), black background, no camera effects: the
// picture's channel k is then exactly rod k's visible coverage, and the label rule says
// label == k + 1 exactly when that channel is >= 128 (coverage >= 0.5).
SynthConfig flat_config() {
  nlohmann::json over = {{"scene", {{"rods", {3, 3}}, {"planned_crossings", 2}, {"self_loop", 1},
                                    {"crossing_angle_deg", {3, 60}}, {"complexity", {0.4, 0.9}}}},
                         {"render", {{"shading", 0}, {"glare", 0}, {"shadow", 0},
                                     {"background", {{"types", {"solid"}}, {"color_rgb", {0, 0, 0}}}}}},
                         {"camera", {{"blur_sigma", {0, 0}}, {"noise_sigma", {0, 0}}, {"exposure", {1, 1}}}}};
  return make_config("s3", over, "test").value();
}

TEST(Render, LabelsAndPictureAgreePixelForPixel) {
  const SynthConfig config = flat_config();
  int overlap_pixels = 0, crossings_checked = 0;
  for (int seed = 0; seed < 5; ++seed) {
    Rng rng(scene_seed(3, seed));
    Scene scene = compose_scene(config, rng);
    ASSERT_EQ(scene.rods.size(), 3u);
    for (int k = 0; k < 3; ++k) {
      cv::Vec3b rgb(0, 0, 0);
      rgb[2 - k] = 255;  // BGR channel k
      scene.rods[k].color_rgb = rgb;
    }
    const RenderedScene r = render_scene(scene, config, rng).value();
    ASSERT_EQ(r.labels.type(), CV_16UC1);
    for (int y = 0; y < r.image.rows; ++y) {
      for (int x = 0; x < r.image.cols; ++x) {
        const cv::Vec3b p = r.image.at<cv::Vec3b>(y, x);
        const int label = r.labels.at<ushort>(y, x);
        int present = 0;
        for (int k = 0; k < 3; ++k) {
          present += p[k] > 0;
          ASSERT_EQ(label == k + 1, p[k] >= 128) << "pixel " << x << "," << y << " seed " << seed;
        }
        overlap_pixels += present >= 2;
      }
    }
    // Where two rods fully cover the crossing pixel, the label is the recorded top.
    for (const CrossingAnnotation& c : r.crossings) {
      if (c.rod_a == c.rod_b) continue;
      const cv::Point q(static_cast<int>(std::lround(c.location.x)), static_cast<int>(std::lround(c.location.y)));
      if (!cv::Rect(0, 0, r.image.cols, r.image.rows).contains(q)) continue;
      const cv::Vec3b p = r.image.at<cv::Vec3b>(q);
      const int top_channel = c.top - 1;
      int covering = 0;
      for (const cv::Mat& m : r.amodal) covering += m.at<uchar>(q) > 0;
      // Both rods cover the pixel and no third rod does (it could lie above both).
      if (r.amodal[c.rod_a - 1].at<uchar>(q) && r.amodal[c.rod_b - 1].at<uchar>(q) && covering == 2) {
        EXPECT_EQ(r.labels.at<ushort>(q), c.top) << "seed " << seed << " rods " << c.rod_a << "," << c.rod_b << " at " << c.location << " pixel " << p;
        EXPECT_GE(p[top_channel], 128);
        ++crossings_checked;
      }
    }
  }
  EXPECT_GT(overlap_pixels, 500);  // the test really exercises stacked rods
  EXPECT_GT(crossings_checked, 5);
}

TEST(Render, AmodalMasksContainTheVisibleLabels) {
  const SynthConfig config = flat_config();
  Rng rng(scene_seed(9, 0));
  const Scene scene = compose_scene(config, rng);
  const RenderedScene r = render_scene(scene, config, rng).value();
  for (size_t k = 0; k < scene.rods.size(); ++k) {
    const cv::Mat visible = r.labels == static_cast<int>(k + 1);
    EXPECT_EQ(cv::countNonZero(visible & ~r.amodal[k]), 0);
    EXPECT_GE(cv::countNonZero(r.amodal[k]), cv::countNonZero(visible));
  }
}

}  // namespace
}  // namespace mbest::synth

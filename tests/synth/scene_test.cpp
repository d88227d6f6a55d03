#include "mbest/synth/scene.h"

#include <cmath>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "mbest/synth/config.h"

namespace mbest::synth {
namespace {

SceneRod straight(cv::Point2d from, double angle_deg, int length, double width = 10) {
  SceneRod r;
  r.width = width;
  const cv::Point2d d(std::cos(angle_deg * M_PI / 180), std::sin(angle_deg * M_PI / 180));
  for (int i = 0; i <= length; ++i) r.centerline.push_back(from + d * static_cast<double>(i));
  return r;
}

TEST(Crossings, TwoStraightRodsCrossOnceAtTheirAngle) {
  const std::vector<SceneRod> rods = {straight({100, 200}, 0, 400), straight({200.5, 100.5}, 63, 300)};
  const auto x = find_crossings(rods, 640, 480);
  ASSERT_EQ(x.size(), 1u);
  // Rod 2 meets y = 200 after 99.5 / sin(63 deg) px.
  const double t = 99.5 / std::sin(63 * M_PI / 180);
  const cv::Point2d expected(200.5 + t * std::cos(63 * M_PI / 180), 200);
  EXPECT_NEAR(x[0].location.x, expected.x, 1e-6);
  EXPECT_NEAR(x[0].location.y, expected.y, 1e-6);
  EXPECT_NEAR(x[0].angle_deg, 63, 1e-6);
  EXPECT_EQ(x[0].rod_a, 1);
  EXPECT_EQ(x[0].rod_b, 2);
  EXPECT_EQ(x[0].arc_index_a, static_cast<int>(std::lround(expected.x - 100)));
  EXPECT_EQ(x[0].arc_index_b, static_cast<int>(std::lround(t)));
}

TEST(Crossings, NearParallelAndOutsideAndSideBySide) {
  // 4 degrees apart: still one crossing.
  EXPECT_EQ(find_crossings({straight({0, 100}, 0, 600), straight({0, 80}, 4, 600)}, 640, 480).size(), 1u);
  // Side by side, never touching centerlines: none.
  EXPECT_TRUE(find_crossings({straight({0, 100}, 0, 600), straight({0, 113}, 0, 600)}, 640, 480).empty());
  // Crossing outside the image is not reported.
  EXPECT_TRUE(find_crossings({straight({0, 100}, 0, 600), straight({500, 0}, 90, 300)}, 400, 300).empty());
}

TEST(Crossings, LoopCrossesItself) {
  // A loop: a circle of radius 40 entered and left along a line through its bottom.
  SceneRod r;
  r.width = 8;
  double heading = 0;
  cv::Point2d x(50, 300);
  for (int i = 0; i < 600; ++i) {
    r.centerline.push_back(x);
    const bool in_loop = i >= 200 && i < 200 + 2 * M_PI * 40 + 20;
    heading += in_loop ? -1 / 40.0 : 0;
    x += cv::Point2d(std::cos(heading), std::sin(heading));
  }
  const auto xs = find_crossings({r}, 800, 600);
  ASSERT_GE(xs.size(), 1u);
  EXPECT_EQ(xs[0].rod_a, 1);
  EXPECT_EQ(xs[0].rod_b, 1);
  EXPECT_GT(std::abs(xs[0].arc_index_b - xs[0].arc_index_a), 100);
}

TEST(Compose, RecordedCrossingsLieOnBothStrands) {
  SynthConfig config = preset_config("stress").value();
  for (int seed = 0; seed < 4; ++seed) {
    Rng rng(scene_seed(11, seed));
    const Scene s = compose_scene(config, rng);
    ASSERT_GE(s.rods.size(), 4u);
    for (const CrossingAnnotation& c : s.crossings) {
      const auto& a = s.rods[c.rod_a - 1].centerline;
      const auto& b = s.rods[c.rod_b - 1].centerline;
      EXPECT_LT(cv::norm(a[c.arc_index_a] - c.location), 1.0);
      EXPECT_LT(cv::norm(b[c.arc_index_b] - c.location), 1.0);
      EXPECT_GE(c.angle_deg, 0);
      EXPECT_LE(c.angle_deg, 90);
      EXPECT_TRUE(c.top == c.rod_a || c.top == c.rod_b);
    }
    EXPECT_EQ(s.crossings.size(), find_crossings(s.rods, s.width, s.height).size());
  }
}

TEST(Compose, PlannedNearParallelCrossingsHaveSmallAngles) {
  // One planned crossing at 3-20 degrees between two gentle rods: the crossing made by
  // the pin is there, at about the drawn angle.
  SynthConfig config = make_config("s2", {{"scene", {{"planned_crossings", 1}, {"crossing_angle_deg", {3, 20}},
                                                     {"self_loop", 0}, {"complexity", {0.1, 0.2}}}}},
                                   "test").value();
  int near_parallel = 0;
  for (int seed = 0; seed < 6; ++seed) {
    Rng rng(scene_seed(5, seed));
    const Scene s = compose_scene(config, rng);
    for (const CrossingAnnotation& c : s.crossings) near_parallel += c.angle_deg <= 22;
  }
  EXPECT_GE(near_parallel, 5);
}

}  // namespace
}  // namespace mbest::synth

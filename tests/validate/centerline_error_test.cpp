#include "mbest/validate/centerline_error.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>
#include <algorithm>

#include <gtest/gtest.h>

namespace mbest::validate {
namespace {

TEST(CenterlineError, DistanceIsToSegmentsNotOnlyVertices) {
  const Polyline line{{{0, 0}, {10, 0}}, false};
  const std::vector<double> d = distances_to_polyline({{5, 3}, {-4, 3}, {10, 0}}, line);
  ASSERT_EQ(d.size(), 3u);
  EXPECT_DOUBLE_EQ(d[0], 3.0);
  EXPECT_DOUBLE_EQ(d[1], 5.0);
  EXPECT_DOUBLE_EQ(d[2], 0.0);
}

TEST(CenterlineError, ClosedPolylineIncludesTheSeam) {
  const std::vector<cv::Point2d> square = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  EXPECT_DOUBLE_EQ(distances_to_polyline({{-2, 5}}, Polyline{square, true})[0], 2.0);
  EXPECT_NEAR(distances_to_polyline({{-2, 5}}, Polyline{square, false})[0], std::sqrt(29.0), 1e-12);
}

TEST(CenterlineError, MatchesBruteForceOnRandomPolylines) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-50, 250), step(-6, 6);
  for (int trial = 0; trial < 50; ++trial) {
    Polyline line{{}, trial % 2 == 0};
    cv::Point2d p(coord(rng), coord(rng));
    const bool jumps = trial % 5 == 0;  // long segments crossing many cells
    const int n = 1 + static_cast<int>(rng() % (jumps ? 12 : 120));
    for (int i = 0; i < n; ++i) {
      line.points.push_back(p);
      p += jumps ? cv::Point2d(coord(rng), coord(rng)) : cv::Point2d(step(rng), step(rng));
    }
    std::vector<cv::Point2d> queries;
    for (int q = 0; q < 40; ++q) queries.emplace_back(coord(rng) * 2, coord(rng) * 2);
    const std::vector<double> d = distances_to_polyline(queries, line);
    for (size_t q = 0; q < queries.size(); ++q) {
      double best = std::numeric_limits<double>::infinity();
      const size_t segments = n == 1 ? 1 : (line.closed ? n : n - 1);
      for (size_t s = 0; s < segments; ++s) {
        const cv::Point2d a = line.points[s], b = line.points[n == 1 ? 0 : (s + 1) % n];
        const double len2 = (b - a).dot(b - a);
        const double t = len2 > 0 ? std::clamp((queries[q] - a).dot(b - a) / len2, 0.0, 1.0) : 0;
        best = std::min(best, cv::norm(queries[q] - (a + t * (b - a))));
      }
      EXPECT_NEAR(d[q], best, 1e-9) << "trial " << trial << " query " << q;
    }
  }
}

TEST(CenterlineError, GroundTruthOutsideThePictureIsNotCounted) {
  synth::SceneAnnotation scene;
  scene.width = 10;
  scene.height = 10;
  synth::RodAnnotation a;
  a.id = 1;
  for (int x = -5; x <= 5; ++x) a.centerline.emplace_back(x, 2);  // 6 samples inside
  scene.rods = {a};
  DiceScore dice;
  dice.gt_ids = {1};
  dice.matched_pred = {1};
  const CenterlineDistances d =
      centerline_distances(scene, {Polyline{{{0, 2}, {5, 2}}, false}}, dice);
  EXPECT_EQ(d.gt_to_pred, std::vector<double>(6, 0.0));
}

TEST(CenterlineError, EmptyTargetIsInfinitelyFar) {
  EXPECT_TRUE(std::isinf(distances_to_polyline({{1, 1}}, Polyline{})[0]));
}

TEST(CenterlineError, BothWaysOnlyForMatchedRods) {
  synth::SceneAnnotation scene;
  synth::RodAnnotation a, b;
  a.id = 1;
  b.id = 2;
  for (int x = 0; x <= 20; ++x) a.centerline.emplace_back(x, 0), b.centerline.emplace_back(x, 50);
  scene.rods = {a, b};
  DiceScore dice;
  dice.gt_ids = {1, 2};
  dice.matched_pred = {2, 0};  // rod 1 found as label 2, rod 2 missed
  const std::vector<Polyline> predicted = {{{{0, 50}, {20, 50}}, false},
                                           {{{0, 1}, {10, 1}}, false}};
  const CenterlineDistances d = centerline_distances(scene, predicted, dice);
  EXPECT_EQ(d.pred_to_gt, (std::vector<double>{1.0, 1.0}));
  ASSERT_EQ(d.gt_to_pred.size(), 21u);
  EXPECT_DOUBLE_EQ(d.gt_to_pred[0], 1.0);
  EXPECT_NEAR(d.gt_to_pred[20], std::hypot(10.0, 1.0), 1e-12);
}

TEST(CenterlineError, SummaryMeanAndInterpolatedP95) {
  std::vector<double> v;
  for (int i = 0; i <= 100; ++i) v.push_back(i);
  const DistanceSummary s = summarise(v);
  EXPECT_EQ(s.count, 101);
  EXPECT_DOUBLE_EQ(s.mean, 50.0);
  EXPECT_DOUBLE_EQ(s.p95, 95.0);
  EXPECT_DOUBLE_EQ(summarise({1.0, 3.0}).p95, 1.0 + 0.95 * 2.0);
  EXPECT_EQ(summarise({}).count, 0);
}

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(CenterlineError, ReadsDetectJson) {
  const std::string path =
      write_temp("cl_ok.json", R"({"dlos": [{"centerline": [[1, 2], [3, 4]], "closed": true},
                                            {"centerline": []}], "crossings": []})");
  Result<std::vector<Polyline>> r = read_predicted_centerlines(path);
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r.value().size(), 2u);
  EXPECT_EQ(r.value()[0].points[1], cv::Point2d(3, 4));
  EXPECT_TRUE(r.value()[0].closed);
  EXPECT_TRUE(r.value()[1].points.empty());
}

TEST(CenterlineError, BadDetectJsonNamesFileAndField) {
  const std::string bad_point = write_temp("cl_bad.json", R"({"dlos": [{"centerline": [[1]]}]})");
  Result<std::vector<Polyline>> r = read_predicted_centerlines(bad_point);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find(bad_point), std::string::npos);
  EXPECT_NE(r.error().message.find("dlos[0].centerline"), std::string::npos);
  EXPECT_FALSE(read_predicted_centerlines(write_temp("cl_trunc.json", "{\"dlos\": [")).ok());
  EXPECT_FALSE(read_predicted_centerlines(write_temp("cl_nodlos.json", "{}")).ok());
  EXPECT_FALSE(read_predicted_centerlines(::testing::TempDir() + "no_such.json").ok());
}

}  // namespace
}  // namespace mbest::validate

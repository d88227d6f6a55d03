#include "mbest/core/keypoints.h"

#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "scenes.h"

namespace mbest {
namespace {

SkeletonGraph graph_of(const cv::Mat& mask) {
  Skeleton s = skeletonize(mask);
  SkeletonGraph g = build_skeleton_graph(s, detect_keypoints(s));
  measure_radii(g, mask);
  return g;
}

int count(const SkeletonGraph& g, Node::Kind kind) {
  int n = 0;
  for (const Node& node : g.nodes) n += node.kind == kind;
  return n;
}

TEST(Keypoints, RodIsTwoEndsAndOneBranch) {
  cv::Mat mask = cv::Mat::zeros(100, 200, CV_8UC1);
  test::draw_rod(mask, {{30, 50}, {170, 50}}, 15);
  const SkeletonGraph g = graph_of(mask);
  EXPECT_EQ(count(g, Node::Kind::end), 2);
  EXPECT_EQ(count(g, Node::Kind::junction), 0);
  ASSERT_EQ(g.branches.size(), 1u);
  EXPECT_TRUE(test::eight_connected_chain(g.branches[0].pixels));
  EXPECT_GT(g.branches[0].length, 100);
}

TEST(Keypoints, XCrossingIsOneJunctionWithFourBranches) {
  cv::Mat mask = cv::Mat::zeros(200, 200, CV_8UC1);
  test::draw_rod(mask, test::line_through({100, 100}, 30, 170), 13);
  test::draw_rod(mask, test::line_through({100, 100}, 120, 170), 13);
  const SkeletonGraph g = graph_of(mask);
  EXPECT_EQ(count(g, Node::Kind::end), 4);
  int degree_sum = 0;
  for (const Node& n : g.nodes)
    if (n.kind == Node::Kind::junction) degree_sum += n.degree();
  EXPECT_EQ(degree_sum, 4 + 2 * (count(g, Node::Kind::junction) - 1))
      << "junctions of an X form a tree with four leaves";
}

TEST(Keypoints, RingWithoutNodesIsARing) {
  cv::Mat mask = cv::Mat::zeros(200, 200, CV_8UC1);
  cv::circle(mask, {100, 100}, 67, 255, -1);  // a thick cv::circle has pinholes: cut the hole
  cv::circle(mask, {100, 100}, 53, 0, -1);
  const SkeletonGraph g = graph_of(mask);
  EXPECT_TRUE(g.nodes.empty());
  ASSERT_EQ(g.rings.size(), 1u);
  EXPECT_TRUE(test::eight_connected_chain(g.rings[0]));
  EXPECT_EQ(g.ring_radius[0].size(), g.rings[0].size());
}

TEST(Keypoints, DistanceToBackgroundIsTheL2DistanceTransform) {
  cv::Mat mask = cv::Mat::zeros(120, 160, CV_8UC1);
  test::draw_rod(mask, {{10, 20}, {150, 100}}, 21);
  cv::circle(mask, {40, 90}, 25, 255, -1);
  cv::Mat padded, dt;  // a one-pixel zero border: outside the image is background
  cv::copyMakeBorder(mask, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, 0);
  cv::distanceTransform(padded, dt, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  std::mt19937 rng(7);
  int checked = 0;
  for (int k = 0; k < 3000; ++k) {
    const cv::Point p(static_cast<int>(rng() % 160), static_cast<int>(rng() % 120));
    EXPECT_NEAR(distance_to_background(mask, p), dt.at<float>(p.y + 1, p.x + 1), 1e-3) << p;
    checked += mask.at<uint8_t>(p) != 0;
  }
  EXPECT_GT(checked, 100);
}

TEST(Keypoints, WidestRadiusIgnoresJunctionsButSeesTheWidestDlo) {
  cv::Mat mask = cv::Mat::zeros(300, 300, CV_8UC1);
  test::draw_rod(mask, test::line_through({150, 150}, 0, 260), 9);
  test::draw_rod(mask, test::line_through({150, 150}, 90, 260), 21);
  SkeletonGraph g;
  Skeleton s = skeletonize(mask);
  g = build_skeleton_graph(s, detect_keypoints(s));
  const float r = measure_radii(g, mask);
  // A line of thickness t is t + 2 px wide; its middle pixel is (t + 3) / 2 from background.
  EXPECT_NEAR(r, (21 + 3) / 2.0, 0.5);
}

// A short wide piece (as where two rods lie side by side) sets the widest radius but not
// the radius that 95 % of the skeleton's length stays within: the long thin rod's.
TEST(Keypoints, LengthQuantileRadiusIsTheLongRodsNotAShortWidePiecesOne) {
  cv::Mat mask = cv::Mat::zeros(300, 600, CV_8UC1);
  test::draw_rod(mask, test::line_through({300, 150}, 0, 560), 9);
  test::draw_rod(mask, test::line_through({300, 150}, 90, 30), 21);
  Skeleton s = skeletonize(mask);
  SkeletonGraph g = build_skeleton_graph(s, detect_keypoints(s));
  const float widest = measure_radii(g, mask);
  EXPECT_NEAR(widest, (21 + 3) / 2.0, 0.5);
  EXPECT_NEAR(length_quantile_radius(g, 0.95), (9 + 3) / 2.0, 0.5);
  EXPECT_FLOAT_EQ(length_quantile_radius(g, 1.0), widest);
  EXPECT_EQ(length_quantile_radius(SkeletonGraph(), 0.95), 0.0f);
}

}  // namespace
}  // namespace mbest

#include "mbest/core/prune.h"

#include <gtest/gtest.h>

#include "scenes.h"

namespace mbest {
namespace {

TEST(Prune, BumpOnTheSideOfARodIsASplitEnd) {
  cv::Mat mask = cv::Mat::zeros(100, 300, CV_8UC1);
  test::draw_rod(mask, {{20, 50}, {280, 50}}, 15);
  cv::rectangle(mask, {140, 38}, {150, 57}, 255, -1);  // a jagged bump
  cv::rectangle(mask, {143, 34}, {147, 40}, 255, -1);
  Skeleton s = skeletonize(mask);
  SkeletonGraph g = build_skeleton_graph(s, detect_keypoints(s));
  const float r = measure_radii(g, mask);
  int spurs_before = 0;
  for (const Branch& b : g.branches) spurs_before += b.length < 2 * r;
  ASSERT_GE(spurs_before, 1) << "the bump should make a spur";
  EXPECT_GE(prune_split_ends(g, 2 * r, mask.size()), 1);
  for (const Branch& b : g.branches)
    if (b.alive) {
      EXPECT_GE(b.length, 2 * r);
    }
}

TEST(Prune, ShortIsolatedPieceAndLongBranchesStay) {
  cv::Mat mask = cv::Mat::zeros(100, 300, CV_8UC1);
  test::draw_rod(mask, {{20, 30}, {280, 30}}, 11);
  test::draw_rod(mask, {{100, 75}, {108, 75}}, 11);
  Skeleton s = skeletonize(mask);
  SkeletonGraph g = build_skeleton_graph(s, detect_keypoints(s));
  const float r = measure_radii(g, mask);
  EXPECT_EQ(prune_split_ends(g, 2 * r, mask.size()), 0);
}

TEST(Prune, ForkedEndKeepsItsLongerSpur) {
  // A rod whose end splits into two short prongs: one goes, one stays as the end.
  cv::Mat mask = cv::Mat::zeros(100, 300, CV_8UC1);
  test::draw_rod(mask, {{60, 50}, {280, 50}}, 15);
  cv::rectangle(mask, {30, 38}, {62, 62}, 255, -1);
  Skeleton s = skeletonize(mask);
  SkeletonGraph g = build_skeleton_graph(s, detect_keypoints(s));
  const float r = measure_radii(g, mask);
  prune_split_ends(g, 2 * r, mask.size());
  int ends = 0;
  for (const Node& n : g.nodes) ends += n.kind == Node::Kind::end && n.alive;
  EXPECT_EQ(ends, 2);
}

TEST(Prune, ForkedTipWhoseProngsShowTheShadedEdgeKeepsOneProng) {
  // A red rod with a notched square tip, dark with shading as a lit tube's end is: the
  // skeleton forks into two short prongs that run into the dark corners, so their colour
  // differs from the rod's. That is no second DLO (only the trunk runs on through the
  // fork), so one prong goes, as it does without colour.
  cv::Mat mask = cv::Mat::zeros(100, 300, CV_8UC1), bgr = cv::Mat::zeros(100, 300, CV_8UC3);
  cv::rectangle(mask, {30, 42}, {280, 58}, 255, -1);
  const std::vector<cv::Point> notch = {{30, 46}, {30, 54}, {34, 50}};
  cv::fillConvexPoly(mask, notch, 0);
  bgr.setTo(cv::Scalar(40, 40, 200), mask);
  cv::Mat tip = cv::Mat::zeros(mask.size(), CV_8UC1);
  cv::rectangle(tip, {30, 38}, {40, 62}, 255, -1);
  bgr.setTo(cv::Scalar(25, 20, 70), tip & mask);
  Skeleton s = skeletonize(mask);
  SkeletonGraph g = build_skeleton_graph(s, detect_keypoints(s));
  const float r = measure_radii(g, mask);
  const auto ends = [](const SkeletonGraph& graph) {
    int n = 0;
    for (const Node& node : graph.nodes) n += node.kind == Node::Kind::end && node.alive;
    return n;
  };
  ASSERT_EQ(ends(g), 3) << "the notch should fork the tip into two prongs";
  SkeletonGraph plain = g;
  prune_split_ends(plain, 2 * r, mask.size());
  ASSERT_EQ(ends(plain), 2) << "without colour one prong should go";
  prune_split_ends(g, 2 * r, mask.size(), ColourSource{bgr, r});
  EXPECT_EQ(ends(g), 2);
}

}  // namespace
}  // namespace mbest

namespace mbest {
namespace {

TEST(Prune, StubOfARodEndingJustPastACrossingStays) {
  // A vertical rod crosses a horizontal one and ends a few pixels past its edge: the stub
  // is shorter than 2 r but it is the vertical rod's end, not a split end.
  cv::Mat mask = cv::Mat::zeros(200, 300, CV_8UC1);
  test::draw_rod(mask, {{20, 100}, {280, 100}}, 15);  // 17 px wide: rows 92..108
  test::draw_rod(mask, {{150, 20}, {150, 116}}, 9);   // ends 8 px past the other's edge
  Skeleton s = skeletonize(mask);
  SkeletonGraph g = build_skeleton_graph(s, detect_keypoints(s));
  const float r = measure_radii(g, mask);
  int short_spurs = 0;
  for (const Branch& b : g.branches)
    short_spurs += b.length < 2 * r && (g.nodes[b.node[0]].kind == Node::Kind::end) !=
                                           (g.nodes[b.node[1]].kind == Node::Kind::end);
  ASSERT_EQ(short_spurs, 1) << "the scene should give the stub as the only short spur";
  EXPECT_EQ(prune_split_ends(g, 2 * r, mask.size()), 0);
}

}  // namespace
}  // namespace mbest

namespace mbest {
namespace {

// A thin blue rod comes in at `angle_deg` and ends lying on a wide red one, its tip a few
// pixels past the red rod's far edge.
struct EndOnRod {
  cv::Mat mask, bgr;
};
EndOnRod end_on_rod(double angle_deg, const cv::Scalar& blue) {
  EndOnRod s;
  s.mask = cv::Mat::zeros(200, 400, CV_8UC1);
  s.bgr = cv::Mat::zeros(200, 400, CV_8UC3);
  const double a = angle_deg * M_PI / 180;
  const cv::Point tip(200, 88);
  const cv::Point tail(cvRound(200 + 150 * std::cos(a)), cvRound(88 + 150 * std::sin(a)));
  test::draw_rod(s.mask, {{20, 100}, {380, 100}}, 15);
  test::draw_rod(s.bgr, {{20, 100}, {380, 100}}, 15, 0);
  s.bgr.setTo(cv::Scalar(40, 40, 200), s.mask);
  cv::Mat blue_mask = cv::Mat::zeros(s.mask.size(), CV_8UC1);
  test::draw_rod(blue_mask, {tail, tip}, 9);
  s.mask |= blue_mask;
  s.bgr.setTo(blue, blue_mask);
  return s;
}

TEST(Prune, EndOfARodLyingOnAnotherOfAnotherColourStays) {
  // Where the blue end crosses the red rod's far edge the skeleton forks into a short spur.
  // By the mask alone it is a split end; the colours of the branches at its junction show
  // two DLOs meeting there, so it stays (and the red rod is not cut at the blue end).
  for (double angle : {20.0, 30.0, 45.0, 60.0}) {
    for (const bool same_colour : {false, true}) {
      const EndOnRod s = end_on_rod(angle, same_colour ? cv::Scalar(40, 40, 200) : cv::Scalar(200, 90, 30));
      Skeleton sk = skeletonize(s.mask);
      SkeletonGraph g = build_skeleton_graph(sk, detect_keypoints(sk));
      const float r = measure_radii(g, s.mask);
      SkeletonGraph plain = g;
      ASSERT_EQ(prune_split_ends(plain, 2 * r, s.mask.size()), 1)
          << "angle " << angle << ": the scene should make one spur";
      EXPECT_EQ(prune_split_ends(g, 2 * r, s.mask.size(), ColourSource{s.bgr, r}),
                same_colour ? 1 : 0)
          << "angle " << angle << (same_colour ? ", one colour" : ", two colours");
    }
  }
}

TEST(Prune, StubOfAnotherColourPastAShallowCrossingStays) {
  // A blue rod crosses a red one at 40-50 degrees and ends a few pixels past it. The
  // skeleton splits the crossing into two junctions of three branches; the stub's junction
  // has only red branches besides it, so by the other branches alone it looks like a split
  // end of the red rod. Its own colour shows it is the blue rod's end.
  for (double angle : {40.0, 45.0, 50.0}) {
    cv::Mat mask = cv::Mat::zeros(200, 400, CV_8UC1), bgr = cv::Mat::zeros(200, 400, CV_8UC3);
    const double a = angle * M_PI / 180;
    const cv::Point2d dir(-std::cos(a), -std::sin(a));  // from the lower right, up-left
    const cv::Point2d cross(200, 100);
    const cv::Point tail(cross - 150 * dir), tip(cross + (7.5 + 6) / std::sin(a) * dir);
    cv::Mat red = cv::Mat::zeros(mask.size(), CV_8UC1), blue = red.clone();
    test::draw_rod(red, {{20, 100}, {380, 100}}, 15);
    test::draw_rod(blue, {tail, tip}, 11);
    mask = red | blue;
    bgr.setTo(cv::Scalar(40, 40, 200), red);
    bgr.setTo(cv::Scalar(200, 90, 30), blue & ~red);
    Skeleton sk = skeletonize(mask);
    SkeletonGraph g = build_skeleton_graph(sk, detect_keypoints(sk));
    const float r = measure_radii(g, mask);
    SkeletonGraph plain = g;
    ASSERT_GE(prune_split_ends(plain, 2 * r, mask.size()), 1)
        << "angle " << angle << ": without colour the stub should look like a split end";
    EXPECT_EQ(prune_split_ends(g, 2 * r, mask.size(), ColourSource{bgr, r}), 0) << "angle " << angle;
  }
}

}  // namespace
}  // namespace mbest

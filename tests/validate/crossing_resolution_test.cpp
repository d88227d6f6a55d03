#include "mbest/validate/crossing_resolution.h"

#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace mbest::validate {
namespace {

using synth::CrossingAnnotation;
using synth::RodAnnotation;
using synth::SceneAnnotation;

// A rod whose centerline runs through `corners`, sampled 1 px apart.
RodAnnotation rod(int id, const std::vector<cv::Point2d>& corners, double width) {
  RodAnnotation r;
  r.id = id;
  r.width_px = width;
  for (size_t k = 0; k + 1 < corners.size(); ++k) {
    const cv::Point2d d = corners[k + 1] - corners[k];
    const int steps = static_cast<int>(std::ceil(cv::norm(d)));
    for (int s = 0; s < steps; ++s) r.centerline.push_back(corners[k] + d * (double(s) / steps));
  }
  r.centerline.push_back(corners.back());
  return r;
}

// Draws centerline samples [from, to) of `r` with value `label`, `r.width_px` thick.
void draw(cv::Mat* labels, const RodAnnotation& r, int label, size_t from = 0,
          size_t to = static_cast<size_t>(-1)) {
  to = std::min(to, r.centerline.size());
  std::vector<cv::Point> pts;
  for (size_t i = from; i < to; ++i)
    pts.emplace_back(cvRound(r.centerline[i].x), cvRound(r.centerline[i].y));
  cv::polylines(*labels, pts, false, cv::Scalar(label), static_cast<int>(r.width_px));
}

int nearest_index(const RodAnnotation& r, cv::Point2d p) {
  int best = 0;
  for (size_t i = 0; i < r.centerline.size(); ++i)
    if (cv::norm(r.centerline[i] - p) < cv::norm(r.centerline[best] - p)) best = static_cast<int>(i);
  return best;
}

// Rod 1 from the left to the right through (100, 60); rod 2 through the same point at
// `angle_deg` to it. Rod 1 is on top.
struct TwoRods {
  SceneAnnotation scene;
  cv::Mat gt = cv::Mat::zeros(120, 200, CV_16UC1);

  explicit TwoRods(double angle_deg) {
    const double t = angle_deg * CV_PI / 180;
    const cv::Point2d c(100, 60), dir(std::cos(t), std::sin(t));
    scene.rods = {rod(1, {{5, 60}, {195, 60}}, 8), rod(2, {c - 55.0 * dir, c + 55.0 * dir}, 8)};
    CrossingAnnotation x;
    x.location = c;
    x.angle_deg = angle_deg;
    x.rod_a = 1;
    x.rod_b = 2;
    x.top = 1;
    x.arc_index_a = nearest_index(scene.rods[0], c);
    x.arc_index_b = nearest_index(scene.rods[1], c);
    scene.crossings = {x};
    draw(&gt, scene.rods[1], 2);
    draw(&gt, scene.rods[0], 1);
  }

  CrossingResolution resolve(const cv::Mat& pred) const {
    Result<DiceScore> d = matched_dice(gt, pred);
    EXPECT_TRUE(d.ok());
    const std::vector<CrossingResolution> r = crossing_resolution(scene, gt, pred, d.value());
    EXPECT_EQ(r.size(), 1u);
    return r.empty() ? CrossingResolution{} : r[0];
  }
};

cv::Mat relabel(const cv::Mat& gt, int one, int two) {
  cv::Mat out = cv::Mat::zeros(gt.size(), CV_16UC1);
  out.setTo(one, gt == 1);
  out.setTo(two, gt == 2);
  return out;
}

TEST(CrossingResolution, PerfectPredictionIsPairedAndOrdered) {
  for (double angle : {90.0, 45.0, 25.0, 12.0}) {
    const TwoRods s(angle);
    const CrossingResolution r = s.resolve(relabel(s.gt, 5, 9));
    EXPECT_TRUE(r.pairing_assessed) << angle << ": " << r.note;
    EXPECT_TRUE(r.pairing_correct) << angle;
    EXPECT_EQ(r.a_before, 5);
    EXPECT_EQ(r.a_after, 5);
    EXPECT_EQ(r.b_before, 9);
    EXPECT_EQ(r.b_after, 9);
    EXPECT_TRUE(r.order_assessed);
    EXPECT_TRUE(r.order_correct) << angle;
  }
}

TEST(CrossingResolution, NeighboursAreTheOtherCrossingsWithinFourWidths) {
  // Rods 8 px wide, so within 32 px. Crossing 0 at (100, 60); the annotation also lists
  // crossings 20, 31 and 34 px from it (the last 14 px from the first).
  TwoRods s(90);
  for (const cv::Point2d p : {cv::Point2d(120, 60), cv::Point2d(100, 91), cv::Point2d(134, 60)}) {
    CrossingAnnotation x = s.scene.crossings[0];
    x.location = p;
    s.scene.crossings.push_back(x);
  }
  Result<DiceScore> d = matched_dice(s.gt, s.gt);
  ASSERT_TRUE(d.ok());
  std::vector<CrossingResolution> r = crossing_resolution(s.scene, s.gt, s.gt, d.value());
  ASSERT_EQ(r.size(), 4u);
  EXPECT_EQ(r[0].neighbours, 2);  // 20 and 31 px; 34 px is out
  EXPECT_EQ(r[1].neighbours, 2);  // 20 and 14 px; (100, 91) is 37 px off
  EXPECT_EQ(r[2].neighbours, 1);  // 31 px; the others are 37 and 46 px off
  EXPECT_EQ(r[3].neighbours, 1);  // 14 px; (100, 60) is 34 px off
  // The radius is an option: at 5 widths (40 px) crossing 0 has all three.
  CrossingOptions wider;
  wider.crowding_radius_widths = 5;
  r = crossing_resolution(s.scene, s.gt, s.gt, d.value(), wider);
  EXPECT_EQ(r[0].neighbours, 3);
  // A lone crossing has none.
  const TwoRods lone(90);
  EXPECT_EQ(lone.resolve(lone.gt.clone()).neighbours, 0);
}

TEST(CrossingResolution, WrongRodOnTopIsPairedButNotOrdered) {
  const TwoRods s(60);
  cv::Mat pred = cv::Mat::zeros(s.gt.size(), CV_16UC1);
  draw(&pred, s.scene.rods[0], 1);
  draw(&pred, s.scene.rods[1], 2);  // drawn last: on top
  const CrossingResolution r = s.resolve(pred);
  EXPECT_TRUE(r.pairing_correct);
  EXPECT_TRUE(r.order_assessed);
  EXPECT_FALSE(r.order_correct);
  EXPECT_EQ(r.at_crossing, 2);
}

TEST(CrossingResolution, SwitchedStrandsAreNotPaired) {
  // Label 1 runs in along rod 1 and out along rod 2; label 2 the other way round.
  const TwoRods s(60);
  const int ia = s.scene.crossings[0].arc_index_a, ib = s.scene.crossings[0].arc_index_b;
  cv::Mat pred = cv::Mat::zeros(s.gt.size(), CV_16UC1);
  draw(&pred, s.scene.rods[0], 1, 0, ia + 1);
  draw(&pred, s.scene.rods[1], 1, ib);
  draw(&pred, s.scene.rods[1], 2, 0, ib + 1);
  draw(&pred, s.scene.rods[0], 2, ia);
  const CrossingResolution r = s.resolve(pred);
  EXPECT_TRUE(r.pairing_assessed);
  EXPECT_FALSE(r.pairing_correct);
  EXPECT_EQ(r.a_before, 1);
  EXPECT_EQ(r.a_after, 2);
}

TEST(CrossingResolution, MergedRodsAreNotPaired) {
  const TwoRods s(60);
  const CrossingResolution r = s.resolve(relabel(s.gt, 3, 3));
  EXPECT_TRUE(r.pairing_assessed);
  EXPECT_FALSE(r.pairing_correct);
}

TEST(CrossingResolution, EmptyPredictionResolvesNothing) {
  const TwoRods s(60);
  const CrossingResolution r = s.resolve(cv::Mat::zeros(s.gt.size(), CV_16UC1));
  EXPECT_TRUE(r.pairing_assessed);
  EXPECT_FALSE(r.pairing_correct);
  EXPECT_FALSE(r.order_correct);
}

TEST(CrossingResolution, SamplesBeyondTheOverlapOfAShallowCrossing) {
  // At 12 degrees the strands overlap for ~40 px each side; a sample 1.5 widths out would
  // read rod 1's label on rod 2. The sample must clear the overlap.
  const TwoRods s(12);
  cv::Mat pred = relabel(s.gt, 1, 2);
  const CrossingResolution r = s.resolve(pred);
  EXPECT_EQ(r.b_before, 2);
  EXPECT_EQ(r.b_after, 2);
  EXPECT_TRUE(r.pairing_correct);
}

TEST(CrossingResolution, SamplesWhereNoThirdRodOverlapsTheStrand) {
  // Rod 3 lies across rod 1 at 13 degrees just right of the crossing, under rod 1 in the
  // truth and on top in the prediction. Where their bodies overlap, the prediction's label
  // on rod 1 tests the order of rods 1 and 3, not the pairing at the crossing of 1 and 2:
  // the sample must be taken past the overlap.
  TwoRods s(90);
  s.scene.rods.push_back(rod(3, {{106, 63}, {190, 44}}, 8));
  s.gt.setTo(0);
  draw(&s.gt, s.scene.rods[2], 3);
  draw(&s.gt, s.scene.rods[1], 2);
  draw(&s.gt, s.scene.rods[0], 1);
  cv::Mat pred = cv::Mat::zeros(s.gt.size(), CV_16UC1);
  draw(&pred, s.scene.rods[1], 9);
  draw(&pred, s.scene.rods[0], 5);
  draw(&pred, s.scene.rods[2], 7);
  const CrossingResolution r = s.resolve(pred);
  EXPECT_TRUE(r.pairing_assessed) << r.note;
  EXPECT_EQ(r.a_before, 5);
  EXPECT_EQ(r.a_after, 5);
  EXPECT_TRUE(r.pairing_correct);
}

TEST(CrossingResolution, OrderUnderAThirdRodIsNotAssessed) {
  // Rod 3 lies over the crossing of rods 1 and 2: the truth's label image shows rod 3 there,
  // so no label image tells which of 1 and 2 is on top. The pairing is still assessed.
  TwoRods s(90);
  s.scene.rods.push_back(rod(3, {{60, 20}, {140, 100}}, 8));
  draw(&s.gt, s.scene.rods[2], 3);
  const CrossingResolution r = s.resolve(s.gt.clone());
  EXPECT_FALSE(r.order_assessed);
  EXPECT_FALSE(r.note.empty());
  EXPECT_TRUE(r.pairing_assessed) << r.note;
  EXPECT_TRUE(r.pairing_correct);
  // Without rod 3 the same crossing's order is assessed (and right).
  const TwoRods plain(90);
  EXPECT_TRUE(plain.resolve(plain.gt.clone()).order_assessed);
}

TEST(CrossingResolution, ShortRodWithoutAClearSampleIsNotAssessed) {
  const TwoRods s(5);  // rod 2 ends before it clears rod 1
  const CrossingResolution r = s.resolve(relabel(s.gt, 1, 2));
  EXPECT_FALSE(r.pairing_assessed);
  EXPECT_FALSE(r.note.empty());
  EXPECT_TRUE(r.order_assessed);
}

// One rod drawn as A -> B -> C -> D whose first and last legs cross at (90, 70), 71 degrees.
// A rod crossing itself at (90, 70) once, its loop reaching x = 160: inside the default image,
// outside (from x = 144) an image 140 px wide.
struct Loop {
  SceneAnnotation scene;
  cv::Mat gt;
  explicit Loop(int image_width = 180) : gt(cv::Mat::zeros(140, image_width, CV_16UC1)) {
    RodAnnotation loop = rod(1, {{20, 120}, {160, 20}, {160, 120}, {20, 20}}, 7);
    const cv::Point2d centre(90, 70);
    int first = 0, last = 0;  // nearest samples to the crossing on the first and last legs
    const int half = static_cast<int>(loop.centerline.size()) / 2;
    for (int i = 0; i < static_cast<int>(loop.centerline.size()); ++i) {
      int& best = i < half ? first : last;
      if (cv::norm(loop.centerline[i] - centre) < cv::norm(loop.centerline[best] - centre)) best = i;
    }
    CrossingAnnotation x;
    x.location = centre;
    x.angle_deg = 71;
    x.rod_a = x.rod_b = x.top = 1;
    x.arc_index_a = first;
    x.arc_index_b = last;
    scene.rods = {loop};
    scene.crossings = {x};
    draw(&gt, loop, 1);
  }
};

TEST(CrossingResolution, SelfCrossingKeptAsOneInstanceIsPaired) {
  const Loop s;
  ASSERT_LT(cv::norm(s.scene.rods[0].centerline[s.scene.crossings[0].arc_index_a] -
                     s.scene.rods[0].centerline[s.scene.crossings[0].arc_index_b]),
            2.0);
  Result<DiceScore> d = matched_dice(s.gt, s.gt);
  const std::vector<CrossingResolution> r = crossing_resolution(s.scene, s.gt, s.gt, d.value());
  ASSERT_EQ(r.size(), 1u);
  EXPECT_TRUE(r[0].pairing_assessed) << r[0].note;
  EXPECT_TRUE(r[0].pairing_correct);
  EXPECT_FALSE(r[0].order_assessed);
}

TEST(CrossingResolution, SelfCrossingCutAtTheCrossingIsNotPaired) {
  const Loop s;
  const RodAnnotation& loop = s.scene.rods[0];
  const int mid = (s.scene.crossings[0].arc_index_a + s.scene.crossings[0].arc_index_b) / 2;
  cv::Mat pred = cv::Mat::zeros(s.gt.size(), CV_16UC1);
  draw(&pred, loop, 1, 0, s.scene.crossings[0].arc_index_a);  // tail in
  draw(&pred, loop, 2, s.scene.crossings[0].arc_index_a, mid);  // half the loop
  draw(&pred, loop, 1, mid);  // other half and tail out
  pred.setTo(0, s.gt == 0);
  Result<DiceScore> d = matched_dice(s.gt, pred);
  const std::vector<CrossingResolution> r = crossing_resolution(s.scene, s.gt, pred, d.value());
  ASSERT_EQ(r.size(), 1u);
  EXPECT_TRUE(r[0].pairing_assessed) << r[0].note;
  EXPECT_FALSE(r[0].pairing_correct);
}

// Labels 1 up to the middle of the loop, 2 after it: both strands go straight through the
// crossing, as two instances.
CrossingResolution split_in_the_loop(const Loop& s) {
  const RodAnnotation& loop = s.scene.rods[0];
  const int mid = (s.scene.crossings[0].arc_index_a + s.scene.crossings[0].arc_index_b) / 2;
  cv::Mat pred = cv::Mat::zeros(s.gt.size(), CV_16UC1);
  draw(&pred, loop, 1, 0, mid);
  draw(&pred, loop, 2, mid);
  pred.setTo(0, s.gt == 0);
  Result<DiceScore> d = matched_dice(s.gt, pred);
  const std::vector<CrossingResolution> r = crossing_resolution(s.scene, s.gt, pred, d.value());
  EXPECT_EQ(r.size(), 1u);
  return r.empty() ? CrossingResolution{} : r[0];
}

TEST(CrossingResolution, SelfCrossingSplitInItsVisibleLoopIsNotPaired) {
  const CrossingResolution r = split_in_the_loop(Loop());
  EXPECT_TRUE(r.pairing_assessed) << r.note;
  EXPECT_NE(r.a_before, r.b_before);
  EXPECT_FALSE(r.pairing_correct);
}

TEST(CrossingResolution, SelfCrossingWhoseLoopLeavesTheImageMayBeTwoInstances) {
  const Loop s(140);
  EXPECT_GT(cv::countNonZero(s.gt.col(139)), 0);  // the loop leaves through the right edge
  const CrossingResolution r = split_in_the_loop(s);
  EXPECT_TRUE(r.pairing_assessed) << r.note;
  EXPECT_NE(r.a_before, r.b_before);
  EXPECT_TRUE(r.pairing_correct);
  // Kept as one instance, it is paired too.
  Result<DiceScore> d = matched_dice(s.gt, s.gt);
  const std::vector<CrossingResolution> one = crossing_resolution(s.scene, s.gt, s.gt, d.value());
  ASSERT_EQ(one.size(), 1u);
  EXPECT_TRUE(one[0].pairing_correct);
}

}  // namespace
}  // namespace mbest::validate

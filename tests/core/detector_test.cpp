// End-to-end: drawn scenes through the whole pipeline, and bad input.
#include "mbest/core/detector.h"

#include <algorithm>
#include <set>
#include <string>
#include <utility>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "scenes.h"

namespace mbest {
namespace {

// Draws each rod into its own mask and into the union; returns the union.
cv::Mat scene(cv::Size size, const std::vector<std::vector<cv::Point>>& rods, int width,
              std::vector<cv::Mat>* instances = nullptr) {
  cv::Mat mask = cv::Mat::zeros(size, CV_8UC1);
  for (const auto& rod : rods) {
    cv::Mat m = cv::Mat::zeros(size, CV_8UC1);
    test::draw_rod(m, rod, width);
    mask |= m;
    if (instances) instances->push_back(m);
  }
  return mask;
}

void expect_labels_cover_mask(const Detection& d, const cv::Mat& mask) {
  const cv::Mat labelled = d.labels != 0, in_mask = mask != 0;
  EXPECT_EQ(cv::countNonZero(labelled & ~in_mask), 0) << "labels outside the mask";
  EXPECT_EQ(cv::countNonZero(in_mask & ~labelled), 0) << "mask pixels without a label";
}

// A black picture with each instance of `gt` painted in its colour (BGR), in order.
cv::Mat painted(const std::vector<cv::Mat>& gt, const std::vector<cv::Scalar>& colours) {
  cv::Mat bgr(gt.at(0).size(), CV_8UC3, cv::Scalar(0, 0, 0));
  for (size_t k = 0; k < gt.size(); ++k) bgr.setTo(colours.at(k), gt[k]);
  return bgr;
}

TEST(Detector, StraightRodIsOneOpenDloEndToEnd) {
  const cv::Mat mask = scene({300, 120}, {{{20, 60}, {280, 60}}}, 15);
  auto r = detect(mask);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const Detection& d = r.value();
  ASSERT_EQ(d.dlos.size(), 1u);
  const Dlo& dlo = d.dlos[0];
  EXPECT_FALSE(dlo.closed);
  EXPECT_TRUE(test::eight_connected_chain(dlo.centerline));
  EXPECT_EQ(dlo.radius.size(), dlo.centerline.size());
  EXPECT_LE(std::min(dlo.centerline.front().x, dlo.centerline.back().x), 30);
  EXPECT_GE(std::max(dlo.centerline.front().x, dlo.centerline.back().x), 270);
  // Radius = distance to the nearest background pixel; a thickness-15 line is 17 px wide.
  EXPECT_NEAR(dlo.radius[dlo.radius.size() / 2], (15 + 3) / 2.0, 0.5);
  expect_labels_cover_mask(d, mask);
  EXPECT_FALSE(d.timings.empty());
}

TEST(Detector, CenterlineReachesTheTipsOfAFlatEndedRod) {
  // Thinning stops a flat end's skeleton about a radius short, forked into the corners.
  cv::Mat mask = cv::Mat::zeros(120, 300, CV_8UC1);
  cv::rectangle(mask, {20, 52}, {280, 68}, 255, -1);  // 17 px wide, radius 9
  auto r = detect(mask);
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r.value().dlos.size(), 1u);
  const auto& line = r.value().dlos[0].centerline;
  const int left = std::min(line.front().x, line.back().x), right = std::max(line.front().x, line.back().x);
  EXPECT_LE(left, 20 + 9) << "within a radius of the left tip";
  EXPECT_GE(left, 20);
  EXPECT_GE(right, 280 - 9) << "within a radius of the right tip";
  EXPECT_LE(right, 280);
  for (const cv::Point& p : line) EXPECT_NEAR(p.y, 60, 1) << p;
}

TEST(Detector, XCrossingIsTwoDlosAndOneCrossing) {
  for (double angle : {90.0, 50.0, 25.0}) {
    std::vector<cv::Mat> gt;
    const cv::Mat mask = scene({400, 400},
                               {test::line_through({200, 200}, 10, 360),
                                test::line_through({200, 200}, 10 + angle, 360)},
                               13, &gt);
    auto r = detect(mask);
    ASSERT_TRUE(r.ok());
    const Detection& d = r.value();
    ASSERT_EQ(d.dlos.size(), 2u) << "angle " << angle;
    ASSERT_EQ(d.crossings.size(), 1u) << "angle " << angle;
    EXPECT_NEAR(d.crossings[0].angle_deg, angle > 90 ? 180 - angle : angle, 4.0);
    EXPECT_LT(cv::norm(d.crossings[0].location - cv::Point2f(200, 200)), 4.0);
    for (const Dlo& dlo : d.dlos) EXPECT_EQ(dlo.crossings, std::vector<int>{0});
    EXPECT_GT(test::strict_dice(gt, d.labels), 0.97) << "angle " << angle;
    expect_labels_cover_mask(d, mask);
  }
}

// A red rod and a blue one that ends on it or past it, painted in those colours (BGR).
const cv::Scalar kRed(40, 40, 200), kBlue(200, 90, 30);
struct EndOnRod {
  cv::Mat mask, bgr;
  std::vector<cv::Mat> gt;  // red, blue: each without the pixels the other covers
};

// The blue rod ends lying on the red one at `angle_deg`, its tip just past the red rod's axis;
// drawn over it, or under it when `blue_over` is false.
EndOnRod end_on_rod(double angle_deg, bool blue_over = true) {
  EndOnRod s;
  const cv::Size size(420, 240);
  const double a = angle_deg * M_PI / 180;
  const std::vector<std::vector<cv::Point>> rods{
      {{20, 120}, {400, 120}},
      {cv::Point(cvRound(210 + 170 * std::cos(a)), cvRound(117 + 170 * std::sin(a))), {210, 117}}};
  s.mask = scene(size, rods, 13, &s.gt);
  if (blue_over)
    s.gt[0] &= ~s.gt[1];
  else
    s.gt[1] &= ~s.gt[0];
  s.bgr = painted(s.gt, {kRed, kBlue});
  return s;
}

TEST(Detector, DloEndingOnAnotherLeavesTheOtherWhole) {
  // Guards the colour cue: next to a shallow crossing the top strand's colour covers the
  // other's branch; sampled over too short a stretch, colour paired the red rod's left half
  // with the blue end (it did at 25 and 35 degrees with 3 r and 6 r stretches).
  for (double angle : {25.0, 35.0, 50.0}) {
    const EndOnRod s = end_on_rod(angle);
    auto r = detect(s.mask, s.bgr);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r.value().dlos.size(), 2u) << "angle " << angle;
    // Where the blue end lies on the red rod the mask cannot say how far it reaches; the
    // colour gives that overlap to the blue one (RodEndingOnAnotherIsOnTopWhereItsColourShows).
    EXPECT_GT(test::strict_dice(s.gt, r.value().labels), 0.93) << "angle " << angle;
    // The red rod keeps one label on both sides of where the blue one lies on it.
    const cv::Mat& labels = r.value().labels;
    EXPECT_EQ(labels.at<uint16_t>(120, 40), labels.at<uint16_t>(120, 380)) << "angle " << angle;
    EXPECT_NE(labels.at<uint16_t>(120, 40), 0);
  }
}

// The blue rod ends on the red one (end_on_rod), drawn over it or under it. Where it lies
// over it, the overlap shows blue and is the blue DLO's; where under, the red one's. The
// crossing's top as a user reads it from the labels is the label there.
TEST(Detector, RodEndingOnAnotherIsOnTopWhereItsColourShows) {
  for (double angle : {35.0, 50.0, 70.0, 90.0})
    for (bool blue_on_top : {true, false}) {
      const std::string scene = std::to_string(static_cast<int>(angle)) + " degrees, blue " +
                                (blue_on_top ? "over" : "under") + " red";
      const EndOnRod s = end_on_rod(angle, blue_on_top);
      auto r = detect(s.mask, s.bgr);
      ASSERT_TRUE(r.ok());
      ASSERT_EQ(r.value().dlos.size(), 2u) << scene;
      const cv::Mat& labels = r.value().labels;
      const uint16_t red = labels.at<uint16_t>(120, 40);
      const uint16_t blue = labels.at<uint16_t>(cvRound(117 + 100 * std::sin(angle * M_PI / 180)),
                                                cvRound(210 + 100 * std::cos(angle * M_PI / 180)));
      ASSERT_NE(red, blue) << scene;
      EXPECT_EQ(labels.at<uint16_t>(120, 380), red) << scene;
      // Just short of the blue tip, on the red rod's axis.
      const double a = angle * M_PI / 180;
      const cv::Point on_red(cvRound(210 + 3 * std::cos(a)), 120);
      EXPECT_EQ(labels.at<uint16_t>(on_red), blue_on_top ? blue : red) << scene;
      EXPECT_GT(test::strict_dice(s.gt, labels), 0.97) << scene;
    }
}

// A blue rod crosses a red one at about 30 degrees, then lies along the red one's side, half
// under it, for 110 px and ends there: past the crossing the mask is a band wider than
// either rod, the blue rod's half of it showing blue.
TEST(Detector, RodEndingAlongAnotherAfterCrossingItIsLabelledAlongIt) {
  for (bool mirrored : {false, true}) {
    SCOPED_TRACE(mirrored ? "mirrored" : "as drawn");
    const cv::Size size(420, 240);
    cv::Mat red = cv::Mat::zeros(size, CV_8UC1), blue = red.clone();
    test::draw_rod(red, {{20, 100}, {400, 100}}, 13);
    test::draw_rod(blue, {{60, 10}, {205, 107}, {330, 107}}, 9);
    if (mirrored) {
      cv::flip(red, red, 1);
      cv::flip(blue, blue, 1);
    }
    const cv::Mat mask = red | blue;
    std::vector<cv::Mat> gt{red, blue & ~red};
    const cv::Mat bgr = painted(gt, {kRed, kBlue});
    auto r = detect(mask, bgr);
    ASSERT_TRUE(r.ok());
    ASSERT_EQ(r.value().dlos.size(), 2u);
    const cv::Mat& labels = r.value().labels;
    const auto at = [&](int x, int y) { return labels.at<uint16_t>(y, mirrored ? size.width - 1 - x : x); };
    const uint16_t blue_label = at(90, 30), red_label = at(40, 100);
    ASSERT_NE(blue_label, red_label);
    // The blue rod's visible half below the red one, all along the stretch.
    int blue_below = 0, below = 0;
    for (int x = 230; x <= 320; x += 5, ++below) blue_below += at(x, 109) == blue_label;
    EXPECT_EQ(blue_below, below);
    EXPECT_EQ(at(300, 100), red_label);
    EXPECT_GT(test::strict_dice(gt, labels), 0.97);
  }
}

// A blue rod that passes under a red one and ends `stub` px past its edge (to the blue
// rod's tip, measured along it).
EndOnRod end_past_rod(double angle_deg, double stub, int wa = 13, int wb = 13) {
  EndOnRod s;
  const cv::Size size(420, 240);
  const double a = angle_deg * M_PI / 180;
  const cv::Point2d up(-std::cos(a), -std::sin(a)), centre(210, 120);
  const cv::Point2d tip = centre + up * (wa / 2.0 / std::sin(a) + stub - wb / 2);  // less the round cap
  s.mask = cv::Mat::zeros(size, CV_8UC1);
  s.gt = {s.mask.clone(), s.mask.clone()};
  test::draw_rod(s.gt[0], {{20, 120}, {400, 120}}, wa);
  test::draw_rod(s.gt[1], {cv::Point(centre - up * 150.0), cv::Point(tip)}, wb);
  s.mask = s.gt[0] | s.gt[1];
  s.gt[1] &= ~s.gt[0];
  s.bgr = painted(s.gt, {kRed, kBlue});
  return s;
}

// The stub past the red rod is too short to keep a skeleton branch of its own: it is
// pruned or folded into the crossing, and without reach_past_crossings its pixels went to
// the red rod in 5 of these 54 scenes (red or blue the thinner, or the same width).
TEST(Detector, RodEndingJustPastAnotherKeepsItsStub) {
  for (int wa : {5, 9, 13})
    for (int wb : {5, 9, 13})
      for (double angle : {50.0, 70.0, 90.0})
        for (double stub : {9.0, 12.0}) {
          const EndOnRod s = end_past_rod(angle, stub, wa, wb);
          auto r = detect(s.mask, s.bgr);
          ASSERT_TRUE(r.ok());
          const std::string scene = "red " + std::to_string(wa) + " px, blue " + std::to_string(wb) +
                                    " px, " + std::to_string(static_cast<int>(angle)) + " degrees, stub " +
                                    std::to_string(static_cast<int>(stub)) + " px";
          EXPECT_EQ(r.value().dlos.size(), 2u) << scene;
          const cv::Mat& labels = r.value().labels;
          const double a = angle * M_PI / 180;
          const cv::Point2d up(-std::cos(a), -std::sin(a)), centre(210, 120);
          const cv::Point in_stub(centre + up * (wa / 2.0 / std::sin(a) + stub / 2));
          const cv::Point below(centre - up * 60.0);
          EXPECT_NE(labels.at<uint16_t>(below), 0) << scene;
          EXPECT_NE(labels.at<uint16_t>(below), labels.at<uint16_t>(120, 40)) << scene;
          EXPECT_EQ(labels.at<uint16_t>(in_stub), labels.at<uint16_t>(below)) << scene;
          EXPECT_GT(test::strict_dice(s.gt, labels), 0.95) << scene;
        }
}

// A blue rod lying over a red one (13 px each, red along y = 120) and ending with the tip
// of its centerline `past` px beyond the red rod's axis (negative: short of it), the blue
// one coming in from below at `angle_deg`.
EndOnRod end_over_rod(double angle_deg, double past) {
  EndOnRod s;
  const cv::Size size(420, 240);
  const double a = angle_deg * M_PI / 180;
  const cv::Point2d down(std::cos(a), std::sin(a));
  const cv::Point2d tip = cv::Point2d(210, 120) - down * (past / std::sin(a));
  s.gt = {cv::Mat::zeros(size, CV_8UC1), cv::Mat::zeros(size, CV_8UC1)};
  test::draw_rod(s.gt[0], {{20, 120}, {400, 120}}, 13);
  test::draw_rod(s.gt[1], {cv::Point(tip + down * 170.0), cv::Point(tip)}, 13);
  s.mask = s.gt[0] | s.gt[1];
  s.gt[0] &= ~s.gt[1];
  s.bgr = painted(s.gt, {kRed, kBlue});
  return s;
}

// The truth lists a crossing where a rod's centerline crosses another's: a rod ending over
// another with its tip past the other's axis, or under it with its stub showing past it.
// The detector's list says so, with the top the picture shows.
TEST(Detector, RodEndingAcrossAnotherIsListedAsACrossing) {
  const auto crossings_of_two = [](const Detection& d) {
    int n = 0;
    for (const Crossing& c : d.crossings) n += c.dlos.size() == 2 && c.dlos[0] != c.dlos[1];
    return n;
  };
  for (double angle : {40.0, 60.0, 90.0}) {
    for (double past : {-5.0, 5.0}) {
      const std::string scene = "blue over red at " + std::to_string(static_cast<int>(angle)) +
                                " degrees, tip " + std::to_string(static_cast<int>(past)) + " px past the axis";
      const EndOnRod s = end_over_rod(angle, past);
      auto r = detect(s.mask, s.bgr);
      ASSERT_TRUE(r.ok());
      const Detection& d = r.value();
      ASSERT_EQ(d.dlos.size(), 2u) << scene;
      if (past < 0) {
        EXPECT_EQ(crossings_of_two(d), 0) << scene;
        continue;
      }
      ASSERT_EQ(d.crossings.size(), 1u) << scene;
      const Crossing& c = d.crossings[0];
      const uint16_t blue = d.labels.at<uint16_t>(cvRound(120 + 80 * std::sin(angle * M_PI / 180)),
                                                  cvRound(210 + 80 * std::cos(angle * M_PI / 180)));
      ASSERT_NE(blue, 0) << scene;
      EXPECT_EQ(c.dlos.at(0), blue - 1) << scene << ": the blue rod is on top";
      EXPECT_LT(std::abs(c.location.y - 120), 4.0f) << scene;
      EXPECT_NEAR(c.angle_deg, angle, 6.0) << scene;
      for (const Dlo& dlo : d.dlos) EXPECT_EQ(dlo.crossings, std::vector<int>{0}) << scene;
    }
  }
  // Under the red rod, with a stub showing past it (end_past_rod): red on top.
  for (double angle : {50.0, 90.0}) {
    const EndOnRod s = end_past_rod(angle, 12.0);
    auto r = detect(s.mask, s.bgr);
    ASSERT_TRUE(r.ok());
    const Detection& d = r.value();
    ASSERT_EQ(d.crossings.size(), 1u) << angle;
    EXPECT_EQ(d.crossings[0].dlos.at(0), d.labels.at<uint16_t>(120, 40) - 1) << angle;
  }
}

// One 13 px rod along y = 160 that turns back over itself (an arc up and round) and ends
// with its tip coming down onto its own strand at `angle_deg`, the tip of its centerline
// `past` px beyond the strand's axis (negative: short of it, a T).
cv::Mat hook_onto_itself(double angle_deg, double past) {
  std::vector<cv::Point> rod{{20, 160}, {300, 160}};
  const std::vector<cv::Point> round = test::arc({300, 100}, 60, M_PI / 2, -M_PI, 120);
  rod.insert(rod.end(), round.begin(), round.end());
  const double a = angle_deg * M_PI / 180;
  const cv::Point2d down(-std::cos(a), std::sin(a)), from(240, 100);
  rod.push_back(cv::Point(from + down * ((60 + past) / std::sin(a))));
  cv::Mat mask = cv::Mat::zeros(240, 420, CV_8UC1);
  test::draw_rod(mask, rod, 13);
  return mask;
}

// A rod's tip poking through its own strand is a self-crossing in the truth (a loop closing
// at its end); a tip ending against its own strand (a T) is not. One label covers both
// strands there, so the detector tells them by how far the label runs past the strand.
TEST(Detector, RodEndingAcrossItselfIsListedAsASelfCrossing) {
  for (double angle : {60.0, 90.0}) {
    for (double past : {-5.0, 0.0, 7.0}) {
      const std::string scene = std::to_string(static_cast<int>(angle)) + " degrees, tip " +
                                std::to_string(static_cast<int>(past)) + " px past the axis";
      const cv::Mat mask = hook_onto_itself(angle, past);
      auto r = detect(mask);
      ASSERT_TRUE(r.ok());
      const Detection& d = r.value();
      ASSERT_EQ(d.dlos.size(), 1u) << scene;
      EXPECT_FALSE(d.dlos[0].closed) << scene;
      if (past <= 0) {
        EXPECT_TRUE(d.crossings.empty()) << scene;
        continue;
      }
      ASSERT_EQ(d.crossings.size(), 1u) << scene;
      const Crossing& c = d.crossings[0];
      EXPECT_EQ(c.dlos, (std::vector<int>{0, 0})) << scene;
      const cv::Point2f expected(240 - 60 / std::tan(angle * M_PI / 180), 160);
      EXPECT_LT(cv::norm(c.location - expected), 4.0) << scene;
      EXPECT_NEAR(c.angle_deg, angle, 6.0) << scene;
      expect_labels_cover_mask(d, mask);
    }
  }
}

// Three rods of three colours crossing pairwise within a few radii of one point: the
// skeleton may split that cluster into regions that cannot be paired right one by one.
TEST(Detector, ThreeColouredRodsCrossingNearOnePoint) {
  for (const cv::Point2d offset : {cv::Point2d(0, 0), cv::Point2d(14, 0), cv::Point2d(0, 12)}) {
    const cv::Size size(400, 400);
    const std::vector<std::vector<cv::Point>> rods{
        test::line_through(cv::Point2d(200, 200), 0, 360),
        test::line_through(cv::Point2d(200, 200) + offset, 60, 360),
        test::line_through(cv::Point2d(200, 200) - offset, 120, 360)};
    std::vector<cv::Mat> gt;
    const cv::Mat mask = scene(size, rods, 13, &gt);
    cv::Mat bgr(size, CV_8UC3, cv::Scalar(0, 0, 0));
    const cv::Scalar colours[] = {{40, 40, 200}, {200, 90, 30}, {40, 200, 60}};
    for (int i = 0; i < 3; ++i) bgr.setTo(colours[i], gt[i]);
    auto r = detect(mask, bgr);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r.value().dlos.size(), 3u) << offset;
    const cv::Mat& labels = r.value().labels;
    for (const auto& rod : rods) {  // each rod's two far ends carry one label
      const cv::Point a = rod.front() + (rod.back() - rod.front()) * 0.05;
      const cv::Point b = rod.front() + (rod.back() - rod.front()) * 0.95;
      EXPECT_EQ(labels.at<uint16_t>(a), labels.at<uint16_t>(b)) << offset << " rod from " << rod.front();
    }
  }
}

// Two rods of different colours lying side by side, touching, along a curved stretch: the
// mask is one band there and the paths drawn through it are a guess, but every pixel shows
// its rod's colour.
TEST(Detector, SideBySideRodsOfTwoColoursAreLabelledByColour) {
  // Rods lying side by side: with the branch they share split in two (strands.h) off, the
  // paths drawn through the one crossing region their Ys make are a guess, which the
  // colour labels put right.
  std::vector<cv::Mat> gt;
  const test::SideBySide rods = test::side_by_side(13, 13);
  const cv::Mat mask = scene({420, 300}, {rods.a, rods.b}, 13, &gt);
  const cv::Mat bgr = painted(gt, {cv::Scalar(40, 40, 200), cv::Scalar(200, 90, 30)});
  DetectorConfig unsplit;
  unsplit.side_by_side_radii = 1000;
  auto r = detect(mask, bgr, unsplit);
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r.value().dlos.size(), 2u);
  EXPECT_GT(test::strict_dice(gt, r.value().labels), 0.98);
  expect_labels_cover_mask(r.value(), mask);
  DetectorConfig unsplit_drawn = unsplit;
  unsplit_drawn.colour_label_margin = 0;
  auto drawn = detect(mask, bgr, unsplit_drawn);
  ASSERT_TRUE(drawn.ok());
  EXPECT_LT(test::strict_dice(gt, drawn.value().labels), 0.9)
      << "drawn paths alone must get this scene wrong: else this test proves nothing";
}

// The mask of the two rods `gt` is detected (from the mask alone) as two DLOs matching
// them, labels covering the mask; detected with `rule_off`, the rule under test turned
// off, it is not, or the test would prove nothing. The detection goes to `out` if given.
void expect_two_dlos_needing(const cv::Mat& mask, const std::vector<cv::Mat>& gt,
                             const DetectorConfig& rule_off, const std::string& rule,
                             Detection* out = nullptr) {
  auto r = detect(mask);
  ASSERT_TRUE(r.ok());
  const Detection& d = r.value();
  EXPECT_EQ(d.dlos.size(), 2u);
  EXPECT_GT(test::strict_dice(gt, d.labels), 0.95);
  expect_labels_cover_mask(d, mask);
  auto without = detect(mask, cv::Mat(), rule_off);
  ASSERT_TRUE(without.ok());
  EXPECT_LT(test::strict_dice(gt, without.value().labels), 0.9)
      << "the scene must need " << rule << ": else this test proves nothing";
  if (out) *out = d;
}

// A 6 px and a 10 px wide rod crossing, each turning `turn_deg` where they cross, so that
// the mask is two straight bands of changing width: by bending alone each DLO goes
// straight on (and changes width); a DLO keeps its width, so the pairing follows it.
TEST(Detector, ARodKeepsItsWidthThroughACrossing) {
  for (const double turn_deg : {25.0, 40.0}) {
    const double t = turn_deg * M_PI / 180;
    const cv::Point c(210, 150);
    const cv::Point along_turn(static_cast<int>(std::lround(190 * std::cos(t))),
                               static_cast<int>(std::lround(-190 * std::sin(t))));
    const std::vector<cv::Point> thin{{20, 150}, c, c + along_turn};
    const std::vector<cv::Point> thick{c - along_turn, c, {400, 150}};
    std::vector<cv::Mat> gt{cv::Mat::zeros(300, 420, CV_8UC1), cv::Mat::zeros(300, 420, CV_8UC1)};
    test::draw_rod(gt[0], thin, 6);
    test::draw_rod(gt[1], thick, 10);
    const cv::Mat mask = gt[0] | gt[1];
    for (const bool mirrored : {false, true}) {
      SCOPED_TRACE(testing::Message() << turn_deg << " degrees" << (mirrored ? ", mirrored" : ""));
      std::vector<cv::Mat> truth = gt;
      cv::Mat m = mask.clone();
      if (mirrored) {
        for (cv::Mat& g : truth) cv::flip(g, g, 1);
        cv::flip(m, m, 1);
      }
      DetectorConfig bending_alone;
      bending_alone.width_weight = 0;
      expect_two_dlos_needing(m, truth, bending_alone, "the width cost");
    }
  }
}

// Two rods (`gt`) lying side by side over a stretch are two DLOs that do not cross, from
// the mask alone: the branch they share is split in two, one strand on each side.
void expect_two_dlos_side_by_side(const cv::Mat& mask, const std::vector<cv::Mat>& gt) {
  DetectorConfig unsplit;
  unsplit.side_by_side_radii = 1000;
  Detection d;
  expect_two_dlos_needing(mask, gt, unsplit, "the split", &d);
  EXPECT_TRUE(d.crossings.empty()) << d.crossings.size() << " crossings";
}

// expect_two_dlos_side_by_side for `rods` drawn `width` px wide, as drawn and mirrored
// (the skeleton's branches then run the other way).
void expect_two_rods_side_by_side(const std::vector<std::vector<cv::Point>>& rods, int width) {
  std::vector<cv::Mat> drawn;
  const cv::Mat unmirrored = scene({420, 300}, rods, width, &drawn);
  for (int flip : {2, 0, 1}) {  // none, about the x axis, about the y axis
    SCOPED_TRACE(flip);
    cv::Mat mask = unmirrored.clone();
    std::vector<cv::Mat> gt;
    for (const cv::Mat& m : drawn) gt.push_back(m.clone());
    if (flip < 2) {
      cv::flip(unmirrored, mask, flip);
      for (size_t k = 0; k < gt.size(); ++k) cv::flip(drawn[k], gt[k], flip);
    }
    expect_two_dlos_side_by_side(mask, gt);
  }
}

TEST(Detector, RodsTouchingSideBySideAreTwoDlosThatDoNotCross) {
  for (int width : {9, 13}) {
    SCOPED_TRACE(width);
    const test::SideBySide rods = test::side_by_side(width, width);
    expect_two_rods_side_by_side({rods.a, rods.b}, width);
  }
}

TEST(Detector, RodEndingAlongAnotherEndsThere) {
  for (int width : {9, 13}) {
    SCOPED_TRACE(width);
    const test::SideBySide rods = test::side_by_side(width, width, 250);
    expect_two_rods_side_by_side({rods.a, rods.b}, width);
  }
}

TEST(Detector, RodsLeavingTheImageSideBySideAlongAStretch) {
  // Apart on the left, side by side from x = 200 out through the right edge.
  std::vector<cv::Point> a, b;
  for (int x = 20; x <= 430; x += 4) {
    const double apart = x < 200 ? (200 - x) * 0.5 : 0;
    a.emplace_back(x, static_cast<int>(std::lround(150 - 5.5 - apart)));
    b.emplace_back(x, static_cast<int>(std::lround(150 + 5.5 + apart)));
  }
  expect_two_rods_side_by_side({a, b}, 11);
}

TEST(Detector, NearParallelCrossingFromTwoYs) {
  std::vector<cv::Mat> gt;
  const cv::Mat mask = scene({600, 300},
                             {test::line_through({300, 150}, 0, 560),
                              test::line_through({300, 150}, 14, 560)},
                             15, &gt);
  auto r = detect(mask);
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r.value().dlos.size(), 2u);
  EXPECT_EQ(r.value().crossings.size(), 1u);
  EXPECT_GT(test::strict_dice(gt, r.value().labels), 0.95);
}

// A thin rod passing along a wide one at a shallow angle lies inside it for a long stretch:
// the mask shows the wide rod with a thin branch on either side, two Ys further apart than
// Y-pair matching reaches and joined by a branch no wider than the wide rod.
TEST(Detector, ThinRodAlongAWideOneIsOneCrossing) {
  for (double angle : {7.0, 9.0}) {
    std::vector<cv::Mat> gt;
    const cv::Size size(600, 300);
    const cv::Mat wide = scene(size, {test::line_through({300, 150}, 0, 560)}, 17, &gt);
    const cv::Mat thin = scene(size, {test::line_through({300, 150}, angle, 560)}, 5, &gt);
    gt[0] &= ~thin;  // the thin rod on top
    cv::Mat bgr(size, CV_8UC3, cv::Scalar(0, 0, 0));
    bgr.setTo(cv::Scalar(40, 40, 200), gt[0]);
    bgr.setTo(cv::Scalar(200, 90, 30), gt[1]);
    for (const bool colour : {false, true}) {
      auto r = detect(wide | thin, colour ? bgr : cv::Mat());
      ASSERT_TRUE(r.ok());
      EXPECT_EQ(r.value().dlos.size(), 2u) << angle << " deg, colour " << colour;
      const cv::Mat& labels = r.value().labels;
      const double t = angle * CV_PI / 180;
      const auto at = [&](double s) {
        return labels.at<uint16_t>(cv::Point(cvRound(300 + s * std::cos(t)), cvRound(150 + s * std::sin(t))));
      };
      EXPECT_NE(at(-260), 0);
      EXPECT_EQ(at(-260), at(260)) << angle << " deg, colour " << colour << ": the thin rod split";
      EXPECT_EQ(labels.at<uint16_t>(150, 25), labels.at<uint16_t>(150, 575))
          << angle << " deg, colour " << colour << ": the wide rod split";
    }
  }
}

TEST(Detector, SelfLoopIsOneDloCrossingItself) {
  // A rod that comes from the left, loops once and leaves to the right.
  std::vector<cv::Point> rod{{20, 200}, {150, 200}};
  const std::vector<cv::Point> loop = test::arc({200, 150}, 55, M_PI * 0.75, M_PI * 0.75 - 2 * M_PI * 0.95, 120);
  rod.insert(rod.end(), loop.begin(), loop.end());
  rod.push_back({380, 60});
  cv::Mat mask = cv::Mat::zeros(320, 400, CV_8UC1);
  test::draw_rod(mask, rod, 13);
  auto r = detect(mask);
  ASSERT_TRUE(r.ok());
  const Detection& d = r.value();
  ASSERT_EQ(d.dlos.size(), 1u);
  ASSERT_EQ(d.crossings.size(), 1u);
  EXPECT_EQ(d.crossings[0].dlos, (std::vector<int>{0, 0}));
  EXPECT_EQ(d.dlos[0].crossings, (std::vector<int>{0, 0}));
  expect_labels_cover_mask(d, mask);
}

TEST(Detector, RingIsOneClosedDlo) {
  cv::Mat mask = cv::Mat::zeros(300, 300, CV_8UC1);
  cv::circle(mask, {150, 150}, 98, 255, -1);  // a thick cv::circle has pinholes: cut the hole
  cv::circle(mask, {150, 150}, 82, 0, -1);
  auto r = detect(mask);
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r.value().dlos.size(), 1u);
  const Dlo& ring = r.value().dlos[0];
  EXPECT_TRUE(ring.closed);
  EXPECT_TRUE(test::eight_connected_chain(ring.centerline));
  EXPECT_LE(std::abs(ring.centerline.front().x - ring.centerline.back().x), 1);
  EXPECT_LE(std::abs(ring.centerline.front().y - ring.centerline.back().y), 1);
  expect_labels_cover_mask(r.value(), mask);
}

TEST(Detector, RingCrossedByARod) {
  cv::Mat mask = cv::Mat::zeros(300, 400, CV_8UC1);
  cv::circle(mask, {200, 150}, 90, 255, 13);
  test::draw_rod(mask, {{10, 150}, {390, 150}}, 13);
  auto r = detect(mask);
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r.value().dlos.size(), 2u);
  int closed = 0;
  for (const Dlo& d : r.value().dlos) closed += d.closed;
  EXPECT_EQ(closed, 1);
  EXPECT_EQ(r.value().crossings.size(), 2u);
}

TEST(Detector, ThreeRodsThroughOnePoint) {
  std::vector<cv::Mat> gt;
  const cv::Mat mask = scene({400, 400},
                             {test::line_through({200, 200}, 0, 360), test::line_through({200, 200}, 60, 360),
                              test::line_through({200, 200}, 120, 360)},
                             13, &gt);
  auto r = detect(mask);
  ASSERT_TRUE(r.ok());
  const Detection& d = r.value();
  ASSERT_EQ(d.dlos.size(), 3u);
  // One crossing per pair of DLOs, near the centre; each DLO takes part in two.
  ASSERT_EQ(d.crossings.size(), 3u);
  std::set<std::pair<int, int>> pairs;
  for (const Crossing& c : d.crossings) {
    ASSERT_EQ(c.dlos.size(), 2u);
    pairs.insert(std::minmax(c.dlos[0], c.dlos[1]));
    EXPECT_LT(cv::norm(c.location - cv::Point2f(200, 200)), 10.0);
    EXPECT_NEAR(c.angle_deg, 60, 5);
  }
  EXPECT_EQ(pairs, (std::set<std::pair<int, int>>{{0, 1}, {0, 2}, {1, 2}}));
  for (const Dlo& dlo : d.dlos) EXPECT_EQ(dlo.crossings.size(), 2u);
  // Each DLO runs straight: its ends are on opposite sides of the centre.
  for (const Dlo& dlo : d.dlos) {
    const cv::Point2f a(dlo.centerline.front()), b(dlo.centerline.back()), c(200, 200);
    EXPECT_LT((a - c).dot(b - c), 0);
    EXPECT_GT(cv::norm(a - b), 300);
  }
  EXPECT_GT(test::strict_dice(gt, d.labels), 0.9);
}

TEST(Detector, RodsTouchingWithoutCrossingHaveNoCrossing) {
  // Two arcs of two colours bulging towards each other, touching at (200, 115): the mask
  // joins them there, so the skeleton has a junction, but neither strand passes over the
  // other. (Without colour the pairing there is a tie.)
  std::vector<cv::Mat> gt;
  const cv::Mat mask = scene({400, 230},
                             {test::arc({200, -60}, 172, 0.35, M_PI - 0.35),
                              test::arc({200, 290}, 172, -M_PI + 0.35, -0.35)},
                             13, &gt);
  ASSERT_GT(cv::countNonZero(gt[0] & gt[1]), 0) << "the rods must touch";
  const cv::Mat bgr = painted(gt, {cv::Scalar(40, 40, 200), cv::Scalar(200, 90, 30)});
  auto r = detect(mask, bgr);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().dlos.size(), 2u);
  EXPECT_GT(test::strict_dice(gt, r.value().labels), 0.95);
  EXPECT_TRUE(r.value().crossings.empty()) << r.value().crossings.size() << " crossings";
}

// A straight rod (gt[0]) along y = 100, and a parabola (gt[1]) running along it that
// crosses it at x = 160 and at x = 240, about 14 degrees, 5 px to its far side in between:
// one crossing region, whose strands enter and leave on the same sides.
cv::Mat twisted_pair(std::vector<cv::Mat>* gt) {
  std::vector<cv::Point> twisted;
  for (int x = 10; x <= 390; x += 5) twisted.emplace_back(x, cvRound(95 + 5 * (x - 200.0) * (x - 200.0) / 1600));
  return scene({400, 220}, {{{10, 100}, {390, 100}}, twisted}, 11, gt);
}

TEST(Detector, RodsTwistedOnceRoundEachOtherCrossTwice) {
  // Two crossings, not one and not none.
  std::vector<cv::Mat> gt;
  const cv::Mat mask = twisted_pair(&gt);
  const cv::Mat bgr = painted(gt, {cv::Scalar(40, 40, 200), cv::Scalar(200, 90, 30)});
  auto r = detect(mask, bgr);
  ASSERT_TRUE(r.ok());
  const Detection& d = r.value();
  ASSERT_EQ(d.dlos.size(), 2u);
  EXPECT_GT(test::strict_dice(gt, d.labels), 0.9);
  ASSERT_EQ(d.crossings.size(), 2u);
  std::vector<float> xs;
  for (const Crossing& c : d.crossings) {
    EXPECT_NEAR(c.location.y, 100, 6);
    EXPECT_GT(c.angle_deg, 5);
    EXPECT_LT(c.angle_deg, 25);
    EXPECT_EQ(std::set<int>(c.dlos.begin(), c.dlos.end()).size(), 2u);
    xs.push_back(c.location.x);
  }
  std::sort(xs.begin(), xs.end());
  EXPECT_NEAR(xs[0], 160, 12);
  EXPECT_NEAR(xs[1], 240, 12);
}

// The twisted pair, painted so that the straight rod is on top at x = 160 and under at
// x = 240 (`alternate`), or on top at both.
void expect_tops_of_twisted_pair(bool alternate) {
  std::vector<cv::Mat> gt;
  const cv::Mat mask = twisted_pair(&gt);
  cv::Mat straight_over = gt[0].clone();
  if (alternate) straight_over(cv::Rect(200, 0, 200, 220)) = 0;
  const cv::Scalar red(40, 40, 200), blue(200, 90, 30);
  const cv::Mat bgr = painted({gt[0], gt[1], straight_over}, {red, blue, red});
  auto r = detect(mask, bgr);
  ASSERT_TRUE(r.ok());
  const Detection& d = r.value();
  ASSERT_EQ(d.crossings.size(), 2u);
  const int straight = d.labels.at<uint16_t>(100, 20) - 1;  // only the straight rod is there
  ASSERT_GE(straight, 0);
  for (const Crossing& c : d.crossings) {
    const bool straight_on_top = !alternate || c.location.x < 200;
    EXPECT_EQ(c.dlos[0] == straight, straight_on_top) << "crossing at x = " << c.location.x;
  }
}

TEST(Detector, EachCrossingOfATwistedPairHasItsOwnTop) {
  expect_tops_of_twisted_pair(true);
  expect_tops_of_twisted_pair(false);
}

TEST(Detector, RodsLeavingTheImageAndCrossingNearTheBorder) {
  std::vector<cv::Mat> gt;
  const cv::Mat mask = scene({200, 200}, {{{-20, 22}, {220, 22}}, {{24, -20}, {24, 220}}}, 13, &gt);
  auto r = detect(mask);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().dlos.size(), 2u);
  EXPECT_EQ(r.value().crossings.size(), 1u);
  EXPECT_GT(test::strict_dice(gt, r.value().labels), 0.95);
  expect_labels_cover_mask(r.value(), mask);
}

// The two rods `gt` of `mask` meet in a V: they come out as two DLOs, and as one DLO folded
// back when `without` turns off the rule that parts them (else the test proves nothing).
void expect_two_dlos_not_one_folded(const cv::Mat& mask, const std::vector<cv::Mat>& gt,
                                    const DetectorConfig& without) {
  auto r = detect(mask);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().dlos.size(), 2u);
  EXPECT_GT(test::strict_dice(gt, r.value().labels), 0.95);
  expect_labels_cover_mask(r.value(), mask);
  auto folded = detect(mask, cv::Mat(), without);
  ASSERT_TRUE(folded.ok());
  EXPECT_EQ(folded.value().dlos.size(), 1u) << "the scene must make the fold: else this test proves nothing";
}

// Two rods whose ends touch at a sharp angle: the mask is a V, and the skeleton's spur at
// its tip is pruned, leaving a junction with two exits. Joining them would fold one DLO
// back on itself by 155 degrees.
TEST(Detector, RodsTouchingEndToEndInAVAreTwoDlos) {
  std::vector<cv::Mat> gt;
  const cv::Mat mask = scene({240, 240}, {{{80, 220}, {120, 40}}, {{160, 220}, {120, 40}}}, 13, &gt);
  DetectorConfig never_fold_apart;
  never_fold_apart.fold_energy = 1000;
  expect_two_dlos_not_one_folded(mask, gt, never_fold_apart);
}

TEST(Detector, RodsLeavingTheImageSideBySideAreTwoDlos) {
  // Two straight rods leave through the top edge at one point, 74 degrees apart: the mask
  // is a V with its tip on the border, and the skeleton runs round the tip without a junction.
  std::vector<cv::Mat> gt;
  const cv::Mat mask = scene({240, 200}, {{{30, 150}, {120, -2}}, {{210, 150}, {120, -2}}}, 11, &gt);
  DetectorConfig never_cut;
  never_cut.border_fold_energy = 1000;
  expect_two_dlos_not_one_folded(mask, gt, never_cut);
}

TEST(Detector, RodsLeavingTheImageALittleApartAreTwoDlos) {
  // Two straight rods reach the top edge 9 px apart, one steep, one at 25 degrees to it:
  // the mask joins them along the border, and thinning runs the skeleton along it from one
  // to the other, so the turn is split between two corners, each too gentle alone.
  std::vector<cv::Mat> gt;
  const cv::Mat mask = scene({240, 200}, {{{20, 150}, {113, -3}}, {{235, 50}, {122, -3}}}, 11, &gt);
  DetectorConfig never_cut;
  never_cut.border_fold_energy = 1000;
  expect_two_dlos_not_one_folded(mask, gt, never_cut);
}

TEST(Detector, RodsLeavingTheImageSideBySideJustPastACrossingAreTwoDlos) {
  // As above, and a third rod crosses both arms 30 px below the edge: the arms run into
  // its junctions sooner than the 2 reach px the turn is first measured over, so it is
  // measured with the shorter chords they allow.
  std::vector<cv::Mat> gt;
  const cv::Mat mask =
      scene({240, 200}, {{{30, 150}, {120, -2}}, {{210, 150}, {120, -2}}, {{-10, 30}, {250, 30}}}, 11, &gt);
  auto r = detect(mask);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().dlos.size(), 3u);
  EXPECT_GT(test::strict_dice(gt, r.value().labels), 0.95);
  expect_labels_cover_mask(r.value(), mask);
}

TEST(Detector, BendLeavingTheImageAndComingBackStaysOneDlo) {
  // A rod bent round a circle of radius 50 px whose top runs just outside the top edge: its
  // skeleton runs along the border as two rods leaving it would, and turns as much, but
  // the arms bend at the same rate on either side, so it is not cut.
  std::vector<cv::Point> bend = test::arc({120, 45}, 50, M_PI * 0.8, M_PI * 2.2);
  const cv::Mat mask = scene({240, 200}, {bend}, 11);
  ASSERT_GT(cv::countNonZero(mask.row(0)), 20) << "the bend must run along the border";
  auto r = detect(mask);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().dlos.size(), 1u);
}

TEST(Detector, HairpinAtTheBorderStaysOneDlo) {
  // One rod bent back in a hairpin of radius 13 px (about 2 radii) whose apex grazes the
  // top edge: it turns as sharply as a V, but along the whole bend, so it is not cut.
  std::vector<cv::Point> hairpin = test::arc({120, 19}, 13, M_PI, 2 * M_PI);
  hairpin.insert(hairpin.begin(), cv::Point(107, 150));
  hairpin.emplace_back(133, 150);
  const cv::Mat mask = scene({240, 200}, {hairpin}, 11);
  ASSERT_GT(cv::countNonZero(mask.row(0)), 0) << "the bend must touch the border";
  auto r = detect(mask);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().dlos.size(), 1u);
}

// Two rods, the first green and the second red in the picture (`gt` as scene returns it),
// whose mask is one path: with the picture they are two DLOs; without it, one.
void expect_two_dlos_by_colour_alone(const cv::Mat& mask, const std::vector<cv::Mat>& gt) {
  auto r = detect(mask, painted(gt, {cv::Scalar(60, 170, 40), cv::Scalar(70, 60, 210)}));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().dlos.size(), 2u);
  EXPECT_GT(test::strict_dice(gt, r.value().labels), 0.95);
  auto joined = detect(mask);
  ASSERT_TRUE(joined.ok());
  EXPECT_EQ(joined.value().dlos.size(), 1u) << "without colour the rods must join: else this test proves nothing";
}

TEST(Detector, RodsOfTwoColoursTouchingEndToEndAreTwoDlos) {
  // A green rod comes down and ends where a red one starts, the red one's round end a little
  // past the green one's side: the mask is one gently bent path with a bump there.
  std::vector<cv::Mat> gt;
  const cv::Mat mask = scene({320, 260}, {{{80, 20}, {110, 120}, {130, 200}}, {{122, 208}, {200, 220}, {300, 215}}}, 13, &gt);
  expect_two_dlos_by_colour_alone(mask, gt);
}

// A green rod and a red one whose ends touch in the middle of the picture at the point
// `left_end`, `right_end` mirrored about x = 202: the mask is one V with no junction. With
// the picture, two DLOs; with colour_fold_energy at `uncut_at`, one.
void expect_v_of_two_colours_cut_below(cv::Point left_end, double uncut_at, const char* why) {
  std::vector<cv::Mat> gt;
  const cv::Point right_end(404 - left_end.x, left_end.y);
  const cv::Mat mask = scene({420, 300}, {{left_end, {200, 60}}, {right_end, {204, 60}}}, 13, &gt);
  expect_two_dlos_by_colour_alone(mask, gt);
  DetectorConfig uncut_config;
  uncut_config.colour_fold_energy = uncut_at;
  auto uncut = detect(mask, painted(gt, {cv::Scalar(60, 170, 40), cv::Scalar(70, 60, 210)}), uncut_config);
  ASSERT_TRUE(uncut.ok());
  EXPECT_EQ(uncut.value().dlos.size(), 1u) << why;
}

TEST(Detector, RodsOfTwoColoursMeetingTipToTipAreTwoDlos) {
  // Meeting at about 100 degrees.
  expect_v_of_two_colours_cut_below({62, 260}, 1000, "only the cut between colours must part them");
}

TEST(Detector, RodsOfTwoColoursMeetingTipToTipAt82DegreesAreTwoDlos) {
  // The same V, opened to a turn of 82 degrees (an inner angle of 98). The skeleton rounds
  // the tip, so the turn measured over its arms is smaller: enough for the default
  // colour_fold_energy (0.7) to cut it, not for its first value (1), which let such a V
  // through as one DLO (up to a drawn turn of about 90 degrees).
  expect_v_of_two_colours_cut_below({49, 191}, 1.0, "else this test does not tell the two thresholds apart");
}

TEST(Detector, TightHairpinOfOneColourStaysOneDlo) {
  // One red rod bent back in a hairpin of radius 13 px (about 2 radii) in the middle of the
  // picture: with the colour image, only a fold between two colours is cut.
  std::vector<cv::Point> hairpin = test::arc({200, 80}, 13, M_PI, 2 * M_PI);
  hairpin.insert(hairpin.begin(), cv::Point(187, 260));
  hairpin.emplace_back(213, 260);
  std::vector<cv::Mat> gt;
  const cv::Mat mask = scene({400, 300}, {hairpin}, 11, &gt);
  auto r = detect(mask, painted(gt, {cv::Scalar(70, 60, 210)}));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().dlos.size(), 1u);
}

TEST(Detector, CrossingInTheCornerDoesNotCrash) {
  // Two rods crossing where both leave the image: an L-shaped blob, ambiguous by nature.
  const cv::Mat mask = scene({200, 200}, {{{-20, 8}, {220, 8}}, {{5, -20}, {5, 220}}}, 13);
  auto r = detect(mask);
  ASSERT_TRUE(r.ok());
  EXPECT_GE(r.value().dlos.size(), 1u);
  expect_labels_cover_mask(r.value(), mask);
}

TEST(Detector, SplitEndsDoNotMakeExtraDlos) {
  cv::Mat mask = cv::Mat::zeros(120, 400, CV_8UC1);
  test::draw_rod(mask, {{20, 60}, {380, 60}}, 17);
  for (int x = 40; x < 360; x += 37) cv::circle(mask, {x, 68}, 4, 255, -1);  // a jagged edge
  auto r = detect(mask);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().dlos.size(), 1u);
}

TEST(Detector, EmptyMaskGivesNoDlosAndEmptyLabels) {
  auto r = detect(cv::Mat::zeros(50, 80, CV_8UC1));
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r.value().dlos.empty());
  EXPECT_EQ(r.value().labels.size(), cv::Size(80, 50));
  EXPECT_EQ(r.value().labels.type(), CV_16UC1);
  EXPECT_EQ(cv::countNonZero(r.value().labels), 0);
}

TEST(Detector, FullAndTinyMasksDoNotCrash) {
  for (cv::Size s : {cv::Size(80, 50), cv::Size(1, 1), cv::Size(1, 40), cv::Size(40, 1), cv::Size(2, 2)}) {
    cv::Mat full(s, CV_8UC1, cv::Scalar(255));
    auto r = detect(full);
    ASSERT_TRUE(r.ok()) << s;
    EXPECT_EQ(r.value().labels.size(), s);
    for (const Dlo& d : r.value().dlos) EXPECT_EQ(d.radius.size(), d.centerline.size());
  }
}

TEST(Detector, NonBinaryMaskIsTreatedAsBinary) {
  cv::Mat a = scene({300, 120}, {{{20, 60}, {280, 60}}}, 15);
  cv::Mat b = a.clone();
  b.setTo(7, a > 0);
  b(cv::Rect(0, 0, 150, 120)).setTo(200, a(cv::Rect(0, 0, 150, 120)) > 0);
  auto ra = detect(a), rb = detect(b);
  ASSERT_TRUE(ra.ok() && rb.ok());
  EXPECT_EQ(cv::countNonZero(ra.value().labels != rb.value().labels), 0);
}

TEST(Detector, BadInputIsAnErrorNamingTheProblem) {
  auto empty = detect(cv::Mat());
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.error().message.find("empty"), std::string::npos);

  auto wrong_type = detect(cv::Mat::zeros(10, 10, CV_32FC1));
  ASSERT_FALSE(wrong_type.ok());
  EXPECT_NE(wrong_type.error().message.find("CV_8UC1"), std::string::npos);

  auto wrong_size = detect(cv::Mat::zeros(10, 10, CV_8UC1), cv::Mat::zeros(12, 10, CV_8UC3));
  ASSERT_FALSE(wrong_size.ok());
  EXPECT_NE(wrong_size.error().message.find("10x12"), std::string::npos);

  auto gray_image = detect(cv::Mat::zeros(10, 10, CV_8UC1), cv::Mat::zeros(10, 10, CV_8UC1));
  ASSERT_FALSE(gray_image.ok());
  EXPECT_NE(gray_image.error().message.find("CV_8UC3"), std::string::npos);

  DetectorConfig bad;
  bad.fit_radii = 0;
  auto bad_config = detect(cv::Mat::zeros(10, 10, CV_8UC1), cv::Mat(), bad);
  ASSERT_FALSE(bad_config.ok());
  EXPECT_NE(bad_config.error().message.find("fit_radii"), std::string::npos);
  DetectorConfig negative;
  negative.merge_radii = -1;
  auto negative_config = detect(cv::Mat::zeros(10, 10, CV_8UC1), cv::Mat(), negative);
  ASSERT_FALSE(negative_config.ok());
  EXPECT_NE(negative_config.error().message.find("merge_radii"), std::string::npos);
}

}  // namespace
}  // namespace mbest

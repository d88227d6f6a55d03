#include "mbest/validate/crossing_list.h"

#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

namespace mbest::validate {
namespace {

using synth::CrossingAnnotation;
using synth::RodAnnotation;
using synth::SceneAnnotation;

// Rods 1 (6 px wide), 2 (8 px) and 3 (4 px). Crossing 0: rods 1 and 2 at (50, 40), rod 2 on
// top, 80 degrees; crossing 1: rod 3 over itself at (150, 40), 30 degrees. Matched DICE gave
// rod 1 label 5, rod 2 label 7, rod 3 label 9.
struct Scene {
  SceneAnnotation scene;
  DiceScore dice;

  Scene() {
    for (const auto& [id, width] : {std::pair{1, 6.0}, {2, 8.0}, {3, 4.0}}) {
      RodAnnotation r;
      r.id = id;
      r.width_px = width;
      scene.rods.push_back(r);
    }
    scene.crossings = {crossing({50, 40}, 80, 1, 2, 2), crossing({150, 40}, 30, 3, 3, 3)};
    dice.n = dice.m = 3;
    dice.gt_ids = {1, 2, 3};
    dice.pred_ids = {5, 7, 9};
    dice.matched_pred = {5, 7, 9};
    dice.matched_dice = {0.9, 0.9, 0.9};
  }

  static CrossingAnnotation crossing(cv::Point2d at, double angle, int a, int b, int top) {
    CrossingAnnotation c;
    c.location = at;
    c.angle_deg = angle;
    c.rod_a = a;
    c.rod_b = b;
    c.top = top;
    return c;
  }

  CrossingListScore match(const std::vector<DetectedCrossing>& detected) const {
    return match_crossing_list(scene, dice, detected);
  }
};

DetectedCrossing listed(cv::Point2d at, double angle, int top, int under) {
  return DetectedCrossing{at, angle, top, under};
}

TEST(CrossingList, ACorrectDetectionMatches) {
  const CrossingListScore s = Scene().match({listed({53, 44}, 77, 7, 5)});
  EXPECT_EQ(s.gt, 2);
  EXPECT_EQ(s.detected, 1);
  ASSERT_EQ(s.matches.size(), 1u);
  EXPECT_EQ(s.matches[0].detected, 0);
  EXPECT_EQ(s.matches[0].gt, 0);
  EXPECT_DOUBLE_EQ(s.matches[0].distance_px, 5.0);
  EXPECT_DOUBLE_EQ(s.matches[0].angle_error_deg, 3.0);
  EXPECT_TRUE(s.matches[0].top_assessed);
  EXPECT_TRUE(s.matches[0].top_correct);
}

TEST(CrossingList, AWrongLabelPairDoesNotMatch) {
  const Scene x;
  EXPECT_TRUE(x.match({listed({50, 40}, 80, 7, 9)}).matches.empty());  // rods 2 and 3
  EXPECT_TRUE(x.match({listed({50, 40}, 80, 7, 7)}).matches.empty());  // rod 2 over itself
  EXPECT_TRUE(x.match({listed({50, 40}, 80, 7, 6)}).matches.empty());  // a label no rod has
  // A rod left unmatched (label 0) matches no crossing, whatever the labels listed.
  Scene unmatched;
  unmatched.dice.matched_pred = {0, 7, 9};
  EXPECT_TRUE(unmatched.match({listed({50, 40}, 80, 7, 0)}).matches.empty());
  EXPECT_TRUE(unmatched.match({listed({50, 40}, 80, 7, 5)}).matches.empty());
}

TEST(CrossingList, ToleranceIsTwiceTheWiderRodAndAtLeastTenPixels) {
  const Scene x;
  // Rods 1 (6 px) and 2 (8 px): 16 px, not the narrower rod's 12.
  EXPECT_EQ(x.match({listed({50, 55.9}, 80, 5, 7)}).matches.size(), 1u);
  EXPECT_TRUE(x.match({listed({50, 56.1}, 80, 5, 7)}).matches.empty());
  // Rod 3 (4 px) over itself: 10 px, not 8.
  EXPECT_EQ(x.match({listed({159.9, 40}, 30, 9, 9)}).matches.size(), 1u);
  EXPECT_TRUE(x.match({listed({160.1, 40}, 30, 9, 9)}).matches.empty());
}

TEST(CrossingList, TwoDetectionsNearOneCrossingMatchItOnce) {
  const CrossingListScore s =
      Scene().match({listed({53, 40}, 80, 7, 5), listed({51, 40}, 80, 7, 5)});
  EXPECT_EQ(s.detected, 2);
  ASSERT_EQ(s.matches.size(), 1u);
  EXPECT_EQ(s.matches[0].detected, 1);  // the nearer one
  EXPECT_EQ(s.matches[0].gt, 0);
}

TEST(CrossingList, GreedyByAscendingDistanceOverAllPairs) {
  Scene x;
  x.scene.crossings.push_back(Scene::crossing({60, 40}, 80, 2, 1, 1));
  // Detection 0 lies 4 px from crossing 0 and 6 px from crossing 2; detection 1 lies 1 px
  // from crossing 0 and 9 px from crossing 2. The nearest pair goes first: detection 0 takes
  // crossing 2, though crossing 0 is nearer to it.
  const CrossingListScore s = x.match({listed({54, 40}, 80, 7, 5), listed({51, 40}, 80, 7, 5)});
  ASSERT_EQ(s.matches.size(), 2u);
  EXPECT_EQ(s.matches[0].detected, 1);
  EXPECT_EQ(s.matches[0].gt, 0);
  EXPECT_EQ(s.matches[1].detected, 0);
  EXPECT_EQ(s.matches[1].gt, 2);
}

TEST(CrossingList, TopIsTheLabelMatchedToTheTopRod) {
  const Scene x;
  const CrossingListScore right = x.match({listed({50, 40}, 80, 7, 5)});
  const CrossingListScore wrong = x.match({listed({50, 40}, 80, 5, 7)});
  ASSERT_EQ(right.matches.size(), 1u);
  ASSERT_EQ(wrong.matches.size(), 1u);  // the pair is right either way round
  EXPECT_TRUE(right.matches[0].top_assessed);
  EXPECT_TRUE(right.matches[0].top_correct);
  EXPECT_TRUE(wrong.matches[0].top_assessed);
  EXPECT_FALSE(wrong.matches[0].top_correct);
}

TEST(CrossingList, ASelfCrossingMatchesItsRodsLabelTwiceWithoutATopCheck) {
  const Scene x;
  const CrossingListScore s = x.match({listed({152, 41}, 40, 9, 9)});
  ASSERT_EQ(s.matches.size(), 1u);
  EXPECT_EQ(s.matches[0].gt, 1);
  EXPECT_DOUBLE_EQ(s.matches[0].angle_error_deg, 10.0);
  EXPECT_FALSE(s.matches[0].top_assessed);
  EXPECT_FALSE(s.matches[0].top_correct);
  EXPECT_TRUE(x.match({listed({150, 40}, 30, 9, 5)}).matches.empty());  // another rod's label
}

TEST(CrossingList, CountsAreEqualWhenTheListHasAsManyCrossings) {
  const Scene x;
  const DetectedCrossing far = listed({10, 10}, 45, 5, 7);
  EXPECT_TRUE(x.match({far, far}).count_equal());  // as many, even if none matches
  EXPECT_TRUE(x.match({far, far}).matches.empty());
  EXPECT_FALSE(x.match({far}).count_equal());
  EXPECT_FALSE(x.match({far, far, far}).count_equal());
  Scene none;
  none.scene.crossings.clear();
  EXPECT_TRUE(none.match({}).count_equal());
  EXPECT_EQ(none.match({far}).detected, 1);
}

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(CrossingList, ReadsDetectJson) {
  const std::string path = write_temp("xl_ok.json", R"({"dlos": [], "crossings": [
      {"location": [12.5, 7], "angle_deg": 33.3, "dlos_top_first": [2, 1]},
      {"location": [1, 2], "angle_deg": 90, "dlos_top_first": [3, 3]}]})");
  Result<std::vector<DetectedCrossing>> r = read_predicted_crossings(path);
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r.value().size(), 2u);
  EXPECT_EQ(r.value()[0].location, cv::Point2d(12.5, 7));
  EXPECT_DOUBLE_EQ(r.value()[0].angle_deg, 33.3);
  EXPECT_EQ(r.value()[0].top_label, 2);
  EXPECT_EQ(r.value()[0].under_label, 1);
  EXPECT_EQ(r.value()[1].top_label, r.value()[1].under_label);
}

TEST(CrossingList, BadDetectJsonNamesFileAndField) {
  struct Case {
    std::string json, message;
  };
  const std::string ok_location = R"("location": [1, 2])";
  const std::vector<Case> cases = {
      {R"({"dlos": []})", "field \"crossings\" missing"},
      {R"({"crossings": [3]})", "crossings[0] is not an object"},
      {R"({"crossings": [{"location": [1], "angle_deg": 5, "dlos_top_first": [1, 2]}]})",
       "crossings[0].location"},
      {"{\"crossings\": [{" + ok_location + ", \"dlos_top_first\": [1, 2]}]}",
       "crossings[0].angle_deg missing"},
      {"{\"crossings\": [{" + ok_location + ", \"angle_deg\": 95, \"dlos_top_first\": [1, 2]}]}",
       "crossings[0].angle_deg: 95"},
      {"{\"crossings\": [{" + ok_location + ", \"angle_deg\": 5, \"dlos_top_first\": [1]}]}",
       "crossings[0].dlos_top_first"},
      {"{\"crossings\": [{" + ok_location + ", \"angle_deg\": 5, \"dlos_top_first\": [0, 1]}]}",
       "crossings[0].dlos_top_first"},
      {"{\"crossings\": [{" + ok_location + ", \"angle_deg\": 5, \"dlos_top_first\": [1.5, 1]}]}",
       "crossings[0].dlos_top_first"},
      {"{\"crossings\": [{" + ok_location + ", \"angle_deg\": 5, \"dlos_top_first\": [1, 70000]}]}",
       "crossings[0].dlos_top_first"},
      {R"({"crossings": [)", "not valid JSON"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::string path = write_temp("xl_bad" + std::to_string(i) + ".json", cases[i].json);
    Result<std::vector<DetectedCrossing>> r = read_predicted_crossings(path);
    ASSERT_FALSE(r.ok()) << cases[i].json;
    EXPECT_NE(r.error().message.find(path), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find(cases[i].message), std::string::npos) << r.error().message;
  }
  Result<std::vector<DetectedCrossing>> missing =
      read_predicted_crossings(::testing::TempDir() + "xl_no_such.json");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace mbest::validate

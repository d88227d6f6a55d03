#include "mbest/validate/dice.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace mbest::validate {
namespace {

cv::Mat blank(int type = CV_16UC1) { return cv::Mat::zeros(40, 60, type); }

DiceScore score(const cv::Mat& gt, const cv::Mat& pred) {
  Result<DiceScore> r = matched_dice(gt, pred);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  return r.ok() ? r.value() : DiceScore{};
}

TEST(MatchedDice, IdenticalInstancesUnderOtherLabelValuesScoreOne) {
  cv::Mat gt = blank(CV_8UC1), pred = blank();
  gt(cv::Rect(0, 0, 10, 10)) = 1;
  gt(cv::Rect(20, 0, 10, 20)) = 2;
  pred(cv::Rect(0, 0, 10, 10)) = 7;
  pred(cv::Rect(20, 0, 10, 20)) = 3;
  const DiceScore s = score(gt, pred);
  EXPECT_EQ(s.n, 2);
  EXPECT_EQ(s.m, 2);
  EXPECT_DOUBLE_EQ(s.strict, 1.0);
  EXPECT_DOUBLE_EQ(s.lenient, 1.0);
  EXPECT_EQ(s.matched_pred, (std::vector<int>{7, 3}));
  EXPECT_FALSE(s.count_error());
}

TEST(MatchedDice, NoGroundTruthScoresOneOnlyWithoutPrediction) {
  EXPECT_DOUBLE_EQ(score(blank(), blank()).strict, 1.0);
  EXPECT_DOUBLE_EQ(score(blank(), blank()).lenient, 1.0);
  cv::Mat pred = blank();
  pred(cv::Rect(0, 0, 3, 3)) = 1;
  const DiceScore s = score(blank(), pred);
  EXPECT_DOUBLE_EQ(s.strict, 0.0);
  EXPECT_DOUBLE_EQ(s.lenient, 0.0);
  EXPECT_TRUE(s.count_error());
}

TEST(MatchedDice, NoPredictionScoresZero) {
  cv::Mat gt = blank();
  gt(cv::Rect(0, 0, 5, 5)) = 1;
  const DiceScore s = score(gt, blank());
  EXPECT_EQ(s.n, 1);
  EXPECT_EQ(s.m, 0);
  EXPECT_DOUBLE_EQ(s.strict, 0.0);
  EXPECT_DOUBLE_EQ(s.lenient, 0.0);
}

TEST(MatchedDice, SplitInstanceCostsInStrictOnly) {
  cv::Mat gt = blank(), pred = blank();
  gt(cv::Rect(0, 0, 20, 5)) = 1;    // 100 px
  pred(cv::Rect(0, 0, 10, 5)) = 1;  // 50 px each half
  pred(cv::Rect(10, 0, 10, 5)) = 2;
  const DiceScore s = score(gt, pred);
  const double d = 2.0 * 50 / (100 + 50);
  EXPECT_NEAR(s.lenient, d, 1e-12);
  EXPECT_NEAR(s.strict, d / 2, 1e-12);
  EXPECT_TRUE(s.count_error());
}

TEST(MatchedDice, SpuriousInstanceCostsInStrictOnly) {
  cv::Mat gt = blank(), pred = blank();
  gt(cv::Rect(0, 0, 20, 5)) = 1;
  pred(cv::Rect(0, 0, 20, 5)) = 1;
  pred(cv::Rect(40, 30, 4, 4)) = 2;
  const DiceScore s = score(gt, pred);
  EXPECT_DOUBLE_EQ(s.lenient, 1.0);
  EXPECT_DOUBLE_EQ(s.strict, 0.5);
  EXPECT_EQ(s.matched_pred, (std::vector<int>{1}));
}

TEST(MatchedDice, PartialOverlapFollowsTheFormula) {
  cv::Mat gt = blank(), pred = blank();
  gt(cv::Rect(0, 0, 10, 10)) = 1;    // 100 px
  pred(cv::Rect(5, 0, 10, 12)) = 4;  // 120 px, 50 shared
  const DiceScore s = score(gt, pred);
  EXPECT_NEAR(s.strict, 2.0 * 50 / 220, 1e-12);
  EXPECT_NEAR(s.matched_dice[0], 2.0 * 50 / 220, 1e-12);
}

TEST(MatchedDice, MatchingMaximisesTheTotalNotEachPair) {
  // GT 1 overlaps P 1 best, but giving P 1 to GT 2 (which has nothing else) wins overall.
  cv::Mat gt = blank(), pred = blank();
  gt(cv::Rect(0, 0, 20, 2)) = 1;   // 40 px
  gt(cv::Rect(0, 2, 20, 2)) = 2;   // 40 px
  pred(cv::Rect(0, 0, 20, 3)) = 1;  // 60 px: 40 of GT 1, 20 of GT 2
  pred(cv::Rect(0, 3, 20, 1)) = 2;  // 20 px of GT 2
  const DiceScore s = score(gt, pred);
  // GT1-P1 + GT2-P2 = 0.8 + 0.667; GT1-P2 + GT2-P1 = 0 + 0.4.
  EXPECT_EQ(s.matched_pred, (std::vector<int>{1, 2}));
  EXPECT_NEAR(s.strict, (80.0 / 100 + 40.0 / 60) / 2, 1e-12);
}

TEST(MatchedDice, OverlappingGroundTruthMasks) {
  cv::Mat a = cv::Mat::zeros(40, 60, CV_8UC1), b = a.clone(), pred = blank();
  a(cv::Rect(0, 10, 40, 4)) = 255;   // horizontal rod, 160 px
  b(cv::Rect(18, 0, 4, 40)) = 255;   // vertical rod, 160 px, 16 px shared with a
  pred(cv::Rect(0, 10, 40, 4)) = 1;  // the horizontal rod on top
  pred(cv::Rect(18, 0, 4, 10)) = 2;
  pred(cv::Rect(18, 14, 4, 26)) = 2;  // 144 px
  Result<DiceScore> r = matched_dice(std::vector<cv::Mat>{a, b}, pred);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r.value().gt_ids, (std::vector<int>{1, 2}));
  EXPECT_DOUBLE_EQ(r.value().matched_dice[0], 1.0);
  EXPECT_NEAR(r.value().matched_dice[1], 2.0 * 144 / (160 + 144), 1e-12);
  EXPECT_NEAR(r.value().strict, (1.0 + 288.0 / 304) / 2, 1e-12);
}

TEST(MatchedDice, RejectsMismatchedSizesAndTypes) {
  Result<DiceScore> size = matched_dice(blank(), cv::Mat::zeros(41, 60, CV_16UC1));
  ASSERT_FALSE(size.ok());
  EXPECT_NE(size.error().message.find("size"), std::string::npos);
  Result<DiceScore> type = matched_dice(blank(), cv::Mat::zeros(40, 60, CV_8UC3));
  ASSERT_FALSE(type.ok());
  EXPECT_NE(type.error().message.find("predicted labels"), std::string::npos);
  EXPECT_FALSE(matched_dice(cv::Mat(), blank()).ok());
}

TEST(MatchedDice, MissingPredictionScoresZeroEvenWithoutGroundTruth) {
  const DiceScore s = missing_prediction_score({});
  EXPECT_DOUBLE_EQ(s.strict, 0.0);
  const DiceScore t = missing_prediction_score({1, 2});
  EXPECT_EQ(t.n, 2);
  EXPECT_DOUBLE_EQ(t.lenient, 0.0);
}

}  // namespace
}  // namespace mbest::validate

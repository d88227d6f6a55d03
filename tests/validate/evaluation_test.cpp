#include "mbest/validate/evaluation.h"

#include <cmath>

#include <gtest/gtest.h>

#include "mbest/validate/dataset.h"
#include "mbest/validate/summary.h"
#include "test_data.h"

namespace mbest::validate {
namespace {

using namespace testing;  // NOLINT

Evaluation evaluate_ok(const fs::path& root, const fs::path& pred) {
  Result<Dataset> d = open_dataset(root.string());
  EXPECT_TRUE(d.ok()) << (d.ok() ? "" : d.error().message);
  EvalOptions o;
  o.pred_dir = pred.string();
  Result<Evaluation> e = evaluate(d.value(), o);
  EXPECT_TRUE(e.ok()) << (e.ok() ? "" : e.error().message);
  return e.ok() ? e.value() : Evaluation{};
}

TEST(Dataset, ListsTiersAndImagesInNaturalOrder) {
  const fs::path root = fresh_dir();
  for (const char* stem : {"img10", "img2", "img1"}) add_real_image(root, "S2", stem, two_bars());
  add_real_image(root, "S1", "img0", two_bars());
  Result<Dataset> d = open_dataset(root.string());
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_FALSE(d.value().synthetic);
  EXPECT_EQ(d.value().tiers, (std::vector<std::string>{"S1", "S2"}));
  std::vector<std::string> stems;
  for (const DatasetItem& i : d.value().items) stems.push_back(i.tier + "/" + i.stem);
  EXPECT_EQ(stems, (std::vector<std::string>{"S1/img0", "S2/img1", "S2/img2", "S2/img10"}));
  EXPECT_EQ(prediction_paths(d.value().items[0], "P").labels, "P/S1/images/img0.labels.png");
  EXPECT_EQ(prediction_paths(d.value().items[0], "P").json, "P/S1/images/img0.json");
}

TEST(Dataset, ASingleTierFolderIsItsOwnTier) {
  const fs::path root = fresh_dir();
  add_real_image(root, "S3", "img0", two_bars());
  Result<Dataset> d = open_dataset((root / "S3").string());
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_EQ(d.value().tiers, (std::vector<std::string>{"S3"}));
  EXPECT_EQ(prediction_paths(d.value().items[0], "P").labels, "P/images/img0.labels.png");
}

TEST(Dataset, BadLayoutsNameThePath) {
  const fs::path root = fresh_dir();
  Result<Dataset> missing = open_dataset((root / "nope").string());
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("nope"), std::string::npos);

  Result<Dataset> empty = open_dataset(root.string());
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.error().message.find("no tier folder"), std::string::npos);

  add_real_image(root, "S1", "img0", two_bars());
  fs::remove(root / "S1" / "labels" / "img0.png");
  Result<Dataset> no_label = open_dataset(root.string());
  ASSERT_FALSE(no_label.ok());
  EXPECT_NE(no_label.error().message.find("labels/img0.png"), std::string::npos);

  fs::remove_all(root / "S1" / "labels");
  Result<Dataset> no_labels_dir = open_dataset(root.string());
  ASSERT_FALSE(no_labels_dir.ok());
  EXPECT_NE(no_labels_dir.error().message.find("missing folder"), std::string::npos);
}

TEST(Evaluation, ScoresPredictionsAndMissingOnesAsZero) {
  const fs::path root = fresh_dir(), pred = root / "pred";
  const cv::Mat gt = two_bars();
  cv::Mat half = gt.clone();
  half.setTo(0, gt == 2);  // finds one bar of two
  add_real_image(root / "data", "S1", "img0", gt);
  add_real_image(root / "data", "S1", "img1", gt);
  add_real_image(root / "data", "S1", "img2", gt);
  add_prediction(pred, "S1", "img0", gt);
  add_prediction(pred, "S1", "img1", half);
  // img2 has no prediction.
  const Evaluation e = evaluate_ok(root / "data", pred);
  ASSERT_EQ(e.images.size(), 3u);
  EXPECT_DOUBLE_EQ(e.images[0].dice.strict, 1.0);
  EXPECT_DOUBLE_EQ(e.images[1].dice.strict, 0.5);
  EXPECT_DOUBLE_EQ(e.images[1].dice.lenient, 0.5);
  EXPECT_DOUBLE_EQ(e.images[2].dice.strict, 0.0);
  EXPECT_NE(e.images[2].prediction_error.find("img2.labels.png"), std::string::npos);
  EXPECT_TRUE(e.images[0].prediction_error.empty());

  const Summary s = summarise(e);
  ASSERT_EQ(s.tiers.size(), 1u);
  const TierSummary& t = s.tiers[0];
  EXPECT_EQ(t.images, 3);
  EXPECT_NEAR(t.strict_mean, 50.0, 1e-9);
  EXPECT_NEAR(t.strict_std, 100 * std::sqrt((0.25 + 0 + 0.25) / 3), 1e-9);  // population std
  EXPECT_EQ(t.below_90, 2);
  EXPECT_EQ(t.below_95, 2);
  EXPECT_EQ(t.count_errors, 2);
  EXPECT_EQ(t.missing_predictions, 1);
  ASSERT_EQ(s.strict_by_rod_count.size(), 1u);
  EXPECT_EQ(s.strict_by_rod_count[0].bin.label, "2");
  EXPECT_EQ(worst_images(e, 2), (std::vector<int>{2, 1}));
}

TEST(Evaluation, BelowNinetyFiveButNotNinety) {
  const fs::path root = fresh_dir(), pred = root / "pred";
  cv::Mat gt = cv::Mat::zeros(30, 40, CV_8UC1), p = gt.clone();
  gt(cv::Rect(0, 0, 40, 10)) = 1;  // 400 px
  p(cv::Rect(0, 0, 40, 9)) = 1;    // 360 px: D = 720 / 760 = 0.947
  add_real_image(root / "data", "S1", "img0", gt);
  add_prediction(pred, "S1", "img0", p);
  const Summary s = summarise(evaluate_ok(root / "data", pred));
  EXPECT_NEAR(s.tiers[0].strict_mean, 100 * 720.0 / 760, 1e-9);
  EXPECT_EQ(s.tiers[0].below_90, 0);
  EXPECT_EQ(s.tiers[0].below_95, 1);
  EXPECT_EQ(s.tiers[0].count_errors, 0);
}

TEST(Evaluation, UnusablePredictionsScoreZeroWithTheReason) {
  const fs::path root = fresh_dir(), pred = root / "pred";
  add_real_image(root / "data", "S1", "img0", two_bars());
  add_real_image(root / "data", "S1", "img1", two_bars());
  add_prediction(pred, "S1", "img0", cv::Mat::zeros(31, 40, CV_8UC1));  // wrong size
  write_text(pred / "S1" / "images" / "img1.labels.png", "not a png");
  const Evaluation e = evaluate_ok(root / "data", pred);
  ASSERT_EQ(e.images.size(), 2u);
  EXPECT_DOUBLE_EQ(e.images[0].dice.strict, 0.0);
  EXPECT_NE(e.images[0].prediction_error.find("differs from the ground truth"), std::string::npos);
  EXPECT_DOUBLE_EQ(e.images[1].dice.strict, 0.0);
  EXPECT_NE(e.images[1].prediction_error.find("cannot read"), std::string::npos);
}

TEST(Evaluation, UnreadableGroundTruthIsAnErrorNamingTheFile) {
  const fs::path root = fresh_dir();
  add_real_image(root / "data", "S1", "img0", two_bars());
  write_text(root / "data" / "S1" / "labels" / "img0.png", "garbage");
  Result<Dataset> d = open_dataset((root / "data").string());
  ASSERT_TRUE(d.ok());
  EvalOptions o;
  o.pred_dir = (root / "pred").string();
  Result<Evaluation> e = evaluate(d.value(), o);
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error().message.find("labels/img0.png"), std::string::npos);

  write_png(root / "data" / "S1" / "labels" / "img0.png", cv::Mat::zeros(30, 40, CV_8UC3));
  Result<Evaluation> colour = evaluate(d.value(), o);
  ASSERT_FALSE(colour.ok());
  EXPECT_NE(colour.error().message.find("1-channel"), std::string::npos);
}

TEST(Evaluation, KeepsOnlyTheWorstPredictions) {
  const fs::path root = fresh_dir(), pred = root / "pred";
  const cv::Mat gt = two_bars();
  for (int i = 0; i < 6; ++i) {
    cv::Mat p = gt.clone();
    p(cv::Rect(0, 5, 4 * i, 4)) = 0;  // image i loses more of bar 1 the larger i is
    add_real_image(root / "data", "S1", "img" + std::to_string(i), gt);
    add_prediction(pred, "S1", "img" + std::to_string(i), p);
  }
  Result<Dataset> d = open_dataset((root / "data").string());
  EvalOptions o;
  o.pred_dir = pred.string();
  o.keep_worst = 2;
  Result<Evaluation> e = evaluate(d.value(), o);
  ASSERT_TRUE(e.ok());
  for (int i = 0; i < 6; ++i)
    EXPECT_EQ(e.value().images[i].kept_prediction.empty(), i < 4) << "image " << i;
  EXPECT_EQ(worst_images(e.value(), 2), (std::vector<int>{5, 4}));
}

}  // namespace
}  // namespace mbest::validate

namespace mbest::validate {
namespace {

using namespace testing;  // NOLINT

TEST(Evaluation, SyntheticScenesGetCrossingsAndCenterlines) {
  const fs::path root = fresh_dir(), pred = root / "pred";
  synth::SceneAnnotation scene;
  const cv::Mat gt = add_synth_scene(root / "data", "s2", "000000", &scene);
  // Predicted labels: rod 1 as 2, rod 2 as 1; centerlines: DLO 0 (label 1) is rod 2's, one
  // pixel off; DLO 1 (label 2) is rod 1's exactly.
  cv::Mat p = cv::Mat::zeros(gt.size(), CV_16UC1);
  p.setTo(2, gt == 1);
  p.setTo(1, gt == 2);
  add_prediction(pred, "s2", "000000", p);
  std::string json = "{\"dlos\": [{\"centerline\": [";
  for (size_t i = 0; i < scene.rods[1].centerline.size(); ++i)
    json += (i ? ",[" : "[") + std::to_string(scene.rods[1].centerline[i].x + 1) + "," +
            std::to_string(scene.rods[1].centerline[i].y) + "]";
  json += "]}, {\"centerline\": [[5, 40], [95, 40]]}]";
  // One crossing, rod 1 (label 2) on top, 1.5 degrees off; one more that is not there.
  json += R"(, "crossings": [{"location": [52, 41], "angle_deg": 58.5, "dlos_top_first": [2, 1]},
                             {"location": [20, 40], "angle_deg": 10, "dlos_top_first": [2, 1]}]})";
  write_text(pred / "s2" / "images" / "000000.json", json);

  Result<Dataset> d = open_dataset((root / "data").string());
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_TRUE(d.value().synthetic);
  EvalOptions o;
  o.pred_dir = pred.string();
  Result<Evaluation> e = evaluate(d.value(), o);
  ASSERT_TRUE(e.ok()) << e.error().message;
  const ImageResult& r = e.value().images[0];
  EXPECT_DOUBLE_EQ(r.dice.strict, 1.0);
  ASSERT_EQ(r.rods.size(), 2u);
  EXPECT_EQ(r.rods[0].matched_pred, 2);
  EXPECT_DOUBLE_EQ(r.rods[1].complexity, 4.0);
  ASSERT_EQ(r.crossings.size(), 1u);
  EXPECT_TRUE(r.crossings[0].pairing_correct);
  EXPECT_TRUE(r.crossings[0].order_correct);
  ASSERT_TRUE(r.has_centerlines);
  const DistanceSummary p2g = summarise(r.centerline.pred_to_gt);
  EXPECT_GT(p2g.mean, 0.1);  // rod 2's prediction is one pixel to the right...
  EXPECT_LT(p2g.mean, 1.0);  // ...which is under a pixel from a 60-degree line
  EXPECT_EQ(p2g.count, static_cast<int>(scene.rods[1].centerline.size()) + 2);
  ASSERT_TRUE(r.has_crossing_list);
  EXPECT_EQ(r.crossing_list.gt, 1);
  EXPECT_EQ(r.crossing_list.detected, 2);
  ASSERT_EQ(r.crossing_list.matches.size(), 1u);
  EXPECT_EQ(r.crossing_list.matches[0].detected, 0);
  EXPECT_TRUE(r.crossing_list.matches[0].top_correct);
  EXPECT_DOUBLE_EQ(r.crossing_list.matches[0].angle_error_deg, 1.5);

  const Summary s = summarise(e.value());
  EXPECT_EQ(s.all.crossings, 1);
  EXPECT_EQ(s.pairing_by_angle[3].correct, 1);  // 45-90
  EXPECT_EQ(s.pairing_by_complexity[1].assessed, 1);  // max(0.5, 4.0) is in 3.14-6.28
  EXPECT_EQ(s.rod_dice_by_complexity[0].count, 1);
  EXPECT_EQ(s.rod_dice_by_complexity[1].count, 1);
  const CrossingListTotals& l = s.all.crossing_list;
  EXPECT_EQ(l.images, 1);
  EXPECT_EQ(l.gt, 1);
  EXPECT_EQ(l.detected, 2);
  EXPECT_EQ(l.matched, 1);
  EXPECT_EQ(l.count_equal, 0);
  EXPECT_EQ(l.top_assessed, 1);
  EXPECT_EQ(l.top_correct, 1);
  EXPECT_DOUBLE_EQ(l.angle_error_median, 1.5);
}

TEST(Evaluation, CrossingListsOfSeveralImagesAddUp) {
  const fs::path root = fresh_dir(), pred = root / "pred";
  const std::string dlos = R"("dlos": [{"centerline": [[5, 40]]}, {"centerline": [[5, 40]]}])";
  // Three images of the same scene, prediction = ground truth (rod 1 is label 1): the crossing
  // listed right, with the wrong rod on top and 4 degrees off, and not at all.
  const std::vector<std::string> crossings = {
      R"([{"location": [50, 40], "angle_deg": 60, "dlos_top_first": [1, 2]}])",
      R"([{"location": [50, 40], "angle_deg": 64, "dlos_top_first": [2, 1]}])", "[]"};
  for (int i = 0; i < 3; ++i) {
    const std::string stem = "00000" + std::to_string(i);
    add_prediction(pred, "s2", stem, add_synth_scene(root / "data", "s2", stem));
    write_text(pred / "s2" / "images" / (stem + ".json"),
               "{" + dlos + ", \"crossings\": " + crossings[i] + "}");
  }
  const CrossingListTotals l = summarise(evaluate_ok(root / "data", pred)).all.crossing_list;
  EXPECT_EQ(l.images, 3);
  EXPECT_EQ(l.gt, 3);
  EXPECT_EQ(l.detected, 2);
  EXPECT_EQ(l.matched, 2);
  EXPECT_EQ(l.count_equal, 2);
  EXPECT_EQ(l.top_assessed, 2);
  EXPECT_EQ(l.top_correct, 1);
  EXPECT_DOUBLE_EQ(l.angle_error_median, 2.0);  // of 0 and 4
}

TEST(Evaluation, WithRunTheCrossingListIsTheDetectors) {
  const fs::path root = fresh_dir();
  const cv::Mat gt = add_synth_scene(root, "s2", "000000");
  cv::Mat bgr(gt.size(), CV_8UC3, cv::Scalar(0, 0, 0));
  bgr.setTo(cv::Scalar(0, 200, 0), gt > 0);  // green: a hue the colour filter takes
  write_png(root / "s2" / "images" / "000000.png", bgr);
  Result<Dataset> d = open_dataset(root.string());
  ASSERT_TRUE(d.ok()) << d.error().message;
  EvalOptions o;
  o.run = true;
  Result<Evaluation> e = evaluate(d.value(), o);
  ASSERT_TRUE(e.ok()) << e.error().message;
  const ImageResult& r = e.value().images[0];
  ASSERT_EQ(r.dice.m, 2) << r.prediction_error;
  ASSERT_TRUE(r.has_crossing_list);
  EXPECT_EQ(r.crossing_list.detected, 1);
  // Matched only when DLO index d is read as label d + 1.
  ASSERT_EQ(r.crossing_list.matches.size(), 1u);
  EXPECT_LT(r.crossing_list.matches[0].angle_error_deg, 10);
}

TEST(Evaluation, MissingOrBadCrossingListIsSkippedWithAWarning) {
  const fs::path root = fresh_dir(), pred = root / "pred";
  for (const char* stem : {"000000", "000001", "000002"})
    add_prediction(pred, "s2", stem, add_synth_scene(root / "data", "s2", stem));
  write_text(pred / "s2" / "images" / "000000.json",
             R"({"dlos": [], "crossings": [{"location": [1, 2], "angle_deg": 5}]})");
  write_text(pred / "s2" / "images" / "000001.json", "{\"dlos\": [");
  // 000002 has no JSON.
  const Evaluation e = evaluate_ok(root / "data", pred);
  ASSERT_EQ(e.images.size(), 3u);
  for (const ImageResult& r : e.images) {
    EXPECT_FALSE(r.has_crossing_list) << r.item.stem;
    ASSERT_EQ(r.warnings.size(), 1u) << r.item.stem;
    EXPECT_NE(r.warnings[0].find(r.item.stem + ".json"), std::string::npos) << r.warnings[0];
    EXPECT_NE(r.warnings[0].find("detected crossings skipped"), std::string::npos) << r.warnings[0];
    EXPECT_DOUBLE_EQ(r.dice.strict, 1.0);
  }
  EXPECT_TRUE(e.images[0].has_centerlines);
  EXPECT_NE(e.images[0].warnings[0].find("crossings[0].dlos_top_first"), std::string::npos);
  EXPECT_NE(e.images[1].warnings[0].find("not valid JSON"), std::string::npos);
  EXPECT_NE(e.images[2].warnings[0].find("missing"), std::string::npos);
  EXPECT_EQ(summarise(e).all.crossing_list.images, 0);
}

TEST(Evaluation, MalformedPredictionJsonSkipsCenterlinesWithAWarning) {
  const fs::path root = fresh_dir(), pred = root / "pred";
  const cv::Mat gt = add_synth_scene(root / "data", "s2", "000000");
  add_prediction(pred, "s2", "000000", gt);
  write_text(pred / "s2" / "images" / "000000.json", "{\"dlos\": 3, \"crossings\": []}");
  Result<Dataset> d = open_dataset((root / "data").string());
  EvalOptions o;
  o.pred_dir = pred.string();
  Result<Evaluation> e = evaluate(d.value(), o);
  ASSERT_TRUE(e.ok());
  EXPECT_FALSE(e.value().images[0].has_centerlines);
  ASSERT_EQ(e.value().images[0].warnings.size(), 1u);
  EXPECT_NE(e.value().images[0].warnings[0].find("000000.json"), std::string::npos);
  EXPECT_TRUE(e.value().images[0].has_crossing_list);  // the crossings are read all the same
  EXPECT_DOUBLE_EQ(e.value().images[0].dice.strict, 1.0);
}

TEST(Evaluation, SynthImageWithoutAnnotationIsAnError) {
  const fs::path root = fresh_dir();
  add_synth_scene(root, "s2", "000000");
  add_synth_scene(root, "s2", "000001");
  fs::remove(root / "s2" / "annotations" / "000001.json");
  Result<Dataset> d = open_dataset(root.string());
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("000001.json"), std::string::npos);
}

}  // namespace
}  // namespace mbest::validate

namespace mbest::validate {
namespace {

// One s3 image: rods 1 and 2 found whole (matched D 0.99 and exactly 0.95), rod 3 split (0.6).
Evaluation failures_by_cause() {
  return one_scored_image({{1, 0.99}, {2, 0.95}, {3, 0.6}},
                          {scored_crossing(1, 2, 30, true, false),    // local, 20-45
                           scored_crossing(1, 3, 30, true, false),    // rod 3 split, 20-45
                           scored_crossing(3, 3, 60, true, false),    // self-crossing of the split rod, 45-90
                           scored_crossing(2, 2, 50, true, false),    // self-crossing of a whole rod, 45-90
                           scored_crossing(1, 2, 15, true, true),     // right
                           scored_crossing(1, 3, 15, false, false)});  // not assessed
}

TEST(Summary, APairingFailureIsLocalOnlyWhenEveryRodOfTheCrossingIsFoundWhole) {
  const Evaluation e = failures_by_cause();
  const ImageResult& r = e.images[0];
  EXPECT_EQ(pairing_failure(r, r.crossings[0]), PairingFailure::kLocal);
  EXPECT_EQ(pairing_failure(r, r.crossings[1]), PairingFailure::kRodSplitOrMerged);
  EXPECT_EQ(pairing_failure(r, r.crossings[2]), PairingFailure::kRodSplitOrMerged);
  EXPECT_EQ(pairing_failure(r, r.crossings[3]), PairingFailure::kLocal);
  EXPECT_EQ(pairing_failure(r, r.crossings[4]), PairingFailure::kNone);
  EXPECT_EQ(pairing_failure(r, r.crossings[5]), PairingFailure::kNone);

  const Summary s = summarise(e);
  ASSERT_EQ(s.tiers.size(), 1u);
  for (const TierSummary* t : {&s.tiers[0], &s.all}) {
    const std::vector<FailureBin>& f = t->pairing_failures_by_angle;
    ASSERT_EQ(f.size(), 4u);
    EXPECT_EQ(f[1].local + f[1].rod_split_or_merged, 0);  // 10-20: one right, one not assessed
    EXPECT_EQ(f[2].local, 1);
    EXPECT_EQ(f[2].rod_split_or_merged, 1);
    EXPECT_EQ(f[3].local, 1);
    EXPECT_EQ(f[3].rod_split_or_merged, 1);
  }
}

TEST(Summary, TheFailureGalleryTakesTheFirstImagesOfEachTierAndAngle) {
  Evaluation e = one_scored_image({{1, 0.99}, {2, 0.99}},
                                  {scored_crossing(1, 2, 30, true, false),
                                   scored_crossing(1, 2, 60, true, true),
                                   scored_crossing(1, 2, 35, true, false)});  // same bin: not shown
  e.dataset.tiers = {"a", "b"};
  const auto add = [&](const std::string& tier, std::vector<CrossingResolution> crossings) {
    ImageResult r = e.images[0];
    r.item.tier = tier;
    r.crossings = std::move(crossings);
    e.images.push_back(std::move(r));
  };
  e.images[0].item.tier = "a";
  add("b", {scored_crossing(1, 2, 70, true, false)});                 // image 1
  add("a", {scored_crossing(1, 2, 15, false, false),                  // not assessed
            scored_crossing(1, 2, 15, true, false),                   // image 2, 10-20
            scored_crossing(1, 2, 25, true, false)});                 // image 2, 20-45
  add("a", {scored_crossing(1, 2, 40, true, false)});                 // third at 20-45
  const std::vector<FailureView> g = failure_gallery(e, 2);
  ASSERT_EQ(g.size(), 4u);
  const auto is = [](const FailureView& v, int image, int crossing, int bin) {
    return v.image == image && v.crossing == crossing && v.bin == bin;
  };
  EXPECT_TRUE(is(g[0], 2, 1, 1));  // tier a, 10-20
  EXPECT_TRUE(is(g[1], 0, 0, 2));  // tier a, 20-45: images 0 and 2, not 3
  EXPECT_TRUE(is(g[2], 2, 2, 2));
  EXPECT_TRUE(is(g[3], 1, 0, 3));  // tier b, 45-90
  EXPECT_EQ(failure_gallery(e, 1).size(), 3u);
  EXPECT_TRUE(failure_gallery(e, 0).empty());
}

// evaluate() keeps the predictions the report's gallery of failed crossings shows, and no
// more, whatever order its threads finish in.
TEST(Evaluation, KeepsThePredictionsOfTheFirstFailedCrossings) {
  const fs::path root = fresh_dir(), pred = root / "pred";
  for (int i = 0; i < 5; ++i) {
    const std::string stem = "00000" + std::to_string(i);
    const cv::Mat gt = add_synth_scene(root / "data", "s2", stem);
    add_prediction(pred, "s2", stem, i == 0 ? gt : switched_at_the_crossing(gt));
  }
  Result<Dataset> d = open_dataset((root / "data").string());
  ASSERT_TRUE(d.ok()) << d.error().message;
  for (const int threads : {1, 3}) {
    EvalOptions o;
    o.pred_dir = pred.string();
    o.threads = threads;
    o.keep_failed_crossings = 2;
    Result<Evaluation> e = evaluate(d.value(), o);
    ASSERT_TRUE(e.ok()) << e.error().message;
    for (int i = 0; i < 5; ++i)
      EXPECT_EQ(e.value().images[i].kept_prediction.empty(), i != 1 && i != 2)
          << "image " << i << ", threads " << threads;
    const std::vector<FailureView> g = failure_gallery(e.value(), 2);
    ASSERT_EQ(g.size(), 2u);
    EXPECT_EQ(g[0].image, 1);
    EXPECT_EQ(g[1].image, 2);
    EXPECT_EQ(g[0].bin, 3);  // 60 degrees
  }
}

TEST(Summary, PairingIsBinnedByCrowdingUnderAndFromTwentyDegrees) {
  const auto crowded = [](double angle, bool assessed, bool correct, int neighbours) {
    CrossingResolution c = scored_crossing(1, 2, angle, assessed, correct);
    c.neighbours = neighbours;
    return c;
  };
  const Evaluation e = one_scored_image({{1, 0.99}, {2, 0.99}},
                                        {crowded(30, true, true, 0),
                                         crowded(20, true, false, 0),     // 20 counts as from 20
                                         crowded(15, true, true, 1),
                                         crowded(60, true, false, 3),     // bin 2-3
                                         crowded(60, true, true, 9),      // bin 4+
                                         crowded(5, false, false, 9)});   // not assessed
  const Summary s = summarise(e);
  for (const TierSummary* t : {&s.tiers[0], &s.all}) {
    const std::vector<RateBin>& under = t->pairing_by_crowding_under_20;
    const std::vector<RateBin>& from = t->pairing_by_crowding_from_20;
    ASSERT_EQ(under.size(), 4u);
    ASSERT_EQ(from.size(), 4u);
    EXPECT_EQ(from[0].assessed, 2);
    EXPECT_EQ(from[0].correct, 1);
    EXPECT_EQ(under[0].assessed, 0);
    EXPECT_EQ(under[1].assessed, 1);
    EXPECT_EQ(under[1].correct, 1);
    EXPECT_EQ(from[2].assessed, 1);
    EXPECT_EQ(from[2].correct, 0);
    EXPECT_EQ(from[3].assessed, 1);
    EXPECT_EQ(under[3].assessed, 0);
  }
  EXPECT_EQ(bin_index(crowding_bins(), 0), 0);
  EXPECT_EQ(bin_index(crowding_bins(), 3), 2);
  EXPECT_EQ(bin_index(crowding_bins(), 4), 3);
}

TEST(Summary, BinsAreHalfOpenAndTheLastHoldsItsTop) {
  EXPECT_EQ(bin_index(angle_bins(), 0), 0);
  EXPECT_EQ(bin_index(angle_bins(), 9.99), 0);
  EXPECT_EQ(bin_index(angle_bins(), 10), 1);
  EXPECT_EQ(bin_index(angle_bins(), 45), 3);
  EXPECT_EQ(bin_index(angle_bins(), 90), 3);
  EXPECT_EQ(bin_index(angle_bins(), 90.5), -1);
  EXPECT_EQ(bin_index(complexity_bins(), 3.0), 0);
  EXPECT_EQ(bin_index(complexity_bins(), 7.0), 2);
  EXPECT_EQ(bin_index(complexity_bins(), 1e6), 4);
  EXPECT_EQ(bin_index(complexity_bins(), -1), -1);
}

}  // namespace
}  // namespace mbest::validate

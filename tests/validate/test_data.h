// Tiny data sets written to a temporary folder, for the validate tests.
#pragma once

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "mbest/validate/evaluation.h"

namespace mbest::validate::testing {

namespace fs = std::filesystem;

// A fresh folder under the test temp dir, named after the running test.
inline fs::path fresh_dir(const std::string& tag = "") {
  const ::testing::TestInfo* t = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::path(::testing::TempDir()) /
                       ("mbest_validate_" + std::string(t->test_suite_name()) + "_" + t->name() + tag);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

inline void write_png(const fs::path& path, const cv::Mat& image) {
  fs::create_directories(path.parent_path());
  ASSERT_TRUE(cv::imwrite(path.string(), image)) << path;
}

inline void write_text(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

// Two horizontal bars (labels 1, 2) on a 40 x 30 picture.
inline cv::Mat two_bars() {
  cv::Mat labels = cv::Mat::zeros(30, 40, CV_8UC1);
  labels(cv::Rect(0, 5, 40, 4)) = 1;
  labels(cv::Rect(0, 20, 40, 4)) = 2;
  return labels;
}

// An mbest-real-layout data set ROOT/<tier>/{images,labels}/<stem>.png.
inline void add_real_image(const fs::path& root, const std::string& tier, const std::string& stem,
                           const cv::Mat& labels) {
  cv::Mat bgr(labels.size(), CV_8UC3, cv::Scalar(0, 0, 0));
  bgr.setTo(cv::Scalar(0, 200, 255), labels > 0);
  write_png(root / tier / "images" / (stem + ".png"), bgr);
  write_png(root / tier / "labels" / (stem + ".png"), labels);
}

// A prediction as `mbest detect --out PRED` writes it.
inline void add_prediction(const fs::path& pred, const std::string& tier, const std::string& stem,
                           const cv::Mat& labels) {
  cv::Mat l16;
  labels.convertTo(l16, CV_16U);
  write_png(pred / tier / "images" / (stem + ".labels.png"), l16);
}

}  // namespace mbest::validate::testing

#include "mbest/synth/annotation.h"

namespace mbest::validate::testing {

// A synth-layout scene ROOT/<split>/{images,labels,annotations}/<stem>: rod 1 horizontal
// through (50, 40), rod 2 at 60 degrees through the same point, rod 1 on top; 100 x 80.
// Returns the 16-bit ground-truth labels.
inline cv::Mat add_synth_scene(const fs::path& root, const std::string& split,
                               const std::string& stem, synth::SceneAnnotation* out = nullptr) {
  synth::SceneAnnotation scene;
  scene.image = "images/" + stem + ".png";
  scene.labels = "labels/" + stem + ".png";
  scene.width = 100;
  scene.height = 80;
  scene.preset = "test";
  const cv::Point2d c(50, 40), along(std::cos(CV_PI / 3), std::sin(CV_PI / 3));
  synth::RodAnnotation a, b;
  a.id = 1;
  b.id = 2;
  a.width_px = b.width_px = 6;
  a.complexity.total_turning_rad = 0.5;
  b.complexity.total_turning_rad = 4.0;
  for (int i = 0; i <= 90; ++i) a.centerline.emplace_back(5 + i, 40);
  for (int i = -40; i <= 40; ++i) b.centerline.push_back(c + i * along);
  scene.rods = {a, b};
  synth::CrossingAnnotation x;
  x.location = c;
  x.angle_deg = 60;
  x.rod_a = 1;
  x.rod_b = 2;
  x.top = 1;
  x.arc_index_a = 45;
  x.arc_index_b = 40;
  scene.crossings = {x};
  cv::Mat labels = cv::Mat::zeros(80, 100, CV_16UC1);
  for (const synth::RodAnnotation* r : {&b, &a}) {  // bottom first
    std::vector<cv::Point> pts;
    for (const cv::Point2d& p : r->centerline) pts.emplace_back(cvRound(p.x), cvRound(p.y));
    cv::polylines(labels, pts, false, cv::Scalar(r->id), static_cast<int>(r->width_px));
  }
  const fs::path split_dir = root / split;
  cv::Mat bgr(labels.size(), CV_8UC3, cv::Scalar(0, 0, 0));
  bgr.setTo(cv::Scalar(0, 200, 255), labels > 0);
  write_png(split_dir / scene.image, bgr);
  write_png(split_dir / scene.labels, labels);
  fs::create_directories(split_dir / "annotations");
  EXPECT_TRUE(synth::write_annotation(scene, (split_dir / "annotations" / (stem + ".json")).string()).ok());
  if (out) *out = scene;
  return labels;
}

// The prediction of an add_synth_scene scene that switches the strands at its crossing:
// right of x = 50 each rod carries the other's label.
inline cv::Mat switched_at_the_crossing(const cv::Mat& gt) {
  cv::Mat p = gt.clone();
  const cv::Rect right(51, 0, gt.cols - 51, gt.rows);
  p(right).setTo(2, gt(right) == 1);
  p(right).setTo(1, gt(right) == 2);
  return p;
}

// A scored crossing of rods a and b (a == b: a self-crossing), as crossing_resolution
// would leave it.
inline CrossingResolution scored_crossing(int a, int b, double angle_deg, bool assessed,
                                          bool correct) {
  CrossingResolution c;
  c.rod_a = a;
  c.rod_b = b;
  c.angle_deg = angle_deg;
  c.pairing_assessed = assessed;
  c.pairing_correct = correct;
  return c;
}

// An evaluation of one synthetic image of tier s3, already scored: its rods (id and matched
// DICE) and crossings, for what summaries and reports make of them.
inline Evaluation one_scored_image(const std::vector<std::pair<int, double>>& rod_dice,
                                   std::vector<CrossingResolution> crossings) {
  Evaluation e;
  e.dataset.synthetic = true;
  e.dataset.tiers = {"s3"};
  ImageResult r;
  r.item.tier = "s3";
  r.item.stem = "000000";
  r.item.annotation = "s3/annotations/000000.json";
  for (const auto& [id, dice] : rod_dice) r.rods.push_back({id, 8, 1, id, dice});
  r.crossings = std::move(crossings);
  e.images.push_back(std::move(r));
  return e;
}

}  // namespace mbest::validate::testing

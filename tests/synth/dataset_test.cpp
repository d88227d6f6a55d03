#include "mbest/synth/dataset.h"

#include <atomic>
#include <filesystem>
#include <iterator>
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

namespace mbest::synth {
namespace {

namespace fs = std::filesystem;

// Every file under dir, by relative path, with its bytes.
std::map<std::string, std::string> files_of(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    std::ifstream in(e.path(), std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    out[fs::relative(e.path(), dir).string()] = ss.str();
  }
  return out;
}

class Dataset : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("mbest_synth_dataset_test_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    // Smaller frames keep the suite fast; every feature of the stress preset stays on.
    config_ = make_config("stress", {{"scene", {{"width", 448}, {"height", 336}, {"rods", {3, 5}},
                                                {"length_px", {300, 700}}}},
                                     {"camera", {{"format", "jpg"}}}},
                          "test").value();
  }
  void TearDown() override { fs::remove_all(root_); }

  DatasetOptions options(const std::string& name, int jobs) {
    DatasetOptions o;
    o.config = config_;
    o.seed = 42;
    o.count = 6;
    o.out = (root_ / name).string();
    o.jobs = jobs;
    return o;
  }

  fs::path root_;
  SynthConfig config_;
};

TEST_F(Dataset, SameBytesWhateverTheJobsOrSharding) {
  ASSERT_TRUE(generate_dataset(options("one", 1), nullptr));
  ASSERT_TRUE(generate_dataset(options("three", 3), nullptr));
  for (int shard = 0; shard < 2; ++shard) {
    DatasetOptions o = options("sharded", 2);
    o.shard_index = shard;
    o.shard_count = 2;
    ASSERT_TRUE(generate_dataset(o, nullptr));
  }
  const auto one = files_of(root_ / "one");
  EXPECT_GE(one.size(), 6u * 6);  // image, labels, semantic, >= 3 amodal, annotation
  EXPECT_TRUE(one.count("train/coco.json"));
  EXPECT_TRUE(one.count("dataset.json"));
  EXPECT_EQ(one, files_of(root_ / "three"));
  EXPECT_EQ(one, files_of(root_ / "sharded"));
}

TEST_F(Dataset, ResumeRedoesOnlyUnfinishedScenesAndLeavesNoTemporaries) {
  const DatasetOptions o = options("resume", 2);
  ASSERT_TRUE(generate_dataset(o, nullptr));
  const auto before = files_of(o.out);
  // Simulate an interruption in scene 3: its annotation (written last) is missing and a
  // temporary file is left over.
  fs::remove(fs::path(o.out) / "train/annotations/000003.json");
  std::ofstream(fs::path(o.out) / "train/images/.000003.tmp.jpg") << "partial";
  Progress last;
  ASSERT_TRUE(generate_dataset(o, [&](const Progress& p) { last = p; }));
  EXPECT_EQ(last.skipped, 5);
  EXPECT_EQ(last.done, 1);
  EXPECT_EQ(files_of(o.out), before);  // same bytes, no .tmp left
}

TEST_F(Dataset, StopRequestEndsWithWholeScenesThatTheSameCallCompletes) {
  DatasetOptions o = options("stopped", 2);
  std::atomic<bool> stop{false};
  o.stop = &stop;
  // An interrupt arrives once two scenes are written.
  Status s = generate_dataset(o, [&](const Progress& p) {
    if (p.done == 2) stop = true;
  });
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find("interrupted"), std::string::npos) << s.error().message;
  const fs::path split = fs::path(o.out) / "train";
  const auto count = [&](const char* sub) {
    return std::distance(fs::directory_iterator(split / sub), fs::directory_iterator{});
  };
  // Only whole scenes (the scenes already started when the flag was seen are finished),
  // and no COCO file for an incomplete split.
  EXPECT_GE(count("annotations"), 2);
  EXPECT_LT(count("annotations"), 6);
  EXPECT_EQ(count("images"), count("annotations"));
  EXPECT_EQ(count("labels"), count("annotations"));
  EXPECT_FALSE(fs::exists(split / "coco.json"));

  stop = false;
  ASSERT_TRUE(generate_dataset(o, nullptr));
  ASSERT_TRUE(generate_dataset(options("whole", 1), nullptr));
  EXPECT_EQ(files_of(o.out), files_of(root_ / "whole"));
}

TEST_F(Dataset, RefusesAnotherConfigInTheSameSplit) {
  DatasetOptions o = options("mismatch", 1);
  o.count = 1;
  ASSERT_TRUE(generate_dataset(o, nullptr));
  o.seed = 43;
  Status s = generate_dataset(o, nullptr);
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find("already holds split 'train'"), std::string::npos);
}

TEST_F(Dataset, AnnotationsRoundTripAndMatchTheLabels) {
  DatasetOptions o = options("files", 1);
  o.count = 2;
  ASSERT_TRUE(generate_dataset(o, nullptr));
  const fs::path split = fs::path(o.out) / "train";
  Result<SceneAnnotation> a = read_annotation((split / "annotations/000001.json").string());
  ASSERT_TRUE(a) << a.error().message;
  const SceneAnnotation& s = a.value();
  EXPECT_EQ(s.index, 1);
  EXPECT_EQ(s.seed, 42u);
  EXPECT_EQ(s.preset, "stress");
  const cv::Mat labels = cv::imread((split / s.labels).string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(labels.type(), CV_16UC1);
  EXPECT_EQ(labels.cols, s.width);
  for (const RodAnnotation& r : s.rods) {
    const cv::Mat amodal = cv::imread((split / r.amodal_mask).string(), cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(amodal.empty()) << r.amodal_mask;
    EXPECT_EQ(cv::countNonZero((labels == r.id) & ~amodal), 0);
    EXPECT_GT(r.complexity.total_turning_rad, 0);
    EXPECT_GT(r.centerline.size(), 10u);
  }
  // Writing what was read gives the same file.
  const fs::path copy = root_ / "copy.json";
  ASSERT_TRUE(write_annotation(s, copy.string()));
  std::ifstream x(copy), y(split / "annotations/000001.json");
  std::stringstream sx, sy;
  sx << x.rdbuf();
  sy << y.rdbuf();
  EXPECT_EQ(sx.str(), sy.str());
  // A damaged file names the field.
  std::ofstream(copy) << R"({"image": "a", "labels": "b", "width": 1, "height": "x"})";
  Result<SceneAnnotation> bad = read_annotation(copy.string());
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("'height'"), std::string::npos);
}

}  // namespace
}  // namespace mbest::synth

// The `mbest detect` command as a user runs it: outputs, progress, and bad input.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "scenes.h"

namespace {

namespace fs = std::filesystem;

struct CommandRun {
  int code;
  std::string output;  // stdout and stderr
};

CommandRun mbest(const std::string& args) {
  const std::string cmd = std::string(MBEST_BINARY) + " " + args + " 2>&1";
  CommandRun r{0, ""};
  FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  while (p && fgets(buf, sizeof buf, p)) r.output += buf;
  const int status = p ? pclose(p) : -1;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

class DetectCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() /
          ("mbest_detect_test_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir);
    fs::create_directories(dir / "data/a/images");
    cv::Mat img = cv::Mat::zeros(120, 200, CV_8UC3);
    cv::Mat m = cv::Mat::zeros(120, 200, CV_8UC1);
    mbest::test::draw_rod(m, {{10, 60}, {190, 60}}, 13);
    img.setTo(cv::Scalar(90, 170, 60), m);
    cv::imwrite((dir / "data/a/images/good.png").string(), img);
    std::ofstream(dir / "data/a/images/broken.jpg") << "not a jpeg";
  }
  void TearDown() override { fs::remove_all(dir); }

  static int hidden_files(const fs::path& root) {
    int n = 0;
    for (const auto& e : fs::recursive_directory_iterator(root))
      n += e.path().filename().string().rfind('.', 0) == 0;
    return n;
  }
  fs::path dir;
};

TEST_F(DetectCommand, FolderRunWritesMirroredOutputsAndReportsTheBrokenImage) {
  const fs::path out = dir / "out";
  CommandRun r = mbest("detect " + (dir / "data").string() + " --out " + out.string() + " --overlay --timings " +
                (out / "timings.json").string());
  EXPECT_EQ(r.code, 1) << r.output;  // one image failed
  EXPECT_NE(r.output.find("broken.jpg"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("[2/2]"), std::string::npos) << "progress line: " << r.output;

  const fs::path stem = out / "a/images/good";
  ASSERT_TRUE(fs::exists(stem.string() + ".labels.png"));
  ASSERT_TRUE(fs::exists(stem.string() + ".overlay.png"));
  EXPECT_FALSE(fs::exists(out / "a/images/broken.labels.png"));
  const cv::Mat labels = cv::imread(stem.string() + ".labels.png", cv::IMREAD_UNCHANGED);
  EXPECT_EQ(labels.type(), CV_16UC1);
  EXPECT_GT(cv::countNonZero(labels == 1), 1500);

  std::ifstream js(stem.string() + ".json");
  const nlohmann::json j = nlohmann::json::parse(js);
  ASSERT_EQ(j["dlos"].size(), 1u);
  EXPECT_GT(j["dlos"][0]["centerline"].size(), 150u);
  EXPECT_EQ(j["dlos"][0]["centerline"].size(), j["dlos"][0]["radius"].size());

  std::ifstream ts(out / "timings.json");
  const nlohmann::json t = nlohmann::json::parse(ts);
  ASSERT_EQ(t["images"].size(), 1u);
  EXPECT_EQ(t["images"][0]["path"], "a/images/good.png");
  EXPECT_TRUE(t["median_stages_ms"].contains("skeleton"));
  EXPECT_GT(t["median_total_ms"].get<double>(), 0);
  EXPECT_EQ(hidden_files(out), 0) << "temporary files left behind";
}

TEST_F(DetectCommand, MaskOfAnotherSizeIsRejectedWithBothSizes) {
  cv::imwrite((dir / "mask.png").string(), cv::Mat::zeros(50, 50, CV_8UC1));
  CommandRun r = mbest("detect " + (dir / "data/a/images/good.png").string() + " --mask " + (dir / "mask.png").string() +
                " --out " + (dir / "out").string());
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("50x50"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("200x120"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out/good.labels.png"));
}

TEST_F(DetectCommand, EmptyMaskGivesValidEmptyOutputs) {
  cv::imwrite((dir / "mask.png").string(), cv::Mat::zeros(120, 200, CV_8UC1));
  CommandRun r = mbest("detect " + (dir / "data/a/images/good.png").string() + " --mask " + (dir / "mask.png").string() +
                " --out " + (dir / "out").string());
  EXPECT_EQ(r.code, 0) << r.output;
  const cv::Mat labels = cv::imread((dir / "out/good.labels.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(labels.empty());
  EXPECT_EQ(cv::countNonZero(labels), 0);
  std::ifstream js(dir / "out/good.json");
  EXPECT_TRUE(nlohmann::json::parse(js)["dlos"].empty());
  EXPECT_NE(r.output.find("the mask is empty"), std::string::npos) << r.output;
}

// A mask covering every pixel is a segmentation gone wrong, not a frame without DLOs: the
// image fails with a message naming it, and nothing is written for it.
TEST_F(DetectCommand, MaskCoveringEveryPixelIsAFailedImage) {
  cv::imwrite((dir / "mask.png").string(), cv::Mat(120, 200, CV_8UC1, cv::Scalar(255)));
  CommandRun r = mbest("detect " + (dir / "data/a/images/good.png").string() + " --mask " + (dir / "mask.png").string() +
                " --out " + (dir / "out").string());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("good.png: the mask covers every pixel (200x120)"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out/good.labels.png"));
  EXPECT_FALSE(fs::exists(dir / "out/good.json"));
}

TEST_F(DetectCommand, UnwritableOutputFolderIsAClearError) {
  std::ofstream(dir / "file") << "x";
  CommandRun r = mbest("detect " + (dir / "data/a/images/good.png").string() + " --out " + (dir / "file/sub").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("file/sub"), std::string::npos) << r.output;
}

// The timings file is written after the whole batch; a path that cannot take it is found
// before any image is detected.
TEST_F(DetectCommand, UnwritableTimingsPathFailsBeforeTheBatch) {
  std::ofstream(dir / "file") << "x";
  const std::string input = (dir / "data").string();
  for (const fs::path& bad : {dir / "file/sub/t.json", dir / "data"}) {
    const fs::path out = dir / ("out_" + bad.filename().string());
    CommandRun r = mbest("detect " + input + " --out " + out.string() + " --timings " + bad.string());
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("--timings"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out / "a/images/good.labels.png")) << bad << ": the batch ran first";
  }
  // A folder that does not exist yet is made, as --out's is.
  CommandRun ok = mbest("detect " + input + " --out " + (dir / "out").string() + " --quiet --timings " +
                        (dir / "new/t.json").string());
  EXPECT_EQ(ok.code, 1) << ok.output;  // the broken image
  EXPECT_TRUE(fs::exists(dir / "new/t.json")) << ok.output;
}

TEST_F(DetectCommand, MissingInputAndMissingArgument) {
  CommandRun missing = mbest("detect " + (dir / "nothing.png").string());
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.output.find("no such file"), std::string::npos) << missing.output;
  CommandRun no_args = mbest("detect");
  EXPECT_EQ(no_args.code, 2);
  EXPECT_NE(no_args.output.find("INPUT"), std::string::npos) << no_args.output;
}

// --config takes a JSON file or the same text inline, for detect's constants as for synth's
// preset fields; either way a bad field is named.
TEST_F(DetectCommand, ConfigIsAFileOrAnInlineObject) {
  const std::string input = (dir / "data/a/images/good.png").string();
  std::ofstream(dir / "fit.json") << R"({"fit_radii": 4})";
  const CommandRun from_file =
      mbest("detect " + input + " --config " + (dir / "fit.json").string() + " --out " + (dir / "f").string());
  EXPECT_EQ(from_file.code, 0) << from_file.output;
  const CommandRun from_text =
      mbest("detect " + input + " --config ' {\"fit_radii\": 4}' --out " + (dir / "t").string());
  EXPECT_EQ(from_text.code, 0) << from_text.output;
  const cv::Mat a = cv::imread((dir / "f/good.labels.png").string(), cv::IMREAD_UNCHANGED);
  const cv::Mat b = cv::imread((dir / "t/good.labels.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(a.empty());
  ASSERT_FALSE(b.empty());
  EXPECT_EQ(cv::countNonZero(a != b), 0);
  const CommandRun bad = mbest("detect " + input + " --config '{\"fit_radii\": -4}' --out " + (dir / "b").string());
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("fit_radii"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(dir / "b"));

  const std::string synth = "synth --count 1 --seed 3 --quiet --out ";
  const CommandRun one_rod = mbest(synth + (dir / "s").string() + R"( --config '{"scene": {"rods": [1, 1]}}')");
  ASSERT_EQ(one_rod.code, 0) << one_rod.output;
  std::ifstream annotation(dir / "s/train/annotations/000000.json");
  ASSERT_TRUE(annotation.good());
  EXPECT_EQ(nlohmann::json::parse(annotation)["rods"].size(), 1u);
  const CommandRun typo = mbest(synth + (dir / "u").string() + R"( --config '{"scene": {"rodz": 1}}')");
  EXPECT_EQ(typo.code, 2);
  EXPECT_NE(typo.output.find("scene.rodz"), std::string::npos) << typo.output;
  EXPECT_FALSE(fs::exists(dir / "u"));
  const CommandRun broken = mbest(synth + (dir / "v").string() + " --config '{\"scene\"'");
  EXPECT_EQ(broken.code, 2);
  EXPECT_NE(broken.output.find("not valid JSON"), std::string::npos) << broken.output;
}

// Whoever catches the mistake (the option parser or the command), an error in the arguments
// names the option and exits 2, or 1 for eval (whose 2 means a tier missed a gate); --help
// exits 0.
TEST_F(DetectCommand, ArgumentErrorsExitAsEachCommandDocuments) {
  const std::string out = (dir / "out").string();
  struct Case {
    std::string args, named;
    int code;
  };
  for (const Case& c : std::vector<Case>{
           {"synth --count -1 --out " + out, "--count", 2},
           {"synth --count 1 --preset bogus --out " + out, "bogus", 2},
           {"detect " + (dir / "data").string() + " --config " + (dir / "none.json").string(), "--config", 2},
           {"eval " + (dir / "data").string() + " --frobnicate", "--frobnicate", 1},
           {"unknown-command", "unknown-command", 2}}) {
    const CommandRun r = mbest(c.args);
    EXPECT_EQ(r.code, c.code) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.named), std::string::npos) << c.args << "\n" << r.output;
  }
  EXPECT_EQ(mbest("synth --help").code, 0);
}

}  // namespace

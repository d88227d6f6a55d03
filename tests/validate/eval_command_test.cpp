// `mbest eval` end to end: exit codes, messages, outputs. Runs the built binary.
#include <sys/wait.h>

#include <array>
#include <cstdio>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "test_data.h"

namespace mbest::validate {
namespace {

using namespace testing;  // NOLINT

struct Outcome {
  int code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

Outcome mbest(const std::string& args) {
  // One file per test: CTest runs the tests of this file in parallel processes.
  const std::string err_file = ::testing::TempDir() + "mbest_eval_stderr_" +
                               ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".txt";
  const std::string cmd = std::string(MBEST_BINARY) + " " + args + " 2>" + err_file;
  Outcome r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err_file);
  r.err.assign(std::istreambuf_iterator<char>(in), {});
  return r;
}

// data/S1: img0 found perfectly, img1 half; predictions in pred/.
fs::path small_dataset() {
  const fs::path root = fresh_dir();
  const cv::Mat gt = two_bars();
  cv::Mat half = gt.clone();
  half.setTo(0, gt == 2);
  add_real_image(root / "data", "S1", "img0", gt);
  add_real_image(root / "data", "S1", "img1", gt);
  add_prediction(root / "pred", "S1", "img0", gt);
  add_prediction(root / "pred", "S1", "img1", half);
  return root;
}

TEST(EvalCommand, PrintsTheTierTable) {
  const fs::path root = small_dataset();
  const Outcome r = mbest("eval " + (root / "data").string() + " --pred " + (root / "pred").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("S1         2          75.00  25.00      75.00         1         1"),
            std::string::npos)
      << r.out;
}

TEST(EvalCommand, MinDiceSetsTheExitCode) {
  const fs::path root = small_dataset();
  const std::string base = "eval " + (root / "data").string() + " --pred " + (root / "pred").string();
  EXPECT_EQ(mbest(base + " --min-dice 75").code, 0);
  const Outcome r = mbest(base + " --min-dice 75.01");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("tier S1: strict DICE 75.00 % is below --min-dice 75.01 %"),
            std::string::npos)
      << r.err;
}

TEST(EvalCommand, JsonAndReport) {
  const fs::path root = small_dataset();
  const Outcome r = mbest("eval " + (root / "data").string() + " --pred " + (root / "pred").string() +
                      " --json --report " + (root / "report").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["images"].size(), 2u);
  EXPECT_TRUE(fs::exists(root / "report" / "report.html"));
  EXPECT_TRUE(fs::exists(root / "report" / "report.md"));
  EXPECT_TRUE(fs::exists(root / "report" / "report.json"));
}

TEST(EvalCommand, BadInputEndsInAMessageAndExitCodeOne) {
  const fs::path root = small_dataset();
  const std::string data = (root / "data").string(), pred = (root / "pred").string();
  struct Case {
    std::string args, message;
  };
  fs::create_directories(root / "empty");
  write_text(root / "file", "x");
  const std::vector<Case> cases = {
      {"eval " + data, "--pred DIR"},
      {"eval " + (root / "nope").string() + " --pred " + pred, "nope: not a folder"},
      {"eval " + data + " --pred " + (root / "nope").string(), "prediction folder not found"},
      {"eval " + data + " --pred " + (root / "empty").string(), "no prediction for any image"},
      {"eval " + data + " --pred " + pred + " --report " + (root / "file").string(),
       "cannot create the report folder"},
  };
  for (const Case& c : cases) {
    const Outcome r = mbest(c.args);
    EXPECT_EQ(r.code, 1) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
  }
  EXPECT_NE(mbest("eval " + data + " --pred " + pred + " --run").code, 0);  // exclusive
}

TEST(EvalCommand, UnreadableLabelFailsWithoutWritingAReport) {
  const fs::path root = small_dataset();
  write_text(root / "data" / "S1" / "labels" / "img1.png", "truncated");
  const Outcome r = mbest("eval " + (root / "data").string() + " --pred " + (root / "pred").string() +
                      " --report " + (root / "report").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("S1/labels/img1.png: cannot read"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(root / "report"));
}

// A synth-layout scene on a plain grey picture, where the colour filter (made for coloured
// DLOs on a dark background) finds nothing, with the generator's mask in semantic/.
fs::path grey_synth_dataset() {
  const fs::path root = fresh_dir();
  const cv::Mat labels = add_synth_scene(root / "data", "test", "000000");
  write_png(root / "data" / "test" / "images" / "000000.png",
            cv::Mat(labels.size(), CV_8UC3, cv::Scalar(128, 128, 128)));
  cv::Mat semantic = cv::Mat::zeros(labels.size(), CV_8UC1);
  semantic.setTo(255, labels > 0);
  write_png(root / "data" / "test" / "semantic" / "000000.png", semantic);
  return root;
}

double strict_dice_pct(const Outcome& r) {
  return nlohmann::json::parse(r.out)["all"]["strict_dice_pct"].get<double>();
}

TEST(EvalCommand, RunTakesTheGeneratorsMasksWhereTheDataSetHasThem) {
  const fs::path root = grey_synth_dataset();
  const std::string data = (root / "data").string();
  const Outcome semantic = mbest("eval " + data + " --run --json");
  ASSERT_EQ(semantic.code, 0) << semantic.err;
  EXPECT_EQ(nlohmann::json::parse(semantic.out)["masks"], "semantic/");
  EXPECT_GT(strict_dice_pct(semantic), 90);
  const Outcome colour = mbest("eval " + data + " --run --colour-filter --json");
  ASSERT_EQ(colour.code, 0) << colour.err;
  EXPECT_EQ(nlohmann::json::parse(colour.out)["masks"], "colour_filter");
  EXPECT_LT(strict_dice_pct(colour), 10);
  const Outcome named = mbest("eval " + data + " --run --mask-sibling semantic --json");
  ASSERT_EQ(named.code, 0) << named.err;
  EXPECT_EQ(strict_dice_pct(named), strict_dice_pct(semantic));
  // The same figures as detecting first with the same masks, then scoring the folder.
  const std::string pred = (root / "pred").string();
  ASSERT_EQ(mbest("detect " + data + " --mask-sibling semantic --quiet --out " + pred).code, 0);
  const Outcome detected = mbest("eval " + data + " --pred " + pred + " --json");
  ASSERT_EQ(detected.code, 0) << detected.err;
  const nlohmann::json a = nlohmann::json::parse(semantic.out)["all"];
  const nlohmann::json b = nlohmann::json::parse(detected.out)["all"];
  EXPECT_EQ(a["strict_dice_pct"], b["strict_dice_pct"]);
  EXPECT_EQ(a["count_errors"], b["count_errors"]);
  EXPECT_EQ(a["crossings"], b["crossings"]);
  EXPECT_EQ(a["centerline_px"], b["centerline_px"]);

  // Without a mask for every image, --run falls back to the colour filter; a named folder
  // must have them all.
  fs::remove(root / "data" / "test" / "semantic" / "000000.png");
  const Outcome fallback = mbest("eval " + data + " --run --json");
  ASSERT_EQ(fallback.code, 0) << fallback.err;
  EXPECT_EQ(nlohmann::json::parse(fallback.out)["masks"], "colour_filter");
  const Outcome missing = mbest("eval " + data + " --run --mask-sibling semantic");
  EXPECT_EQ(missing.code, 1);
  EXPECT_NE(missing.err.find("semantic/000000.png"), std::string::npos) << missing.err;
}

TEST(EvalCommand, RunReportsProgressUnlessQuiet) {
  const fs::path root = grey_synth_dataset();
  const std::string data = (root / "data").string();
  // Not a terminal: a line per tenth of the images, the last one at the end.
  const Outcome loud = mbest("eval " + data + " --run");
  ASSERT_EQ(loud.code, 0) << loud.err;
  EXPECT_NE(loud.err.find("eval: "), std::string::npos) << loud.err;
  for (const char* flag : {" --quiet", " -q"}) {
    const Outcome quiet = mbest("eval " + data + " --run" + flag);
    ASSERT_EQ(quiet.code, 0) << quiet.err;
    EXPECT_EQ(quiet.err, "") << flag;
    // The same tables (the first line ends in the time taken).
    EXPECT_EQ(quiet.out.substr(quiet.out.find('\n')), loud.out.substr(loud.out.find('\n'))) << flag;
  }
}

TEST(EvalCommand, RunTakesDetectorConstantsInlineOrFromAFile) {
  const fs::path root = grey_synth_dataset();
  const std::string data = (root / "data").string();
  const Outcome inline_ok = mbest("eval " + data + " --run --json --config '{\"epsilon_radii\": 12}'");
  ASSERT_EQ(inline_ok.code, 0) << inline_ok.err;
  EXPECT_GT(strict_dice_pct(inline_ok), 90);
  EXPECT_NE(nlohmann::json::parse(inline_ok.out)["command"].get<std::string>().find("epsilon_radii"),
            std::string::npos);

  write_text(root / "bad.json", "{\"epsilon_radii\": -1}");
  const std::vector<std::string> bad_configs = {"'{\"epsilon_radii\": -1}'", (root / "bad.json").string()};
  for (const std::string& config : bad_configs) {
    const Outcome bad = mbest("eval " + data + " --run --config " + config);
    EXPECT_EQ(bad.code, 1) << config;
    EXPECT_NE(bad.err.find("epsilon_radii"), std::string::npos) << bad.err;
  }
  const Outcome unreadable = mbest("eval " + data + " --run --config " + (root / "none.json").string());
  EXPECT_EQ(unreadable.code, 1);
  EXPECT_NE(unreadable.err.find("none.json: cannot read the file"), std::string::npos) << unreadable.err;
  const Outcome folder = mbest("eval " + data + " --run --config " + root.string());
  EXPECT_EQ(folder.code, 1);
  EXPECT_NE(folder.err.find("is a folder, not a JSON file"), std::string::npos) << folder.err;
  // The options that shape --run make no sense with --pred.
  for (const char* option : {" --colour-filter", " --mask-sibling semantic", " --config x.json"})
    EXPECT_EQ(mbest("eval " + data + " --pred " + (root / "pred").string() + option).code, 1) << option;
}

}  // namespace
}  // namespace mbest::validate

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

}  // namespace
}  // namespace mbest::validate

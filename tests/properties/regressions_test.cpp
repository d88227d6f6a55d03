// Replays every shrunk failing case of the property suites stored in fixtures/regressions/
// (one test per file): {"property", "preset", "overrides", "seed", "transform", "note",
// "known_failure"}. A file with "known_failure" is a failure not fixed yet: its test is
// skipped with that message while the failure persists, and fails once the case passes, so
// the mark is removed when the fix lands.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "scene_case.h"

namespace mbest::properties {
namespace {

namespace fs = std::filesystem;

const fs::path kDir = fs::path(MBEST_FIXTURES_DIR) / "regressions";

std::vector<std::string> regression_files() {
  std::vector<std::string> files;
  if (!fs::is_directory(kDir)) return files;
  for (const auto& e : fs::directory_iterator(kDir)) {
    if (e.path().extension() == ".json") files.push_back(e.path().filename().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

class Regression : public ::testing::TestWithParam<std::string> {};

TEST_P(Regression, Replays) {
  const fs::path path = kDir / GetParam();
  std::ifstream in(path);
  ASSERT_TRUE(in) << "cannot read " << path;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    FAIL() << path << ": not valid JSON (" << e.what() << ")";
  }
  Result<SceneSpec> spec = spec_from_json(j, path.string());
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  const Verdict v = check(spec.value());
  ASSERT_TRUE(v.discard.empty()) << path << ": the scene no longer meets the premise of "
                                 << spec.value().property << " (" << v.discard
                                 << "); the generator changed: shrink the case again";
  const std::string known = j.value("known_failure", "");
  if (!known.empty()) {
    ASSERT_FALSE(v.passed()) << "regression " << GetParam()
                             << " passes now: remove its \"known_failure\" mark";
    GTEST_SKIP() << "KNOWN FAILURE, regression " << GetParam() << " not fixed in core/ yet: " << known
                 << "\n" << v.describe();
  }
  EXPECT_TRUE(v.failures.empty()) << "regression " << GetParam() << ":\n" << v.describe();
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = fs::path(info.param).stem().string();
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}

INSTANTIATE_TEST_SUITE_P(Fixtures, Regression, ::testing::ValuesIn(regression_files()), test_name);
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(Regression);

// The folder exists, so a misplaced checkout does not pass by replaying nothing.
TEST(Regressions, FolderExists) { EXPECT_TRUE(fs::is_directory(kDir)) << kDir; }

}  // namespace
}  // namespace mbest::properties

#include "mbest/synth/config.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace mbest::synth {
namespace {

using nlohmann::json;

std::string error_of(const json& overrides, const std::string& preset = "s3") {
  Result<SynthConfig> c = make_config(preset, overrides, "cfg.json");
  return c ? std::string() : c.error().message;
}

TEST(Config, PresetsAreValidAndDistinct) {
  for (const std::string& name : preset_names()) {
    Result<SynthConfig> c = make_config(name, json(), "none");
    ASSERT_TRUE(c) << c.error().message;
    EXPECT_EQ(c.value().preset, name);
  }
  EXPECT_EQ(make_config("s2", json(), "x").value().scene.rods.lo, 2);
  EXPECT_EQ(make_config("s1", json(), "x").value().scene.width, 672);  // portrait, as mbest-real
  EXPECT_EQ(make_config("s1", json(), "x").value().scene.height, 896);
  EXPECT_NE(error_of(json(), "s4").find("unknown preset 's4'"), std::string::npos);
}

TEST(Config, OverridesApplyFieldByField) {
  const SynthConfig c = make_config("s3", {{"scene", {{"rods", {2, 5}}}}, {"camera", {{"format", "png"}}}}, "x").value();
  EXPECT_EQ(c.scene.rods.lo, 2);
  EXPECT_EQ(c.scene.rods.hi, 5);
  EXPECT_EQ(c.camera.format, "png");
  EXPECT_EQ(c.scene.width, 672);  // untouched fields keep the preset's value
  // The full JSON form round-trips.
  json full = to_json(c);
  full.erase("preset");
  const SynthConfig again = make_config("s3", full, "x").value();
  EXPECT_EQ(to_json(again), to_json(c));
}

TEST(Config, ErrorsNameTheField) {
  EXPECT_NE(error_of({{"scene", {{"rodz", {1, 2}}}}}).find("unknown field 'scene.rodz'"), std::string::npos);
  EXPECT_NE(error_of({{"colour", 1}}).find("unknown field 'colour'"), std::string::npos);
  EXPECT_NE(error_of({{"scene", {{"rods", {0, 3}}}}}).find("'scene.rods'"), std::string::npos);
  EXPECT_NE(error_of({{"scene", {{"rods", {1, 13}}}}}).find("'scene.rods'"), std::string::npos);
  EXPECT_NE(error_of({{"scene", {{"rods", {3, 1}}}}}).find("lo > hi"), std::string::npos);
  EXPECT_NE(error_of({{"scene", {{"rods", {1.5, 2}}}}}).find("'scene.rods' must be a range of integers"), std::string::npos);
  EXPECT_NE(error_of({{"scene", {{"leave_image", 1.5}}}}).find("'scene.leave_image' value 1.5 is outside [0, 1]"), std::string::npos);
  EXPECT_NE(error_of({{"scene", {{"width", "wide"}}}}).find("'scene.width' must be an integer"), std::string::npos);
  EXPECT_NE(error_of({{"render", {{"palette", "neon"}}}}).find("'render.palette' 'neon' is not one of"), std::string::npos);
  EXPECT_NE(error_of({{"render", {{"background", {{"types", {"marble"}}}}}}}).find("'render.background.types'"), std::string::npos);
  EXPECT_NE(error_of({{"camera", {{"jpeg_quality", 0}}}}).find("'camera.jpeg_quality'"), std::string::npos);
  EXPECT_NE(error_of({{"scene", 3}}).find("'scene' must be a JSON object"), std::string::npos);
  EXPECT_NE(error_of({{"preset", "s1"}}).find("'preset'"), std::string::npos);
}

TEST(Config, BackgroundFolderMustBeReadable) {
  const json missing = {{"render", {{"background", {{"types", {"folder"}}, {"folder", "/nonexistent/bg"}}}}}};
  EXPECT_NE(error_of(missing).find("'render.background.folder': cannot read folder '/nonexistent/bg'"), std::string::npos);
  const auto dir = std::filesystem::temp_directory_path() / "mbest_synth_config_test_empty";
  std::filesystem::create_directories(dir);
  const json empty = {{"render", {{"background", {{"types", {"folder"}}, {"folder", dir.string()}}}}}};
  EXPECT_NE(error_of(empty).find("no .png or .jpg images"), std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(Config, LoadConfigNamesTheFile) {
  const auto file = std::filesystem::temp_directory_path() / "mbest_synth_config_test.json";
  std::ofstream(file) << "{\"scene\": {\"rods\": [2, 2],}";
  Result<SynthConfig> c = load_config("s3", file.string());
  ASSERT_FALSE(c);
  EXPECT_NE(c.error().message.find(file.string()), std::string::npos);
  std::ofstream(file) << "{\"camera\": {\"noise_sigma\": [0, 99]}}";
  c = load_config("s3", file.string());
  ASSERT_FALSE(c);
  EXPECT_NE(c.error().message.find(file.string() + ": field 'camera.noise_sigma'"), std::string::npos);
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace mbest::synth

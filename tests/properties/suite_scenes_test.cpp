// Scenes of the generated data sets where the detector once went wrong, regenerated in
// memory from their preset, seed and index: plain tests of what a user sees there (the
// property suites' shrunk cases live in fixtures/regressions/ instead).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "mbest/core/detector.h"
#include "mbest/synth/config.h"
#include "mbest/synth/dataset.h"
#include "mbest/validate/dice.h"

namespace mbest {
namespace {

synth::GeneratedScene scene(const std::string& preset, std::uint64_t seed, int index) {
  Result<synth::SynthConfig> config = synth::make_config(preset, nlohmann::json::object(), "test");
  EXPECT_TRUE(config.ok());
  Result<synth::GeneratedScene> s = synth::generate_scene(config.value(), seed, index);
  EXPECT_TRUE(s.ok()) << s.error().message;
  return std::move(s).value();
}

// `accuracy-suite.sh out/fresh-17000 200 17000`, s2 scene 000156: a rod crosses another,
// then makes a self-loop that lies along itself where it crosses itself at 41 degrees.
// Pairing the loop's two ends with each other and the rod's way in with its way out bent
// about as little as the rod's own path, and the loop came out a ring of its own.
TEST(SuiteScenes, ASelfLoopLyingAlongItsRodStaysPartOfTheRod) {
  const synth::GeneratedScene s = scene("s2", 17002, 156);
  ASSERT_EQ(s.annotation.rods.size(), 2u);
  const cv::Mat mask = s.render.labels > 0;
  const Result<Detection> d = detect(mask, s.render.image);
  ASSERT_TRUE(d.ok()) << d.error().message;
  ASSERT_EQ(d.value().dlos.size(), 2u);
  for (const Dlo& dlo : d.value().dlos) EXPECT_FALSE(dlo.closed);
  const Result<validate::DiceScore> dice = validate::matched_dice(s.render.labels, d.value().labels);
  ASSERT_TRUE(dice.ok());
  for (double v : dice.value().matched_dice) EXPECT_GE(v, 0.97);
  // Without the cost of closing a loop, the loop is a ring: the case this test is for.
  DetectorConfig no_loop_cost;
  no_loop_cost.loop_closing_cost = 0;
  EXPECT_EQ(detect(mask, s.render.image, no_loop_cost).value().dlos.size(), 3u);
}

// `accuracy-suite.sh out/fresh-15000 200 15000`, stress scene 000071: a ring of its own
// colour touches the other rods at one crossing cluster only. Its colour, which no other
// exit there shares, keeps it closed.
TEST(SuiteScenes, ARingOfItsOwnColourTouchingOneCrossingStaysARing) {
  const synth::GeneratedScene s = scene("stress", 15005, 71);
  int rings = 0;
  for (const auto& rod : s.annotation.rods) rings += rod.closed;
  ASSERT_EQ(rings, 1);
  const Result<Detection> d = detect(s.render.labels > 0, s.render.image);
  ASSERT_TRUE(d.ok()) << d.error().message;
  int closed = 0;
  for (const Dlo& dlo : d.value().dlos) closed += dlo.closed;
  EXPECT_EQ(closed, 1);
  EXPECT_EQ(d.value().dlos.size(), s.annotation.rods.size());
}

}  // namespace
}  // namespace mbest

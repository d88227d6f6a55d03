// The scenes the property tests run on, as replayable specs, and the properties themselves
// as checks of one spec. A spec is a synth preset, overrides of its config (the JSON form of
// mbest/synth/config.h), the data set seed (scene index 0), and, for the equivariance
// property, the transform applied to the detector's input. The rapidcheck generators
// (generators.h) draw specs; fixtures/regressions/<name>.json stores shrunk failing ones.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "mbest/core/detector.h"
#include "mbest/core/result.h"
#include "mbest/synth/dataset.h"

namespace mbest::properties {

struct SceneSpec {
  // The check the spec is for: two_rods, one_rod, equivariance, any_scene, ring, triple,
  // loop.
  std::string property;
  std::string preset = "s2";
  nlohmann::json overrides = nlohmann::json::object();  // synth config overrides
  std::uint64_t seed = 0;                               // data set seed, scene index 0
  // equivariance only: rot90, rot180, rot270 (clockwise), flip_x (mirror left-right),
  // flip_y (mirror top-bottom), transpose (mirror about the main diagonal).
  std::string transform = "none";
};

// {"property", "preset", "overrides", "seed", "transform"}; reading also accepts and ignores
// the regression files' "note" and "known_failure" fields. Errors name the source and field.
nlohmann::json to_json(const SceneSpec& spec);
Result<SceneSpec> spec_from_json(const nlohmann::json& j, const std::string& source);

// rapidcheck prints a counterexample with showValue (found by argument-dependent lookup).
void showValue(const SceneSpec& spec, std::ostream& os);

// The spec's scene, generated in memory, and the detector's result on its ground-truth
// foreground (labels > 0) with the rendered colour image.
struct Case {
  synth::GeneratedScene scene;
  cv::Mat mask;  // CV_8UC1, 255 = some rod's label
  Detection detection;
};
// Errors: a bad config, a generator error, or the detector's error or exception.
Result<Case> run_case(const SceneSpec& spec);

// The outcome of one property on one spec.
struct Verdict {
  std::string discard;                // non-empty: the scene misses the property's premise
  std::vector<std::string> failures;  // what the detector got wrong
  bool passed() const { return discard.empty() && failures.empty(); }
  std::string describe() const;       // the failures (or the discard reason), one per line
};

// Runs spec.property's check. An unknown property is a failure naming it.
Verdict check(const SceneSpec& spec);

// The properties (issue 4), one per spec.property value.
//   two_rods: two rods crossing once (their masks meet in one place) at 20-90 deg -> two
//     DLOs, the crossing's pairing
//     correct, each rod's matched DICE >= kMinRodDice.
//   one_rod: one rod inside the picture without self-contact -> one open DLO whose
//     centerline follows the rod end to end, monotonically in GT arc length up to
//     kArcJitterWidths rod widths of backtracking, endpoints within one width of the truth.
//   equivariance: detect(T(input)) mapped back by T^-1 equals detect(input): same DLO
//     count, same number of detected crossings, the same pairing outcome at every GT
//     crossing, and labels that disagree (after matching ids) on at most
//     kMaxEquivarianceDisagreement of the mask pixels.
//   any_scene: no error or exception; labels CV_16UC1 of the mask's size, values in
//     0..#DLOs, none outside the mask; every centerline non-empty, 8-connected (consecutive
//     pixels are distinct 8-neighbours; a ring also across its seam), inside the image and
//     no further than kMaxCenterlineOffMask px from the mask, labelled where on the mask;
//     one radius per pixel. A pixel may recur: a self-crossing passes it twice.
//   ring: one closed rod fully inside the picture -> one closed DLO.
//   triple: three rods through one point (and no crossing under 20 deg elsewhere) -> three
//     DLOs, pairing correct at every GT crossing the metric can assess.
//   loop: one rod inside the picture that crosses itself once (a self-loop) and touches
//     itself nowhere else -> one open DLO, matched DICE >= kMinRodDice, and one detected
//     crossing: a self-crossing of that DLO within two rod widths of the true one.
constexpr double kMinRodDice = 0.97;
constexpr double kArcJitterWidths = 0.5;
constexpr double kMaxEquivarianceDisagreement = 0.01;
constexpr float kMaxCenterlineOffMask = 2;

}  // namespace mbest::properties

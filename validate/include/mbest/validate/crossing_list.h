// The detector's own crossing list (`mbest detect`'s JSON, or Detection::crossings) against
// the ground truth's crossings of a synthetic scene. A figure beyond ../shared/docs/metrics.md,
// which scores crossings through the label image only (crossing_resolution.h).
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mbest/core/result.h"
#include "mbest/synth/annotation.h"
#include "mbest/validate/dice.h"

namespace mbest::validate {

// One crossing as the detector lists it. Labels are the predicted label image's values (DLO
// index + 1); a self-crossing lists one label twice.
struct DetectedCrossing {
  cv::Point2d location;  // pixels
  double angle_deg = 0;  // line angle, in [0, 90]
  int top_label = 0, under_label = 0;
};

struct CrossingListMatch {
  int detected = 0;  // index into the detected list
  int gt = 0;        // index into SceneAnnotation::crossings
  double distance_px = 0;
  double angle_error_deg = 0;  // |detected angle - ground-truth angle|
  // Top: the detected top label is the one matched to the ground-truth top rod. Assessed for
  // two different rods only: one label cannot tell a self-crossing's strands apart.
  bool top_assessed = false, top_correct = false;
};

struct CrossingListScore {
  int gt = 0;        // ground-truth crossings
  int detected = 0;  // listed crossings
  std::vector<CrossingListMatch> matches;  // by ascending distance
  bool count_equal() const { return gt == detected; }
};

// Matches detected crossings to ground-truth ones one-to-one, greedily by ascending distance
// over the admissible pairs. A pair is admissible when the detected labels are, as an
// unordered pair, the labels matched (dice.matched_pred) to the ground-truth crossing's two
// rods (that rod's label twice for a self-crossing), and the detected location lies within
// max(10 px, 2 x the wider rod's width_px) of the ground-truth one. A crossing naming a rod
// that is missing or unmatched matches nothing.
CrossingListScore match_crossing_list(const synth::SceneAnnotation& scene, const DiceScore& dice,
                                      const std::vector<DetectedCrossing>& detected);

// Reads the crossings of a `mbest detect` JSON: {"crossings": [{"location": [x, y],
// "angle_deg": a, "dlos_top_first": [top, under]}, ...]}, labels 1..65535, a in [0, 90].
// Errors name the file and the field.
Result<std::vector<DetectedCrossing>> read_predicted_crossings(const std::string& path);

}  // namespace mbest::validate

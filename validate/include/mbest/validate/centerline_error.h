// Centerline error (../shared/docs/metrics.md): distances, in pixels, from each predicted
// centerline point to the matched ground-truth centerline and from each ground-truth sample
// to the predicted one.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mbest/core/result.h"
#include "mbest/synth/annotation.h"
#include "mbest/validate/dice.h"

namespace mbest::validate {

struct Polyline {
  std::vector<cv::Point2d> points;  // ordered
  bool closed = false;              // the last point joins the first
};

// #from distances from each point of `from` to the nearest point of the polyline `to`
// (its segments, not only its vertices). Empty `to`: every distance is +infinity.
std::vector<double> distances_to_polyline(const std::vector<cv::Point2d>& from,
                                          const Polyline& to);

struct CenterlineDistances {
  std::vector<double> pred_to_gt;  // one per predicted centerline point of a matched DLO
  std::vector<double> gt_to_pred;  // one per ground-truth centerline sample of a matched rod
};

// For every rod matched (dice.matched_pred) to a predicted label L whose DLO L - 1 has a
// centerline in `predicted`, the distances both ways; ground-truth samples outside the
// scene's width x height (when set) are left out. Unmatched rods and DLOs add nothing.
CenterlineDistances centerline_distances(const synth::SceneAnnotation& scene,
                                         const std::vector<Polyline>& predicted,
                                         const DiceScore& dice);

struct DistanceSummary {
  int count = 0;
  double mean = 0;
  double p95 = 0;  // 95th percentile, linear interpolation between order statistics
};
DistanceSummary summarise(std::vector<double> distances);

// Reads the predicted centerlines of a `mbest detect` JSON: {"dlos": [{"centerline":
// [[x, y], ...], "closed": bool (optional)}, ...]}; entry i is the DLO of label i + 1.
// Errors name the file and the field.
Result<std::vector<Polyline>> read_predicted_centerlines(const std::string& path);

}  // namespace mbest::validate

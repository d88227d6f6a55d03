// Matched DICE of one image, exactly as ../shared/docs/metrics.md defines it:
// D[i][j] = 2 |G_i ∩ P_j| / (|G_i| + |P_j|); ground-truth instances are matched one-to-one to
// predicted ones maximising the total D; strict = sum / max(n, m), lenient = sum / n;
// n = 0 scores 1 if m = 0 else 0; m = 0 < n scores 0.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mbest/core/result.h"

namespace mbest::validate {

struct DiceScore {
  int n = 0;  // ground-truth instances
  int m = 0;  // predicted instances (distinct non-zero labels present)
  double strict = 0;
  double lenient = 0;
  std::vector<int> gt_ids;    // #n: label value (or mask index + 1) of each GT instance
  std::vector<int> pred_ids;  // #m: label value of each predicted instance, ascending
  // #n: the predicted label matched to GT instance i, 0 when unmatched (or matched at D = 0).
  std::vector<int> matched_pred;
  std::vector<double> matched_dice;  // #n: D of that match, 0 when unmatched
  bool count_error() const { return n != m; }
  // Index of the GT instance whose id is `gt_id`, -1 when there is none.
  int instance_of(int gt_id) const;
};

// A CV_8UC1 or CV_16UC1 label image as CV_16UC1 (the same data when it already is).
cv::Mat labels_16u(const cv::Mat& labels);

// gt_labels, pred_labels: CV_8UC1 or CV_16UC1, same size; 0 = background, every other value
// one instance. Errors name the argument and the offending type or size.
Result<DiceScore> matched_dice(const cv::Mat& gt_labels, const cv::Mat& pred_labels);

// gt_masks: one CV_8UC1 mask per GT instance (non-zero = inside), masks may overlap;
// instance i gets id i + 1. pred_labels as above, every mask its size.
Result<DiceScore> matched_dice(const std::vector<cv::Mat>& gt_masks, const cv::Mat& pred_labels);

// The score of an image whose prediction is missing or unreadable: 0, with the GT ids.
DiceScore missing_prediction_score(std::vector<int> gt_ids);

// The non-zero values present in a CV_8UC1 or CV_16UC1 label image, ascending.
std::vector<int> label_values(const cv::Mat& labels);

}  // namespace mbest::validate

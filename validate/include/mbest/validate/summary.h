// Aggregates of an Evaluation: per tier (../shared/docs/metrics.md) and per bin.
#pragma once

#include <string>
#include <vector>

#include "mbest/validate/centerline_error.h"
#include "mbest/validate/evaluation.h"

namespace mbest::validate {

// A half-open interval [lo, hi) of some figure; the last bin of a list also holds hi.
struct Bin {
  std::string label;
  double lo = 0, hi = 0;
};

// Crossing angle, degrees: 0-10, 10-20, 20-45, 45-90.
const std::vector<Bin>& angle_bins();
// Curvature complexity of a rod: its total absolute turning, total_turning_rad, in radians,
// binned by half turns: 0-π, π-2π, 2π-3π, 3π-4π, 4π and more (labels 0-3.14, ..., 12.57+).
// A crossing's complexity is the larger of its two rods'.
const std::vector<Bin>& complexity_bins();
// How crowded a crossing's place is: its neighbours (crossing_resolution.h), other
// crossings within a few widths: 0, 1, 2-3, 4 and more. Beyond metrics.md.
const std::vector<Bin>& crowding_bins();
// Index of the bin holding `value`, -1 when none does.
int bin_index(const std::vector<Bin>& bins, double value);

struct RateBin {
  Bin bin;
  int assessed = 0, correct = 0;
};

// Why a crossing's pairing failed (beyond metrics.md), read from the matched DICE of its
// rods: kLocal when every rod of the crossing is found whole (matched D >= kWholeRodDice), so
// the strands switch near this crossing and nowhere much else; kRodSplitOrMerged when a rod
// of the crossing is not (split into pieces, merged with another rod, or missed), a failure
// that usually starts elsewhere, at a stretch where strands lie along each other. Fixing the
// first is a matter of the crossing's own pairing, the second of the whole scene's.
enum class PairingFailure { kNone, kLocal, kRodSplitOrMerged };
constexpr double kWholeRodDice = 0.95;
// kNone for a crossing not assessed or paired right.
PairingFailure pairing_failure(const ImageResult& image, const CrossingResolution& crossing);

// Pairing failures of one angle bin by cause.
struct FailureBin {
  Bin bin;
  int local = 0, rod_split_or_merged = 0;
};

// The detector's crossing lists against the ground truth (crossing_list.h), summed over the
// images whose list was read. Beyond metrics.md.
struct CrossingListTotals {
  int images = 0;
  int gt = 0, detected = 0, matched = 0;  // recall = matched / gt, precision = matched / detected
  int count_equal = 0;                    // images listing as many crossings as the ground truth
  int top_assessed = 0, top_correct = 0;  // matched crossings of two different rods
  double angle_error_median = -1;         // degrees, over the matches; -1 without any
};

struct TierSummary {
  std::string tier;  // "all" for the whole data set
  int images = 0;
  // Mean and population standard deviation over the images, in percent.
  double strict_mean = 0, strict_std = 0;
  double lenient_mean = 0, lenient_std = 0;
  int below_90 = 0, below_95 = 0;  // images whose strict score is below 0.90, 0.95
  int count_errors = 0;            // images with n != m
  int missing_predictions = 0;     // images scored 0 for a missing or unusable prediction
  // Synthetic data only.
  int crossings = 0;
  int pairing_assessed = 0, pairing_correct = 0;
  int order_assessed = 0, order_correct = 0;
  std::vector<RateBin> pairing_by_angle;  // angle_bins(); the accuracy goal is per angle
  std::vector<FailureBin> pairing_failures_by_angle;  // angle_bins()
  // Pairing by crowding_bins(), crossings under 20 degrees and at 20 or more apart (the
  // accuracy goal's two ranges): whether failures come from lone crossings or from tangles.
  std::vector<RateBin> pairing_by_crowding_under_20, pairing_by_crowding_from_20;
  bool has_centerlines = false;  // some image had predicted centerlines
  DistanceSummary pred_to_gt, gt_to_pred;  // pooled over every point of the tier
  CrossingListTotals crossing_list;
  double detect_ms_median = -1;            // with --run
};

struct MeanBin {
  Bin bin;
  int count = 0;
  double mean = 0;  // a score in [0, 1]
};

struct Summary {
  std::vector<TierSummary> tiers;
  TierSummary all;
  // Synthetic data only (empty bins otherwise).
  std::vector<RateBin> pairing_by_angle, order_by_angle;
  std::vector<RateBin> pairing_by_complexity, order_by_complexity;
  std::vector<MeanBin> rod_dice_by_complexity;  // matched D of each rod, by its complexity
  // Strict score of each image by its number of ground-truth instances n (one bin per n).
  std::vector<MeanBin> strict_by_rod_count;
};

Summary summarise(const Evaluation& evaluation);

// Indices into evaluation.images of the `k` lowest strict scores, lowest first (ties: the
// earlier image first, the order evaluate() keeps predictions in).
std::vector<int> worst_images(const Evaluation& evaluation, int k);

// A crossing paired wrong, shown in a report's gallery of failures.
struct FailureView {
  int image = 0;     // index into evaluation.images
  int crossing = 0;  // index into that image's crossings
  int bin = 0;       // angle_bins() index
};
// The angle bins (angle_bins() indices) in which `image` has a crossing paired wrong, and for
// each the first such crossing.
std::vector<FailureView> failures_by_bin(const ImageResult& image, int image_index);
// Per tier and angle bin, the first `per_bin` images (in the data set's order) with a
// crossing paired wrong in that bin, each with its first such crossing; by tier, bin, image.
// evaluate() keeps the predictions of these images (EvalOptions::keep_failed_crossings).
std::vector<FailureView> failure_gallery(const Evaluation& evaluation, int per_bin);

}  // namespace mbest::validate

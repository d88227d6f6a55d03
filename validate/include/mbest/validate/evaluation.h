// Scores every image of a data set against a prediction: read from a `mbest detect --out`
// folder, or computed on the fly (colour_filter -> detect).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mbest/core/detector.h"
#include "mbest/core/result.h"
#include "mbest/synth/annotation.h"
#include "mbest/validate/centerline_error.h"
#include "mbest/validate/crossing_list.h"
#include "mbest/validate/crossing_resolution.h"
#include "mbest/validate/dataset.h"
#include "mbest/validate/dice.h"

namespace mbest::validate {

struct EvalOptions {
  std::string pred_dir;  // a `mbest detect --out` folder; used when run is false
  bool run = false;      // detect on the fly instead
  // With run: the mask of DIR/images/x.jpg is DIR/<mask_sibling>/x.png (e.g. "semantic" in
  // the synth layout); empty: the colour filter (coloured DLOs on a dark background).
  std::string mask_sibling;
  DetectorConfig detector;  // with run: the detector's constants
  int threads = 2;       // images scored in parallel
  // Keep the predicted labels of this many lowest-scoring images (for a report's gallery).
  int keep_worst = 0;
  // ... and per tier and crossing-angle bin, of the first this many images with a crossing
  // paired wrong in that bin (summary.h, failure_gallery: a report's gallery of failures).
  int keep_failed_crossings = 0;
  CrossingOptions crossing;
};

// One ground-truth rod of a synthetic scene and how well it was found.
struct RodResult {
  int id = 0;
  double width_px = 0;
  double complexity = 0;  // its total_turning_rad (see summary.h)
  int matched_pred = 0;   // matched predicted label, 0 = none
  double dice = 0;        // D of the match, 0 = none
};

struct ImageResult {
  DatasetItem item;
  std::string prediction;        // the predicted label file read; "(run)" with --run
  std::string prediction_error;  // why the prediction is missing or unusable (scored 0)
  DiceScore dice;
  std::vector<RodResult> rods;                // synthetic scenes only
  std::vector<CrossingResolution> crossings;  // synthetic scenes only
  bool has_centerlines = false;  // predicted centerlines and a synthetic ground truth
  CenterlineDistances centerline;
  // The detector's crossing list (its JSON, or with --run the Detection) against the ground
  // truth's: a figure beyond metrics.md, with a usable prediction on a synthetic scene only.
  bool has_crossing_list = false;
  CrossingListScore crossing_list;
  double detect_ms = -1;              // with --run: the detector's total time
  // The predicted labels, kept only for the EvalOptions::keep_worst lowest strict scores and
  // the images of the gallery of failed crossings (EvalOptions::keep_failed_crossings).
  cv::Mat kept_prediction;
  // E.g. a missing or unreadable prediction JSON on a synthetic scene (metrics skipped).
  std::vector<std::string> warnings;
};

struct Evaluation {
  Dataset dataset;
  EvalOptions options;
  std::vector<ImageResult> images;  // the data set's order
  double seconds = 0;               // wall time of evaluate()
};

// Scores one image against a prediction already in memory: pred_labels (CV_16UC1 or
// CV_8UC1, empty = missing) and, optionally (null when unknown), its centerlines and its
// crossing list. `scene` is null for a data set without annotations.
ImageResult score_image(const DatasetItem& item, const cv::Mat& gt_labels,
                        const synth::SceneAnnotation* scene, const cv::Mat& pred_labels,
                        const std::vector<Polyline>* pred_centerlines,
                        const std::vector<DetectedCrossing>* pred_crossings,
                        const CrossingOptions& options);

// Reads a label image (1-channel, 8- or 16-bit). Errors name the file.
Result<cv::Mat> read_label_image(const std::string& path);

// Scores every image of `dataset`. A missing or unreadable prediction scores 0 (its reason in
// ImageResult::prediction_error); an unreadable ground truth (label image, annotation,
// or with --run the colour image) is an error naming the file. `progress(done, total)` is
// called after each image, from the worker threads, one call at a time.
Result<Evaluation> evaluate(const Dataset& dataset, const EvalOptions& options,
                            const std::function<void(int, int)>& progress = {});

}  // namespace mbest::validate

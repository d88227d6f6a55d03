#include "mbest/validate/evaluation.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include <opencv2/imgcodecs.hpp>

#include "mbest/core/detector.h"
#include "mbest/core/segmentation.h"
#include "mbest/validate/summary.h"
#include "prediction_json.h"

namespace mbest::validate {

namespace {

// A prediction: its labels (empty when missing) and, when known, its centerlines and its
// crossing list.
struct Prediction {
  cv::Mat labels;
  std::string source;
  std::string error;
  bool has_centerlines = false;
  std::vector<Polyline> centerlines;
  bool has_crossings = false;
  std::vector<DetectedCrossing> crossings;
  std::vector<std::string> warnings;
  double detect_ms = -1;
};

// `want_json`: read the centerlines and crossings of the prediction's JSON too.
Prediction read_prediction(const DatasetItem& item, const std::string& pred_dir, bool want_json) {
  const PredictionPaths paths = prediction_paths(item, pred_dir);
  Prediction p;
  p.source = paths.labels;
  if (!std::filesystem::exists(paths.labels)) {
    p.error = paths.labels + ": missing prediction";
    return p;
  }
  Result<cv::Mat> labels = read_label_image(paths.labels);
  if (!labels) {
    p.error = labels.error().message;
    return p;
  }
  p.labels = std::move(labels).value();
  if (!want_json) return p;
  const std::string both_skipped = " (centerline error and detected crossings skipped)";
  if (!std::filesystem::exists(paths.json)) {
    p.warnings.push_back(paths.json + ": missing" + both_skipped);
    return p;
  }
  Result<nlohmann::json> json = read_json_file(paths.json);
  if (!json) {
    p.warnings.push_back(json.error().message + both_skipped);
    return p;
  }
  Result<std::vector<Polyline>> lines = centerlines_from_json(json.value(), paths.json);
  if (lines) {
    p.has_centerlines = true;
    p.centerlines = std::move(lines).value();
  } else {
    p.warnings.push_back(lines.error().message + " (centerline error skipped)");
  }
  Result<std::vector<DetectedCrossing>> crossings = crossings_from_json(json.value(), paths.json);
  if (crossings) {
    p.has_crossings = true;
    p.crossings = std::move(crossings).value();
  } else {
    p.warnings.push_back(crossings.error().message + " (detected crossings skipped)");
  }
  return p;
}

Result<Prediction> run_detector(const DatasetItem& item, const EvalOptions& options) {
  Result<cv::Mat> bgr = read_image(item.image);
  if (!bgr) return bgr.error();
  Prediction p;
  p.source = "(run)";
  const bool filter = options.mask_sibling.empty();
  Result<cv::Mat> mask =
      filter ? colour_filter(bgr.value())
             : read_mask(sibling_mask_path(item.image, options.mask_sibling), bgr.value().size());
  if (!mask) {  // read_mask's error names the file
    p.error = filter ? item.image + ": colour filter failed: " + mask.error().message
                     : mask.error().message;
    return p;
  }
  // An exception from the detector is its failure on this image, not the evaluation's.
  Result<Detection> detection = Error{"no result"};
  try {
    detection = detect(mask.value(), bgr.value(), options.detector);
  } catch (const std::exception& e) {
    detection = Error{std::string("threw ") + e.what()};
  }
  if (!detection) {
    p.error = item.image + ": detect failed: " + detection.error().message;
    return p;
  }
  p.labels = detection.value().labels;
  p.detect_ms = detection.value().total_ms();
  p.has_centerlines = true;
  for (const Dlo& dlo : detection.value().dlos) {
    Polyline line;
    line.closed = dlo.closed;
    for (const cv::Point& q : dlo.centerline) line.points.emplace_back(q.x, q.y);
    p.centerlines.push_back(std::move(line));
  }
  p.has_crossings = true;
  for (const Crossing& c : detection.value().crossings) {
    if (c.dlos.size() != 2) {
      p.has_crossings = false;
      p.crossings.clear();
      p.warnings.push_back(item.image + ": the detector listed a crossing of " +
                           std::to_string(c.dlos.size()) + " DLOs (detected crossings skipped)");
      break;
    }
    // DLO index d is label d + 1, as in the label image and `mbest detect`'s JSON.
    p.crossings.push_back(DetectedCrossing{c.location, c.angle_deg, c.dlos[0] + 1, c.dlos[1] + 1});
  }
  return p;
}

Result<ImageResult> evaluate_item(const DatasetItem& item, const EvalOptions& options) {
  Result<cv::Mat> gt = read_label_image(item.labels);
  if (!gt) return gt.error();
  std::optional<synth::SceneAnnotation> scene;
  if (!item.annotation.empty()) {
    Result<synth::SceneAnnotation> a = synth::read_annotation(item.annotation);
    if (!a) return a.error();
    scene = std::move(a).value();
  }
  Prediction pred;
  if (options.run) {
    Result<Prediction> r = run_detector(item, options);
    if (!r) return r.error();
    pred = std::move(r).value();
  } else {
    pred = read_prediction(item, options.pred_dir, scene.has_value());
  }
  if (!pred.labels.empty() && pred.labels.size() != gt.value().size()) {
    pred.error = pred.source + ": size " + std::to_string(pred.labels.cols) + "x" +
                 std::to_string(pred.labels.rows) + " differs from the ground truth's " +
                 std::to_string(gt.value().cols) + "x" + std::to_string(gt.value().rows);
    pred.labels = cv::Mat();
  }
  ImageResult r = score_image(item, gt.value(), scene ? &*scene : nullptr, pred.labels,
                              pred.has_centerlines ? &pred.centerlines : nullptr,
                              pred.has_crossings ? &pred.crossings : nullptr, options.crossing);
  r.prediction = pred.source;
  if (!pred.error.empty()) r.prediction_error = pred.error;
  r.detect_ms = pred.detect_ms;
  r.kept_prediction = pred.labels;
  r.warnings = std::move(pred.warnings);
  return r;
}

}  // namespace

Result<cv::Mat> read_label_image(const std::string& path) {
  cv::Mat m;
  try {
    m = cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    return Error{path + ": cannot read as an image (" + e.what() + ")"};
  }
  if (m.empty()) return Error{path + ": cannot read as an image"};
  if (m.channels() != 1 || (m.depth() != CV_8U && m.depth() != CV_16U))
    return Error{path + ": expected a 1-channel 8- or 16-bit label image, got " +
                 std::to_string(m.channels()) + " channel(s)" +
                 (m.depth() == CV_8U || m.depth() == CV_16U ? "" : " of an unsupported depth")};
  return m;
}

ImageResult score_image(const DatasetItem& item, const cv::Mat& gt_labels,
                        const synth::SceneAnnotation* scene, const cv::Mat& pred_labels,
                        const std::vector<Polyline>* pred_centerlines,
                        const std::vector<DetectedCrossing>* pred_crossings,
                        const CrossingOptions& options) {
  ImageResult r;
  r.item = item;
  if (pred_labels.empty()) {
    r.prediction_error = "missing prediction";
    r.dice = missing_prediction_score(label_values(gt_labels));
  } else {
    Result<DiceScore> d = matched_dice(gt_labels, pred_labels);
    if (d) {
      r.dice = std::move(d).value();
    } else {
      r.prediction_error = d.error().message;
      r.dice = missing_prediction_score(label_values(gt_labels));
    }
  }
  if (!scene) return r;
  for (const synth::RodAnnotation& rod : scene->rods) {
    RodResult rr;
    rr.id = rod.id;
    rr.width_px = rod.width_px;
    rr.complexity = rod.complexity.total_turning_rad;
    if (const int i = r.dice.instance_of(rod.id); i >= 0) {
      rr.matched_pred = r.dice.matched_pred[i];
      rr.dice = r.dice.matched_dice[i];
    }
    r.rods.push_back(rr);
  }
  // With no usable prediction every crossing is unresolved: sampled on an empty label image.
  const cv::Mat pred = r.prediction_error.empty() ? pred_labels
                                                  : cv::Mat::zeros(gt_labels.size(), CV_16UC1);
  r.crossings = crossing_resolution(*scene, gt_labels, pred, r.dice, options);
  if (pred_centerlines && r.prediction_error.empty()) {
    r.has_centerlines = true;
    r.centerline = centerline_distances(*scene, *pred_centerlines, r.dice);
  }
  if (pred_crossings && r.prediction_error.empty()) {
    r.has_crossing_list = true;
    r.crossing_list = match_crossing_list(*scene, r.dice, *pred_crossings);
  }
  return r;
}

Result<Evaluation> evaluate(const Dataset& dataset, const EvalOptions& options,
                            const std::function<void(int, int)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  const int total = static_cast<int>(dataset.items.size());
  std::vector<std::optional<ImageResult>> results(total);
  std::vector<std::string> errors(total);
  std::atomic<int> next{0};
  std::atomic<bool> failed{false};
  std::mutex mutex;  // guards results, errors, kept, first_failures and done
  std::vector<int> kept;  // images whose prediction is kept, at most options.keep_worst
  // Per (tier, angle bin): the first images with a crossing paired wrong there, at most
  // options.keep_failed_crossings, whose predictions are kept too (failure_gallery).
  std::map<std::pair<std::string, int>, std::vector<int>> first_failures;
  int done = 0;
  const auto still_kept = [&](int i) {
    if (std::find(kept.begin(), kept.end(), i) != kept.end()) return true;
    for (const auto& [key, images] : first_failures)
      if (std::find(images.begin(), images.end(), i) != images.end()) return true;
    return false;
  };
  // Keeps image i's prediction if it is among the worst or the first failures so far, and
  // drops the predictions that leaves out.
  const auto keep = [&](int i) {
    std::vector<int> dropped;
    kept.push_back(i);
    if (static_cast<int>(kept.size()) > options.keep_worst) {
      // Ties go to the earlier image, as in the report's ranking of the worst.
      const auto best = std::max_element(kept.begin(), kept.end(), [&](int a, int b) {
        return std::make_pair(results[a]->dice.strict, a) < std::make_pair(results[b]->dice.strict, b);
      });
      dropped.push_back(*best);
      kept.erase(best);
    }
    if (options.keep_failed_crossings > 0) {
      for (const FailureView& v : failures_by_bin(*results[i], i)) {
        std::vector<int>& images = first_failures[{results[i]->item.tier, v.bin}];
        images.insert(std::upper_bound(images.begin(), images.end(), i), i);
        if (static_cast<int>(images.size()) <= options.keep_failed_crossings) continue;
        dropped.push_back(images.back());
        images.pop_back();
      }
    }
    for (const int d : dropped)
      if (!still_kept(d)) results[d]->kept_prediction = cv::Mat();
  };
  const auto work = [&] {
    for (int i = next++; i < total && !failed; i = next++) {
      Result<ImageResult> r = Error{""};
      try {
        r = evaluate_item(dataset.items[i], options);
      } catch (const std::exception& e) {
        r = Error{dataset.items[i].image + ": " + e.what()};
      }
      std::lock_guard<std::mutex> lock(mutex);
      if (r) {
        results[i] = std::move(r).value();
        keep(i);
      } else {
        errors[i] = r.error().message;
        failed = true;
      }
      ++done;
      if (progress) progress(done, total);
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::max(1, options.threads); ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  for (const std::string& e : errors)
    if (!e.empty()) return Error{e};

  Evaluation ev;
  ev.dataset = dataset;
  ev.options = options;
  for (std::optional<ImageResult>& r : results) ev.images.push_back(std::move(*r));
  ev.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return ev;
}

}  // namespace mbest::validate

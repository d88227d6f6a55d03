#include "mbest/validate/dice.h"

#include <algorithm>
#include <cstdint>

#include "mbest/validate/hungarian.h"

namespace mbest::validate {

namespace {

Status check_labels(const cv::Mat& labels, const char* name) {
  if (labels.empty()) return Error{std::string(name) + ": empty image"};
  if (labels.type() != CV_8UC1 && labels.type() != CV_16UC1)
    return Error{std::string(name) + ": expected a 1-channel 8- or 16-bit label image, got " +
                 std::to_string(labels.channels()) + " channel(s) of depth code " +
                 std::to_string(labels.depth())};
  return ok_status();
}

// index[v] = position of label v in `values`, -1 for values not present (and for 0).
std::vector<int> index_of_values(const std::vector<int>& values) {
  std::vector<int> index(65536, -1);
  for (size_t k = 0; k < values.size(); ++k) index[values[k]] = static_cast<int>(k);
  return index;
}

// Fills the score from the overlap table: gt_area[i], pred_area[j], overlap[i][j].
DiceScore score_from_overlaps(std::vector<int> gt_ids, std::vector<int> pred_ids,
                              const std::vector<int64_t>& gt_area,
                              const std::vector<int64_t>& pred_area,
                              const std::vector<std::vector<int64_t>>& overlap) {
  DiceScore s;
  s.n = static_cast<int>(gt_ids.size());
  s.m = static_cast<int>(pred_ids.size());
  s.gt_ids = std::move(gt_ids);
  s.pred_ids = std::move(pred_ids);
  s.matched_pred.assign(s.n, 0);
  s.matched_dice.assign(s.n, 0.0);
  if (s.n == 0) {
    s.strict = s.lenient = s.m == 0 ? 1.0 : 0.0;
    return s;
  }
  if (s.m == 0) return s;
  std::vector<std::vector<double>> d(s.n, std::vector<double>(s.m, 0.0));
  for (int i = 0; i < s.n; ++i)
    for (int j = 0; j < s.m; ++j)
      d[i][j] = 2.0 * static_cast<double>(overlap[i][j]) /
                static_cast<double>(gt_area[i] + pred_area[j]);
  const std::vector<int> match = max_weight_assignment(d);
  double sum = 0;
  for (int i = 0; i < s.n; ++i) {
    if (match[i] < 0 || d[i][match[i]] <= 0) continue;
    s.matched_pred[i] = s.pred_ids[match[i]];
    s.matched_dice[i] = d[i][match[i]];
    sum += d[i][match[i]];
  }
  s.strict = sum / std::max(s.n, s.m);
  s.lenient = sum / s.n;
  return s;
}

}  // namespace

int DiceScore::instance_of(int gt_id) const {
  const auto it = std::find(gt_ids.begin(), gt_ids.end(), gt_id);
  return it == gt_ids.end() ? -1 : static_cast<int>(it - gt_ids.begin());
}

cv::Mat labels_16u(const cv::Mat& labels) {
  if (labels.type() == CV_16UC1) return labels;
  cv::Mat out;
  labels.convertTo(out, CV_16U);
  return out;
}

std::vector<int> label_values(const cv::Mat& labels) {
  const cv::Mat l16 = labels_16u(labels);
  std::vector<bool> present(65536, false);
  for (int y = 0; y < l16.rows; ++y) {
    const uint16_t* row = l16.ptr<uint16_t>(y);
    for (int x = 0; x < l16.cols; ++x) present[row[x]] = true;
  }
  std::vector<int> values;
  for (int v = 1; v < 65536; ++v)
    if (present[v]) values.push_back(v);
  return values;
}

Result<DiceScore> matched_dice(const cv::Mat& gt_labels, const cv::Mat& pred_labels) {
  if (Status s = check_labels(gt_labels, "ground-truth labels"); !s) return s.error();
  if (Status s = check_labels(pred_labels, "predicted labels"); !s) return s.error();
  if (gt_labels.size() != pred_labels.size())
    return Error{"predicted labels: size " + std::to_string(pred_labels.cols) + "x" +
                 std::to_string(pred_labels.rows) + " differs from the ground truth's " +
                 std::to_string(gt_labels.cols) + "x" + std::to_string(gt_labels.rows)};
  const cv::Mat g = labels_16u(gt_labels), p = labels_16u(pred_labels);
  std::vector<int> gt_ids = label_values(g), pred_ids = label_values(p);
  const std::vector<int> gi = index_of_values(gt_ids), pj = index_of_values(pred_ids);
  const size_t n = gt_ids.size(), m = pred_ids.size();
  std::vector<int64_t> gt_area(n, 0), pred_area(m, 0);
  std::vector<std::vector<int64_t>> overlap(n, std::vector<int64_t>(m, 0));
  for (int y = 0; y < g.rows; ++y) {
    const uint16_t* grow = g.ptr<uint16_t>(y);
    const uint16_t* prow = p.ptr<uint16_t>(y);
    for (int x = 0; x < g.cols; ++x) {
      const int i = gi[grow[x]], j = pj[prow[x]];
      if (i >= 0) ++gt_area[i];
      if (j >= 0) ++pred_area[j];
      if (i >= 0 && j >= 0) ++overlap[i][j];
    }
  }
  return score_from_overlaps(std::move(gt_ids), std::move(pred_ids), gt_area, pred_area, overlap);
}

Result<DiceScore> matched_dice(const std::vector<cv::Mat>& gt_masks, const cv::Mat& pred_labels) {
  if (Status s = check_labels(pred_labels, "predicted labels"); !s) return s.error();
  for (size_t i = 0; i < gt_masks.size(); ++i) {
    const std::string name = "ground-truth mask " + std::to_string(i);
    if (gt_masks[i].type() != CV_8UC1) return Error{name + ": expected CV_8UC1"};
    if (gt_masks[i].size() != pred_labels.size())
      return Error{name + ": size differs from the predicted labels'"};
  }
  const cv::Mat p = labels_16u(pred_labels);
  std::vector<int> pred_ids = label_values(p);
  const std::vector<int> pj = index_of_values(pred_ids);
  const size_t n = gt_masks.size(), m = pred_ids.size();
  std::vector<int> gt_ids(n);
  std::vector<int64_t> gt_area(n, 0), pred_area(m, 0);
  std::vector<std::vector<int64_t>> overlap(n, std::vector<int64_t>(m, 0));
  for (int y = 0; y < p.rows; ++y) {
    const uint16_t* prow = p.ptr<uint16_t>(y);
    for (int x = 0; x < p.cols; ++x)
      if (pj[prow[x]] >= 0) ++pred_area[pj[prow[x]]];
  }
  for (size_t i = 0; i < n; ++i) {
    gt_ids[i] = static_cast<int>(i) + 1;
    for (int y = 0; y < p.rows; ++y) {
      const uint8_t* grow = gt_masks[i].ptr<uint8_t>(y);
      const uint16_t* prow = p.ptr<uint16_t>(y);
      for (int x = 0; x < p.cols; ++x) {
        if (!grow[x]) continue;
        ++gt_area[i];
        if (pj[prow[x]] >= 0) ++overlap[i][pj[prow[x]]];
      }
    }
  }
  return score_from_overlaps(std::move(gt_ids), std::move(pred_ids), gt_area, pred_area, overlap);
}

DiceScore missing_prediction_score(std::vector<int> gt_ids) {
  DiceScore s;
  s.n = static_cast<int>(gt_ids.size());
  s.gt_ids = std::move(gt_ids);
  s.matched_pred.assign(s.n, 0);
  s.matched_dice.assign(s.n, 0.0);
  return s;
}

}  // namespace mbest::validate

#include "mbest/validate/report.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "charts.h"
#include "mbest/core/atomic_file.h"

namespace mbest::validate {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

// A rate in percent with two decimals, "-" when nothing was assessed.
std::string rate(int correct, int assessed) {
  return assessed == 0 ? "-" : fixed(100.0 * correct / assessed, 2);
}

std::string distance(const DistanceSummary& d) {
  return d.count == 0 ? "-" : fixed(d.mean, 2) + " / " + fixed(d.p95, 2);
}

bool synthetic(const Evaluation& e) { return e.dataset.synthetic; }

// Where --run took each image's mask from.
std::string run_masks(const Evaluation& e) {
  return e.options.mask_sibling.empty() ? "colour_filter" : e.options.mask_sibling + "/";
}

std::string prediction_source(const Evaluation& e) {
  return e.options.run ? "computed with --run (" + run_masks(e) + " -> detect)" : e.options.pred_dir;
}

// ---- Rows shared by the terminal table, Markdown and HTML -------------------------------

using Row = std::vector<std::string>;

Row dice_header() {
  return {"tier", "images", "strict DICE %", "std", "lenient %", "below 90", "below 95",
          "count errors"};
}
Row dice_row(const TierSummary& t) {
  return {t.tier,
          std::to_string(t.images),
          fixed(t.strict_mean, 2),
          fixed(t.strict_std, 2),
          fixed(t.lenient_mean, 2),
          std::to_string(t.below_90),
          std::to_string(t.below_95),
          std::to_string(t.count_errors)};
}
Row crossing_header() {
  return {"tier", "crossings", "pairing %", "(assessed)", "order %", "(assessed)",
          "centerline pred->GT mean/p95 px", "GT->pred mean/p95 px"};
}
Row crossing_row(const TierSummary& t) {
  return {t.tier,
          std::to_string(t.crossings),
          rate(t.pairing_correct, t.pairing_assessed),
          std::to_string(t.pairing_assessed),
          rate(t.order_correct, t.order_assessed),
          std::to_string(t.order_assessed),
          t.has_centerlines ? distance(t.pred_to_gt) : "-",
          t.has_centerlines ? distance(t.gt_to_pred) : "-"};
}
Row crossing_list_header() {
  return {"tier", "images", "GT crossings", "detected", "matched", "recall %", "precision %",
          "count = GT", "count = GT %", "top correct %", "(assessed)", "median angle error deg"};
}
Row crossing_list_row(const TierSummary& t) {
  const CrossingListTotals& l = t.crossing_list;
  return {t.tier,
          std::to_string(l.images),
          std::to_string(l.gt),
          std::to_string(l.detected),
          std::to_string(l.matched),
          rate(l.matched, l.gt),
          rate(l.matched, l.detected),
          std::to_string(l.count_equal),
          rate(l.count_equal, l.images),
          rate(l.top_correct, l.top_assessed),
          std::to_string(l.top_assessed),
          l.angle_error_median < 0 ? "-" : fixed(l.angle_error_median, 2)};
}
// One row per tier, then one for all tiers when there are several.
std::vector<Row> tier_rows(const Summary& s, Row (*row)(const TierSummary&)) {
  std::vector<Row> rows;
  for (const TierSummary& t : s.tiers) rows.push_back(row(t));
  if (s.tiers.size() > 1) rows.push_back(row(s.all));
  return rows;
}
// Pairing per tier and angle bin: "rate (assessed)" cells, "-" where none was assessed.
Row tier_angle_header() {
  Row h{"tier"};
  for (const Bin& b : angle_bins()) h.push_back(b.label);
  return h;
}
// "rate (assessed)", or "-" where none was assessed.
std::string rate_cell(const RateBin& b) {
  return b.assessed ? rate(b.correct, b.assessed) + " (" + std::to_string(b.assessed) + ")" : "-";
}
Row tier_angle_row(const TierSummary& t) {
  Row r{t.tier};
  for (const RateBin& b : t.pairing_by_angle) r.push_back(rate_cell(b));
  return r;
}
// Pairing failures per tier and angle bin by cause: "local + split/merged" cells, "-" where
// the bin has none.
Row tier_failure_header() {
  Row h = tier_angle_header();
  h.push_back("all angles");
  return h;
}
std::string failure_cell(int local, int split) {
  return local + split ? std::to_string(local) + " + " + std::to_string(split) : "-";
}
Row tier_failure_row(const TierSummary& t) {
  Row r{t.tier};
  int local = 0, split = 0;
  for (const FailureBin& b : t.pairing_failures_by_angle) {
    r.push_back(failure_cell(b.local, b.rod_split_or_merged));
    local += b.local;
    split += b.rod_split_or_merged;
  }
  r.push_back(failure_cell(local, split));
  return r;
}
// Pairing by crowding: one row per tier and crowding bin with crossings assessed, then the
// same for all tiers when there are several.
Row crowding_header() { return {"tier", "crowding", "under 20 degrees", "20 degrees and over"}; }
std::vector<Row> crowding_rows(const Summary& s) {
  std::vector<const TierSummary*> tiers;
  for (const TierSummary& t : s.tiers) tiers.push_back(&t);
  if (s.tiers.size() > 1) tiers.push_back(&s.all);
  std::vector<Row> rows;
  for (const TierSummary* t : tiers)
    for (size_t i = 0; i < crowding_bins().size(); ++i) {
      const RateBin& under = t->pairing_by_crowding_under_20[i];
      const RateBin& from = t->pairing_by_crowding_from_20[i];
      if (under.assessed + from.assessed > 0)
        rows.push_back({t->tier, crowding_bins()[i].label, rate_cell(under), rate_cell(from)});
    }
  return rows;
}
Row bin_header(const std::string& figure) {
  return {figure, "pairing %", "(assessed)", "order %", "(assessed)"};
}
std::vector<Row> bin_rows(const std::vector<RateBin>& pairing, const std::vector<RateBin>& order) {
  std::vector<Row> rows;
  for (size_t i = 0; i < pairing.size(); ++i)
    rows.push_back({pairing[i].bin.label, rate(pairing[i].correct, pairing[i].assessed),
                    std::to_string(pairing[i].assessed), rate(order[i].correct, order[i].assessed),
                    std::to_string(order[i].assessed)});
  return rows;
}
std::vector<Row> mean_rows(const std::vector<MeanBin>& bins) {
  std::vector<Row> rows;
  for (const MeanBin& b : bins)
    rows.push_back({b.bin.label, b.count ? fixed(100 * b.mean, 2) : "-", std::to_string(b.count)});
  return rows;
}
Row worst_header() { return {"image", "strict %", "lenient %", "n", "m", "note"}; }
Row worst_row(const ImageResult& r) {
  std::string note = r.prediction_error;
  for (const std::string& w : r.warnings) note += (note.empty() ? "" : "; ") + w;
  return {r.item.tier + "/" + r.item.stem, fixed(100 * r.dice.strict, 2),
          fixed(100 * r.dice.lenient, 2), std::to_string(r.dice.n), std::to_string(r.dice.m), note};
}

std::string text_table(const Row& header, const std::vector<Row>& rows) {
  std::vector<size_t> width(header.size());
  for (size_t c = 0; c < header.size(); ++c) {
    width[c] = header[c].size();
    for (const Row& r : rows) width[c] = std::max(width[c], r[c].size());
  }
  std::ostringstream out;
  const auto line = [&](const Row& r) {
    for (size_t c = 0; c < r.size(); ++c) {
      const std::string pad(width[c] - r[c].size(), ' ');
      out << (c ? "  " : "") << (c ? pad + r[c] : r[c] + pad);  // names left, numbers right
    }
    out << "\n";
  };
  line(header);
  for (const Row& r : rows) line(r);
  return out.str();
}

// A column is numeric when each of its cells is a number or "-".
bool numeric_column(const std::vector<Row>& rows, size_t c) {
  for (const Row& r : rows) {
    if (r[c] == "-") continue;
    char* end = nullptr;
    std::strtod(r[c].c_str(), &end);
    if (r[c].empty() || *end != '\0') return false;
  }
  return true;
}

std::string markdown_table(const Row& header, const std::vector<Row>& rows) {
  std::ostringstream out;
  const auto line = [&](const Row& r) {
    out << "|";
    for (const std::string& cell : r) out << " " << cell << " |";
    out << "\n";
  };
  line(header);
  out << "|";
  for (size_t c = 0; c < header.size(); ++c) out << (numeric_column(rows, c) ? "---:|" : "---|");
  out << "\n";
  for (const Row& r : rows) line(r);
  return out.str();
}

std::string html_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string html_table(const Row& header, const std::vector<Row>& rows) {
  std::ostringstream out;
  out << "<table><thead><tr>";
  for (const std::string& h : header) out << "<th>" << html_escape(h) << "</th>";
  out << "</tr></thead><tbody>\n";
  std::vector<bool> numeric(header.size());
  for (size_t c = 0; c < header.size(); ++c) numeric[c] = numeric_column(rows, c);
  for (const Row& r : rows) {
    out << "<tr>";
    for (size_t c = 0; c < r.size(); ++c)
      out << (numeric[c] ? "<td class=num>" : "<td>") << html_escape(r[c]) << "</td>";
    out << "</tr>\n";
  }
  out << "</tbody></table>\n";
  return out.str();
}

// Under the heading of the pairing-failure table, in report.md and report.html.
constexpr char kFailureNote[] =
    "Each cell: local failures (every rod of the crossing found whole, matched DICE >= 0.95) + "
    "failures where a rod of the crossing is split, merged or missed (matched DICE < 0.95), a "
    "figure beyond ../shared/docs/metrics.md.";

// Under the heading of the crowding table.
constexpr char kCrowdingNote[] =
    "Crowding: how many other ground-truth crossings lie within 4 widths (of the wider rod) of "
    "the crossing, a figure beyond ../shared/docs/metrics.md. Each cell: pairing % (crossings "
    "assessed); crossings under 20 degrees and at 20 or more apart, the accuracy goal's ranges.";

// Under the heading of the detected-crossings table.
constexpr char kCrossingListNote[] =
    "The detector's own crossing list matched to the ground truth's crossings, a figure beyond "
    "../shared/docs/metrics.md (see Definitions).";

std::string definitions(const Evaluation& e) {
  std::ostringstream out;
  out << "Matched DICE as ../shared/docs/metrics.md defines it: D = 2|G∩P| / (|G|+|P|), GT "
         "instances matched one-to-one to predicted ones maximising the total D (Hungarian); "
         "strict = sum / max(n, m), lenient = sum / n; a missing prediction scores 0. Tier "
         "figures: mean over images in percent, population standard deviation, images with a "
         "strict score below 90 % and 95 %, images with n != m.";
  if (synthetic(e))
    out << " Crossings: a strand is sampled at the first centerline point at least 1.5 widths "
           "of arc from the crossing, clear of the other strand, visible in the ground truth and "
           "overlapped by no other rod's body (votes there read the order of that overlap); "
           "pairing is correct when each strand keeps one predicted label across the crossing "
           "and two rods keep different labels; order is correct when the predicted label at "
           "the crossing is the one matched to the top rod (not assessed for self-crossings, nor "
           "where the ground truth shows a third rod lying over the crossing). "
           "Curvature complexity: total absolute turning of the rod (total_turning_rad, "
           "radians), a crossing takes the larger of its rods'; bins of half turns: 0-3.14, "
           "3.14-6.28, 6.28-9.42, 9.42-12.57, 12.57+. Angle bins 0-10, 10-20, 20-45, 45-90 "
           "degrees. "
           "Crowding, a figure beyond ../shared/docs/metrics.md: the number of other "
           "ground-truth crossings within 4 widths of the wider rod of a crossing; bins 0, 1, "
           "2-3, 4+. "
           "Pairing failures by cause, a figure beyond ../shared/docs/metrics.md: local when "
           "both rods of the crossing (its one rod for a self-crossing) have a matched DICE of "
           "at least 0.95, so the strands switch near the crossing only; otherwise a rod is "
           "split, merged or missed, a failure that usually starts away from the crossing. "
           "Centerline error: pixel distance from each predicted centerline point to the matched "
           "rod's ground-truth centerline and back, pooled per tier; p95 interpolated. "
           "Detected crossings, a figure beyond ../shared/docs/metrics.md: the crossing list of "
           "the detector's JSON (with --run, of its result) matched one-to-one to the "
           "ground-truth crossings, greedily by ascending distance; a listed crossing matches a "
           "ground-truth one when its two labels are the ones matched DICE gave the crossing's "
           "two rods (that rod's label twice for a self-crossing) and it lies within 2 widths "
           "of the wider rod, at least 10 px. Recall = matched / GT crossings, precision = "
           "matched / detected; count = GT: images listing as many crossings as the ground "
           "truth; top correct: the listed top label is the one matched to the top rod (matched "
           "crossings of two rods); angle error: |listed - GT| crossing angle, median over the "
           "matches. Images without a readable prediction JSON are left out.";
  return out.str();
}

// ---- JSON ---------------------------------------------------------------------------------

json rate_bins_json(const std::vector<RateBin>& bins);

json failure_bins_json(const std::vector<FailureBin>& bins) {
  json out = json::array();
  for (const FailureBin& b : bins)
    out.push_back({{"bin", b.bin.label}, {"local", b.local},
                   {"rod_split_or_merged", b.rod_split_or_merged}});
  return out;
}

json failure_json(PairingFailure f) {
  switch (f) {
    case PairingFailure::kLocal: return "local";
    case PairingFailure::kRodSplitOrMerged: return "rod_split_or_merged";
    case PairingFailure::kNone: break;
  }
  return nullptr;
}

std::string failure_cause_text(PairingFailure f) {
  return f == PairingFailure::kLocal ? "local (both rods found whole)"
                                     : "a rod of the crossing split, merged or missed";
}

json tier_json(const TierSummary& t) {
  json j = {{"tier", t.tier},
            {"images", t.images},
            {"strict_dice_pct", t.strict_mean},
            {"strict_dice_std_pct", t.strict_std},
            {"lenient_dice_pct", t.lenient_mean},
            {"lenient_dice_std_pct", t.lenient_std},
            {"below_90", t.below_90},
            {"below_95", t.below_95},
            {"count_errors", t.count_errors},
            {"missing_predictions", t.missing_predictions},
            {"crossings", {{"total", t.crossings},
                           {"pairing_assessed", t.pairing_assessed},
                           {"pairing_correct", t.pairing_correct},
                           {"order_assessed", t.order_assessed},
                           {"order_correct", t.order_correct},
                           {"pairing_by_angle", rate_bins_json(t.pairing_by_angle)},
                           {"pairing_failures_by_angle", failure_bins_json(t.pairing_failures_by_angle)},
                           {"pairing_by_crowding",
                            {{"under_20_deg", rate_bins_json(t.pairing_by_crowding_under_20)},
                             {"from_20_deg", rate_bins_json(t.pairing_by_crowding_from_20)}}}}}};
  if (t.has_centerlines)
    j["centerline_px"] = {
        {"pred_to_gt", {{"mean", t.pred_to_gt.mean}, {"p95", t.pred_to_gt.p95}, {"points", t.pred_to_gt.count}}},
        {"gt_to_pred", {{"mean", t.gt_to_pred.mean}, {"p95", t.gt_to_pred.p95}, {"points", t.gt_to_pred.count}}}};
  if (t.crossing_list.images > 0) {
    const CrossingListTotals& l = t.crossing_list;
    const auto pct = [](int part, int whole) {
      return whole ? json(100.0 * part / whole) : json();
    };
    j["detected_crossings"] = {
        {"images", l.images},
        {"gt", l.gt},
        {"detected", l.detected},
        {"matched", l.matched},
        {"recall_pct", pct(l.matched, l.gt)},
        {"precision_pct", pct(l.matched, l.detected)},
        {"count_equal", l.count_equal},
        {"count_equal_pct", pct(l.count_equal, l.images)},
        {"top_assessed", l.top_assessed},
        {"top_correct", l.top_correct},
        {"top_correct_pct", pct(l.top_correct, l.top_assessed)},
        {"angle_error_median_deg", l.angle_error_median < 0 ? json() : json(l.angle_error_median)}};
  }
  if (t.detect_ms_median >= 0) j["detect_ms_median"] = t.detect_ms_median;
  return j;
}

json rate_bins_json(const std::vector<RateBin>& bins) {
  json out = json::array();
  for (const RateBin& b : bins)
    out.push_back({{"bin", b.bin.label}, {"lo", b.bin.lo}, {"hi", std::isinf(b.bin.hi) ? json() : json(b.bin.hi)},
                   {"assessed", b.assessed}, {"correct", b.correct},
                   {"rate_pct", b.assessed ? json(100.0 * b.correct / b.assessed) : json()}});
  return out;
}

json mean_bins_json(const std::vector<MeanBin>& bins) {
  json out = json::array();
  for (const MeanBin& b : bins)
    out.push_back({{"bin", b.bin.label}, {"lo", b.bin.lo}, {"hi", std::isinf(b.bin.hi) ? json() : json(b.bin.hi)},
                   {"count", b.count}, {"mean_pct", b.count ? json(100 * b.mean) : json()}});
  return out;
}

json image_json(const ImageResult& r) {
  json instances = json::array();
  for (size_t i = 0; i < r.dice.gt_ids.size(); ++i)
    instances.push_back({{"gt", r.dice.gt_ids[i]}, {"pred", r.dice.matched_pred[i]},
                         {"dice", r.dice.matched_dice[i]}});
  json j = {{"tier", r.item.tier},
            {"stem", r.item.stem},
            {"image", r.item.image},
            {"labels", r.item.labels},
            {"prediction", r.prediction},
            {"prediction_error", r.prediction_error},
            {"n", r.dice.n},
            {"m", r.dice.m},
            {"strict", r.dice.strict},
            {"lenient", r.dice.lenient},
            {"count_error", r.dice.count_error()},
            {"instances", instances},
            {"warnings", r.warnings}};
  if (!r.item.annotation.empty()) {
    j["annotation"] = r.item.annotation;
    json rods = json::array();
    for (const RodResult& rod : r.rods)
      rods.push_back({{"id", rod.id}, {"width_px", rod.width_px},
                      {"total_turning_rad", rod.complexity}, {"pred", rod.matched_pred},
                      {"dice", rod.dice}});
    j["rods"] = rods;
    json crossings = json::array();
    for (const CrossingResolution& c : r.crossings)
      crossings.push_back({{"index", c.index}, {"rods", {c.rod_a, c.rod_b}}, {"top", c.top},
                           {"angle_deg", c.angle_deg}, {"complexity", c.complexity},
                           {"neighbours", c.neighbours},
                           {"location", {c.location.x, c.location.y}},
                           {"labels", {{"a_before", c.a_before}, {"a_after", c.a_after},
                                       {"b_before", c.b_before}, {"b_after", c.b_after},
                                       {"at_crossing", c.at_crossing}}},
                           {"pairing_assessed", c.pairing_assessed},
                           {"pairing_correct", c.pairing_correct},
                           {"pairing_failure", failure_json(pairing_failure(r, c))},
                           {"order_assessed", c.order_assessed},
                           {"order_correct", c.order_correct}, {"note", c.note}});
    j["crossings"] = crossings;
  }
  if (r.has_crossing_list) {
    json matches = json::array();
    for (const CrossingListMatch& m : r.crossing_list.matches)
      matches.push_back({{"detected", m.detected}, {"gt", m.gt}, {"distance_px", m.distance_px},
                         {"angle_error_deg", m.angle_error_deg}, {"top_assessed", m.top_assessed},
                         {"top_correct", m.top_correct}});
    j["detected_crossings"] = {{"gt", r.crossing_list.gt},
                               {"detected", r.crossing_list.detected},
                               {"matched", r.crossing_list.matches.size()},
                               {"count_equal", r.crossing_list.count_equal()},
                               {"matches", matches}};
  }
  if (r.has_centerlines) {
    const DistanceSummary p2g = summarise(r.centerline.pred_to_gt);
    const DistanceSummary g2p = summarise(r.centerline.gt_to_pred);
    j["centerline_px"] = {{"pred_to_gt", {{"mean", p2g.mean}, {"p95", p2g.p95}, {"points", p2g.count}}},
                          {"gt_to_pred", {{"mean", g2p.mean}, {"p95", g2p.p95}, {"points", g2p.count}}}};
  }
  if (r.detect_ms >= 0) j["detect_ms"] = r.detect_ms;
  return j;
}

// ---- Gallery ------------------------------------------------------------------------------

const cv::Vec3b kPalette[] = {{60, 180, 75},  {200, 130, 0}, {48, 130, 245}, {180, 30, 145},
                              {240, 240, 70}, {75, 25, 230}, {0, 128, 128},  {255, 190, 230}};
const cv::Vec3b kUnmatched(255, 0, 255), kMissed(40, 40, 230), kWrong(0, 200, 255),
    kSpurious(255, 200, 0), kRight(150, 150, 150);

// Ground-truth label -> GT instance index, and predicted label -> index of the GT instance
// matched to it: the colours of the gallery's panels.
struct InstanceIndex {
  std::map<int, int> gt, pred;
};
InstanceIndex instance_index(const ImageResult& r) {
  InstanceIndex index;
  for (size_t i = 0; i < r.dice.gt_ids.size(); ++i) {
    index.gt[r.dice.gt_ids[i]] = static_cast<int>(i);
    if (r.dice.matched_pred[i]) index.pred[r.dice.matched_pred[i]] = static_cast<int>(i);
  }
  return index;
}

// The picture of image r, or a grey one of `size` where it cannot be read or differs in size.
cv::Mat picture_of(const ImageResult& r, cv::Size size) {
  cv::Mat image = cv::imread(r.item.image, cv::IMREAD_COLOR);
  if (image.size() != size) image = cv::Mat(size, CV_8UC3, cv::Scalar(60, 60, 60));
  return image;
}

// Paints `roi` of the labels into panels the size of roi: the ground truth's instances in
// gt_panel, the predicted ones in pred_panel (each in the colour of the GT instance matched
// to it, kUnmatched when none is) and, when given, the disagreement in err_panel.
void paint_labels(const ImageResult& r, const cv::Mat& gt16, const cv::Mat& pred16, cv::Rect roi,
                  cv::Mat& gt_panel, cv::Mat& pred_panel, cv::Mat* err_panel) {
  InstanceIndex index = instance_index(r);
  for (int y = 0; y < roi.height; ++y) {
    for (int x = 0; x < roi.width; ++x) {
      const int g = gt16.at<uint16_t>(roi.y + y, roi.x + x), p = pred16.at<uint16_t>(roi.y + y, roi.x + x);
      const int gi = g ? index.gt[g] : -1;
      const auto it = index.pred.find(p);
      const int pi = p ? (it == index.pred.end() ? -2 : it->second) : -1;
      if (gi >= 0) gt_panel.at<cv::Vec3b>(y, x) = kPalette[gi % 8];
      if (pi != -1) pred_panel.at<cv::Vec3b>(y, x) = pi >= 0 ? kPalette[pi % 8] : kUnmatched;
      if (err_panel && (gi >= 0 || pi != -1))
        err_panel->at<cv::Vec3b>(y, x) = gi == pi ? kRight
                                       : gi < 0   ? kSpurious
                                       : pi == -1 ? kMissed
                                                  : kWrong;
    }
  }
}

// The panels side by side, `gap` white pixels apart.
cv::Mat side_by_side(const std::vector<cv::Mat>& panels, int gap) {
  std::vector<cv::Mat> row;
  for (const cv::Mat& m : panels) {
    if (!row.empty()) row.push_back(cv::Mat(m.rows, gap, CV_8UC3, cv::Scalar(255, 255, 255)));
    row.push_back(m);
  }
  cv::Mat out;
  cv::hconcat(row, out);
  return out;
}

// Three panels: ground truth, prediction (each predicted instance in the colour of the GT
// instance matched to it; magenta when unmatched), and the disagreement.
cv::Mat overlay(const ImageResult& r, const cv::Mat& gt_in, const cv::Mat& pred_in) {
  const cv::Mat gt = labels_16u(gt_in), pred = labels_16u(pred_in);
  const cv::Mat base = picture_of(r, gt.size()) * 0.45;
  cv::Mat gt_panel = base.clone(), pred_panel = base.clone(), err_panel = base * 0.5;
  paint_labels(r, gt, pred, cv::Rect(0, 0, gt.cols, gt.rows), gt_panel, pred_panel, &err_panel);
  const double scale = std::min(1.0, 320.0 / gt.cols);
  std::vector<cv::Mat> panels;
  for (const cv::Mat& m : {gt_panel, pred_panel, err_panel}) {  // headers: no pixel copies
    cv::Mat small;
    cv::resize(m, small, cv::Size(), scale, scale, cv::INTER_AREA);
    panels.push_back(small);
  }
  return side_by_side(panels, 6);
}

// A close view of crossing `c` of image r: the picture, the ground truth and the prediction
// (coloured as in `overlay`), over a square of 16 widths of the wider rod (at least 64 px)
// centred on the crossing and clipped to the image, scaled to 180 px high, a ring marking
// the crossing.
cv::Mat crossing_view(const ImageResult& r, const cv::Mat& gt_in, const cv::Mat& pred_in,
                      const CrossingResolution& c) {
  const cv::Mat gt = labels_16u(gt_in), pred = labels_16u(pred_in);
  const int half = std::max(32, static_cast<int>(std::lround(8 * c.width_px)));
  const cv::Rect roi = cv::Rect(cvRound(c.location.x) - half, cvRound(c.location.y) - half,
                                2 * half, 2 * half) &
                       cv::Rect(0, 0, gt.cols, gt.rows);
  if (roi.empty()) return cv::Mat();
  const cv::Mat picture = picture_of(r, gt.size())(roi).clone();
  cv::Mat gt_panel = picture * 0.3, pred_panel = picture * 0.3;
  paint_labels(r, gt, pred, roi, gt_panel, pred_panel, nullptr);
  const double scale = 180.0 / roi.height;
  const cv::Point centre(cvRound((c.location.x - roi.x) * scale), cvRound((c.location.y - roi.y) * scale));
  std::vector<cv::Mat> panels;
  for (const cv::Mat& m : {picture, gt_panel, pred_panel}) {  // headers: no pixel copies
    cv::Mat big;
    cv::resize(m, big, cv::Size(), scale, scale, cv::INTER_NEAREST);
    cv::circle(big, centre, std::max(6, cvRound(c.width_px * scale)), cv::Scalar(255, 255, 255), 1,
               cv::LINE_AA);
    panels.push_back(big);
  }
  return side_by_side(panels, 4);
}

std::string failed_crossings_note(const Evaluation& e) {
  return "Per tier and crossing-angle bin, the first " +
         std::to_string(e.options.keep_failed_crossings) +
         " image(s) with a crossing paired wrong in that bin, and their first such crossing "
         "(all of them are in report.json).";
}

std::string failure_caption(const ImageResult& r, const CrossingResolution& c) {
  std::ostringstream out;
  out << r.item.relative_dir << "/" << r.item.stem << ", crossing " << c.index << ": "
      << fixed(c.angle_deg, 1) << " degrees, "
      << (c.rod_a == c.rod_b ? "rod " + std::to_string(c.rod_a) + " over itself"
                             : "rods " + std::to_string(c.rod_a) + " and " + std::to_string(c.rod_b))
      << ", " << failure_cause_text(pairing_failure(r, c));
  return out.str();
}

std::string chart_img(const std::string& png) {
  return "<img class=chart alt=chart src=\"data:image/png;base64," + base64(png) + "\">\n";
}

ChartSeries rate_series(const std::string& name, const std::vector<RateBin>& bins) {
  ChartSeries s{name, {}, {}};
  for (const RateBin& b : bins) {
    s.percent.push_back(b.assessed ? 100.0 * b.correct / b.assessed : NAN);
    s.counts.push_back(b.assessed);
  }
  return s;
}

ChartSeries mean_series(const std::string& name, const std::vector<MeanBin>& bins) {
  ChartSeries s{name, {}, {}};
  for (const MeanBin& b : bins) {
    s.percent.push_back(b.count ? 100 * b.mean : NAN);
    s.counts.push_back(b.count);
  }
  return s;
}

template <class B>
std::vector<std::string> labels_of(const std::vector<B>& bins) {
  std::vector<std::string> out;
  for (const B& b : bins) out.push_back(b.bin.label);
  return out;
}

}  // namespace

std::string tier_table(const Evaluation& e, const Summary& s) {
  std::string out = text_table(dice_header(), tier_rows(s, dice_row));
  if (synthetic(e)) out += "\n" + text_table(crossing_header(), tier_rows(s, crossing_row));
  if (s.all.missing_predictions > 0) {
    out += "\n" + std::to_string(s.all.missing_predictions) +
           " image(s) had no usable prediction and scored 0 (see report.json)";
    const auto first = std::find_if(e.images.begin(), e.images.end(),
                                    [](const ImageResult& r) { return !r.prediction_error.empty(); });
    if (first != e.images.end()) out += ", e.g. " + first->prediction_error;
    out += ".\n";
  }
  return out;
}

std::string report_json(const Evaluation& e, const Summary& s, const ReportInfo& info) {
  json tiers = json::array();
  for (const TierSummary& t : s.tiers) tiers.push_back(tier_json(t));
  json images = json::array();
  for (const ImageResult& r : e.images) images.push_back(image_json(r));
  json j = {{"command", info.command},
            {"dataset", e.dataset.root},
            {"layout", synthetic(e) ? "synth" : "mbest-real"},
            {"predictions", e.options.run ? "run" : e.options.pred_dir},
            {"masks", e.options.run ? run_masks(e) : "as given to `mbest detect`"},
            {"seconds", e.seconds},
            {"definitions", definitions(e)},
            {"tiers", tiers},
            {"all", tier_json(s.all)},
            {"strict_by_rod_count", mean_bins_json(s.strict_by_rod_count)}};
  if (synthetic(e)) {
    j["complexity_figure"] = "total_turning_rad";
    j["pairing_by_angle"] = rate_bins_json(s.pairing_by_angle);
    j["order_by_angle"] = rate_bins_json(s.order_by_angle);
    j["pairing_by_complexity"] = rate_bins_json(s.pairing_by_complexity);
    j["order_by_complexity"] = rate_bins_json(s.order_by_complexity);
    j["rod_dice_by_complexity"] = mean_bins_json(s.rod_dice_by_complexity);
  }
  j["images"] = images;
  return j.dump(1) + "\n";
}

std::string report_markdown(const Evaluation& e, const Summary& s, const ReportInfo& info) {
  std::ostringstream out;
  out << "# mbest eval report\n\n"
      << "- data set: `" << e.dataset.root << "` (" << (synthetic(e) ? "synth" : "mbest-real")
      << " layout, " << e.images.size() << " images)\n"
      << "- predictions: " << prediction_source(e) << "\n"
      << "- command: `" << info.command << "`\n"
      << "- evaluated in " << fixed(e.seconds, 2) << " s\n\n"
      << "## Matched DICE per tier\n\n"
      << markdown_table(dice_header(), tier_rows(s, dice_row)) << "\n";
  if (synthetic(e)) {
    out << "## Crossing resolution and centerline error per tier\n\n"
        << markdown_table(crossing_header(), tier_rows(s, crossing_row)) << "\n"
        << "## Detected crossings per tier\n\n"
        << kCrossingListNote << "\n\n"
        << markdown_table(crossing_list_header(), tier_rows(s, crossing_list_row)) << "\n"
        << "## Crossings by angle (degrees)\n\n"
        << markdown_table(bin_header("angle"), bin_rows(s.pairing_by_angle, s.order_by_angle))
        << "\n## Pairing % by tier and angle (degrees), crossings assessed in brackets\n\n"
        << markdown_table(tier_angle_header(), tier_rows(s, tier_angle_row))
        << "\n## Pairing failures by cause, per tier and angle (degrees)\n\n"
        << kFailureNote << "\n\n"
        << markdown_table(tier_failure_header(), tier_rows(s, tier_failure_row))
        << "\n## Pairing % by crowding, per tier\n\n"
        << kCrowdingNote << "\n\n"
        << markdown_table(crowding_header(), crowding_rows(s))
        << "\n## Crossings by curvature complexity (total_turning_rad)\n\n"
        << markdown_table(bin_header("complexity"),
                          bin_rows(s.pairing_by_complexity, s.order_by_complexity))
        << "\n## Rod DICE by curvature complexity (total_turning_rad)\n\n"
        << markdown_table({"complexity", "mean matched DICE %", "rods"},
                          mean_rows(s.rod_dice_by_complexity))
        << "\n";
  }
  out << "## Strict DICE by number of rods\n\n"
      << markdown_table({"rods", "strict DICE %", "images"}, mean_rows(s.strict_by_rod_count))
      << "\n## Worst images\n\n";
  std::vector<Row> worst;
  for (int i : worst_images(e, 10)) worst.push_back(worst_row(e.images[i]));
  out << markdown_table(worst_header(), worst);
  if (synthetic(e) && e.options.keep_failed_crossings > 0) {
    std::vector<Row> rows;
    for (const FailureView& v : failure_gallery(e, e.options.keep_failed_crossings)) {
      const ImageResult& r = e.images[v.image];
      const CrossingResolution& c = r.crossings[v.crossing];
      rows.push_back({r.item.tier, angle_bins()[v.bin].label, r.item.relative_dir + "/" + r.item.stem,
                      std::to_string(c.index), fixed(c.angle_deg, 1),
                      fixed(c.location.x, 0) + ", " + fixed(c.location.y, 0),
                      c.rod_a == c.rod_b ? std::to_string(c.rod_a)
                                         : std::to_string(c.rod_a) + ", " + std::to_string(c.rod_b),
                      failure_cause_text(pairing_failure(r, c))});
    }
    out << "\n## Failed crossings\n\n" << failed_crossings_note(e)
        << " Close views in report.html.\n\n"
        << (rows.empty() ? std::string("None: every crossing assessed was paired right.\n")
                         : markdown_table({"tier", "angle bin", "image", "crossing", "angle", "x, y",
                                           "rods", "cause"},
                                          rows));
  }
  out << "\n## Definitions\n\n" << definitions(e) << "\n";
  return out.str();
}

std::string report_html(const Evaluation& e, const Summary& s, const ReportInfo& info) {
  std::ostringstream out;
  out << "<!DOCTYPE html>\n<html lang=en><head><meta charset=utf-8>\n"
      << "<title>mbest eval: " << html_escape(e.dataset.root) << "</title>\n<style>\n"
      << "body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}\n"
      << "table{border-collapse:collapse;margin:0.5em 0 1.5em}\n"
      << "th,td{border:1px solid #ccc;padding:3px 8px}th{background:#f0f0f0}\n"
      << "td.num{text-align:right;font-variant-numeric:tabular-nums}\n"
      << ".charts{display:flex;flex-wrap:wrap;gap:0.5em}\n"
      << ".chart{width:540px;max-width:100%;border:1px solid #ddd}\n"
      << "figure{margin:0 0 1.5em}figcaption{font-size:90%;color:#444}\n"
      << ".key span{display:inline-block;padding:0 6px;margin-right:6px;color:#000}\n"
      << "</style></head><body>\n<h1>mbest eval report</h1>\n<ul>\n"
      << "<li>data set: <code>" << html_escape(e.dataset.root) << "</code> ("
      << (synthetic(e) ? "synth" : "mbest-real") << " layout, " << e.images.size()
      << " images)</li>\n<li>predictions: " << html_escape(prediction_source(e)) << "</li>\n"
      << "<li>command: <code>" << html_escape(info.command) << "</code></li>\n"
      << "<li>evaluated in " << fixed(e.seconds, 2) << " s</li>\n</ul>\n"
      << "<h2>Matched DICE per tier</h2>\n" << html_table(dice_header(), tier_rows(s, dice_row));
  if (synthetic(e))
    out << "<h2>Crossing resolution and centerline error per tier</h2>\n"
        << html_table(crossing_header(), tier_rows(s, crossing_row))
        << "<h2>Detected crossings per tier</h2>\n<p>" << html_escape(kCrossingListNote) << "</p>\n"
        << html_table(crossing_list_header(), tier_rows(s, crossing_list_row));

  out << "<h2>Charts</h2>\n<div class=charts>\n"
      << chart_img(bar_chart_png("Strict matched DICE by number of rods", "rods in the image",
                                 labels_of(s.strict_by_rod_count),
                                 {mean_series("strict DICE", s.strict_by_rod_count)}));
  if (synthetic(e)) {
    out << chart_img(bar_chart_png("Crossings resolved by crossing angle", "angle (degrees)",
                                   labels_of(s.pairing_by_angle),
                                   {rate_series("pairing", s.pairing_by_angle),
                                    rate_series("order", s.order_by_angle)}))
        << chart_img(bar_chart_png("Crossings resolved by curvature complexity",
                                   "total absolute turning of the rods (radians)",
                                   labels_of(s.pairing_by_complexity),
                                   {rate_series("pairing", s.pairing_by_complexity),
                                    rate_series("order", s.order_by_complexity)}))
        << chart_img(bar_chart_png("Matched DICE of each rod by curvature complexity",
                                   "total absolute turning of the rod (radians)",
                                   labels_of(s.rod_dice_by_complexity),
                                   {mean_series("rod DICE", s.rod_dice_by_complexity)}))
        << chart_img(bar_chart_png("Crossings paired right by crowding",
                                   "other crossings within 4 widths",
                                   labels_of(s.all.pairing_by_crowding_under_20),
                                   {rate_series("under 20 degrees", s.all.pairing_by_crowding_under_20),
                                    rate_series("20 degrees and over",
                                                s.all.pairing_by_crowding_from_20)}));
  }
  out << "</div>\n";
  if (synthetic(e)) {
    out << "<h3>Crossings by angle</h3>\n"
        << html_table(bin_header("angle (degrees)"), bin_rows(s.pairing_by_angle, s.order_by_angle))
        << "<h3>Pairing % by tier and angle (degrees), crossings assessed in brackets</h3>\n"
        << html_table(tier_angle_header(), tier_rows(s, tier_angle_row))
        << "<h3>Pairing failures by cause, per tier and angle (degrees)</h3>\n<p>"
        << html_escape(kFailureNote) << "</p>\n"
        << html_table(tier_failure_header(), tier_rows(s, tier_failure_row))
        << "<h3>Pairing % by crowding, per tier</h3>\n<p>" << html_escape(kCrowdingNote)
        << "</p>\n"
        << html_table(crowding_header(), crowding_rows(s))
        << "<h3>Crossings by curvature complexity</h3>\n"
        << html_table(bin_header("total_turning_rad"),
                      bin_rows(s.pairing_by_complexity, s.order_by_complexity));
  }

  out << "<h2>Worst images</h2>\n<p class=key>Panels: ground truth | prediction (each "
         "predicted instance in the colour of the ground-truth instance matched to it, "
         "<span style=\"background:#f0f\">unmatched</span>) | disagreement: "
      << "<span style=\"background:#969696\">right</span><span style=\"background:#e62828\">"
         "missed</span><span style=\"background:#ffc800\">other instance</span>"
         "<span style=\"background:#00c8ff\">spurious</span></p>\n";
  for (int i : worst_images(e, e.options.keep_worst)) {
    const ImageResult& r = e.images[i];
    Result<cv::Mat> gt = read_label_image(r.item.labels);
    if (!gt) continue;
    const cv::Mat pred = r.kept_prediction.empty() ? cv::Mat::zeros(gt.value().size(), CV_16UC1)
                                                   : r.kept_prediction;
    std::vector<uchar> jpeg;
    cv::imencode(".jpg", overlay(r, gt.value(), pred), jpeg, {cv::IMWRITE_JPEG_QUALITY, 85});
    const Row w = worst_row(r);
    out << "<figure><img alt=\"" << html_escape(w[0]) << "\" src=\"data:image/jpeg;base64,"
        << base64(std::string(jpeg.begin(), jpeg.end())) << "\"><figcaption><b>"
        << html_escape(w[0]) << "</b>: strict " << w[1] << " %, lenient " << w[2] << " %, n = "
        << w[3] << ", m = " << w[4] << (w[5].empty() ? "" : ". " + html_escape(w[5]))
        << "</figcaption></figure>\n";
  }

  if (synthetic(e) && e.options.keep_failed_crossings > 0) {
    out << "<h2>Failed crossings</h2>\n<p>" << html_escape(failed_crossings_note(e))
        << " Panels: picture | ground truth | prediction (colours as above); the ring marks "
           "the crossing.</p>\n";
    const std::vector<FailureView> gallery = failure_gallery(e, e.options.keep_failed_crossings);
    if (gallery.empty()) out << "<p>None: every crossing assessed was paired right.</p>\n";
    std::string heading;
    for (const FailureView& v : gallery) {
      const ImageResult& r = e.images[v.image];
      const CrossingResolution& c = r.crossings[v.crossing];
      const std::string h = r.item.tier + ", " + angle_bins()[v.bin].label + " degrees";
      if (h != heading) out << "<h3>" << html_escape(heading = h) << "</h3>\n";
      Result<cv::Mat> gt = read_label_image(r.item.labels);
      if (!gt || r.kept_prediction.empty()) continue;
      const cv::Mat view = crossing_view(r, gt.value(), r.kept_prediction, c);
      if (view.empty()) continue;
      std::vector<uchar> jpeg;
      cv::imencode(".jpg", view, jpeg, {cv::IMWRITE_JPEG_QUALITY, 85});
      out << "<figure><img alt=\"" << html_escape(r.item.stem) << "\" src=\"data:image/jpeg;base64,"
          << base64(std::string(jpeg.begin(), jpeg.end())) << "\"><figcaption>"
          << html_escape(failure_caption(r, c)) << "</figcaption></figure>\n";
    }
  }

  std::vector<Row> all;
  for (const ImageResult& r : e.images) all.push_back(worst_row(r));
  out << "<details><summary>Every image</summary>\n" << html_table(worst_header(), all)
      << "</details>\n<h2>Definitions</h2>\n<p>" << html_escape(definitions(e)) << "</p>\n"
      << "</body></html>\n";
  return out.str();
}

Status write_report(const Evaluation& e, const Summary& s, const ReportInfo& info,
                    const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) return Error{dir + ": cannot create the report folder"};
  const fs::path d(dir);
  if (Status st = write_file_atomically((d / "report.json").string(), report_json(e, s, info)); !st) return st;
  if (Status st = write_file_atomically((d / "report.md").string(), report_markdown(e, s, info)); !st) return st;
  return write_file_atomically((d / "report.html").string(), report_html(e, s, info));
}

}  // namespace mbest::validate

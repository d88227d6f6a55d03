#include "mbest/validate/summary.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "mbest/core/median.h"

namespace mbest::validate {

namespace {

constexpr double kPi = 3.14159265358979323846;

void mean_std_percent(const std::vector<double>& v, double* mean, double* std_dev) {
  if (v.empty()) return;
  double sum = 0;
  for (double x : v) sum += x;
  const double m = sum / v.size();
  double sq = 0;
  for (double x : v) sq += (x - m) * (x - m);
  *mean = 100 * m;
  *std_dev = 100 * std::sqrt(sq / v.size());
}

std::vector<RateBin> rate_bins(const std::vector<Bin>& bins);
void add(std::vector<RateBin>* bins, int index, bool correct);

TierSummary summarise_images(const std::string& tier, const std::vector<const ImageResult*>& images) {
  TierSummary t;
  t.tier = tier;
  t.pairing_by_angle = rate_bins(angle_bins());
  for (const Bin& b : angle_bins()) t.pairing_failures_by_angle.push_back(FailureBin{b});
  t.pairing_by_crowding_under_20 = t.pairing_by_crowding_from_20 = rate_bins(crowding_bins());
  t.images = static_cast<int>(images.size());
  std::vector<double> strict, lenient, detect_ms, p2g, g2p, angle_errors;
  for (const ImageResult* r : images) {
    strict.push_back(r->dice.strict);
    lenient.push_back(r->dice.lenient);
    if (r->dice.strict < 0.90) ++t.below_90;
    if (r->dice.strict < 0.95) ++t.below_95;
    if (r->dice.count_error()) ++t.count_errors;
    if (!r->prediction_error.empty()) ++t.missing_predictions;
    for (const CrossingResolution& c : r->crossings) {
      ++t.crossings;
      t.pairing_assessed += c.pairing_assessed;
      t.pairing_correct += c.pairing_assessed && c.pairing_correct;
      const int angle = bin_index(angle_bins(), c.angle_deg);
      if (c.pairing_assessed) {
        add(&t.pairing_by_angle, angle, c.pairing_correct);
        add(c.angle_deg < 20 ? &t.pairing_by_crowding_under_20 : &t.pairing_by_crowding_from_20,
            bin_index(crowding_bins(), c.neighbours), c.pairing_correct);
      }
      const PairingFailure failure = pairing_failure(*r, c);
      if (failure != PairingFailure::kNone && angle >= 0) {
        FailureBin& f = t.pairing_failures_by_angle[angle];
        ++(failure == PairingFailure::kLocal ? f.local : f.rod_split_or_merged);
      }
      t.order_assessed += c.order_assessed;
      t.order_correct += c.order_assessed && c.order_correct;
    }
    if (r->has_centerlines) {
      t.has_centerlines = true;
      p2g.insert(p2g.end(), r->centerline.pred_to_gt.begin(), r->centerline.pred_to_gt.end());
      g2p.insert(g2p.end(), r->centerline.gt_to_pred.begin(), r->centerline.gt_to_pred.end());
    }
    if (r->has_crossing_list) {
      CrossingListTotals& l = t.crossing_list;
      ++l.images;
      l.gt += r->crossing_list.gt;
      l.detected += r->crossing_list.detected;
      l.matched += static_cast<int>(r->crossing_list.matches.size());
      l.count_equal += r->crossing_list.count_equal();
      for (const CrossingListMatch& m : r->crossing_list.matches) {
        l.top_assessed += m.top_assessed;
        l.top_correct += m.top_correct;
        angle_errors.push_back(m.angle_error_deg);
      }
    }
    if (r->detect_ms >= 0) detect_ms.push_back(r->detect_ms);
  }
  mean_std_percent(strict, &t.strict_mean, &t.strict_std);
  mean_std_percent(lenient, &t.lenient_mean, &t.lenient_std);
  t.pred_to_gt = summarise(std::move(p2g));
  t.gt_to_pred = summarise(std::move(g2p));
  if (!detect_ms.empty()) t.detect_ms_median = median(std::move(detect_ms));
  if (!angle_errors.empty()) t.crossing_list.angle_error_median = median(std::move(angle_errors));
  return t;
}

std::vector<RateBin> rate_bins(const std::vector<Bin>& bins) {
  std::vector<RateBin> out;
  for (const Bin& b : bins) out.push_back(RateBin{b});
  return out;
}

std::vector<MeanBin> mean_bins(const std::vector<Bin>& bins) {
  std::vector<MeanBin> out;
  for (const Bin& b : bins) out.push_back(MeanBin{b});
  return out;
}

void add(std::vector<RateBin>* bins, int index, bool correct) {
  if (index < 0) return;
  ++(*bins)[index].assessed;
  (*bins)[index].correct += correct;
}

void add(std::vector<MeanBin>* bins, int index, double value) {
  if (index < 0) return;
  MeanBin& b = (*bins)[index];
  b.mean = (b.mean * b.count + value) / (b.count + 1);
  ++b.count;
}

}  // namespace

PairingFailure pairing_failure(const ImageResult& image, const CrossingResolution& crossing) {
  if (!crossing.pairing_assessed || crossing.pairing_correct) return PairingFailure::kNone;
  for (const int id : {crossing.rod_a, crossing.rod_b}) {
    const auto rod = std::find_if(image.rods.begin(), image.rods.end(),
                                  [id](const RodResult& r) { return r.id == id; });
    if (rod == image.rods.end() || rod->dice < kWholeRodDice)
      return PairingFailure::kRodSplitOrMerged;
  }
  return PairingFailure::kLocal;
}

const std::vector<Bin>& angle_bins() {
  static const std::vector<Bin> bins = {
      {"0-10", 0, 10}, {"10-20", 10, 20}, {"20-45", 20, 45}, {"45-90", 45, 90}};
  return bins;
}

const std::vector<Bin>& complexity_bins() {
  static const std::vector<Bin> bins = {{"0-3.14", 0, kPi},
                                        {"3.14-6.28", kPi, 2 * kPi},
                                        {"6.28-9.42", 2 * kPi, 3 * kPi},
                                        {"9.42-12.57", 3 * kPi, 4 * kPi},
                                        {"12.57+", 4 * kPi, std::numeric_limits<double>::infinity()}};
  return bins;
}

const std::vector<Bin>& crowding_bins() {
  static const std::vector<Bin> bins = {{"0", 0, 1},
                                        {"1", 1, 2},
                                        {"2-3", 2, 4},
                                        {"4+", 4, std::numeric_limits<double>::infinity()}};
  return bins;
}

int bin_index(const std::vector<Bin>& bins, double value) {
  for (size_t i = 0; i < bins.size(); ++i) {
    const bool last = i + 1 == bins.size();
    if (value >= bins[i].lo && (value < bins[i].hi || (last && value <= bins[i].hi)))
      return static_cast<int>(i);
  }
  return -1;
}

Summary summarise(const Evaluation& evaluation) {
  Summary s;
  std::vector<const ImageResult*> all;
  std::map<std::string, std::vector<const ImageResult*>> by_tier;
  for (const ImageResult& r : evaluation.images) {
    all.push_back(&r);
    by_tier[r.item.tier].push_back(&r);
  }
  for (const std::string& tier : evaluation.dataset.tiers)
    if (by_tier.count(tier)) s.tiers.push_back(summarise_images(tier, by_tier[tier]));
  s.all = summarise_images("all", all);

  s.pairing_by_angle = s.order_by_angle = rate_bins(angle_bins());
  s.pairing_by_complexity = s.order_by_complexity = rate_bins(complexity_bins());
  s.rod_dice_by_complexity = mean_bins(complexity_bins());
  std::map<int, std::vector<double>> strict_by_n;
  for (const ImageResult& r : evaluation.images) {
    strict_by_n[r.dice.n].push_back(r.dice.strict);
    for (const CrossingResolution& c : r.crossings) {
      const int a = bin_index(angle_bins(), c.angle_deg);
      const int k = bin_index(complexity_bins(), c.complexity);
      if (c.pairing_assessed) {
        add(&s.pairing_by_angle, a, c.pairing_correct);
        add(&s.pairing_by_complexity, k, c.pairing_correct);
      }
      if (c.order_assessed) {
        add(&s.order_by_angle, a, c.order_correct);
        add(&s.order_by_complexity, k, c.order_correct);
      }
    }
    for (const RodResult& rod : r.rods)
      add(&s.rod_dice_by_complexity, bin_index(complexity_bins(), rod.complexity), rod.dice);
  }
  for (const auto& [n, scores] : strict_by_n) {
    MeanBin b{Bin{std::to_string(n), static_cast<double>(n), static_cast<double>(n)}};
    b.count = static_cast<int>(scores.size());
    for (double x : scores) b.mean += x / b.count;
    s.strict_by_rod_count.push_back(b);
  }
  return s;
}

std::vector<int> worst_images(const Evaluation& evaluation, int k) {
  std::vector<int> order(evaluation.images.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return evaluation.images[a].dice.strict < evaluation.images[b].dice.strict;
  });
  order.resize(std::min<size_t>(order.size(), static_cast<size_t>(std::max(0, k))));
  return order;
}

std::vector<FailureView> failures_by_bin(const ImageResult& image, int image_index) {
  std::vector<FailureView> out;
  for (size_t k = 0; k < image.crossings.size(); ++k) {
    const CrossingResolution& c = image.crossings[k];
    if (pairing_failure(image, c) == PairingFailure::kNone) continue;
    const int bin = bin_index(angle_bins(), c.angle_deg);
    if (bin < 0) continue;
    const bool seen = std::any_of(out.begin(), out.end(), [bin](const FailureView& v) { return v.bin == bin; });
    if (!seen) out.push_back(FailureView{image_index, static_cast<int>(k), bin});
  }
  return out;
}

std::vector<FailureView> failure_gallery(const Evaluation& evaluation, int per_bin) {
  std::vector<FailureView> out;
  if (per_bin <= 0) return out;
  for (const std::string& tier : evaluation.dataset.tiers) {
    std::vector<std::vector<FailureView>> bins(angle_bins().size());
    for (size_t i = 0; i < evaluation.images.size(); ++i) {
      const ImageResult& r = evaluation.images[i];
      if (r.item.tier != tier) continue;
      for (const FailureView& v : failures_by_bin(r, static_cast<int>(i)))
        if (static_cast<int>(bins[v.bin].size()) < per_bin) bins[v.bin].push_back(v);
    }
    for (const std::vector<FailureView>& b : bins) out.insert(out.end(), b.begin(), b.end());
  }
  return out;
}

}  // namespace mbest::validate

#include "mbest/validate/crossing_list.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "prediction_json.h"

namespace mbest::validate {

namespace {

// A detected crossing is the ground-truth one within this distance. Two strands' bodies
// overlap over a width or more (longer at shallow angles), and the detector places a crossing
// where its two paths come closest in there; the floor spares thin rods a pixel-exact match.
constexpr double kToleranceWidths = 2;
constexpr double kMinTolerancePx = 10;

}  // namespace

CrossingListScore match_crossing_list(const synth::SceneAnnotation& scene, const DiceScore& dice,
                                      const std::vector<DetectedCrossing>& detected) {
  CrossingListScore out;
  out.gt = static_cast<int>(scene.crossings.size());
  out.detected = static_cast<int>(detected.size());
  std::map<int, const synth::RodAnnotation*> rods;
  for (const synth::RodAnnotation& r : scene.rods) rods[r.id] = &r;
  const auto label_of = [&](int rod_id) {
    const int i = dice.instance_of(rod_id);
    return i < 0 ? 0 : dice.matched_pred[i];
  };

  struct Candidate {
    double distance;
    int detected, gt;
  };
  std::vector<Candidate> candidates;
  for (size_t g = 0; g < scene.crossings.size(); ++g) {
    const synth::CrossingAnnotation& c = scene.crossings[g];
    const auto ra = rods.find(c.rod_a), rb = rods.find(c.rod_b);
    const int la = label_of(c.rod_a), lb = label_of(c.rod_b);
    if (ra == rods.end() || rb == rods.end() || la == 0 || lb == 0) continue;
    const double tolerance =
        std::max(kMinTolerancePx,
                 kToleranceWidths * std::max(ra->second->width_px, rb->second->width_px));
    for (size_t d = 0; d < detected.size(); ++d) {
      const DetectedCrossing& x = detected[d];
      const bool same_labels = (x.top_label == la && x.under_label == lb) ||
                               (x.top_label == lb && x.under_label == la);
      const double distance = cv::norm(x.location - c.location);
      if (same_labels && distance <= tolerance)
        candidates.push_back({distance, static_cast<int>(d), static_cast<int>(g)});
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return std::tie(a.distance, a.detected, a.gt) < std::tie(b.distance, b.detected, b.gt);
  });

  std::vector<bool> detected_taken(detected.size(), false), gt_taken(scene.crossings.size(), false);
  for (const Candidate& k : candidates) {
    if (detected_taken[k.detected] || gt_taken[k.gt]) continue;
    detected_taken[k.detected] = gt_taken[k.gt] = true;
    const DetectedCrossing& x = detected[k.detected];
    const synth::CrossingAnnotation& c = scene.crossings[k.gt];
    CrossingListMatch m;
    m.detected = k.detected;
    m.gt = k.gt;
    m.distance_px = k.distance;
    m.angle_error_deg = std::abs(x.angle_deg - c.angle_deg);
    m.top_assessed = c.rod_a != c.rod_b;
    m.top_correct = m.top_assessed && x.top_label == label_of(c.top);
    out.matches.push_back(m);
  }
  return out;
}

Result<std::vector<DetectedCrossing>> read_predicted_crossings(const std::string& path) {
  Result<nlohmann::json> j = read_json_file(path);
  if (!j) return j.error();
  return crossings_from_json(j.value(), path);
}

}  // namespace mbest::validate

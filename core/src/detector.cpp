#include "mbest/core/detector.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "mbest/core/bending.h"
#include "mbest/core/crossing_order.h"
#include "mbest/core/instance_mask.h"
#include "mbest/core/junctions.h"
#include "mbest/core/keypoints.h"
#include "mbest/core/prune.h"
#include "mbest/core/skeleton.h"
#include "mbest/core/traverse.h"

namespace mbest {
namespace {

// Runs one stage and records its wall time under `name`.
class StageClock {
 public:
  explicit StageClock(std::vector<StageTime>& out) : out_(out) {}
  template <class F>
  auto operator()(const char* name, F&& f) {
    const auto t0 = std::chrono::steady_clock::now();
    struct Record {
      std::vector<StageTime>& out;
      const char* name;
      std::chrono::steady_clock::time_point t0;
      ~Record() {
        out.push_back({name, std::chrono::duration<double, std::milli>(
                                 std::chrono::steady_clock::now() - t0).count()});
      }
    } record{out_, name, t0};
    return f();
  }

 private:
  std::vector<StageTime>& out_;
};

double line_angle_deg(cv::Point2f a, cv::Point2f b) {
  const double angle = std::abs(std::atan2(a.x * b.y - a.y * b.x, a.dot(b))) * 180.0 / M_PI;
  return angle > 90 ? 180 - angle : angle;
}

// A strand's direction through a crossing: the mean of its fitted tangents on both sides
// (the chord between the attachment points is bent by the skeleton near the junction).
cv::Point2f direction(const Passage& p) {
  return p.to_tangent.direction - p.from_tangent.direction;
}

// Closest approach of two paths: the midpoint of their closest pixels.
cv::Point2f closest_approach(const std::vector<cv::Point>& a, const std::vector<cv::Point>& b,
                             cv::Point2f fallback) {
  int best = std::numeric_limits<int>::max();
  cv::Point2f at = fallback;
  for (const cv::Point& p : a)
    for (const cv::Point& q : b) {
      const int d = (p.x - q.x) * (p.x - q.x) + (p.y - q.y) * (p.y - q.y);
      if (d < best) {
        best = d;
        at = (cv::Point2f(p) + cv::Point2f(q)) * 0.5f;
      }
    }
  return at;
}

// Fills Detection::crossings and Dlo::crossings, and lists the strands to draw on top.
std::vector<TopStrand> record_crossings(Detection& det, const std::vector<Passage>& passages,
                                        const std::vector<CrossingRegion>& regions,
                                        const Traversal& tr,
                                        const std::vector<std::vector<int>>& ordered) {
  std::vector<TopStrand> tops;
  std::vector<int> crossing_of(passages.size(), -1);
  for (const std::vector<int>& list : ordered) {
    std::vector<int> strands;
    for (int p : list)
      if (tr.passage_dlo[p] >= 0) strands.push_back(p);
    if (strands.size() < 2) continue;
    Crossing c;
    const cv::Point2f centre = regions[passages[strands[0]].region].centre;
    c.location = closest_approach(passages[strands[0]].path, passages[strands[1]].path, centre);
    c.angle_deg = 90;
    for (size_t i = 0; i < strands.size(); ++i) {
      c.dlos.push_back(tr.passage_dlo[strands[i]]);
      crossing_of[strands[i]] = static_cast<int>(det.crossings.size());
      for (size_t j = i + 1; j < strands.size(); ++j)
        c.angle_deg = std::min(c.angle_deg, line_angle_deg(direction(passages[strands[i]]),
                                                           direction(passages[strands[j]])));
    }
    det.crossings.push_back(std::move(c));
    for (size_t i = strands.size() - 1; i-- > 0;) {  // bottom to top, the bottom one not drawn
      const Passage& p = passages[strands[i]];
      tops.push_back({tr.passage_dlo[strands[i]], p.path, p.radius});
    }
  }
  for (size_t d = 0; d < det.dlos.size(); ++d)
    for (int p : tr.dlo_passages[d])
      if (crossing_of[p] >= 0) det.dlos[d].crossings.push_back(crossing_of[p]);
  return tops;
}

// One colour zone per crossing region (refine_labels_by_colour skips those fewer than two
// DLOs run through): discs over its inner branches and junctions (radius: the mask's half
// width there) and over the paths drawn through it, and each DLO's colour at the exits it
// takes.
std::vector<ColourZone> colour_zones(const SkeletonGraph& g, const std::vector<CrossingRegion>& regions,
                                     const std::vector<Passage>& passages, const Traversal& tr) {
  std::vector<ColourZone> zones(regions.size());
  for (size_t i = 0; i < passages.size(); ++i) {
    const Passage& p = passages[i];
    const int d = tr.passage_dlo[i];
    if (d < 0) continue;
    ColourZone& z = zones[p.region];
    for (const BranchTangent* t : {&p.from_tangent, &p.to_tangent})
      if (t->has_colour) z.colours.push_back({d, t->colour});
    for (size_t k = 0; k < p.path.size(); k += 2) z.discs.push_back({p.path[k], p.radius[k]});
  }
  for (size_t r = 0; r < regions.size(); ++r) {
    ColourZone& z = zones[r];
    if (z.colours.empty()) continue;
    for (int b : regions[r].inner_branches) {
      const Branch& br = g.branches[b];
      for (size_t k = 0; k < br.pixels.size(); k += 2) z.discs.push_back({br.pixels[k], br.radius[k]});
    }
    float widest = 0;
    for (const auto& [c, radius] : z.discs) widest = std::max(widest, radius);
    for (int n : regions[r].nodes) z.discs.push_back({cv::Point(g.nodes[n].centre), widest});
  }
  return zones;
}

// Every DetectorConfig field with its accepted range: one table for the JSON reader and for
// detect()'s own check.
struct ConfigField {
  const char* name;
  double DetectorConfig::*member;
  double lo, hi;
};
constexpr ConfigField kConfigFields[] = {
    {"min_dlo_length_radii", &DetectorConfig::min_dlo_length_radii, 0, 1000},
    {"cut_radii", &DetectorConfig::cut_radii, 0, 100},
    {"fit_radii", &DetectorConfig::fit_radii, 0.5, 100},
    {"merge_radii", &DetectorConfig::merge_radii, 0, 100},
    {"epsilon_radii", &DetectorConfig::epsilon_radii, 0, 1000},
    {"wide_radii", &DetectorConfig::wide_radii, 0, 1000},
    {"colour_weight", &DetectorConfig::colour_weight, 0, 100},
    {"merge_gain", &DetectorConfig::merge_gain, 0, 1000},
    {"lone_y_cost", &DetectorConfig::lone_y_cost, 0, 1000},
    {"fold_energy", &DetectorConfig::fold_energy, 0, 1000},
    {"border_fold_energy", &DetectorConfig::border_fold_energy, 0, 1000},
    {"colour_label_margin", &DetectorConfig::colour_label_margin, 0, 1000}};

std::string out_of_range(const ConfigField& f, const std::string& value) {
  char range[64];
  std::snprintf(range, sizeof range, "[%g, %g]", f.lo, f.hi);
  return std::string("detector config: field \"") + f.name + "\" = " + value + " is outside " + range;
}

}  // namespace

Result<DetectorConfig> parse_detector_config(const std::string& json_text) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(json_text);
  } catch (const nlohmann::json::parse_error& e) {
    return Error{std::string("detector config: not valid JSON (") + e.what() + ")"};
  }
  if (!j.is_object()) return Error{"detector config: expected a JSON object of fields"};
  DetectorConfig c;
  for (const auto& [key, value] : j.items()) {
    const ConfigField* f = nullptr;
    for (const ConfigField& candidate : kConfigFields)
      if (key == candidate.name) f = &candidate;
    if (!f) return Error{"detector config: unknown field \"" + key + "\""};
    if (!value.is_number()) return Error{"detector config: field \"" + key + "\" must be a number"};
    const double v = value.get<double>();
    if (!(v >= f->lo && v <= f->hi)) return Error{out_of_range(*f, value.dump())};
    c.*(f->member) = v;
  }
  return c;
}

double Detection::total_ms() const {
  double t = 0;
  for (const StageTime& s : timings) t += s.ms;
  return t;
}

Result<Detection> detect(const cv::Mat& mask, const cv::Mat& bgr, const DetectorConfig& config) {
  if (mask.empty()) return Error{"mask is empty (0 x 0)"};
  if (mask.type() != CV_8UC1)
    return Error{"mask must be 8-bit single-channel (CV_8UC1), got type " + std::to_string(mask.type())};
  if (!bgr.empty() && bgr.type() != CV_8UC3)
    return Error{"image must be 8-bit 3-channel (CV_8UC3), got type " + std::to_string(bgr.type())};
  if (!bgr.empty() && bgr.size() != mask.size())
    return Error{"mask is " + std::to_string(mask.cols) + "x" + std::to_string(mask.rows) +
                 " but the image is " + std::to_string(bgr.cols) + "x" + std::to_string(bgr.rows)};
  for (const ConfigField& f : kConfigFields) {
    const double v = config.*(f.member);
    if (!(v >= f.lo && v <= f.hi)) {
      char value[32];
      std::snprintf(value, sizeof value, "%g", v);
      return Error{out_of_range(f, value)};
    }
  }

  Detection det;
  StageClock stage(det.timings);
  Skeleton skeleton = stage("skeleton", [&] { return skeletonize(mask); });
  float r = 0;
  SkeletonGraph graph = stage("keypoints", [&] {
    SkeletonGraph g = build_skeleton_graph(skeleton, detect_keypoints(skeleton));
    r = std::max(1.0f, measure_radii(g, mask));
    return g;
  });
  const ColourSource colour{config.colour_weight > 0 ? bgr : cv::Mat(), r};
  stage("prune", [&] {
    return prune_split_ends(graph, 2 * r, mask.size(), colour) +
           cut_folds_at_border(graph, config.fit_radii * r, mask.size(), config.border_fold_energy);
  });
  auto regions = stage("junctions", [&] {
    return group_junctions(graph, config.merge_radii * r, config.epsilon_radii * r,
                           config.wide_radii * r);
  });
  const PairingSetup pairing{config.cut_radii * r, config.fit_radii * r, bgr, config.colour_weight};
  auto passages = stage("bending", [&] {
    TangentCache tangents(graph, pairing);
    pair_lone_ys(graph, regions, tangents, config.epsilon_radii * r, config.wide_radii * r,
                 config.lone_y_cost);
    merge_regions_by_pairing_cost(graph, regions, tangents, config.epsilon_radii * r,
                                  config.merge_gain, config.wide_radii * r,
                                  3 * config.merge_radii * r);
    return build_passages(regions, tangents, config.fold_energy);
  });
  Traversal traversal = stage("traverse", [&] {
    return traverse(graph, passages, config.min_dlo_length_radii * r);
  });
  stage("extend_ends", [&] { extend_ends(traversal.dlos, mask, r); });
  auto ordered = stage("crossing_order", [&] {
    return order_crossings(passages, static_cast<int>(regions.size()), bgr);
  });
  det.dlos = std::move(traversal.dlos);
  auto tops = record_crossings(det, passages, regions, traversal, ordered);
  det.labels = stage("instance_mask", [&] {
    cv::Mat labels = instance_labels(mask, det.dlos, tops);
    if (!bgr.empty() && config.colour_weight > 0 && config.colour_label_margin > 0)
      refine_labels_by_colour(labels, mask, bgr, colour_zones(graph, regions, passages, traversal),
                              config.colour_label_margin, 3 * config.colour_label_margin);
    return labels;
  });
  return det;
}

}  // namespace mbest

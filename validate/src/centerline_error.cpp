#include "mbest/validate/centerline_error.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>

#include <nlohmann/json.hpp>

namespace mbest::validate {

namespace {

double distance_to_segment(cv::Point2d p, cv::Point2d a, cv::Point2d b) {
  const cv::Point2d ab = b - a;
  const double len2 = ab.dot(ab);
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return cv::norm(p - (a + t * ab));
}

}  // namespace

std::vector<double> distances_to_polyline(const std::vector<cv::Point2d>& from,
                                          const Polyline& to) {
  const size_t n = to.points.size();
  const size_t segments = n < 2 ? 0 : (to.closed ? n : n - 1);
  std::vector<double> out;
  out.reserve(from.size());
  for (const cv::Point2d& p : from) {
    double best = n == 1 ? cv::norm(p - to.points[0]) : std::numeric_limits<double>::infinity();
    for (size_t s = 0; s < segments; ++s)
      best = std::min(best, distance_to_segment(p, to.points[s], to.points[(s + 1) % n]));
    out.push_back(best);
  }
  return out;
}

CenterlineDistances centerline_distances(const synth::SceneAnnotation& scene,
                                         const std::vector<Polyline>& predicted,
                                         const DiceScore& dice) {
  std::map<int, int> matched;  // rod id -> matched predicted label
  for (size_t i = 0; i < dice.gt_ids.size(); ++i) matched[dice.gt_ids[i]] = dice.matched_pred[i];
  CenterlineDistances out;
  for (const synth::RodAnnotation& rod : scene.rods) {
    const auto it = matched.find(rod.id);
    if (it == matched.end() || it->second <= 0) continue;
    const size_t dlo = static_cast<size_t>(it->second - 1);
    if (dlo >= predicted.size() || predicted[dlo].points.empty() || rod.centerline.empty())
      continue;
    const std::vector<double> p2g =
        distances_to_polyline(predicted[dlo].points, Polyline{rod.centerline, rod.closed});
    const std::vector<double> g2p = distances_to_polyline(rod.centerline, predicted[dlo]);
    out.pred_to_gt.insert(out.pred_to_gt.end(), p2g.begin(), p2g.end());
    out.gt_to_pred.insert(out.gt_to_pred.end(), g2p.begin(), g2p.end());
  }
  return out;
}

DistanceSummary summarise(std::vector<double> distances) {
  DistanceSummary s;
  s.count = static_cast<int>(distances.size());
  if (distances.empty()) return s;
  double sum = 0;
  for (double d : distances) sum += d;
  s.mean = sum / distances.size();
  std::sort(distances.begin(), distances.end());
  const double rank = 0.95 * (distances.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(rank));
  const size_t hi = std::min(lo + 1, distances.size() - 1);
  s.p95 = distances[lo] + (rank - lo) * (distances[hi] - distances[lo]);
  return s;
}

Result<std::vector<Polyline>> read_predicted_centerlines(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{path + ": cannot open"};
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    return Error{path + ": not valid JSON (" + e.what() + ")"};
  }
  if (!j.is_object() || !j.contains("dlos") || !j["dlos"].is_array())
    return Error{path + ": field \"dlos\" missing or not an array"};
  std::vector<Polyline> out;
  for (size_t i = 0; i < j["dlos"].size(); ++i) {
    const nlohmann::json& dlo = j["dlos"][i];
    const std::string field = path + ": dlos[" + std::to_string(i) + "]";
    if (!dlo.is_object() || !dlo.contains("centerline") || !dlo["centerline"].is_array())
      return Error{field + ".centerline missing or not an array"};
    Polyline line;
    for (const nlohmann::json& p : dlo["centerline"]) {
      if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
        return Error{field + ".centerline: a point is not [x, y]"};
      line.points.emplace_back(p[0].get<double>(), p[1].get<double>());
    }
    if (dlo.contains("closed") && dlo["closed"].is_boolean()) line.closed = dlo["closed"];
    out.push_back(std::move(line));
  }
  return out;
}

}  // namespace mbest::validate

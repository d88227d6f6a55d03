#include "mbest/validate/centerline_error.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>

#include "prediction_json.h"

namespace mbest::validate {

namespace {

double distance_to_segment(cv::Point2d p, cv::Point2d a, cv::Point2d b) {
  const cv::Point2d ab = b - a;
  const double len2 = ab.dot(ab);
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return cv::norm(p - (a + t * ab));
}

// The segments of a polyline bucketed in square cells: a nearest-segment query visits rings
// of cells around the point until no farther cell can hold anything nearer.
class SegmentGrid {
 public:
  explicit SegmentGrid(const Polyline& line) {
    const size_t n = line.points.size();
    if (n == 1) segments_.push_back({line.points[0], line.points[0]});
    const size_t count = n < 2 ? 0 : (line.closed ? n : n - 1);
    for (size_t s = 0; s < count; ++s) segments_.push_back({line.points[s], line.points[(s + 1) % n]});
    if (segments_.empty()) return;
    int x1 = INT_MIN, y1 = INT_MIN;
    x0_ = y0_ = INT_MAX;
    for (const cv::Point2d& p : line.points) {
      x0_ = std::min(x0_, cell_of(p.x)), x1 = std::max(x1, cell_of(p.x));
      y0_ = std::min(y0_, cell_of(p.y)), y1 = std::max(y1, cell_of(p.y));
    }
    cols_ = x1 - x0_ + 1;
    rows_ = y1 - y0_ + 1;
    cells_.resize(static_cast<size_t>(cols_) * rows_);
    for (size_t s = 0; s < segments_.size(); ++s) {
      const auto& [a, b] = segments_[s];
      for (int cy = cell_of(std::min(a.y, b.y)); cy <= cell_of(std::max(a.y, b.y)); ++cy)
        for (int cx = cell_of(std::min(a.x, b.x)); cx <= cell_of(std::max(a.x, b.x)); ++cx)
          cells_[(cy - y0_) * cols_ + (cx - x0_)].push_back(static_cast<int>(s));
    }
  }

  double distance(cv::Point2d p) const {
    double best = std::numeric_limits<double>::infinity();
    if (segments_.empty()) return best;
    const int cx = cell_of(p.x), cy = cell_of(p.y);
    const int last_ring = std::max({std::abs(cx - x0_), std::abs(cx - (x0_ + cols_ - 1)),
                                    std::abs(cy - y0_), std::abs(cy - (y0_ + rows_ - 1))});
    for (int r = 0; r <= last_ring; ++r) {
      for (int y = cy - r; y <= cy + r; ++y) {
        const bool edge_row = y == cy - r || y == cy + r;
        for (int x = cx - r; x <= cx + r; x += edge_row ? 1 : 2 * r) {
          if (x < x0_ || y < y0_ || x >= x0_ + cols_ || y >= y0_ + rows_) continue;
          for (int s : cells_[(y - y0_) * cols_ + (x - x0_)])
            best = std::min(best, distance_to_segment(p, segments_[s].first, segments_[s].second));
        }
      }
      // Every cell of a farther ring is at least r whole cells away from p.
      if (best <= r * kCell) break;
    }
    return best;
  }

 private:
  static constexpr double kCell = 8;  // pixels
  static int cell_of(double v) { return static_cast<int>(std::floor(v / kCell)); }

  std::vector<std::pair<cv::Point2d, cv::Point2d>> segments_;
  int x0_ = 0, y0_ = 0, cols_ = 0, rows_ = 0;
  std::vector<std::vector<int>> cells_;  // segment indices per cell, row-major
};

}  // namespace

std::vector<double> distances_to_polyline(const std::vector<cv::Point2d>& from,
                                          const Polyline& to) {
  const SegmentGrid grid(to);
  std::vector<double> out;
  out.reserve(from.size());
  for (const cv::Point2d& p : from) out.push_back(grid.distance(p));
  return out;
}

CenterlineDistances centerline_distances(const synth::SceneAnnotation& scene,
                                         const std::vector<Polyline>& predicted,
                                         const DiceScore& dice) {
  CenterlineDistances out;
  for (const synth::RodAnnotation& rod : scene.rods) {
    const int i = dice.instance_of(rod.id);
    if (i < 0 || dice.matched_pred[i] <= 0) continue;
    const size_t dlo = static_cast<size_t>(dice.matched_pred[i] - 1);
    if (dlo >= predicted.size() || predicted[dlo].points.empty() || rod.centerline.empty())
      continue;
    const std::vector<double> p2g =
        distances_to_polyline(predicted[dlo].points, Polyline{rod.centerline, rod.closed});
    // Ground-truth samples outside the picture cannot be found; they are not counted.
    std::vector<cv::Point2d> seen;
    for (const cv::Point2d& q : rod.centerline)
      if (scene.width <= 0 || (q.x > -0.5 && q.y > -0.5 && q.x < scene.width - 0.5 &&
                               q.y < scene.height - 0.5))
        seen.push_back(q);
    const std::vector<double> g2p = distances_to_polyline(seen, predicted[dlo]);
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
  Result<nlohmann::json> j = read_json_file(path);
  if (!j) return j.error();
  return centerlines_from_json(j.value(), path);
}

}  // namespace mbest::validate

#include "mbest/validate/crossing_resolution.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <utility>

#include <opencv2/imgproc.hpp>

namespace mbest::validate {

namespace {

using synth::RodAnnotation;

int label_at(const cv::Mat& labels16, cv::Point p) {
  if (p.x < 0 || p.y < 0 || p.x >= labels16.cols || p.y >= labels16.rows) return 0;
  return labels16.at<uint16_t>(p);
}

// How many rods' bodies (each rod's centerline drawn at its width) cover each pixel. Where
// two bodies overlap, a label image shows only the one on top: a pixel there tests the order
// at that overlap, not the pairing at the crossing being assessed.
cv::Mat rod_body_count(const synth::SceneAnnotation& scene, cv::Size size) {
  cv::Mat count = cv::Mat::zeros(size, CV_8UC1), body(size, CV_8UC1);
  constexpr int kShift = 3;  // sub-pixel vertices: 1/8 px
  for (const RodAnnotation& rod : scene.rods) {
    if (rod.centerline.empty()) continue;
    std::vector<cv::Point> points;
    points.reserve(rod.centerline.size());
    for (const cv::Point2d& p : rod.centerline)
      points.emplace_back(cvRound(p.x * (1 << kShift)), cvRound(p.y * (1 << kShift)));
    body.setTo(0);
    cv::polylines(body, points, rod.closed, cv::Scalar(1),
                  std::max(1, static_cast<int>(std::lround(rod.width_px))), cv::LINE_8, kShift);
    count += body;
  }
  return count;
}

// The most frequent predicted label (0 included) over the disc's pixels; when `only_gt` is
// non-zero, over the disc's pixels whose ground-truth label is `only_gt` and which no other
// rod's body covers (`bodies`: rod_body_count).
int majority_label(const cv::Mat& pred16, const cv::Mat& gt16, cv::Point2d centre, double radius,
                   int only_gt, const cv::Mat& bodies = cv::Mat()) {
  std::map<int, int> votes;
  const int r = static_cast<int>(std::ceil(radius));
  const cv::Point c(cvRound(centre.x), cvRound(centre.y));
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      if (dx * dx + dy * dy > radius * radius) continue;
      const cv::Point p(c.x + dx, c.y + dy);
      if (p.x < 0 || p.y < 0 || p.x >= pred16.cols || p.y >= pred16.rows) continue;
      if (only_gt != 0 && label_at(gt16, p) != only_gt) continue;
      if (only_gt != 0 && !bodies.empty() && bodies.at<uint8_t>(p) > 1) continue;
      ++votes[label_at(pred16, p)];
    }
  }
  int best = 0, best_votes = -1;
  for (const auto& [label, count] : votes)
    if (count > best_votes) best = label, best_votes = count;
  return best;
}

// Cyclic or linear distance between two sample indices of one centerline.
int index_distance(int i, int j, int size, bool closed) {
  const int d = std::abs(i - j);
  return closed ? std::min(d, size - d) : d;
}

// Whether the two passes of a self-crossing (samples i and j) are joined by a stretch of the
// rod that stays in the image (either way round a closed rod). A stretch leaves the image where
// its centerline is more than half the rod's width outside, so that none of its body shows.
// Where the loop between the passes leaves the image, the picture shows two pieces, and no
// detector can tell that they are one rod.
bool passes_joined_in_image(const RodAnnotation& rod, int i, int j, cv::Size image) {
  const double m = rod.width_px / 2;
  const auto shows = [&](const cv::Point2d& p) {
    return p.x >= -m && p.y >= -m && p.x <= image.width - 1 + m && p.y <= image.height - 1 + m;
  };
  const auto stretch_shows = [&](int from, int to) {  // samples from..to, wrapping round
    const int size = static_cast<int>(rod.centerline.size());
    for (int k = from;; k = (k + 1) % size) {
      if (!shows(rod.centerline[k])) return false;
      if (k == to) return true;
    }
  };
  if (i > j) std::swap(i, j);
  return stretch_shows(i, j) || (rod.closed && stretch_shows(j, i));
}

struct Strand {
  const RodAnnotation* rod = nullptr;
  int arc_index = 0;
};

// The centerline point of `s` where it is clear of the crossing with `other`, walking in
// `direction` (+1 or -1) along the rod; nullopt when the rod ends (or the walk limit is hit)
// first. The other strand is the part of its rod nearer (in samples) to its own crossing
// index than to ours: this separates the two strands of a self-crossing. The sample is where
// the strand lies alone: visible, and no other rod's body overlaps it (`bodies`).
std::optional<cv::Point2d> clear_sample(const Strand& s, const Strand& other, int direction,
                                        const cv::Mat& gt16, const cv::Mat& bodies,
                                        const CrossingOptions& o) {
  const std::vector<cv::Point2d>& line = s.rod->centerline;
  const std::vector<cv::Point2d>& other_line = other.rod->centerline;
  const int size = static_cast<int>(line.size());
  const int other_size = static_cast<int>(other_line.size());
  const bool same_rod = s.rod == other.rod;
  const double width = s.rod->width_px;
  const double clearance = (width + other.rod->width_px) / 2 + 1;
  const double max_walk = o.max_walk_widths * width;
  // Other-strand samples that can be within `clearance` of the walk.
  std::vector<cv::Point2d> other_points;
  const int window = static_cast<int>(std::ceil(max_walk + 2 * clearance)) + 2;
  for (int d = -window; d <= window; ++d) {
    int j = other.arc_index + d;
    if (other.rod->closed) j = ((j % other_size) + other_size) % other_size;
    if (j < 0 || j >= other_size) continue;
    if (same_rod && index_distance(j, s.arc_index, size, s.rod->closed) <=
                        index_distance(j, other.arc_index, size, s.rod->closed))
      continue;
    other_points.push_back(other_line[j]);
  }
  double arc = 0;
  int i = s.arc_index;
  for (int step = 1; step < size; ++step) {
    int next = i + direction;
    if (s.rod->closed) next = (next + size) % size;
    if (next < 0 || next >= size) return std::nullopt;
    arc += cv::norm(line[next] - line[i]);
    i = next;
    if (arc > max_walk) return std::nullopt;
    if (arc < o.offset_widths * width) continue;
    const cv::Point2d p = line[i];
    const cv::Point pixel(cvRound(p.x), cvRound(p.y));
    if (label_at(gt16, pixel) != s.rod->id || bodies.at<uint8_t>(pixel) > 1) continue;
    double nearest = std::numeric_limits<double>::infinity();
    for (const cv::Point2d& q : other_points) nearest = std::min(nearest, cv::norm(p - q));
    if (nearest >= clearance) return p;
  }
  return std::nullopt;
}

}  // namespace

std::vector<CrossingResolution> crossing_resolution(const synth::SceneAnnotation& scene,
                                                    const cv::Mat& gt_labels,
                                                    const cv::Mat& pred_labels,
                                                    const DiceScore& dice,
                                                    const CrossingOptions& options) {
  const cv::Mat gt16 = labels_16u(gt_labels), pred16 = labels_16u(pred_labels);
  const cv::Mat bodies = scene.crossings.empty() ? cv::Mat() : rod_body_count(scene, gt16.size());
  std::map<int, const RodAnnotation*> rods;
  for (const RodAnnotation& r : scene.rods) rods[r.id] = &r;

  std::vector<CrossingResolution> out;
  for (size_t k = 0; k < scene.crossings.size(); ++k) {
    const synth::CrossingAnnotation& c = scene.crossings[k];
    CrossingResolution r;
    r.index = static_cast<int>(k);
    r.rod_a = c.rod_a;
    r.rod_b = c.rod_b;
    r.top = c.top;
    r.angle_deg = c.angle_deg;
    r.location = c.location;
    const auto ra = rods.find(c.rod_a), rb = rods.find(c.rod_b);
    if (ra == rods.end() || rb == rods.end()) {
      r.note = "crossing names a rod missing from the annotation";
      out.push_back(r);
      continue;
    }
    const Strand a{ra->second, c.arc_index_a}, b{rb->second, c.arc_index_b};
    r.width_px = std::max(a.rod->width_px, b.rod->width_px);
    r.complexity = std::max(a.rod->complexity.total_turning_rad,
                            b.rod->complexity.total_turning_rad);
    const auto valid_index = [](const Strand& s) {
      return s.arc_index >= 0 && s.arc_index < static_cast<int>(s.rod->centerline.size());
    };
    if (!valid_index(a) || !valid_index(b)) {
      r.note = "arc_index outside the rod's centerline";
      out.push_back(r);
      continue;
    }

    const auto sample = [&](const Strand& s, const Strand& other, int direction, int* label) {
      const std::optional<cv::Point2d> p = clear_sample(s, other, direction, gt16, bodies, options);
      if (!p) return false;
      *label = majority_label(pred16, gt16, *p, std::max(1.0, options.disc_radius_widths *
                                                                  s.rod->width_px),
                              s.rod->id, bodies);
      return true;
    };
    const bool sampled = sample(a, b, -1, &r.a_before) && sample(a, b, +1, &r.a_after) &&
                         sample(b, a, -1, &r.b_before) && sample(b, a, +1, &r.b_after);
    if (sampled) {
      r.pairing_assessed = true;
      const bool a_kept = r.a_before != 0 && r.a_before == r.a_after;
      const bool b_kept = r.b_before != 0 && r.b_before == r.b_after;
      const bool labels_as_rods =
          c.rod_a != c.rod_b
              ? r.a_before != r.b_before
              : r.a_before == r.b_before ||
                    !passes_joined_in_image(*a.rod, a.arc_index, b.arc_index, gt16.size());
      r.pairing_correct = a_kept && b_kept && labels_as_rods;
    } else {
      r.note = "a strand has no visible sample clear of the crossing";
    }

    const double min_width = std::min(a.rod->width_px, b.rod->width_px);
    const double disc = std::max(1.0, options.disc_radius_widths * min_width);
    r.at_crossing = majority_label(pred16, gt16, c.location, disc, 0);
    // The truth's label image shows the top rod at the crossing, unless a third rod lies
    // over both there: then no label image, the truth's included, shows their order.
    const int shown = majority_label(gt16, gt16, c.location, disc, 0);
    if (c.rod_a == c.rod_b) {
      if (r.note.empty()) r.note = "self-crossing: order not assessed from a label image";
    } else if (shown != c.rod_a && shown != c.rod_b) {
      if (r.note.empty()) r.note = "a third rod lies over the crossing: order not assessed";
    } else {
      r.order_assessed = true;
      const int top = dice.instance_of(c.top);
      const int top_label = top < 0 ? 0 : dice.matched_pred[top];
      r.order_correct = top_label != 0 && r.at_crossing == top_label;
    }
    out.push_back(r);
  }
  for (CrossingResolution& r : out) {
    if (r.width_px <= 0) continue;  // a crossing naming a missing rod: no width to measure by
    const double radius = options.crowding_radius_widths * r.width_px;
    for (const synth::CrossingAnnotation& c : scene.crossings) {
      const cv::Point2d d = c.location - r.location;
      if (d.dot(d) < radius * radius) ++r.neighbours;
    }
    --r.neighbours;  // itself
  }
  return out;
}

}  // namespace mbest::validate

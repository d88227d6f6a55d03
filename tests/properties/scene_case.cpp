#include "scene_case.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <cmath>
#include <limits>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>


#include "mbest/synth/config.h"
#include "mbest/validate/crossing_resolution.h"
#include "mbest/validate/dice.h"

namespace mbest::properties {
namespace {

using nlohmann::json;

const std::vector<std::string> kProperties = {"two_rods", "one_rod", "equivariance", "any_scene",
                                              "ring",     "triple",  "loop"};
const std::vector<std::string> kTransforms = {"none",   "rot90",  "rot180",   "rot270",
                                              "flip_x", "flip_y", "transpose"};

std::string fmt(double x, int digits = 3) {
  std::ostringstream s;
  s.precision(digits);
  s << x;
  return s.str();
}

Result<Detection> detect_caught(const cv::Mat& mask, const cv::Mat& bgr) {
  try {
    return detect(mask, bgr);
  } catch (const std::exception& e) {
    return Error{std::string("detect threw ") + e.what()};
  } catch (...) {
    return Error{"detect threw a non-standard exception"};
  }
}

// The input transform T (inverse = false) or T^-1 (inverse = true) of an image.
cv::Mat transformed(const cv::Mat& m, const std::string& t, bool inverse) {
  cv::Mat out;
  if (t == "rot90") {
    cv::rotate(m, out, inverse ? cv::ROTATE_90_COUNTERCLOCKWISE : cv::ROTATE_90_CLOCKWISE);
  } else if (t == "rot270") {
    cv::rotate(m, out, inverse ? cv::ROTATE_90_CLOCKWISE : cv::ROTATE_90_COUNTERCLOCKWISE);
  } else if (t == "rot180") {
    cv::rotate(m, out, cv::ROTATE_180);
  } else if (t == "flip_x") {
    cv::flip(m, out, 1);
  } else if (t == "flip_y") {
    cv::flip(m, out, 0);
  } else if (t == "transpose") {
    cv::transpose(m, out);
  } else {
    out = m.clone();
  }
  return out;
}

const synth::SceneAnnotation& gt(const Case& c) { return c.scene.annotation; }
const cv::Mat& gt_labels(const Case& c) { return c.scene.render.labels; }

// Labels of pixel p, 0 outside the picture.
int label_at(const cv::Mat& labels, cv::Point p) {
  if (p.x < 0 || p.y < 0 || p.x >= labels.cols || p.y >= labels.rows) return 0;
  return labels.at<std::uint16_t>(p);
}

// Whether every point of the rod's centerline lies at least `margin` px inside the picture.
bool inside_with_margin(const synth::RodAnnotation& rod, int w, int h, double margin) {
  for (const cv::Point2d& p : rod.centerline) {
    if (p.x < margin || p.y < margin || p.x > w - 1 - margin || p.y > h - 1 - margin) return false;
  }
  return true;
}

// Closest approach of two centerline samples at least `min_arc` samples apart along the rod
// (ring: either way round): the rod's self-contact, in px between centres. With `clear` > 0,
// pairs of samples both within `clear` px of `at` are left out: the contact away from a
// crossing there.
double self_approach(const synth::RodAnnotation& rod, double min_arc, cv::Point2d at = {}, double clear = 0) {
  const auto& c = rod.centerline;
  const int n = static_cast<int>(c.size());
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; i += 2) {
    const bool near_i = cv::norm(c[i] - at) < clear;
    for (int j = i + static_cast<int>(min_arc); j < n; j += 2) {
      if (rod.closed && n - (j - i) < min_arc) continue;
      if (near_i && cv::norm(c[j] - at) < clear) continue;
      best = std::min(best, cv::norm(c[i] - c[j]));
    }
  }
  return best;
}

Result<validate::DiceScore> dice_of(const Case& c) {
  return validate::matched_dice(gt_labels(c), c.detection.labels);
}

// Number of separate places where the two rods' full masks touch (8-connected).
int contact_regions(const Case& c) {
  const auto& amodal = c.scene.render.amodal;
  if (amodal.size() != 2) return 0;
  cv::Mat grown, contact, components;
  cv::dilate(amodal[1], grown, cv::Mat::ones(3, 3, CV_8UC1));
  contact = amodal[0] & grown;
  return cv::connectedComponents(contact, components, 8) - 1;
}

// The first rod whose body shows in the picture as more than one piece (it leaves the image
// and comes back), as "rod <id> shows as <n> pieces"; empty when every rod is one piece. Such
// a rod is several DLOs to any detector: nothing in the picture joins its pieces.
std::string rod_in_pieces(const Case& c) {
  const auto& amodal = c.scene.render.amodal;
  const auto& rods = gt(c).rods;
  cv::Mat components;
  for (size_t i = 0; i < amodal.size() && i < rods.size(); ++i) {
    const int pieces = cv::connectedComponents(amodal[i], components, 8) - 1;
    if (pieces > 1) return "rod " + std::to_string(rods[i].id) + " shows as " + std::to_string(pieces) + " pieces";
  }
  return "";
}

Verdict check_two_rods(const SceneSpec& spec) {
  Verdict v;
  Result<Case> run = run_case(spec);
  if (!run) return Verdict{"", {run.error().message}};
  const Case& c = run.value();
  const auto& a = gt(c);
  if (a.rods.size() != 2) return Verdict{"scene has " + std::to_string(a.rods.size()) + " rods", {}};
  if (a.crossings.size() != 1) {
    return Verdict{"scene has " + std::to_string(a.crossings.size()) + " crossings", {}};
  }
  const synth::CrossingAnnotation& x = a.crossings[0];
  if (x.rod_a == x.rod_b) return Verdict{"the crossing is a self-crossing", {}};
  // Crossing once: the rods' masks meet in one place. Where they also touch without
  // crossing, the mask merges them there, and touching strands are outside mBEST's model.
  if (contact_regions(c) > 1) return Verdict{"the rods also touch away from their crossing", {}};
  if (const std::string split = rod_in_pieces(c); !split.empty()) return Verdict{split, {}};
  if (x.angle_deg < 20) return Verdict{"crossing angle " + fmt(x.angle_deg) + " deg < 20", {}};
  Result<validate::DiceScore> dice = dice_of(c);
  if (!dice) return Verdict{"", {dice.error().message}};
  const auto resolution =
      validate::crossing_resolution(a, gt_labels(c), c.detection.labels, dice.value());
  if (!resolution[0].pairing_assessed) return Verdict{"pairing not assessable: " + resolution[0].note, {}};
  if (c.detection.dlos.size() != 2) {
    v.failures.push_back("expected 2 DLOs, got " + std::to_string(c.detection.dlos.size()));
  }
  if (!resolution[0].pairing_correct) {
    std::ostringstream s;
    s << "crossing at (" << fmt(x.location.x, 4) << ", " << fmt(x.location.y, 4) << "), "
      << fmt(x.angle_deg) << " deg: pairing wrong (labels a " << resolution[0].a_before << "->"
      << resolution[0].a_after << ", b " << resolution[0].b_before << "->" << resolution[0].b_after
      << ")";
    v.failures.push_back(s.str());
  }
  for (int i = 0; i < dice.value().n; ++i) {
    if (dice.value().matched_dice[i] < kMinRodDice) {
      v.failures.push_back("rod " + std::to_string(dice.value().gt_ids[i]) + ": matched DICE " +
                           fmt(dice.value().matched_dice[i], 4) + " < " + fmt(kMinRodDice));
    }
  }
  return v;
}

// The premise of one_rod and loop: one open rod, a width inside the picture. Empty when it
// holds, else why the scene is discarded.
std::string not_one_open_rod_inside(const synth::SceneAnnotation& a) {
  if (a.rods.size() != 1 || a.rods[0].closed) return "scene is not one open rod";
  if (!inside_with_margin(a.rods[0], a.width, a.height, a.rods[0].width_px)) return "rod not a width inside the picture";
  return "";
}

Verdict check_one_rod(const SceneSpec& spec) {
  Verdict v;
  Result<Case> run = run_case(spec);
  if (!run) return Verdict{"", {run.error().message}};
  const Case& c = run.value();
  const auto& a = gt(c);
  if (std::string why = not_one_open_rod_inside(a); !why.empty()) return Verdict{why, {}};
  const synth::RodAnnotation& rod = a.rods[0];
  const double w = rod.width_px;
  // No self-contact: strands 3 widths of arc apart stay a width clear of each other.
  if (self_approach(rod, 3 * w) < 2 * w) return Verdict{"rod touches itself", {}};
  if (c.detection.dlos.size() != 1) {
    v.failures.push_back("expected 1 DLO, got " + std::to_string(c.detection.dlos.size()));
    return v;
  }
  const Dlo& dlo = c.detection.dlos[0];
  if (dlo.closed) v.failures.push_back("the DLO is closed");
  if (dlo.centerline.empty()) {
    v.failures.push_back("empty centerline");
    return v;
  }
  // Arc length (GT sample index, samples are 1 px apart) of the GT point nearest each
  // centerline pixel, and that distance.
  std::vector<double> s;
  double worst_off = 0;
  for (const cv::Point& p : dlo.centerline) {
    double best = std::numeric_limits<double>::infinity();
    int arg = 0;
    for (size_t k = 0; k < rod.centerline.size(); ++k) {
      const double d = cv::norm(rod.centerline[k] - cv::Point2d(p));
      if (d < best) best = d, arg = static_cast<int>(k);
    }
    s.push_back(arg);
    worst_off = std::max(worst_off, best);
  }
  if (worst_off > 0.5 * w) {
    v.failures.push_back("centerline strays " + fmt(worst_off) + " px from the rod (> half a width, " +
                         fmt(0.5 * w) + ")");
  }
  if (s.back() < s.front()) std::reverse(s.begin(), s.end());
  double running_max = s.front(), worst_back = 0;
  int worst_at = 0;
  for (size_t i = 1; i < s.size(); ++i) {
    if (running_max - s[i] > worst_back) worst_back = running_max - s[i], worst_at = static_cast<int>(i);
    running_max = std::max(running_max, s[i]);
  }
  if (worst_back > kArcJitterWidths * w) {
    v.failures.push_back("centerline runs back " + fmt(worst_back) + " px of arc at pixel " +
                         std::to_string(worst_at) + " (tolerance " + fmt(kArcJitterWidths * w) + ")");
  }
  // Ends: each predicted end within one width of the GT end on its side.
  cv::Point2d p0(dlo.centerline.front()), p1(dlo.centerline.back());
  const cv::Point2d g0 = rod.centerline.front(), g1 = rod.centerline.back();
  if (cv::norm(p0 - g0) + cv::norm(p1 - g1) > cv::norm(p0 - g1) + cv::norm(p1 - g0)) std::swap(p0, p1);
  for (auto [p, g] : {std::pair{p0, g0}, std::pair{p1, g1}}) {
    if (cv::norm(p - g) > w) {
      v.failures.push_back("end (" + fmt(p.x, 4) + ", " + fmt(p.y, 4) + ") is " + fmt(cv::norm(p - g)) +
                           " px from the rod's end (" + fmt(g.x, 4) + ", " + fmt(g.y, 4) + "), width " + fmt(w));
    }
  }
  return v;
}

Verdict check_equivariance(const SceneSpec& spec) {
  Verdict v;
  Result<Case> run = run_case(spec);
  if (!run) return Verdict{"", {run.error().message}};
  const Case& c = run.value();
  Result<Detection> moved = detect_caught(transformed(c.mask, spec.transform, false),
                                          transformed(c.scene.render.image, spec.transform, false));
  if (!moved) return Verdict{"", {spec.transform + ": " + moved.error().message}};
  const cv::Mat back = transformed(moved.value().labels, spec.transform, true);
  const Detection& d0 = c.detection;
  const Detection& d1 = moved.value();
  if (d0.dlos.size() != d1.dlos.size()) {
    v.failures.push_back(std::to_string(d0.dlos.size()) + " DLOs, " + std::to_string(d1.dlos.size()) +
                         " after " + spec.transform);
  }
  if (d0.crossings.size() != d1.crossings.size()) {
    v.failures.push_back(std::to_string(d0.crossings.size()) + " detected crossings, " +
                         std::to_string(d1.crossings.size()) + " after " + spec.transform);
  }
  // Match the ids of the two label images, then count the mask pixels they disagree on.
  Result<validate::DiceScore> match = validate::matched_dice(d0.labels, back);
  if (!match) return Verdict{"", {match.error().message}};
  std::vector<int> to_back(d0.dlos.size() + 1, -1);
  to_back[0] = 0;
  for (int i = 0; i < match.value().n; ++i) {
    const int id = match.value().gt_ids[i];
    if (id < static_cast<int>(to_back.size())) to_back[id] = match.value().matched_pred[i];
  }
  int disagree = 0;
  const int mask_pixels = cv::countNonZero(c.mask);
  for (int y = 0; y < back.rows; ++y) {
    for (int x = 0; x < back.cols; ++x) {
      const int l0 = d0.labels.at<std::uint16_t>(y, x), l1 = back.at<std::uint16_t>(y, x);
      if (l0 == 0 && l1 == 0) continue;
      if (l0 >= static_cast<int>(to_back.size()) || to_back[l0] != l1) ++disagree;
    }
  }
  const double fraction = mask_pixels ? static_cast<double>(disagree) / mask_pixels : 0;
  if (fraction > kMaxEquivarianceDisagreement) {
    v.failures.push_back("labels disagree on " + fmt(100 * fraction) + " % of the mask after " +
                         spec.transform + " (tolerance " + fmt(100 * kMaxEquivarianceDisagreement) + " %)");
  }
  // The same pairing outcome at every GT crossing.
  Result<validate::DiceScore> dice0 = validate::matched_dice(gt_labels(c), d0.labels);
  Result<validate::DiceScore> dice1 = validate::matched_dice(gt_labels(c), back);
  if (!dice0 || !dice1) return Verdict{"", {"matched DICE failed"}};
  const auto r0 = validate::crossing_resolution(gt(c), gt_labels(c), d0.labels, dice0.value());
  const auto r1 = validate::crossing_resolution(gt(c), gt_labels(c), back, dice1.value());
  for (size_t i = 0; i < r0.size(); ++i) {
    if (r0[i].pairing_assessed && r0[i].pairing_correct != r1[i].pairing_correct) {
      const auto& x = gt(c).crossings[i];
      v.failures.push_back("GT crossing " + std::to_string(i) + " at (" + fmt(x.location.x, 4) + ", " +
                           fmt(x.location.y, 4) + "), " + fmt(x.angle_deg) + " deg: pairing " +
                           (r0[i].pairing_correct ? "right" : "wrong") + ", after " + spec.transform + " " +
                           (r1[i].pairing_correct ? "right" : "wrong"));
    }
  }
  return v;
}

Verdict check_any_scene(const SceneSpec& spec) {
  Verdict v;
  Result<Case> run = run_case(spec);
  if (!run) return Verdict{"", {run.error().message}};
  const Case& c = run.value();
  const Detection& d = c.detection;
  if (d.labels.type() != CV_16UC1 || d.labels.size() != c.mask.size()) {
    return Verdict{"", {"labels are not CV_16UC1 of the mask's size"}};
  }
  const int n = static_cast<int>(d.dlos.size());
  cv::Mat to_mask;  // each pixel's distance to the mask
  cv::distanceTransform(c.mask == 0, to_mask, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  int outside = 0, too_big = 0;
  for (int y = 0; y < d.labels.rows; ++y) {
    for (int x = 0; x < d.labels.cols; ++x) {
      const int l = d.labels.at<std::uint16_t>(y, x);
      if (l != 0 && c.mask.at<uchar>(y, x) == 0) ++outside;
      if (l > n) ++too_big;
    }
  }
  if (outside) v.failures.push_back(std::to_string(outside) + " labelled pixels outside the mask");
  if (too_big) v.failures.push_back(std::to_string(too_big) + " pixels labelled above #DLOs = " + std::to_string(n));
  for (int i = 0; i < n; ++i) {
    const Dlo& dlo = d.dlos[i];
    const std::string name = "DLO " + std::to_string(i);
    if (dlo.centerline.empty()) {
      v.failures.push_back(name + ": empty centerline");
      continue;
    }
    if (dlo.radius.size() != dlo.centerline.size()) v.failures.push_back(name + ": #radius != #centerline");
    // A pixel may recur (a DLO crossing itself passes its crossing twice), but consecutive
    // pixels are distinct 8-neighbours.
    const size_t m = dlo.centerline.size();
    for (size_t k = 0; k + (dlo.closed ? 0 : 1) < m; ++k) {
      const cv::Point a = dlo.centerline[k], b = dlo.centerline[(k + 1) % m];
      if (std::max(std::abs(a.x - b.x), std::abs(a.y - b.y)) != 1) {
        v.failures.push_back(name + ": not 8-connected between pixel " + std::to_string(k) + " (" +
                             std::to_string(a.x) + ", " + std::to_string(a.y) + ") and (" +
                             std::to_string(b.x) + ", " + std::to_string(b.y) + ")");
        break;
      }
    }
    // The path through a crossing is interpolated between the strands' tangents and may
    // graze the background where strands touch (fixtures/regressions/stress_centerline_off_mask),
    // by up to kMaxCenterlineOffMask px; every centerline pixel on the mask is labelled.
    int unlabelled = 0, off_image = 0, off_mask = 0;
    for (const cv::Point& p : dlo.centerline) {
      if (p.x < 0 || p.y < 0 || p.x >= c.mask.cols || p.y >= c.mask.rows) {
        ++off_image;
        continue;
      }
      if (c.mask.at<uchar>(p) != 0 && label_at(d.labels, p) == 0) ++unlabelled;
      if (to_mask.at<float>(p) > kMaxCenterlineOffMask) ++off_mask;
    }
    if (unlabelled) v.failures.push_back(name + ": " + std::to_string(unlabelled) + " centerline pixels unlabelled");
    if (off_image) v.failures.push_back(name + ": " + std::to_string(off_image) + " centerline pixels outside the image");
    if (off_mask)
      v.failures.push_back(name + ": " + std::to_string(off_mask) + " centerline pixels more than " +
                           std::to_string(static_cast<int>(kMaxCenterlineOffMask)) + " px off the mask");
  }
  return v;
}

Verdict check_ring(const SceneSpec& spec) {
  Verdict v;
  Result<Case> run = run_case(spec);
  if (!run) return Verdict{"", {run.error().message}};
  const Case& c = run.value();
  const auto& a = gt(c);
  if (a.rods.size() != 1 || !a.rods[0].closed) return Verdict{"scene is not one ring", {}};
  if (!inside_with_margin(a.rods[0], a.width, a.height, a.rods[0].width_px)) return Verdict{"ring leaves the picture", {}};
  if (!a.crossings.empty()) return Verdict{"ring crosses itself", {}};
  if (self_approach(a.rods[0], 3 * a.rods[0].width_px) < 2 * a.rods[0].width_px) return Verdict{"ring touches itself", {}};
  if (c.detection.dlos.size() != 1) {
    v.failures.push_back("expected 1 DLO, got " + std::to_string(c.detection.dlos.size()));
  } else if (!c.detection.dlos[0].closed) {
    v.failures.push_back("the DLO is open (" + std::to_string(c.detection.dlos[0].centerline.size()) + " px)");
  }
  return v;
}

Verdict check_loop(const SceneSpec& spec) {
  Verdict v;
  Result<Case> run = run_case(spec);
  if (!run) return Verdict{"", {run.error().message}};
  const Case& c = run.value();
  const auto& a = gt(c);
  if (std::string why = not_one_open_rod_inside(a); !why.empty()) return Verdict{why, {}};
  const synth::RodAnnotation& rod = a.rods[0];
  const double w = rod.width_px;
  if (a.crossings.size() != 1) return Verdict{"rod crosses itself " + std::to_string(a.crossings.size()) + " times", {}};
  const synth::CrossingAnnotation& x = a.crossings[0];
  // No other self-contact: away from the crossing, strands 3 widths of arc apart stay clear
  // of each other (their bodies a width apart), so the mask shows the loop's hole.
  if (self_approach(rod, 3 * w, x.location, 3 * w) < 2 * w)
    return Verdict{"the rod also touches itself away from its crossing", {}};
  if (c.detection.dlos.size() != 1) {
    v.failures.push_back("expected 1 DLO, got " + std::to_string(c.detection.dlos.size()));
    return v;
  }
  if (c.detection.dlos[0].closed) v.failures.push_back("the DLO is closed");
  Result<validate::DiceScore> dice = dice_of(c);
  if (!dice) return Verdict{"", {dice.error().message}};
  if (dice.value().matched_dice[0] < kMinRodDice)
    v.failures.push_back("matched DICE " + fmt(dice.value().matched_dice[0], 4) + " < " + fmt(kMinRodDice));
  int near = 0;
  for (const Crossing& d : c.detection.crossings)
    near += d.dlos.size() == 2 && d.dlos[0] == d.dlos[1] && cv::norm(cv::Point2d(d.location) - x.location) <= 2 * w;
  if (c.detection.crossings.size() != 1 || near != 1)
    v.failures.push_back(std::to_string(c.detection.crossings.size()) + " detected crossings, " +
                         std::to_string(near) + " of them a self-crossing within 2 widths of (" +
                         fmt(x.location.x, 4) + ", " + fmt(x.location.y, 4) + "), " + fmt(x.angle_deg) +
                         " deg; expected that one only");
  return v;
}

Verdict check_triple(const SceneSpec& spec) {
  Verdict v;
  Result<Case> run = run_case(spec);
  if (!run) return Verdict{"", {run.error().message}};
  const Case& c = run.value();
  const auto& a = gt(c);
  if (a.rods.size() != 3) return Verdict{"scene has " + std::to_string(a.rods.size()) + " rods", {}};
  if (const std::string split = rod_in_pieces(c); !split.empty()) return Verdict{split, {}};
  Result<validate::DiceScore> dice = dice_of(c);
  if (!dice) return Verdict{"", {dice.error().message}};
  const auto resolution = validate::crossing_resolution(a, gt_labels(c), c.detection.labels, dice.value());
  int assessed = 0;
  for (const auto& r : resolution) assessed += r.pairing_assessed;
  if (assessed == 0) return Verdict{"no crossing assessable", {}};
  // The premise is three rods through one point: rods that also cross each other shallowly
  // (< 20 deg) elsewhere are the near-parallel case the accuracy suite measures, not this one.
  double width = 0;
  for (const auto& rod : a.rods) width = std::max(width, rod.width_px);
  size_t centre = 0;
  int most = -1;
  for (size_t i = 0; i < a.crossings.size(); ++i) {
    int near = 0;
    for (const auto& y : a.crossings) near += cv::norm(y.location - a.crossings[i].location) < 2 * width;
    if (near > most) most = near, centre = i;
  }
  for (const auto& y : a.crossings) {
    if (cv::norm(y.location - a.crossings[centre].location) >= 2 * width && y.angle_deg < 20) {
      return Verdict{"rods also cross at " + fmt(y.angle_deg) + " deg away from the triple point", {}};
    }
  }
  if (c.detection.dlos.size() != 3) {
    v.failures.push_back("expected 3 DLOs, got " + std::to_string(c.detection.dlos.size()));
  }
  for (size_t i = 0; i < resolution.size(); ++i) {
    const auto& r = resolution[i];
    if (r.pairing_assessed && !r.pairing_correct) {
      const auto& x = a.crossings[i];
      v.failures.push_back("GT crossing " + std::to_string(i) + " of rods " + std::to_string(x.rod_a) + ", " +
                           std::to_string(x.rod_b) + " at (" + fmt(x.location.x, 4) + ", " +
                           fmt(x.location.y, 4) + "), " + fmt(x.angle_deg) + " deg: pairing wrong");
    }
  }
  return v;
}

// With MBEST_PROPERTY_DUMP=DIR, writes each case's picture, ground-truth labels and
// predicted labels (scaled for viewing) and the spec to DIR/<property>_<seed>_*.
void dump(const SceneSpec& spec, const Case& c) {
  const char* dir = std::getenv("MBEST_PROPERTY_DUMP");
  if (dir == nullptr || *dir == 0) return;
  const std::string stem = std::string(dir) + "/" + spec.property + "_" + std::to_string(spec.seed);
  cv::imwrite(stem + "_image.png", c.scene.render.image);
  cv::Mat gt8, pred8;
  c.scene.render.labels.convertTo(gt8, CV_8U, 40);
  c.detection.labels.convertTo(pred8, CV_8U, 40);
  cv::imwrite(stem + "_gt.png", gt8);
  cv::imwrite(stem + "_pred.png", pred8);
  cv::Mat lines;
  cv::cvtColor(c.mask / 3, lines, cv::COLOR_GRAY2BGR);
  for (size_t i = 0; i < c.detection.dlos.size(); ++i) {
    const cv::Scalar colour((50 * i) % 256, 255 - (70 * i) % 256, 80 + (90 * i) % 176);
    for (const cv::Point& p : c.detection.dlos[i].centerline)
      if (cv::Rect(0, 0, lines.cols, lines.rows).contains(p)) lines.at<cv::Vec3b>(p) = cv::Vec3b(colour[0], colour[1], colour[2]);
  }
  cv::imwrite(stem + "_centerlines.png", lines);
  std::ofstream(stem + "_spec.json") << to_json(spec).dump(2) << "\n";
}

}  // namespace

json to_json(const SceneSpec& spec) {
  return {{"property", spec.property}, {"preset", spec.preset}, {"overrides", spec.overrides},
          {"seed", spec.seed},         {"transform", spec.transform}};
}

Result<SceneSpec> spec_from_json(const json& j, const std::string& source) {
  if (!j.is_object()) return Error{source + ": a scene spec must be a JSON object"};
  SceneSpec s;
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string& k = it.key();
    const json& x = it.value();
    if (k == "property" || k == "preset" || k == "transform" || k == "note" || k == "known_failure") {
      if (!x.is_string()) return Error{source + ": field '" + k + "' must be a string"};
    }
    if (k == "property") s.property = x.get<std::string>();
    else if (k == "preset") s.preset = x.get<std::string>();
    else if (k == "transform") s.transform = x.get<std::string>();
    else if (k == "overrides") {
      if (!x.is_object()) return Error{source + ": field 'overrides' must be an object"};
      s.overrides = x;
    } else if (k == "seed") {
      if (!x.is_number_unsigned()) return Error{source + ": field 'seed' must be a non-negative integer"};
      s.seed = x.get<std::uint64_t>();
    } else if (k != "note" && k != "known_failure") {
      return Error{source + ": unknown field '" + k + "'"};
    }
  }
  if (std::find(kProperties.begin(), kProperties.end(), s.property) == kProperties.end()) {
    return Error{source + ": field 'property' '" + s.property + "' is not a known property"};
  }
  if (std::find(kTransforms.begin(), kTransforms.end(), s.transform) == kTransforms.end()) {
    return Error{source + ": field 'transform' '" + s.transform + "' is not a known transform"};
  }
  return s;
}

void showValue(const SceneSpec& spec, std::ostream& os) { os << to_json(spec).dump(); }

Result<Case> run_case(const SceneSpec& spec) {
  Result<synth::SynthConfig> config = synth::make_config(spec.preset, spec.overrides, "scene spec");
  if (!config) return config.error();
  Result<synth::GeneratedScene> scene = synth::generate_scene(config.value(), spec.seed, 0);
  if (!scene) return scene.error();
  Case c;
  c.scene = std::move(scene).value();
  c.mask = c.scene.render.labels > 0;
  Result<Detection> d = detect_caught(c.mask, c.scene.render.image);
  if (!d) return d.error();
  c.detection = std::move(d).value();
  dump(spec, c);
  return c;
}

std::string Verdict::describe() const {
  if (!discard.empty()) return "discarded: " + discard;
  std::string s;
  for (const std::string& f : failures) s += f + "\n";
  return s;
}

Verdict check(const SceneSpec& spec) {
  if (spec.property == "two_rods") return check_two_rods(spec);
  if (spec.property == "one_rod") return check_one_rod(spec);
  if (spec.property == "equivariance") return check_equivariance(spec);
  if (spec.property == "any_scene") return check_any_scene(spec);
  if (spec.property == "ring") return check_ring(spec);
  if (spec.property == "triple") return check_triple(spec);
  if (spec.property == "loop") return check_loop(spec);
  return Verdict{"", {"unknown property '" + spec.property + "'"}};
}

}  // namespace mbest::properties

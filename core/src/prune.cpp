#include "mbest/core/prune.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "mbest/core/bending.h"
#include "mbest/core/geometry.h"
#include "mbest/core/median.h"

namespace mbest {

namespace {

// The pixel `reach` px along branch end `e` from its node (or the branch's far end).
cv::Point2f along(const Branch& b, int side, double reach) {
  const int n = static_cast<int>(b.pixels.size());
  const int k = std::min(n - 1, static_cast<int>(reach));
  return cv::Point2f(side == 0 ? b.pixels[k] : b.pixels[n - 1 - k]);
}

// Is the short branch `i` (end side `end_side`) the stub of a DLO that ends just past a
// crossing rather than a split end? Then its junction is a crossing (four or more
// branches) and the stub runs straight on from another branch there; split ends sprout
// sideways from a DLO's body or fork at its end.
bool is_stub_past_crossing(const SkeletonGraph& g, int i, int end_side, double reach) {
  const Branch& b = g.branches[i];
  const Node& junction = g.nodes[b.node[1 - end_side]];
  if (junction.degree() < 4 || b.pixels.empty()) return false;
  const cv::Point2f c = junction.centre;
  const cv::Point2f stub = unit(cv::Point2f(g.nodes[b.node[end_side]].pixels.front()) - c);
  for (const BranchEnd& e : junction.branch_ends) {
    const Branch& other = g.branches[e.branch];
    if (e.branch == i || !other.alive || other.pixels.empty()) continue;
    const cv::Point2f out = unit(along(other, e.side, reach) - c);
    if (stub.dot(-out) > std::cos(35.0 * M_PI / 180)) return true;
  }
  return false;
}

// Is the short branch `i` where two DLOs meet rather than a split end? A split end forks
// off one DLO, so every branch at its junction has that DLO's colour. Where two of them
// differ (colour_penalty > 0) the short branch is a real end: of a DLO lying on another
// (the others differ), or of one ending just past a crossing (the branch itself differs;
// sampled over its outer half, away from the DLO it crosses). Either way a DLO runs on
// through the junction: two of its other branches are not spurs (shorter than `delta`). A
// junction with one such branch is a DLO's forked tip, whose prongs sample the tip's dark,
// shaded edge: their colour tells nothing.
bool joins_two_colours(const SkeletonGraph& g, int i, int end_side, double delta,
                       const ColourSource& colour) {
  if (colour.bgr.empty()) return false;
  const Branch& spur = g.branches[i];
  const Node& junction = g.nodes[spur.node[1 - end_side]];
  int through = 0;
  for (const BranchEnd& e : junction.branch_ends)
    through += e.branch != i && g.branches[e.branch].alive && !is_spur(g, e.branch, delta);
  if (through < 2) return false;
  std::vector<BranchTangent> sampled;
  const BranchEnd tip{i, end_side};
  sampled.push_back(fit_branch_tangent(g, tip, 0, 3 * colour.radius, false));
  sample_branch_colour(g, tip, colour.bgr, &sampled.back(),
                       std::max(1, static_cast<int>(spur.pixels.size()) / 2));
  for (const BranchEnd& e : junction.branch_ends) {
    const Branch& other = g.branches[e.branch];
    if (e.branch == i || !other.alive) continue;
    const bool shared = g.nodes[other.node[1 - e.side]].kind == Node::Kind::junction;
    sampled.push_back(fit_branch_tangent(g, e, colour.radius, 3 * colour.radius, shared));
    sample_branch_colour(g, e, colour.bgr, &sampled.back(),
                         static_cast<int>(std::lround(kColourStretchFits * 3 * colour.radius)));
  }
  // A thin prong of a forked tip is mostly the tip's shaded edge: its own colour counts
  // only when it is about as wide as the branches it leaves.
  float widest = 0;
  for (size_t k = 1; k < sampled.size(); ++k) widest = std::max(widest, sampled[k].radius);
  const size_t from = sampled[0].radius >= 0.6f * widest ? 0 : 1;
  for (size_t a = from; a < sampled.size(); ++a)
    for (size_t b = a + 1; b < sampled.size(); ++b)
      if (colour_penalty(sampled[a], sampled[b]) > 0) return true;
  return false;
}

}  // namespace

bool is_spur(const SkeletonGraph& g, int i, double delta) {
  const Branch& b = g.branches[i];
  if (!b.alive || b.length >= delta) return false;
  return (g.nodes[b.node[0]].kind == Node::Kind::end) != (g.nodes[b.node[1]].kind == Node::Kind::end);
}

int prune_split_ends(SkeletonGraph& g, double delta, cv::Size image, const ColourSource& colour) {
  std::vector<int> spurs;
  for (int i = 0; i < static_cast<int>(g.branches.size()); ++i)
    if (is_spur(g, i, delta)) spurs.push_back(i);
  std::stable_sort(spurs.begin(), spurs.end(),
                   [&](int a, int b) { return g.branches[a].length < g.branches[b].length; });

  int removed = 0;
  for (int i : spurs) {
    Branch& b = g.branches[i];
    const int end_side = g.nodes[b.node[0]].kind == Node::Kind::end ? 0 : 1;
    if (leaves_image(g, b, end_side, image) || is_stub_past_crossing(g, i, end_side, delta) ||
        joins_two_colours(g, i, end_side, delta, colour))
      continue;
    Node& junction = g.nodes[b.node[1 - end_side]];
    if (junction.degree() < 3) continue;  // would cut a line in two
    b.alive = false;
    g.nodes[b.node[end_side]].alive = false;
    auto& ends = junction.branch_ends;
    ends.erase(std::remove(ends.begin(), ends.end(), BranchEnd{i, 1 - end_side}), ends.end());
    ++removed;
  }
  return removed;
}

namespace {

// The turn of a branch at its pixels [s, e]: the cosine between the chords `k` px before s
// and after e when the arms before those chords run straight into them (within 30 degrees
// between the chords from 2 k to k px and from k px to the pixel); 2 (no turn) if they do
// not. Near a junction the chords shrink to what the arm allows, down to `k_min` px.
class BranchTurn {
 public:
  BranchTurn(const std::vector<cv::Point>& px, int k) : px_(px), n_(static_cast<int>(px.size())), k_(k) {}
  int k() const { return k_; }
  int k_min() const { return std::max(2, k_ / 2); }
  int chord_before(int s) const { return std::min(k_, s / 2); }
  int chord_after(int e) const { return std::min(k_, (n_ - 1 - e) / 2); }
  double cosine(int s, int e) const {
    const float straight_arm = std::cos(static_cast<float>(M_PI) / 6);
    const int kb = chord_before(s), ka = chord_after(e);
    if (kb < k_min() || ka < k_min()) return 2;
    const cv::Point2f before = unit(cv::Point2f(px_[s] - px_[s - kb])), after = unit(cv::Point2f(px_[e + ka] - px_[e]));
    if (unit(cv::Point2f(px_[s - kb] - px_[s - 2 * kb])).dot(before) < straight_arm ||
        unit(cv::Point2f(px_[e + 2 * ka] - px_[e + ka])).dot(after) < straight_arm)
      return 2;
    return before.dot(after);
  }

 private:
  const std::vector<cv::Point>& px_;
  int n_, k_;
};

// Does a turn of cosine `cosine` fold back with more bending energy than `fold_energy`
// (that of a turn at a point, 8 tan^2(turn / 4))?
bool folds(double cosine, double fold_energy) {
  if (cosine > 1) return false;
  const double quarter_turn = std::acos(std::clamp(cosine, -1.0, 1.0)) / 4;
  return 8 * std::tan(quarter_turn) * std::tan(quarter_turn) > fold_energy;
}

// Cuts branch `bi` at its pixels [tip, last]: pixels [0, tip - 1) stay with the branch,
// which now ends at pixel tip - 1; pixels tip - 1 and last + 1 become ends, pixels tip to
// last are dropped; [last + 2, n) is a new branch from the end at last + 1 to the old far
// node.
void cut_branch(SkeletonGraph& g, int bi, int tip, int last) {
  const std::vector<cv::Point>& px = g.branches[bi].pixels;
  const std::vector<float>& radius = g.branches[bi].radius;
  const int first_end = static_cast<int>(g.nodes.size()), second_end = first_end + 1;
  const int second = static_cast<int>(g.branches.size());
  for (cv::Point at : {px[tip - 1], px[last + 1]}) {
    Node e;
    e.kind = Node::Kind::end;
    e.pixels = {at};
    e.centre = cv::Point2f(at);
    g.nodes.push_back(e);
  }
  Branch tail;
  tail.pixels.assign(px.begin() + last + 2, px.end());
  if (!radius.empty()) tail.radius.assign(radius.begin() + last + 2, radius.end());
  tail.node[0] = second_end;
  tail.node[1] = g.branches[bi].node[1];
  Branch& head = g.branches[bi];
  head.pixels.resize(tip - 1);
  if (!head.radius.empty()) head.radius.resize(tip - 1);
  for (BranchEnd& e : g.nodes[head.node[1]].branch_ends)
    if (e == BranchEnd{bi, 1}) e = {second, 1};
  head.node[1] = first_end;
  for (Branch* b : {&head, &tail}) b->length = branch_length(b->pixels);
  g.nodes[first_end].branch_ends = {{bi, 1}};
  g.nodes[second_end].branch_ends = {{second, 0}};
  g.branches.push_back(std::move(tail));
}

}  // namespace

int cut_folds_at_border(SkeletonGraph& g, double reach, cv::Size image, double fold_energy) {
  int cuts = 0;
  for (size_t bi = 0, n_branches = g.branches.size(); bi < n_branches; ++bi) {
    if (!g.branches[bi].alive) continue;
    const std::vector<cv::Point>& px = g.branches[bi].pixels;
    const std::vector<float>& radius = g.branches[bi].radius;
    const int n = static_cast<int>(px.size());
    const BranchTurn turn(px, std::max(2, static_cast<int>(reach)));
    const int k = turn.k(), k_min = turn.k_min();
    // Within the radius (plus `slack`) of the border. Thinning leaves a V's tip a pixel
    // further from some borders than from others: a single tip pixel gets one pixel more
    // than a stretch along the border, which would otherwise take in the whole apex of a
    // hairpin grazing the border.
    const auto near_border = [&](int i, float slack) {
      return distance_to_border(px[i], image) <= (radius.empty() ? 1.0f : radius[i]) + slack;
    };
    constexpr float kTipSlack = 2.5f, kStretchSlack = 1.5f;
    int tip = -1;
    double sharpest = 2;  // cosine of the turn: -1 is a full turn back
    for (int i = 2 * k_min; i + 2 * k_min < n; ++i) {
      if (!near_border(i, kTipSlack)) continue;
      const double c = turn.cosine(i, i);
      if (c < sharpest) tip = i, sharpest = c;
    }
    // Where the two leave the image a little apart, thinning runs the branch along the
    // border between them, and the turn is split between the two ends of that stretch, each
    // too gentle alone. A stretch of up to 4 reach px along the border is cut whole when it
    // turns as sharply as one pixel would, and three times as much as its arms, bending at
    // the rate they do, would over its length: a loop or a bend that leaves the image and
    // comes back turns at the border no faster than next to it.
    int last = tip;
    if (!folds(sharpest, fold_energy)) {
      const auto angle = [](cv::Point2f a, cv::Point2f b) {
        return std::acos(std::clamp(static_cast<double>(unit(a).dot(unit(b))), -1.0, 1.0));
      };
      tip = -1;
      sharpest = 2;
      for (int i = 2 * k_min; i + 2 * k_min < n; ++i) {
        if (!near_border(i, kStretchSlack)) continue;
        int e = i;
        while (e + 1 + 2 * k_min < n && near_border(e + 1, kStretchSlack)) ++e;
        const int kb = turn.chord_before(i), ka = turn.chord_after(e);
        if (e > i && e - i <= 4 * k && kb >= k_min && ka >= k_min) {
          const double c = turn.cosine(i, e);
          const double arm_rate =
              std::max(angle(px[i - kb] - px[i - 2 * kb], px[i] - px[i - kb]) / kb,
                       angle(px[e + 2 * ka] - px[e + ka], px[e + ka] - px[e]) / ka);
          if (c < sharpest && std::acos(std::min(c, 1.0)) > 3 * arm_rate * (k + e - i))
            tip = i, last = e, sharpest = c;
        }
        i = e;
      }
      if (!folds(sharpest, fold_energy)) continue;
    }
    cut_branch(g, static_cast<int>(bi), tip, last);
    ++cuts;
  }
  return cuts;
}

int cut_folds_between_colours(SkeletonGraph& g, double reach, const ColourSource& colour, double fold_energy) {
  if (colour.bgr.empty()) return 0;
  // The cosine of the turn whose energy is fold_energy (folds: 8 tan^2(turn / 4)).
  const double fold_cosine = std::cos(4 * std::atan(std::sqrt(fold_energy / 8)));
  const bool acute_fold = fold_cosine > -1e-3;  // a fold of 90 degrees or less
  constexpr int64_t kScale = 1 << 16;
  const double bound = std::max(0.0, fold_cosine + 1e-3);
  const int64_t bound_scaled = static_cast<int64_t>(std::ceil(bound * bound * kScale));
  int cuts = 0;
  for (size_t bi = 0, n_branches = g.branches.size(); bi < n_branches; ++bi) {
    if (!g.branches[bi].alive) continue;
    const std::vector<cv::Point>& px = g.branches[bi].pixels;
    const int n = static_cast<int>(px.size());
    const BranchTurn turn(px, std::max(2, static_cast<int>(reach)));
    const int k_min = turn.k_min();
    int tip = -1;
    double sharpest = 2;
    for (int i = 2 * k_min; i + 2 * k_min < n; ++i) {
      // Every pixel of every branch is looked at: first, in integers, whether the chords
      // turn as far as a fold at all (a turn past 90 degrees, or past `fold_cosine` plus a
      // little, for rounding, when that is smaller).
      const cv::Point before = px[i] - px[i - turn.chord_before(i)], after = px[i + turn.chord_after(i)] - px[i];
      const int dot = before.dot(after);
      if (dot >= 0 && (!acute_fold || static_cast<int64_t>(dot) * dot * kScale >=
                                          bound_scaled * before.dot(before) * after.dot(after)))
        continue;
      const double c = turn.cosine(i, i);
      if (c < sharpest) tip = i, sharpest = c;
    }
    if (!folds(sharpest, fold_energy)) continue;
    // Each arm's colour over its chord's stretch, [tip - 2 kb, tip - kb] and
    // [tip + ka, tip + 2 ka]: clear of the tips, whose pixels blend where they touch.
    const int kb = turn.chord_before(tip), ka = turn.chord_after(tip);
    const Branch& b = g.branches[bi];
    const float radius = b.radius.empty() ? static_cast<float>(colour.radius) : middle_value(b.radius);
    BranchTangent before, after;
    for (BranchTangent* t : {&before, &after}) t->radius = radius;
    before.cut = tip - 2 * kb, before.reach = tip - kb;
    after.cut = n - 1 - (tip + 2 * ka), after.reach = n - 1 - (tip + ka);
    sample_branch_colour(g, {static_cast<int>(bi), 0}, colour.bgr, &before, kb);
    sample_branch_colour(g, {static_cast<int>(bi), 1}, colour.bgr, &after, ka);
    if (colour_penalty(before, after) < kColourPenaltyMax) continue;
    cut_branch(g, static_cast<int>(bi), tip, tip);
    ++cuts;
  }
  return cuts;
}

}  // namespace mbest

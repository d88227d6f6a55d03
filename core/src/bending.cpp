#include "mbest/core/bending.h"

#include "mbest/core/geometry.h"
#include "mbest/core/median.h"
#include "mbest/core/prune.h"
#include "mbest/core/union_find.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <functional>
#include <map>
#include <queue>

#include <opencv2/imgproc.hpp>


namespace mbest {
namespace {

// The least-cost pairing of up to 32 exits by branch and bound: the lowest exit not yet
// paired is paired with each other in order of cost (or left unpaired, once, for an odd
// count), and a branch is cut when its cost plus half the cheapest pair of every exit left
// cannot beat the best pairing found. The first pairing found is the greedy one (each exit
// with its cheapest partner left), so after kMaxPairingSearch steps the best so far is
// kept: a bound on the time a tangle of many exits may take.
class PairingSearch {
 public:
  explicit PairingSearch(const std::vector<std::vector<double>>& e)
      : e_(e), by_cost_(e.size()), half_cheapest_(e.size(), 0) {
    const int n = static_cast<int>(e.size());
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j)
        if (j != i) by_cost_[i].push_back(j);
      std::sort(by_cost_[i].begin(), by_cost_[i].end(), [&](int a, int b) { return e[i][a] < e[i][b]; });
      if (!by_cost_[i].empty()) half_cheapest_[i] = 0.5 * e[i][by_cost_[i][0]];
    }
    const uint32_t all = n == 32 ? ~0u : (1u << n) - 1;
    run(all, n % 2, 0);
  }
  const std::vector<std::pair<int, int>>& best() const { return best_; }

 private:
  static constexpr long kMaxPairingSearch = 50000;

  void run(uint32_t left, int singles, double cost) {
    if (++steps_ > kMaxPairingSearch && !best_.empty()) return;
    if (!left) {
      if (cost < best_cost_) best_cost_ = cost, best_ = pairs_;
      return;
    }
    double bound = cost, dearest = 0;
    for (uint32_t m = left; m; m &= m - 1) {
      const double h = half_cheapest_[__builtin_ctz(m)];
      bound += h;
      dearest = std::max(dearest, h);
    }
    if (singles) bound -= dearest;  // the one left unpaired pays nothing
    if (bound >= best_cost_) return;
    const int i = __builtin_ctz(left);
    const uint32_t rest = left & ~(1u << i);
    for (int j : by_cost_[i]) {
      if (!(rest >> j & 1)) continue;
      pairs_.emplace_back(i, j);
      run(rest & ~(1u << j), singles, cost + e_[i][j]);
      pairs_.pop_back();
    }
    if (singles) run(rest, singles - 1, cost);
  }

  const std::vector<std::vector<double>>& e_;
  std::vector<std::vector<int>> by_cost_;  // per exit, the others, cheapest first
  std::vector<double> half_cheapest_;
  double best_cost_ = std::numeric_limits<double>::infinity();
  std::vector<std::pair<int, int>> pairs_, best_;
  long steps_ = 0;
};

// For each graph node, the index of the region holding it (-1: none).
std::vector<int> region_of_nodes(const SkeletonGraph& g, const std::vector<CrossingRegion>& regions) {
  std::vector<int> region_of(g.nodes.size(), -1);
  for (int r = 0; r < static_cast<int>(regions.size()); ++r)
    for (int n : regions[r].nodes) region_of[n] = r;
  return region_of;
}

// The exits of `regions` joined through their `links` branches: each region's in turn,
// without the links'.
std::vector<BranchEnd> exits_but(std::initializer_list<const CrossingRegion*> regions,
                                 const std::vector<int>& links) {
  std::vector<BranchEnd> exits;
  for (const CrossingRegion* r : regions)
    for (const BranchEnd& e : r->exits)
      if (std::find(links.begin(), links.end(), e.branch) == links.end()) exits.push_back(e);
  return exits;
}

// Makes branch `link` part of the inside of region `a` (marked dead).
void make_inner(SkeletonGraph& g, CrossingRegion& a, int link) {
  a.inner_branches.push_back(link);
  g.branches[link].alive = false;
}

// Makes region `c` part of region `a` through their `link` branch (made inner): `a` takes
// c's nodes and inner branches, `exits` and the mean centre of all its nodes.
void absorb_region(SkeletonGraph& g, CrossingRegion& a, const CrossingRegion& c, int link,
                   std::vector<BranchEnd> exits) {
  a.nodes.insert(a.nodes.end(), c.nodes.begin(), c.nodes.end());
  a.inner_branches.insert(a.inner_branches.end(), c.inner_branches.begin(), c.inner_branches.end());
  make_inner(g, a, link);
  a.exits = std::move(exits);
  cv::Point2f centre(0, 0);
  for (int n : a.nodes) centre += g.nodes[n].centre;
  a.centre = centre * (1.0f / static_cast<float>(a.nodes.size()));
}

// Makes each region gone[k] part of region `keep` through its link links[k], in turn, and
// the branches `beside` (further links between the same regions) inner too; `exits` are
// those of the whole merge, set by the last absorb.
void absorb_regions(SkeletonGraph& g, CrossingRegion& keep, const std::vector<CrossingRegion>& regions,
                    const std::vector<int>& gone, const std::vector<int>& links,
                    std::vector<BranchEnd> exits, const std::vector<int>& beside = {}) {
  for (size_t k = 0; k < gone.size(); ++k)
    absorb_region(g, keep, regions[gone[k]], links[k],
                  k + 1 == gone.size() ? std::move(exits) : std::vector<BranchEnd>());
  for (int link : beside) make_inner(g, keep, link);
}

// The tangent at point(first) of the chain point(first..last) (unit, pointing along it):
// the derivative at arc length 0 of the least-squares quadratics x(s), y(s). Zero when the
// normal equations are singular.
template <class Point>
cv::Point2f quadratic_tangent(Point point, int first, int last) {
  double S[5] = {0, 0, 0, 0, 0}, X[3] = {0, 0, 0}, Y[3] = {0, 0, 0}, s = 0;
  const cv::Point origin = point(first);
  for (int i = first; i <= last; ++i) {
    const cv::Point p = point(i);
    if (i > first) s += std::hypot(p.x - point(i - 1).x, p.y - point(i - 1).y);
    const double dx = p.x - origin.x, dy = p.y - origin.y;
    double power = 1;
    for (double& sk : S) sk += power, power *= s;
    X[0] += dx, X[1] += dx * s, X[2] += dx * s * s;
    Y[0] += dy, Y[1] += dy * s, Y[2] += dy * s * s;
  }
  const cv::Matx33d normal(S[0], S[1], S[2], S[1], S[2], S[3], S[2], S[3], S[4]);
  const double det = cv::determinant(normal);
  if (!(std::abs(det) > 1e-9)) return {0, 0};
  const cv::Matx33d inverse = normal.inv(cv::DECOMP_LU);
  const cv::Vec3d ax = inverse * cv::Vec3d(X[0], X[1], X[2]), ay = inverse * cv::Vec3d(Y[0], Y[1], Y[2]);
  return unit(cv::Point2f(static_cast<float>(ax[1]), static_cast<float>(ay[1])));
}

}  // namespace

BranchTangent fit_branch_tangent(const SkeletonGraph& g, BranchEnd end, double cut_length,
                                 double fit_length, bool shared) {
  const Branch& b = g.branches[end.branch];
  const int n = static_cast<int>(b.pixels.size());
  auto px = [&](int i) { return end.side == 0 ? b.pixels[i] : b.pixels[n - 1 - i]; };
  auto rad = [&](int i) { return end.side == 0 ? b.radius[i] : b.radius[n - 1 - i]; };

  BranchTangent t;
  const cv::Point2f node_centre = g.nodes[b.node[end.side]].centre;
  if (n == 0) {
    const cv::Point2f other = g.nodes[b.node[1 - end.side]].centre;
    t.point = node_centre;
    t.direction = t.path_direction = unit(other - node_centre);
    return t;
  }
  const int usable = shared ? std::max(1, n / 2) : n;
  const int cut = std::min(static_cast<int>(std::lround(cut_length)), usable - 1);
  const int last = std::min(usable - 1, cut + std::max(2, static_cast<int>(std::lround(fit_length))));
  t.cut = cut;
  t.last = last;
  t.reach = usable - 1;
  t.point = cv::Point2f(px(cut));

  // Total least squares line through px(cut..last).
  double mx = 0, my = 0;
  const int m = last - cut + 1;
  for (int i = cut; i <= last; ++i) {
    mx += px(i).x;
    my += px(i).y;
  }
  mx /= m;
  my /= m;
  double sxx = 0, sxy = 0, syy = 0;
  for (int i = cut; i <= last; ++i) {
    const double dx = px(i).x - mx, dy = px(i).y - my;
    sxx += dx * dx;
    sxy += dx * dy;
    syy += dy * dy;
  }
  const double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);
  cv::Point2f dir(static_cast<float>(std::cos(angle)), static_cast<float>(std::sin(angle)));
  // Orient away from the crossing: along the chain from its first to its last fitted pixel,
  // or, for a stretch too short to say, from the junction to the attachment point.
  cv::Point2f along = cv::Point2f(px(last)) - cv::Point2f(px(cut));
  if (m < 3 || along.dot(along) < 4) along = cv::Point2f(px(last)) - node_centre;
  if (dir.dot(along) < 0) dir = -dir;
  if (m < 2 || sxx + syy == 0) dir = unit(along);
  t.direction = dir;

  // A quadratic needs the longer stretch to be steady: on a branch too short for it (a stub
  // at the image border), the line.
  t.path_direction = dir;
  const int curve_last = cut + 2 * std::max(2, static_cast<int>(std::lround(fit_length)));
  if (curve_last <= usable - 1) {
    const cv::Point2f curved = quadratic_tangent(px, cut, curve_last);
    if (curved.dot(dir) > 0.5f) t.path_direction = curved;
  }

  std::vector<float> r;
  for (int i = cut; i <= last; ++i) r.push_back(rad(i));
  t.radius = middle_value(r);
  return t;
}

namespace {

// The middle value of 8-bit samples, by counting (the samples of one exit number hundreds).
uint8_t middle_byte(const std::array<int, 256>& histogram, int count) {
  int seen = 0;
  for (int v = 0; v < 256; ++v)
    if ((seen += histogram[v]) > count / 2) return static_cast<uint8_t>(v);
  return 255;
}

}  // namespace

void sample_branch_colour(const SkeletonGraph& g, BranchEnd end, const cv::Mat& bgr,
                          BranchTangent* t, int stretch) {
  const Branch& b = g.branches[end.branch];
  const int n = static_cast<int>(b.pixels.size());
  if (bgr.empty() || n == 0) return;
  auto px = [&](int i) {
    i = std::clamp(i, 0, n - 1);
    return cv::Point2f(end.side == 0 ? b.pixels[i] : b.pixels[n - 1 - i]);
  };
  const int first = t->cut, last = std::min({t->reach, first + stretch, n - 1});
  const float offset = 0.5f * t->radius;
  // Addresses first, then the reads: the image is large and cold, and issuing every load
  // before using any lets the memory system fetch them in parallel.
  std::vector<const uint8_t*> at;
  at.reserve(3 * (last - first + 1));
  for (int i = first; i <= last; ++i) {
    const cv::Point2f along = px(i + 2) - px(i - 2);
    const float norm = std::hypot(along.x, along.y);
    const cv::Point2f normal = norm > 0 ? cv::Point2f(-along.y, along.x) * (1 / norm)
                                        : cv::Point2f(-t->direction.y, t->direction.x);
    for (const float s : {-offset, 0.f, offset}) {
      const cv::Point2f q = px(i) + normal * s;
      const int x = cvRound(q.x), y = cvRound(q.y);
      if (x < 0 || y < 0 || x >= bgr.cols || y >= bgr.rows) continue;
      at.push_back(bgr.ptr<uint8_t>(y) + 3 * x);
      __builtin_prefetch(at.back());
    }
  }
  const int count = static_cast<int>(at.size());
  if (count == 0) return;
  cv::Mat samples(1, count, CV_8UC3), lab;
  for (int k = 0; k < count; ++k)
    samples.at<cv::Vec3b>(0, k) = cv::Vec3b(at[k][0], at[k][1], at[k][2]);
  // Per sample, so that highlights and shading are outvoted in the space compared.
  cv::cvtColor(samples, lab, cv::COLOR_BGR2Lab);  // 8-bit: L * 255 / 100, a + 128, b + 128
  std::array<std::array<int, 256>, 3> histogram{};
  for (int k = 0; k < count; ++k)
    for (int c = 0; c < 3; ++c) ++histogram[c][lab.at<cv::Vec3b>(0, k)[c]];
  t->colour = cv::Vec3f(middle_byte(histogram[0], count) * 100.0f / 255,
                        middle_byte(histogram[1], count) - 128.0f,
                        middle_byte(histogram[2], count) - 128.0f);
  t->has_colour = true;
}

double colour_distance(const cv::Vec3f& a, const cv::Vec3f& b, float lightness) {
  return std::sqrt(static_cast<double>(colour_distance_squared(a, b, lightness)));
}

double colour_penalty(const BranchTangent& a, const BranchTangent& b, float lightness) {
  if (!a.has_colour || !b.has_colour) return 0;
  const double distance = colour_distance(a.colour, b.colour, lightness);
  const double excess = (distance - kColourTolerance) / (2 * kColourTolerance);
  return kColourPenaltyMax * std::clamp(excess, 0.0, 1.0);
}

double discrete_curvature(cv::Point2f t1, cv::Point2f t2) {
  const double cross = std::abs(static_cast<double>(t1.x) * t2.y - static_cast<double>(t1.y) * t2.x);
  const double dot = static_cast<double>(t1.x) * t2.x + static_cast<double>(t1.y) * t2.y;
  // 2 sin(phi) / (1 + cos(phi)) = 2 tan(phi / 2), written with the turning angle phi so
  // that a full turn back (cross = 0, dot = -1) is the largest value, not 0 / 0.
  const double phi = std::min(std::atan2(cross, dot), M_PI - 1e-4);
  return 2 * std::tan(phi / 2);
}

double bending_energy(const BranchTangent& in, const BranchTangent& out) {
  const cv::Point2f t_in = -in.direction;  // travelling into the crossing
  const cv::Point2f t_out = out.direction;
  cv::Point2f chord = out.point - in.point;
  if (chord.dot(chord) < 1e-6) chord = t_in + t_out;
  const cv::Point2f t_mid = unit(chord);
  const double k1 = discrete_curvature(t_in, t_mid), k2 = discrete_curvature(t_mid, t_out);
  return k1 * k1 + k2 * k2;
}

double width_penalty(const BranchTangent& a, const BranchTangent& b) {
  if (!(a.radius > 0) || !(b.radius > 0)) return 0;
  const double ratio = std::max(a.radius, b.radius) / std::min(a.radius, b.radius);
  return ratio < kTwoStrandRatio ? std::max(0.0, ratio - kWidthTolerance) : 0.0;
}

double pair_cost(const BranchTangent& a, const BranchTangent& b, PairWeights weights) {
  double cost = 0.5 * (bending_energy(a, b) + bending_energy(b, a));
  if (weights.colour > 0) cost += weights.colour * colour_penalty(a, b, weights.lightness);
  if (weights.width > 0) cost += weights.width * width_penalty(a, b);
  return cost;
}

double pairing_cost(const std::vector<BranchTangent>& exits,
                    const std::vector<std::pair<int, int>>& pairs, PairWeights weights) {
  double cost = 0;
  for (const auto& [a, b] : pairs) cost += pair_cost(exits[a], exits[b], weights);
  return cost;
}

namespace {

// The least-cost pairing for the symmetric pair costs `e` (min_energy_pairing).
std::vector<std::pair<int, int>> least_cost_pairing(const std::vector<std::vector<double>>& e) {
  const int n = static_cast<int>(e.size());
  if (n <= kMaxExactExits) return PairingSearch(e).best();
  std::vector<std::pair<int, int>> best;
  std::vector<std::pair<double, std::pair<int, int>>> all;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) all.push_back({e[a][b], {a, b}});
  std::sort(all.begin(), all.end());
  std::vector<bool> used(n, false);
  for (const auto& [cost, p] : all)
    if (!used[p.first] && !used[p.second] && static_cast<int>(best.size()) < n / 2) {
      used[p.first] = used[p.second] = true;
      best.push_back(p);
    }
  return best;
}

}  // namespace

void add_loop_closing_costs(std::vector<std::vector<double>>& costs,
                            const std::vector<BranchTangent>& tangents,
                            const std::vector<BranchEnd>& exits, double weight) {
  if (weight <= 0) return;
  const size_t n = exits.size();
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 1; b < n; ++b) {
      if (exits[a].branch != exits[b].branch) continue;
      // Is the loop's colour (at end `end`) that of no other exit: a ring of its own?
      const auto unlike_the_rest = [&](size_t end) {
        for (size_t c = 0; c < n; ++c) {
          if (exits[c].branch == exits[end].branch || !tangents[c].has_colour) continue;
          const bool same_width = std::abs(tangents[end].radius - tangents[c].radius) <=
                                  std::max(kSameWidth * tangents[c].radius, kRadiusGrain);
          const double tolerance = (same_width ? kSameWidthColourTolerance : 1.0) * kColourTolerance;
          if (colour_distance(tangents[end].colour, tangents[c].colour) <= tolerance) return false;
        }
        return true;
      };
      // Where the region holds no more than the branch's two ends and two other exits (a
      // rod crossing itself), either end's colour matching another exit's says "the rod's
      // loop": a tight loop is lit unevenly, and one end may be a shade off.
      bool ring = tangents[a].has_colour && unlike_the_rest(a);
      if (ring && n <= 4 && tangents[b].has_colour) ring = unlike_the_rest(b);
      if (ring) continue;
      costs[a][b] += weight;
      costs[b][a] += weight;
    }
}

namespace {

std::vector<std::vector<double>> pair_cost_matrix(const std::vector<BranchTangent>& exits,
                                                  PairWeights weights) {
  const int n = static_cast<int>(exits.size());
  std::vector<std::vector<double>> e(n, std::vector<double>(n, 0));
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      e[a][b] = e[b][a] = pair_cost(exits[a], exits[b], weights);
  return e;
}

}  // namespace

std::vector<std::pair<int, int>> min_energy_pairing(const std::vector<BranchTangent>& exits,
                                                    PairWeights weights) {
  return least_cost_pairing(pair_cost_matrix(exits, weights));
}

std::vector<std::pair<int, int>> min_energy_pairing(const std::vector<BranchTangent>& exits,
                                                    const std::vector<BranchEnd>& ends,
                                                    PairWeights weights) {
  std::vector<std::vector<double>> e = pair_cost_matrix(exits, weights);
  add_loop_closing_costs(e, exits, ends, weights.loop);
  return least_cost_pairing(e);
}

}  // namespace mbest

namespace mbest {

namespace {

BranchTangent exit_tangent(const SkeletonGraph& g, BranchEnd e, const PairingSetup& s) {
  const Branch& b = g.branches[e.branch];
  const bool shared = g.nodes[b.node[1 - e.side]].kind == Node::Kind::junction;
  BranchTangent t = fit_branch_tangent(g, e, s.cut_length, s.fit_length, shared);
  if (s.weights.colour > 0)
    sample_branch_colour(g, e, s.bgr, &t,
                         static_cast<int>(std::lround(kColourStretchFits * s.fit_length)));
  return t;
}

}  // namespace

TangentCache::TangentCache(const SkeletonGraph& g, const PairingSetup& s)
    : graph_(g), setup_(s), tangents_(2 * g.branches.size()), done_(2 * g.branches.size(), false) {}

std::vector<BranchTangent> TangentCache::of(const std::vector<BranchEnd>& exits) {
  std::vector<BranchTangent> out;
  out.reserve(exits.size());
  for (const BranchEnd& e : exits) {
    const size_t k = 2 * static_cast<size_t>(e.branch) + e.side;
    if (!done_[k]) tangents_[k] = exit_tangent(graph_, e, setup_), done_[k] = true;
    out.push_back(tangents_[k]);
  }
  return out;
}

std::vector<std::vector<double>> TangentCache::pair_costs(const std::vector<BranchEnd>& exits) {
  const std::vector<BranchTangent> t = of(exits);
  const size_t n = exits.size();
  std::vector<std::vector<double>> e(n, std::vector<double>(n, 0));
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 1; b < n; ++b) {
      const uint64_t ka = 2 * static_cast<uint64_t>(exits[a].branch) + exits[a].side;
      const uint64_t kb = 2 * static_cast<uint64_t>(exits[b].branch) + exits[b].side;
      const uint64_t key = std::min(ka, kb) << 32 | std::max(ka, kb);
      auto known = pair_costs_.find(key);
      if (known == pair_costs_.end())
        known = pair_costs_.emplace(key, pair_cost(t[a], t[b], setup_.weights)).first;
      e[a][b] = e[b][a] = known->second;
    }
  add_loop_closing_costs(e, t, exits, setup_.weights.loop);
  return e;
}

double TangentCache::least_cost(const std::vector<BranchEnd>& exits) {
  std::vector<int> key;
  for (const BranchEnd& e : exits) key.push_back(2 * e.branch + e.side);
  std::sort(key.begin(), key.end());
  const auto known = least_costs_.find(key);
  if (known != least_costs_.end()) return known->second;
  const std::vector<std::vector<double>> e = pair_costs(exits);
  double cost = 0;
  for (const auto& [a, b] : least_cost_pairing(e)) cost += e[a][b];
  least_costs_.emplace(std::move(key), cost);
  return cost;
}

double TangentCache::least_cost_bound(const std::vector<BranchEnd>& exits) {
  const std::vector<std::vector<double>> e = pair_costs(exits);
  const size_t n = e.size();
  double sum = 0, dearest = 0;
  for (size_t i = 0; i < n; ++i) {
    double cheapest = n < 2 ? 0 : std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < n; ++j)
      if (j != i) cheapest = std::min(cheapest, e[i][j]);
    sum += cheapest;
    dearest = std::max(dearest, cheapest);
  }
  return 0.5 * (n % 2 ? sum - dearest : sum);
}

std::vector<BranchTangent> exit_tangents(const SkeletonGraph& g, const std::vector<BranchEnd>& exits,
                                         const PairingSetup& s) {
  std::vector<BranchTangent> tangents;
  for (const BranchEnd& e : exits) tangents.push_back(exit_tangent(g, e, s));
  return tangents;
}

namespace {

// At a Y where one strand ends, its end may lie along another strand: the mask shows the
// two side by side in one exit branch, wider than the others (kTwoStrandWidth), whose
// colour near the Y mixes both. Past the point where that branch narrows to one DLO's
// width, its colour is that of the strand running on, which is the one to pair it with.
// So a wide exit of a Y takes its colour from `cut_length` past that point (within 15 %
// of the wider other exit's radius), when a tangent fit's length of it is left there. That
// may read past the half of the branch an exit shared with another crossing otherwise keeps
// to: the side-by-side stretch often covers that half, and the median of the longer stretch
// still outvotes the far crossing's overlap.
void recolour_wide_exit(const SkeletonGraph& g, const std::vector<BranchEnd>& exits,
                        const PairingSetup& s, std::vector<BranchTangent>& t) {
  if (exits.size() != 3 || s.weights.colour <= 0 || s.bgr.empty()) return;
  for (int w = 0; w < 3; ++w) {
    const float others = std::max(t[(w + 1) % 3].radius, t[(w + 2) % 3].radius);
    if (!t[w].has_colour || !(t[w].radius >= kTwoStrandWidth * others)) continue;
    const Branch& b = g.branches[exits[w].branch];
    const int n = static_cast<int>(b.pixels.size());
    const auto radius = [&](int i) { return exits[w].side == 0 ? b.radius[i] : b.radius[n - 1 - i]; };
    int narrow = t[w].cut;
    while (narrow < n && radius(narrow) > 1.15f * others) ++narrow;
    BranchTangent far = t[w];
    far.cut = narrow + static_cast<int>(std::lround(s.cut_length));
    far.reach = n - 1;
    if (far.cut + static_cast<int>(std::lround(s.fit_length)) >= n) return;
    sample_branch_colour(g, exits[w], s.bgr, &far,
                         static_cast<int>(std::lround(kColourStretchFits * s.fit_length)));
    t[w].colour = far.colour;
    return;
  }
}

}  // namespace

// How strongly a re-routed passage keeps to the middle of the mask: a step at the mask's
// edge costs this much more than one a radius or more inside it (twice as much in all).
// Pairing failures over the nine seed sets with 2 px off allowed: 1 and 4 against 10
// differ by one to three crossings per bin; 1 did best on the held-out pair.
constexpr float kCentreWeight = 1.f;
// And how strongly it keeps near the Hermite curve it replaces, where the mask allows: a
// step two radii or more off the curve costs this much more, times two. Over the nine
// seed sets, `stress` pairing failures: 0 3239, 0.25 3197, 0.5 3211, 1 3267, 2 3280;
// outside `stress` 0 to 0.5 alike (one crossing either way), 1 and 2 lost what 0 mended.
constexpr float kCurveWeight = 0.25f;

std::vector<std::vector<double>> inner_route_bending(const SkeletonGraph& g, const CrossingRegion& region,
                                                     const std::vector<BranchTangent>& exits,
                                                     double cut_length, double fit_length) {
  const size_t n = region.exits.size();
  std::vector<std::vector<double>> route(n, std::vector<double>(n, std::numeric_limits<double>::infinity()));
  // Per node of the region, the inner branches leaving it: the node at their far end, their
  // tangent leaving this node and the direction a path along them arrives at the far one.
  // A path's state is the inner branch end it arrived by (the direction of travel matters,
  // so states are branch ends, not nodes), numbered from 0.
  struct Step {
    int arrival;  // the state a path along the branch reaches
    int far_node;
    cv::Point2f leave, arrive;
  };
  std::map<int, std::vector<Step>> steps_from;
  int states = 0;
  for (int b : region.inner_branches) {
    const Branch& branch = g.branches[b];
    if (branch.node[0] < 0 || branch.node[1] < 0 || branch.node[0] == branch.node[1]) continue;
    const cv::Point2f away[2] = {fit_branch_tangent(g, {b, 0}, cut_length, fit_length, true).direction,
                                 fit_branch_tangent(g, {b, 1}, cut_length, fit_length, true).direction};
    for (int side = 0; side < 2; ++side)
      steps_from[branch.node[side]].push_back({states + 1 - side, branch.node[1 - side], away[side], -away[1 - side]});
    states += 2;
  }
  std::vector<int> node_of(n);
  std::map<int, std::vector<int>> exits_at;
  for (size_t i = 0; i < n; ++i) {
    node_of[i] = g.branches[region.exits[i].branch].node[region.exits[i].side];
    exits_at[node_of[i]].push_back(static_cast<int>(i));
  }
  const auto turn = [](cv::Point2f from, cv::Point2f to) {
    const double k = discrete_curvature(from, to);
    return k * k;
  };
  // From each exit, Dijkstra's search over the states.
  struct Open {
    double cost;
    int node;
    cv::Point2f travel;
    int arrival;  // -1: the start, entering from the exit
    bool operator>(const Open& o) const { return cost > o.cost; }
  };
  for (size_t i = 0; i < n; ++i) {
    std::vector<char> settled(states, 0);
    std::priority_queue<Open, std::vector<Open>, std::greater<Open>> open;
    open.push({0, node_of[i], -exits[i].direction, -1});
    while (!open.empty()) {
      const Open s = open.top();
      open.pop();
      if (s.arrival >= 0) {
        if (settled[s.arrival]) continue;
        settled[s.arrival] = 1;
        const auto there = exits_at.find(s.node);
        if (s.node != node_of[i] && there != exits_at.end())
          for (int j : there->second)
            route[i][j] = std::min(route[i][j], s.cost + turn(s.travel, exits[j].direction));
      }
      const auto from = steps_from.find(s.node);
      if (from == steps_from.end()) continue;
      for (const Step& step : from->second)
        if (!settled[step.arrival])
          open.push({s.cost + turn(s.travel, step.leave) + turn(step.leave, step.arrive), step.far_node,
                     step.arrive, step.arrival});
    }
  }
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) route[i][j] = route[j][i] = std::min(route[i][j], route[j][i]);
  return route;
}

// Regions up to this many exits are paired along their inside (RouteCosts): the clusters it
// mends on generated scenes hold 6 (a rod through a loop) to a few tens; a region of
// hundreds is a mask the detector cannot read (a textured background segmented as
// foreground), where the search, one per exit, only costs time.
constexpr int kMaxRouteExits = 64;
// Regions from this many exits are clusters of strands lying along each other, where the
// route was first used (and tuned) also between a loop's two ends.
constexpr size_t kClusterExits = 10;

namespace {

// Is a point at angle `x` on the arc from angle `from` counter-clockwise to `to`?
bool on_arc(float from, float to, float x) {
  const float turn = 2 * static_cast<float>(M_PI);
  return std::fmod(x - from + 2 * turn, turn) < std::fmod(to - from + 2 * turn, turn);
}

// Do the segments ab and cd cross (each one's ends on the two sides of the other's line)?
bool segments_cross(cv::Point2f a, cv::Point2f b, cv::Point2f c, cv::Point2f d) {
  const auto side = [](cv::Point2f p, cv::Point2f q, cv::Point2f x) { return (q - p).cross(x - p); };
  return side(a, b, c) * side(a, b, d) < 0 && side(c, d, a) * side(c, d, b) < 0;
}

// The least-cost pairing of a region holding a loop's two ends may join them to their two
// partners (exits of other branches, about as wide as the loop) without crossing (an omega:
// the rod runs into the loop and out of it on the same side, the loop touching its neck). A
// rod that makes a loop crosses itself there, and on a tight loop the exits' fitted tangents
// bend with the loop, so the two pairings cost about the same. The crossing one (the pairs'
// exits interleaved round the region's centre) is taken when it costs at most `margin` more.
// Where other strands cross there too (more than four exits: a loop closing on another rod),
// only if the four exits are alike in colour and no other exit is of their colour: a second
// strand of the rod's colour there may be the rod itself (it passes through its loop) or a
// like rod, whose pairing the swap would not weigh.
void prefer_loop_crossing(const CrossingRegion& region, const std::vector<BranchTangent>& t,
                          const PairWeights& weights, double margin, std::vector<std::pair<int, int>>& pairing) {
  const int n = static_cast<int>(region.exits.size());
  if (n < 4 || margin <= 0) return;
  int la = -1, lb = -1;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      if (region.exits[a].branch == region.exits[b].branch) la = a, lb = b;
  if (la < 0) return;
  int pa = -1, pb = -1;  // la's partner, lb's
  for (const auto& [i, j] : pairing) {
    if (i == la || j == la) pa = i == la ? j : i;
    if (i == lb || j == lb) pb = i == lb ? j : i;
  }
  if (pa < 0 || pb < 0 || pa == lb) return;  // pa == lb: the loop closed on itself, a ring
  if (region.exits[pa].branch == region.exits[pb].branch) return;
  const float loop_radius = 0.5f * (t[la].radius + t[lb].radius);
  for (int k : {pa, pb})
    if (t[k].radius > 1.5f * loop_radius || 1.5f * t[k].radius < loop_radius) return;
  const auto angle = [&](int k) {
    const cv::Point2f d = t[k].point - region.centre;
    return std::atan2(d.y, d.x);
  };
  if (on_arc(angle(la), angle(pa), angle(lb)) != on_arc(angle(la), angle(pa), angle(pb))) return;  // crosses
  const double now = pair_cost(t[la], t[pa], weights) + pair_cost(t[lb], t[pb], weights);
  const double crossing = pair_cost(t[la], t[pb], weights) + pair_cost(t[lb], t[pa], weights);
  if (crossing > now + margin) return;
  if (n > 4) {
    // A long region's exits round its centre need not say which pairs cross: the chords do.
    if (segments_cross(t[la].point, t[pa].point, t[lb].point, t[pb].point) ||
        !segments_cross(t[la].point, t[pb].point, t[lb].point, t[pa].point))
      return;
    if (colour_penalty(t[la], t[pb]) > 0 || colour_penalty(t[lb], t[pa]) > 0) return;
    for (int k = 0; k < n; ++k)
      if (k != la && k != lb && k != pa && k != pb &&
          (colour_penalty(t[la], t[k]) == 0 || colour_penalty(t[lb], t[k]) == 0))
        return;
  }
  for (auto& [i, j] : pairing) {
    if (i == la || j == la) i = la, j = pb;
    else if (i == lb || j == lb) i = lb, j = pa;
  }
}

}  // namespace

std::vector<Passage> build_passages(const std::vector<CrossingRegion>& regions, TangentCache& cache,
                                    double fold_energy, double unlike_energy, double unlike_fold_energy,
                                    RouteCosts route, double loop_cross_margin) {
  const PairWeights weights = cache.setup().weights;
  // The folds below are weighed by shape: bending energy, and width where it counts.
  const PairWeights shape{0, weights.width};
  // Two DLOs that end inside one crossing region: its least-cost pairing pairs every exit
  // it can, so their ends are joined unless their colours and the bend say otherwise.
  const auto unlike = [&](const BranchTangent& a, const BranchTangent& b, double energy) {
    return colour_penalty(a, b) >= kColourPenaltyMax && pair_cost(a, b, shape) >= energy;
  };
  // The crossing region an exit's strand reaches next (-1: it ends, or meets a junction of none).
  const SkeletonGraph& graph = cache.graph();
  const std::vector<int> region_of_node = region_of_nodes(graph, regions);
  const auto next_region = [&](const BranchEnd& e) {
    const int node = graph.branches[e.branch].node[1 - e.side];
    return node < 0 ? -1 : region_of_node[node];
  };
  std::vector<Passage> passages;
  for (int r = 0; r < static_cast<int>(regions.size()); ++r) {
    const CrossingRegion& region = regions[r];
    if (region.exits.size() < 2) continue;
    std::vector<BranchTangent> tangents = cache.of(region.exits);
    recolour_wide_exit(graph, region.exits, cache.setup(), tangents);
    if (tangents.size() == 2 && (pair_cost(tangents[0], tangents[1], shape) > fold_energy ||
                                 unlike(tangents[0], tangents[1], unlike_fold_energy)))
      continue;
    std::vector<std::pair<int, int>> pairing;
    if (route.min_exits > 0 && static_cast<int>(region.exits.size()) >= route.min_exits &&
        static_cast<int>(region.exits.size()) <= kMaxRouteExits && !region.inner_branches.empty()) {
      // A cluster: exits at two of its nodes pair at the lesser of their bending energy and
      // the weighted bending of the strand's route between them through the inner branches.
      PairWeights in_cluster = weights;
      in_cluster.lightness = route.lightness;
      std::vector<std::vector<double>> e = pair_cost_matrix(tangents, in_cluster);
      add_loop_closing_costs(e, tangents, region.exits, weights.loop);
      const std::vector<std::vector<double>> routed = inner_route_bending(
          graph, region, tangents, cache.setup().cut_length, cache.setup().fit_length);
      for (size_t a = 0; a < e.size(); ++a)
        for (size_t b = a + 1; b < e.size(); ++b) {
          if (!std::isfinite(routed[a][b])) continue;
          const double bend =
              0.5 * (bending_energy(tangents[a], tangents[b]) + bending_energy(tangents[b], tangents[a]));
          // A loop's two ends: the strand between them is the loop outside the region, so a
          // route inside it says nothing of their pairing (closing the loop, which
          // add_loop_closing_costs weighs). Kept in clusters, where it was tuned. Two exits
          // whose strands both run into one other region may be a loop through it too (a
          // rod crossing it there); the route then counts only where it bends less than the
          // exits' own pairing, not for its weight's discount alone.
          if (region.exits.size() < kClusterExits) {
            if (region.exits[a].branch == region.exits[b].branch) continue;
            const int next = next_region(region.exits[a]);
            if (next >= 0 && next != r && next == next_region(region.exits[b]) && routed[a][b] >= bend)
              continue;
          }
          const double saving = std::min(0.0, route.weight * routed[a][b] - bend);
          e[a][b] += saving;
          e[b][a] += saving;
        }
      pairing = least_cost_pairing(e);
    } else {
      pairing = min_energy_pairing(tangents, region.exits, weights);
    }
    prefer_loop_crossing(region, tangents, weights, loop_cross_margin, pairing);
    for (const auto& [i, j] : pairing) {
      if (unlike(tangents[i], tangents[j], unlike_energy)) continue;  // both strands end here
      passages.push_back(make_passage(r, region.exits[i], tangents[i], region.exits[j], tangents[j]));
    }
  }
  return passages;
}

namespace {

// A passage's radii along its path: from `from` at its first pixel to `to` at its last.
void interpolate_radius(Passage& p, float from, float to) {
  const size_t n = p.path.size();
  p.radius.resize(n);
  for (size_t k = 0; k < n; ++k) {
    const float t = n > 1 ? static_cast<float>(k) / static_cast<float>(n - 1) : 0.f;
    p.radius[k] = from * (1 - t) + to * t;
  }
}

// Routes passage `p` round a loop whose two halves, `h1` and `h2`, run from the group of
// the region's nodes that holds its exits to the other group: out along one half, across,
// back along the other and out, in the order turning least where it joins them; marks
// where the loop begins and ends on its path.
void route_round(Passage& p, std::vector<cv::Point> h1, std::vector<cv::Point> h2) {
  const cv::Point2f in = -p.from_tangent.path_direction, out = p.to_tangent.path_direction;
  const auto turn = [&](const std::vector<cv::Point>& first, const std::vector<cv::Point>& second) {
    const cv::Point2f back_in = -start_direction(second, kDirectionSpan);  // travel into the rod's group
    return (1 - in.dot(start_direction(first, kDirectionSpan))) + (1 - back_in.dot(out));
  };
  if (turn(h2, h1) < turn(h1, h2)) std::swap(h1, h2);
  const std::vector<cv::Point> back(h2.rbegin(), h2.rend());
  std::vector<cv::Point> path;
  const auto add = [&](const std::vector<cv::Point>& piece) {
    for (const cv::Point& q : piece) append_connected(path, q);
  };
  add(hermite_path(p.from_tangent.point, in, cv::Point2f(h1.front()), start_direction(h1, kDirectionSpan)));
  const int loop_begin = static_cast<int>(path.size()) - 1;
  add(h1);
  add(hermite_path(cv::Point2f(h1.back()), end_direction(h1, kDirectionSpan), cv::Point2f(back.front()),
                   start_direction(back, kDirectionSpan)));
  add(back);
  const int loop_end = static_cast<int>(path.size()) - 1;
  add(hermite_path(cv::Point2f(back.back()), end_direction(back, kDirectionSpan), p.to_tangent.point, out));
  const float ra = p.radius.empty() ? p.from_tangent.radius : p.radius.front();
  const float rb = p.radius.empty() ? p.to_tangent.radius : p.radius.back();
  p.path = std::move(path);
  interpolate_radius(p, ra, rb);
  p.loop_begin = loop_begin;
  p.loop_end = loop_end;
}

// Inner branches `i` and `j` of `region` tried as a rod's loop's two halves: the other
// inner branches must group the region's nodes in two, each half joining the groups, each
// passage (`in_region`) within one group (or, `across`, from one to the other, counted in
// neither), exactly one within a group whose colour both halves share more closely than
// any other passage's and within 1.5 colour tolerances: that passage is the rod's.
struct LoopHalves {
  int rod = -1;                      // the rod's passage, -1 if the pair is no loop
  std::vector<cv::Point> h1, h2;     // the halves' pixels from the rod's group to the other
  bool spans = false;                // turned down, not across, for a strand across the groups
};

LoopHalves loop_halves(const std::vector<Passage>& passages, const std::vector<int>& in_region,
                       const CrossingRegion& region, size_t i, size_t j, bool across,
                       TangentCache& cache, double min_half_length) {
  LoopHalves out;
  const SkeletonGraph& g = cache.graph();
  const std::vector<int>& inner = region.inner_branches;
  const Branch &l1 = g.branches[inner[i]], &l2 = g.branches[inner[j]];
  if (l1.twin == inner[j] || l1.length < min_half_length || l2.length < min_half_length ||
      l1.pixels.size() < 2 || l2.pixels.size() < 2)
    return out;
  const auto local = [&](int node) {
    const auto it = std::find(region.nodes.begin(), region.nodes.end(), node);
    return it == region.nodes.end() ? -1 : static_cast<int>(it - region.nodes.begin());
  };
  // The region's nodes grouped by its other inner branches.
  UnionFind uf(region.nodes.size());
  for (size_t k = 0; k < inner.size(); ++k) {
    if (k == i || k == j) continue;
    const int a = local(g.branches[inner[k]].node[0]), b = local(g.branches[inner[k]].node[1]);
    if (a >= 0 && b >= 0) uf.unite(a, b);
  }
  int groups = 0;
  for (int k = 0; k < static_cast<int>(region.nodes.size()); ++k) groups += uf.find(k) == k;
  if (groups != 2) return out;
  const int a1 = local(l1.node[0]), b1 = local(l1.node[1]);
  const int a2 = local(l2.node[0]), b2 = local(l2.node[1]);
  if (a1 < 0 || b1 < 0 || a2 < 0 || b2 < 0 || uf.find(a1) == uf.find(b1) || uf.find(a2) == uf.find(b2))
    return out;
  // Each passage's group, -1 for one across the groups (when allowed).
  const auto group_of = [&](const BranchEnd& e) {
    const int k = local(g.branches[e.branch].node[e.side]);
    return k < 0 ? -1 : uf.find(k);
  };
  std::vector<int> by_group;
  for (int p : in_region) {
    const int gf = group_of(passages[p].from), gt = group_of(passages[p].to);
    if (gf >= 0 && gt >= 0 && gf != gt) {
      if (!across) {
        out.spans = true;
        return out;
      }
      by_group.push_back(-1);  // in neither group: never the rod's passage
      continue;
    }
    if (gf < 0 || gf != gt) return out;
    by_group.push_back(gf);
  }
  // Try each group as the rod's: it must hold one passage within it, the other group the
  // rest of those within one.
  const std::vector<BranchTangent> halves = cache.of({{inner[i], 0}, {inner[j], 0}});
  if (!halves[0].has_colour || !halves[1].has_colour) return out;
  const auto nearest = [&](const BranchTangent& h, const Passage& p) {
    double d = std::numeric_limits<double>::infinity();
    for (const BranchTangent* t : {&p.from_tangent, &p.to_tangent})
      if (t->has_colour) d = std::min(d, colour_distance(h.colour, t->colour));
    return d;
  };
  const double tolerance = 1.5 * kColourTolerance;
  for (int candidate : {uf.find(a1), uf.find(b1)}) {
    int in_loop_group = 0, p_rod = -1;
    for (size_t k = 0; k < by_group.size(); ++k)
      if (by_group[k] == candidate) { ++in_loop_group; p_rod = in_region[k]; }
    if (in_loop_group != 1) continue;
    bool own = true;
    for (const BranchTangent& h : halves) {
      const double to_rod = nearest(h, passages[p_rod]);
      if (!(to_rod <= tolerance)) own = false;
      for (int q : in_region)
        if (q != p_rod && nearest(h, passages[q]) <= to_rod) own = false;
    }
    if (!own) continue;
    out.rod = p_rod;
    out.h1 = l1.pixels;
    out.h2 = l2.pixels;
    if (uf.find(a1) != candidate) std::reverse(out.h1.begin(), out.h1.end());
    if (uf.find(a2) != candidate) std::reverse(out.h2.begin(), out.h2.end());
    return out;
  }
  return out;
}

}  // namespace

Passage make_passage(int region, BranchEnd from, const BranchTangent& from_tangent, BranchEnd to,
                     const BranchTangent& to_tangent) {
  Passage p;
  p.region = region;
  p.from = from;
  p.to = to;
  p.from_tangent = from_tangent;
  p.to_tangent = to_tangent;
  p.energy = bending_energy(from_tangent, to_tangent);
  p.path = hermite_path(from_tangent.point, -from_tangent.path_direction, to_tangent.point,
                        to_tangent.path_direction);
  interpolate_radius(p, from_tangent.radius, to_tangent.radius);
  return p;
}

int route_round_inner_loops(std::vector<Passage>& passages, const std::vector<CrossingRegion>& regions,
                            TangentCache& cache, double min_half_length) {
  if (cache.setup().bgr.empty()) return 0;
  std::vector<std::vector<int>> of_region(regions.size());
  for (int i = 0; i < static_cast<int>(passages.size()); ++i)
    if (passages[i].region >= 0) of_region[passages[i].region].push_back(i);
  int routed = 0;
  for (size_t r = 0; r < regions.size(); ++r) {
    const std::vector<int>& inner = regions[r].inner_branches;
    if (inner.size() < 2 || of_region[r].size() < 2) continue;
    // First with every passage of the region inside one group; then, where that finds no
    // loop, letting strands run from one group to the other (a rod lying across the loop,
    // along one of its halves or through it): only if some pair of halves was turned down
    // for such a strand alone, as the second pass would find nothing new otherwise.
    bool done = false, spans = false;
    for (const bool across : {false, true})
      for (size_t i = 0; i < inner.size() && !done && (!across || spans); ++i)
        for (size_t j = i + 1; j < inner.size() && !done; ++j) {
          LoopHalves loop = loop_halves(passages, of_region[r], regions[r], i, j, across, cache,
                                        min_half_length);
          spans |= loop.spans;
          if (loop.rod < 0) continue;
          route_round(passages[loop.rod], std::move(loop.h1), std::move(loop.h2));
          ++routed;
          done = true;
        }
  }
  return routed;
}

int keep_passages_on_mask(std::vector<Passage>& passages, const cv::Mat& mask, float r,
                          float max_off) {
  const cv::Rect image(0, 0, mask.cols, mask.rows);
  const auto runs_off = [&](const std::vector<cv::Point>& path) {
    int run = 0;
    for (const cv::Point& p : path) {
      if (!image.contains(p)) return true;
      run = mask.at<uint8_t>(p) ? 0 : run + 1;
      if (run > max_off) return true;
    }
    return false;
  };
  // An exit's attachment point may lie a pixel or two off the mask (a skeleton's end at
  // the image border, where the mask thins): the search starts from the nearest mask pixel
  // within a radius, and the path is joined to the point itself.
  const int reach = static_cast<int>(std::ceil(std::max(2.f, r)));
  const auto onto_mask = [&](cv::Point p) {
    if (image.contains(p) && mask.at<uint8_t>(p)) return p;
    cv::Point best = p;
    int best_d2 = std::numeric_limits<int>::max();
    for (int dy = -reach; dy <= reach; ++dy)
      for (int dx = -reach; dx <= reach; ++dx) {
        const cv::Point q(p.x + dx, p.y + dy);
        const int d2 = dx * dx + dy * dy;
        if (d2 < best_d2 && d2 <= reach * reach && image.contains(q) && mask.at<uint8_t>(q)) best = q, best_d2 = d2;
      }
    return best;
  };
  int replaced = 0;
  for (Passage& p : passages) {
    if (p.path.size() < 2 || !runs_off(p.path)) continue;
    const cv::Point a = onto_mask(p.path.front()), b = onto_mask(p.path.back());
    const int margin = static_cast<int>(std::ceil(std::max(16.f, 8 * r)));
    cv::Rect near = cv::boundingRect(std::vector<cv::Point>{a, b});
    near = cv::Rect(near.x - margin, near.y - margin, near.width + 2 * margin, near.height + 2 * margin);
    std::vector<cv::Point> found =
        path_through_mask(mask, a, b, near, r, kCentreWeight, &p.path, kCurveWeight);
    if (found.empty()) found = path_through_mask(mask, a, b, image, r, kCentreWeight, &p.path, kCurveWeight);
    if (found.size() < 2) continue;
    std::vector<cv::Point> path{p.path.front()};
    for (const cv::Point& q : found) append_connected(path, q);
    append_connected(path, p.path.back());
    const float ra = p.radius.front(), rb = p.radius.back();
    p.path = std::move(path);
    p.loop_begin = p.loop_end = -1;
    interpolate_radius(p, ra, rb);
    ++replaced;
  }
  return replaced;
}

}  // namespace mbest

namespace mbest {

namespace {

// A merge of crossing regions that merge_regions_by_pairing_cost may make: region `keep`
// takes in each region gone[k] through its link links[k], and then pairs `exits` `gain`
// cheaper than each region alone (less the extra asked of long links).
struct Merge {
  double gain = 0;
  int keep = -1;
  std::vector<int> gone, links;
  std::vector<BranchEnd> exits;
  std::vector<int> beside;  // further links between the same two regions: inner too
};

}  // namespace

// How far a DLO's forked tip may lie from a region it is merged with, in prongs (tip_prong
// each): a tip beside a crossing may be part of it (a cable's end curled back onto its own
// strand came apart at 2 prongs, held-out suite `cables` seed 19004 scene 102), but past 3
// prongs it is a DLO's end near a crossing, and merged, its prong's shaded colour pairs
// cheaply with a strand there (at epsilon, 5 prongs, a grey cable's end beside a black one
// took the black one's way on, suite `cables` seed 11004 scene 139).
constexpr double kTipReach = 3;

int merge_regions_by_pairing_cost(SkeletonGraph& g, std::vector<CrossingRegion>& regions,
                                  TangentCache& cache, double max_link, double min_gain,
                                  double long_link, double tip_prong) {
  // A forked tip: two exits, one a prong shorter than tip_prong to the DLO's end.
  const auto is_tip = [&](const CrossingRegion& r) {
    return r.exits.size() == 2 && std::any_of(r.exits.begin(), r.exits.end(), [&](const BranchEnd& e) {
             return is_spur(g, e.branch, tip_prong);
           });
  };
  int merged = 0;
  for (;;) {
    const std::vector<int> region_of = region_of_nodes(g, regions);
    std::vector<double> cost(regions.size(), -1);
    const auto cost_of = [&](int r) {
      if (cost[r] < 0) cost[r] = cache.least_cost(regions[r].exits);
      return cost[r];
    };
    // Links: branches up to max_link, or long_link, joining two regions. A long one asks
    // twice min_gain more: past max_link the strands at its two ends are far apart, and a
    // pairing cost is a weaker cue there. Twins (a band split into its two strands, each
    // carrying one) are links only where both are short, and then only together, as the
    // parallel links below: where the strands overlap, both twins show the top strand's
    // colour, and each region alone pairs the strands with them by their bends only.
    std::vector<int> links;
    std::vector<std::vector<int>> links_of(regions.size());
    const auto link_allowance = [&](int i) { return g.branches[i].length > max_link ? 2 * min_gain : 0.0; };
    for (int i = 0; i < static_cast<int>(g.branches.size()); ++i) {
      const Branch& b = g.branches[i];
      if (!b.alive || b.length > std::max(max_link, long_link)) continue;
      if (b.twin >= 0 && std::max(b.length, g.branches[b.twin].length) > max_link) continue;
      const int ra = region_of[b.node[0]], rb = region_of[b.node[1]];
      if (ra < 0 || rb < 0 || ra == rb) continue;
      if (b.length > std::min(max_link, kTipReach * tip_prong) && (is_tip(regions[ra]) || is_tip(regions[rb])))
        continue;
      links.push_back(i);
      links_of[ra].push_back(i);
      links_of[rb].push_back(i);
    }
    const auto other_region = [&](int link, int r) {
      const Branch& b = g.branches[link];
      return region_of[b.node[0]] == r ? region_of[b.node[1]] : region_of[b.node[0]];
    };
    // A candidate merge is the best so far if `alone` (the regions' own least costs, less
    // what their links ask) less the joined exits' least cost beats best.gain. Joining
    // cannot gain more than `alone` (costs are not negative), nor more than its cost's lower
    // bound allows: regions that pair well alone, or a joined set whose exits all pair
    // dearly, are not worth pairing exactly.
    Merge best;
    const auto consider = [&](double alone, int keep, std::vector<int> gone, std::vector<int> through,
                              std::vector<int> beside, const auto& joined_exits) {
      if (alone <= best.gain) return;
      std::vector<BranchEnd> exits = joined_exits();
      if (exits.size() < 3) return;
      if (alone - cache.least_cost_bound(exits) <= best.gain) return;
      const double gain = alone - cache.least_cost(exits);
      if (gain > best.gain)
        best = {gain, keep, std::move(gone), std::move(through), std::move(exits), std::move(beside)};
    };
    // Two regions, through one link; or, where two or more links join them and all are
    // short (a rod through a small loop of another, two strands crossing twice a few radii
    // apart, short twins), through all at once: merged through one, the others would be
    // left as exits of the joined region on both sides, paired as if they were strands.
    best.gain = min_gain;
    for (int i : links) {
      const int ra = region_of[g.branches[i].node[0]], rb = region_of[g.branches[i].node[1]];
      // Two strands end there, one each: joining would pair them (pair_lone_ys).
      if (regions[ra].exits.size() % 2 && regions[rb].exits.size() % 2) continue;
      std::vector<int> through{i}, parallel;
      for (int j : links_of[ra])
        if (other_region(j, ra) == rb) parallel.push_back(j);
      if (parallel.size() > 1 && std::all_of(parallel.begin(), parallel.end(), [&](int j) {
            return g.branches[j].length <= max_link;
          })) {
        if (parallel.front() != i) continue;  // the two regions once
        through = std::move(parallel);
      }
      consider(cost_of(ra) + cost_of(rb) - link_allowance(i), ra, {rb}, {i},
               std::vector<int>(through.begin() + 1, through.end()),
               [&] { return exits_but({&regions[ra], &regions[rb]}, through); });
    }
    // Failing that, three in a row through two links, for three times min_gain: a strand
    // may need all three to pair right where neither end region gains enough joined to the
    // middle one alone (a thin DLO hidden under a wide one across a third DLO's crossing).
    if (best.links.empty()) {
      best.gain = 3 * min_gain;
      for (int m = 0; m < static_cast<int>(regions.size()); ++m)
        for (size_t x = 0; x < links_of[m].size(); ++x)
          for (size_t y = x + 1; y < links_of[m].size(); ++y) {
            const int i = links_of[m][x], j = links_of[m][y];
            if (g.branches[i].twin >= 0 || g.branches[j].twin >= 0) continue;  // in pairs only
            const int ra = other_region(i, m), rc = other_region(j, m);
            if (ra == rc) continue;
            consider(cost_of(ra) + cost_of(m) + cost_of(rc) - link_allowance(i) - link_allowance(j), m,
                     {ra, rc}, {i, j}, {}, [&] { return exits_but({&regions[ra], &regions[m], &regions[rc]}, {i, j}); });
          }
    }
    if (best.links.empty()) return merged;
    absorb_regions(g, regions[best.keep], regions, best.gone, best.links, std::move(best.exits),
                   best.beside);
    merged += static_cast<int>(best.gone.size());
    std::sort(best.gone.rbegin(), best.gone.rend());  // erased last first
    for (int r : best.gone) regions.erase(regions.begin() + r);
  }
}

int pair_lone_ys(SkeletonGraph& g, std::vector<CrossingRegion>& regions, TangentCache& cache,
                 double min_link, double max_cost, double min_gain, bool short_links) {
  if (max_cost <= 0) return 0;
  const PairingSetup& setup = cache.setup();
  // The exit a region with an odd exit count leaves unpaired (a DLO's end), -1 if none.
  const auto lone_exit = [&](const CrossingRegion& r) {
    const std::vector<BranchTangent> t = cache.of(r.exits);
    std::vector<bool> paired(r.exits.size(), false);
    for (const auto& [a, b] : min_energy_pairing(t, r.exits, setup.weights)) paired[a] = paired[b] = true;
    for (size_t k = 0; k < paired.size(); ++k)
      if (!paired[k]) return static_cast<int>(k);
    return -1;
  };
  const std::vector<int> region_of = region_of_nodes(g, regions);
  struct Candidate {
    double cost;
    int ra;                       // the region that takes in the others
    std::vector<int> gone, links;  // each through its link
    std::vector<BranchEnd> exits;
  };
  std::vector<Candidate> candidates;
  for (int i = 0; i < static_cast<int>(g.branches.size()); ++i) {
    const Branch& b = g.branches[i];
    if (!b.alive || b.twin >= 0 || (b.length <= min_link && !short_links)) continue;
    const int ra = region_of[b.node[0]], rb = region_of[b.node[1]];
    if (ra < 0 || rb < 0 || ra == rb) continue;
    const CrossingRegion &a = regions[ra], &c = regions[rb];
    if (a.exits.size() % 2 == 0 || c.exits.size() % 2 == 0) continue;
    std::vector<BranchEnd> exits = exits_but({&a, &c}, {i});
    if (exits.size() > kMaxExactExits) continue;
    const std::vector<BranchTangent> t = cache.of(exits);
    const std::vector<std::pair<int, int>> pairs = min_energy_pairing(t, exits, setup.weights);
    // Either the strands each Y leaves ending continue each other (together, the two ends
    // pair with each other) ...
    bool joined = false;
    double cost = 0;
    const int la = lone_exit(a), lc = lone_exit(c);
    if (la >= 0 && lc >= 0 && a.exits[la].branch != i && c.exits[lc].branch != i) {
      const BranchEnd ea = a.exits[la], ec = c.exits[lc];
      cost = pair_cost(cache.of({ea})[0], cache.of({ec})[0], setup.weights);
      if (cost <= max_cost)
        for (const auto& [x, y] : pairs)
          joined |= (exits[x] == ea && exits[y] == ec) || (exits[x] == ec && exits[y] == ea);
    }
    // ... or, for two plain Ys, both strands run through: each pair joins an exit of one Y to
    // one of the other, at most max_cost each. (Which strand a Y alone leaves ending is a
    // near tie at a shallow crossing; this test does not depend on it.)
    if (!joined && a.exits.size() == 3 && c.exits.size() == 3 && pairs.size() == 2) {
      const size_t from_a = a.exits.size() - 1;  // exits[0 .. from_a) are a's (less the link)
      bool all = true;
      double worst = 0;
      for (const auto& [x, y] : pairs) {
        all &= (static_cast<size_t>(x) < from_a) != (static_cast<size_t>(y) < from_a);
        worst = std::max(worst, pair_cost(t[x], t[y], setup.weights));
      }
      if (all && worst <= max_cost) joined = true, cost = worst;
    }
    // ... or pairing all exits together costs at least min_gain less than pairing each
    // region alone, though together the two strands left ending must pair too: each Y alone
    // was forced into a dear pair (a strand paired with a link whose colour mixes two
    // strands lying along each other) that joining undoes. Taken before the others, best
    // gain first (its cost is the negative gain). The gain asked grows from none at
    // min_link (the paper's epsilon, within which two Ys are one crossing whatever they
    // gain) to min_gain at twice it, so that Ys just past epsilon are not judged by
    // another rule than Ys just within it.
    if (!joined) {
      const double gain = cache.least_cost(a.exits) + cache.least_cost(c.exits) -
                          pairing_cost(t, pairs, setup.weights);
      const double need = min_link > 0 ? min_gain * std::min(1.0, (b.length - min_link) / min_link) : min_gain;
      if (gain > 0 && gain >= need) joined = true, cost = -gain;
    }
    if (joined) candidates.push_back({cost, ra, {rb}, {i}, std::move(exits)});
  }
  // Two plain Ys with the crossing of other strands between them, each joined to it by a
  // link as above: two strands lie along each other from one Y to the other (twisting, or
  // overlapping at a shallow angle), and a third DLO crosses both on the way. Joined, the
  // three are one crossing when the least-cost pairing of all their exits joins each exit
  // of one Y to one of the other, at most max_cost each, and pairs the middle region's exits
  // among themselves.
  for (int m = 0; m < static_cast<int>(regions.size()); ++m) {
    const CrossingRegion& mid = regions[m];
    if (mid.exits.size() % 2) continue;
    std::vector<std::pair<int, int>> ys;  // (link, region): plain Ys linked to m
    for (const BranchEnd& e : mid.exits) {
      const Branch& b = g.branches[e.branch];
      if (!b.alive || b.twin >= 0 || b.length <= min_link) continue;
      const int other = region_of[b.node[1 - e.side]];
      if (other >= 0 && other != m && regions[other].exits.size() == 3) ys.push_back({e.branch, other});
    }
    for (size_t x = 0; x < ys.size(); ++x)
      for (size_t y = x + 1; y < ys.size(); ++y) {
        const auto [i, ra] = ys[x];
        const auto [j, rc] = ys[y];
        if (ra == rc || i == j) continue;
        const CrossingRegion &a = regions[ra], &c = regions[rc];
        std::vector<BranchEnd> exits = exits_but({&a, &mid, &c}, {i, j});
        // Exits [0, 2) are a's, [size - 2, size) c's, the middle region's between.
        if (exits.size() != a.exits.size() + mid.exits.size() + c.exits.size() - 4 ||
            exits.size() > kMaxExactExits)
          continue;
        const std::vector<BranchTangent> t = cache.of(exits);
        const int n = static_cast<int>(exits.size());
        const auto part = [n](int k) { return k < 2 ? 0 : k >= n - 2 ? 2 : 1; };
        bool through = true;
        double worst = 0;
        for (const auto& [u, v] : min_energy_pairing(t, exits, setup.weights)) {
          const int pu = part(u), pv = part(v);
          if (pu == 1 && pv == 1) continue;
          through &= pu + pv == 2 && pu != 1;
          worst = std::max(worst, pair_cost(t[u], t[v], setup.weights));
        }
        if (through && worst <= max_cost) candidates.push_back({worst, m, {ra, rc}, {i, j}, std::move(exits)});
      }
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& x, const Candidate& y) { return x.cost < y.cost; });
  std::vector<bool> used(regions.size(), false), erase(regions.size(), false);
  int merged = 0;
  for (Candidate& k : candidates) {
    if (used[k.ra] || std::any_of(k.gone.begin(), k.gone.end(), [&](int r) { return used[r]; })) continue;
    used[k.ra] = true;
    for (int r : k.gone) used[r] = erase[r] = true;
    absorb_regions(g, regions[k.ra], regions, k.gone, k.links, std::move(k.exits));
    merged += static_cast<int>(k.gone.size());
  }
  if (merged == 0) return 0;
  int kept = 0;
  for (int r = 0; r < static_cast<int>(regions.size()); ++r) {
    if (erase[r]) continue;
    if (kept != r) regions[kept] = std::move(regions[r]);
    ++kept;
  }
  regions.resize(kept);
  return merged;
}

}  // namespace mbest

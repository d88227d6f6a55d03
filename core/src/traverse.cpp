#include "mbest/core/traverse.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "mbest/core/geometry.h"
#include "mbest/core/median.h"

namespace mbest {
namespace {

struct Builder {
  const SkeletonGraph& g;
  const std::vector<Passage>& passages;
  std::vector<int> passage_at;  // per branch end (2 * branch + side): passage index or -1
  std::vector<bool> visited;    // per branch

  Builder(const SkeletonGraph& graph, const std::vector<Passage>& ps)
      : g(graph), passages(ps), passage_at(2 * graph.branches.size(), -1),
        visited(graph.branches.size(), false) {
    for (int i = 0; i < static_cast<int>(ps.size()); ++i) {
      passage_at[2 * ps[i].from.branch + ps[i].from.side] = i;
      passage_at[2 * ps[i].to.branch + ps[i].to.side] = i;
    }
  }

  int passage_of(BranchEnd e) const { return passage_at[2 * e.branch + e.side]; }

  int cut_of(BranchEnd e) const {
    const int p = passage_of(e);
    if (p < 0) return 0;
    return passages[p].from == e ? passages[p].from_tangent.cut : passages[p].to_tangent.cut;
  }

  static void append(Dlo& dlo, cv::Point p, float r) {
    const size_t before = dlo.centerline.size();
    append_connected(dlo.centerline, p);
    const float r0 = dlo.radius.empty() ? r : dlo.radius.back();
    const size_t added = dlo.centerline.size() - before;
    for (size_t k = 1; k <= added; ++k)
      dlo.radius.push_back(r0 + (r - r0) * static_cast<float>(k) / static_cast<float>(added));
  }

  // Walks from `start` (entering its branch there) until a true end or back to the start.
  void walk(BranchEnd start, Dlo& dlo, std::vector<int>& dlo_passages, std::vector<int>& branches) {
    BranchEnd cur = start;
    for (;;) {
      visited[cur.branch] = true;
      branches.push_back(cur.branch);
      const Branch& b = g.branches[cur.branch];
      const int n = static_cast<int>(b.pixels.size());
      const BranchEnd exit{cur.branch, 1 - cur.side};
      const int first = cut_of(cur), last = n - 1 - cut_of(exit);
      for (int i = first; i <= last; ++i) {
        const int k = cur.side == 0 ? i : n - 1 - i;
        append(dlo, b.pixels[k], b.radius[k]);
      }
      const int p = passage_of(exit);
      if (p < 0) return;
      const Passage& ps = passages[p];
      const bool forward = ps.from == exit;
      dlo_passages.push_back(p);
      const size_t m = ps.path.size();
      for (size_t i = 0; i < m; ++i) {
        const size_t k = forward ? i : m - 1 - i;
        append(dlo, ps.path[k], ps.radius[k]);
      }
      const BranchEnd next = forward ? ps.to : ps.from;
      if (visited[next.branch]) {  // back where it started: a closed DLO
        dlo.closed = true;
        return;
      }
      cur = next;
    }
  }
};

}  // namespace

Traversal traverse(const SkeletonGraph& g, const std::vector<Passage>& passages, double min_length) {
  Builder builder(g, passages);
  Traversal t;
  t.passage_dlo.assign(passages.size(), -1);
  t.branch_dlo.assign(g.branches.size(), -1);

  auto keep = [&](Dlo&& dlo, const std::vector<int>& dps, const std::vector<int>& branches) {
    if (dlo.closed && dlo.centerline.size() > 2) {
      // The walk ends where it began: close the gap to the first pixel, without repeating it.
      if (dlo.centerline.back() != dlo.centerline.front())
        Builder::append(dlo, dlo.centerline.front(), dlo.radius.front());
      dlo.centerline.pop_back();
      dlo.radius.pop_back();
    }
    if (chain_length(dlo.centerline) < min_length) return;
    const int id = static_cast<int>(t.dlos.size());
    for (int p : dps) t.passage_dlo[p] = id;
    for (int b : branches) t.branch_dlo[b] = id;
    t.dlo_passages.push_back(dps);
    t.dlos.push_back(std::move(dlo));
  };

  // Open DLOs start at true ends: end nodes, and exits a crossing left unpaired.
  for (int i = 0; i < static_cast<int>(g.branches.size()); ++i) {
    for (int s = 0; s < 2; ++s) {
      const Branch& b = g.branches[i];
      if (!b.alive || builder.visited[i] || builder.passage_of({i, s}) >= 0) continue;
      Dlo dlo;
      std::vector<int> dps, branches;
      builder.walk({i, s}, dlo, dps, branches);
      keep(std::move(dlo), dps, branches);
    }
  }
  // Closed DLOs through crossings: every branch end is paired.
  for (int i = 0; i < static_cast<int>(g.branches.size()); ++i) {
    if (!g.branches[i].alive || builder.visited[i]) continue;
    Dlo dlo;
    std::vector<int> dps, branches;
    builder.walk({i, 0}, dlo, dps, branches);
    dlo.closed = true;
    keep(std::move(dlo), dps, branches);
  }
  // Rings: closed chains that never met a junction.
  for (size_t k = 0; k < g.rings.size(); ++k) {
    Dlo dlo;
    dlo.centerline = g.rings[k];
    dlo.radius = g.ring_radius[k];
    dlo.closed = true;
    keep(std::move(dlo), {}, {});
  }
  return t;
}

bool open_closed_loops(std::vector<Passage>& passages, const Traversal& t, PairWeights weights,
                       double max_cost, double own_colour_cost) {
  if (max_cost <= 0) return false;
  weights.loop = 0;
  const auto cost = [&](const BranchTangent& a, const BranchTangent& b) { return pair_cost(a, b, weights); };
  const auto far = [](const BranchTangent& a, const BranchTangent& b) {
    return a.has_colour && b.has_colour && colour_distance(a.colour, b.colour) > kColourTolerance;
  };
  const auto alike = [](const BranchTangent& a, const BranchTangent& b) {
    return a.has_colour && b.has_colour && colour_distance(a.colour, b.colour) <= kColourTolerance / 2;
  };
  double best = std::numeric_limits<double>::infinity();
  int best_p = -1, best_q = -1;
  bool crossed = false;  // from-from and to-to (else from-to and to-from)
  for (size_t d = 0; d < t.dlos.size(); ++d) {
    if (!t.dlos[d].closed) continue;
    for (int p : t.dlo_passages[d]) {
      const Passage& lp = passages[p];
      for (int q = 0; q < static_cast<int>(passages.size()); ++q) {
        const Passage& op = passages[q];
        const int o = t.passage_dlo[q];
        if (op.region != lp.region || o < 0 || t.dlos[o].closed) continue;
        if (far(lp.from_tangent, op.from_tangent) && far(lp.from_tangent, op.to_tangent)) continue;
        const double before = cost(lp.from_tangent, lp.to_tangent) + cost(op.from_tangent, op.to_tangent);
        const double same = cost(lp.from_tangent, op.from_tangent) + cost(lp.to_tangent, op.to_tangent) - before;
        const double swapped = cost(lp.from_tangent, op.to_tangent) + cost(lp.to_tangent, op.from_tangent) - before;
        // All four exits of one colour: most likely one rod, its loop closed here.
        const bool one_colour = alike(lp.from_tangent, op.from_tangent) && alike(lp.from_tangent, op.to_tangent) &&
                                alike(lp.to_tangent, op.from_tangent) && alike(lp.to_tangent, op.to_tangent);
        const double allowed = one_colour ? std::max(max_cost, own_colour_cost) : max_cost;
        if (std::min(same, swapped) <= std::min(allowed, best)) {
          best = std::min(same, swapped);
          best_p = p;
          best_q = q;
          crossed = same <= swapped;
        }
      }
    }
  }
  if (best_p < 0) return false;
  const Passage lp = passages[best_p], op = passages[best_q];
  if (crossed) {
    passages[best_p] = make_passage(lp.region, lp.from, lp.from_tangent, op.from, op.from_tangent);
    passages[best_q] = make_passage(lp.region, lp.to, lp.to_tangent, op.to, op.to_tangent);
  } else {
    passages[best_p] = make_passage(lp.region, lp.from, lp.from_tangent, op.to, op.to_tangent);
    passages[best_q] = make_passage(lp.region, lp.to, lp.to_tangent, op.from, op.from_tangent);
  }
  return true;
}

namespace {

// Extends `line` (and `radius`) beyond its last pixel; see extend_ends.
void extend_tail(std::vector<cv::Point>& line, std::vector<float>& radius, const cv::Mat& mask, float r) {
  // Direction from the chord 3 r .. r before the end: the last r px bend towards a corner
  // of a flat tip.
  const int n = static_cast<int>(line.size());
  const int back = std::min(n - 1, std::max(2, static_cast<int>(std::lround(3 * r))));
  const int skip = std::min(back - 2, static_cast<int>(std::lround(r)));
  if (back < 2) return;
  cv::Point2f dir = cv::Point2f(line[n - 1 - skip]) - cv::Point2f(line[n - 1 - back]);
  const float len = std::hypot(dir.x, dir.y);
  if (len < 1) return;
  dir *= 1.0f / len;
  // The bent tip is replaced: extend straight on from where the chord ends.
  const cv::Point2f start(line[n - 1 - skip]);
  const float tip_radius = radius.back();
  line.resize(n - skip);
  radius.resize(n - skip);
  const int max_steps = static_cast<int>(std::ceil(2 * r)) + 2 + skip;
  auto inside = [&](cv::Point p) { return p.x >= 0 && p.y >= 0 && p.x < mask.cols && p.y < mask.rows; };
  std::vector<cv::Point> ext;
  bool reached_border = false;
  for (int k = 1; k <= max_steps; ++k) {
    const cv::Point p(start + dir * static_cast<float>(k));  // rounds to the nearest pixel
    if (!inside(p)) {
      reached_border = true;
      break;
    }
    if (!mask.ptr<uint8_t>(p.y)[p.x]) break;
    ext.push_back(p);
  }
  if (!reached_border) {  // stop half a radius inside the edge
    const size_t keep = ext.size() - std::min(ext.size(), static_cast<size_t>(std::lround(tip_radius / 2)));
    ext.resize(keep);
  }
  for (const cv::Point& p : ext) append_connected(line, p);
  radius.resize(line.size(), tip_radius);
}

// Turns `dlo` end for end, so that its first end is its last: ends are extended at the back.
void reverse(Dlo& dlo) {
  std::reverse(dlo.centerline.begin(), dlo.centerline.end());
  std::reverse(dlo.radius.begin(), dlo.radius.end());
}

// A ray from a DLO's end that runs across the body of another strand into a stub of mask
// no strand covers: `steps` px of it to keep (up to half a radius short of the stub's tip,
// or to the border), `stub` of them past the body.
struct StubRay {
  int steps = 0, stub = 0;
};

// A centerline pixel of another strand near a DLO's end: its body's radius and its
// direction there (unit).
struct BodyPixel {
  cv::Point at;
  float radius;
  cv::Point2f direction;
};

// The ray from `end` along `dir`, for a DLO whose end runs along `strand`, as a StubRay if
// it makes one within `max_steps` px: the DLO runs into another strand's body at
// `min_angle` or more to its axis (at the axis pixel nearest the ray; a DLO along a strand,
// beside it, finds the part of a wide overlap that strand leaves uncovered, no stub), and
// the ray goes on into a stub reaching at least `min_stub` px from the bodies (measured
// sideways: along a ray at a shallow angle, the margin of a body a little wider than its
// median looks long). `others` are the centerline pixels near the end, the DLO's own last
// pixels left out.
std::optional<StubRay> stub_past(cv::Point2f end, cv::Point2f dir, cv::Point2f strand, int max_steps,
                                 float min_stub, float tip_radius, double min_angle, const cv::Mat& mask,
                                 const std::vector<BodyPixel>& others) {
  const float min_sine = static_cast<float>(std::sin(min_angle));
  bool crossed = false;  // the ray has run across another strand's body
  bool inside = false;   // ... and is in one now
  int stub = 0;          // steps since it left that body
  float reach = 0;       // the furthest the stub gets from the bodies
  for (int k = 1; k <= max_steps; ++k) {
    const cv::Point p(end + dir * static_cast<float>(k));
    const bool in_image = p.x >= 0 && p.y >= 0 && p.x < mask.cols && p.y < mask.rows;
    if (!in_image || !mask.ptr<uint8_t>(p.y)[p.x]) {
      const int keep = in_image ? k - 1 - static_cast<int>(std::lround(tip_radius / 2)) : k - 1;
      // A stub cut by the border reaches no further from the bodies than the border lets it:
      // there its length counts.
      const float past = in_image ? reach : std::max(reach, static_cast<float>(stub));
      if (crossed && past >= min_stub && keep > k - 1 - stub) return StubRay{keep, stub};
      return std::nullopt;
    }
    const BodyPixel* nearest = nullptr;  // the nearest axis pixel whose body covers p
    float nearest_d2 = 0;
    float clearance = std::numeric_limits<float>::infinity();  // how far past the bodies p lies
    for (const BodyPixel& o : others) {
      const float dx = static_cast<float>(p.x - o.at.x), dy = static_cast<float>(p.y - o.at.y);
      const float d2 = dx * dx + dy * dy;
      clearance = std::min(clearance, std::sqrt(d2) - o.radius);
      if (d2 <= (o.radius + 1) * (o.radius + 1) && (!nearest || d2 < nearest_d2)) nearest = &o, nearest_d2 = d2;
    }
    const bool covered = nearest != nullptr;
    if (!covered && inside && crossed) reach = std::max(reach, clearance);
    if (covered) {
      if (std::abs(strand.x * nearest->direction.y - strand.y * nearest->direction.x) >= min_sine) crossed = true;
      // Into a third body: the DLO ends under it, after a stub between the two.
      if (stub > 0) return reach >= min_stub ? std::optional<StubRay>(StubRay{k - 1, stub}) : std::nullopt;
      inside = true;
    } else if (inside && crossed) {
      ++stub;
    }
  }
  return std::nullopt;  // the mask runs on: not a short stub
}

// Below this angle a ray from an end runs along the strand it meets rather than across.
constexpr double kMinStubCrossingAngle = 10 * M_PI / 180;

}  // namespace

int reach_past_crossings(std::vector<Dlo>& dlos, const cv::Mat& mask, float r) {
  const int back = std::max(2, static_cast<int>(std::lround(3 * r)));
  const int max_steps = static_cast<int>(std::ceil(6 * r)) + 2;
  const float window = static_cast<float>(max_steps) + 4 * r;  // around the end, for `others`
  // A strand's body is its typical width: radii measured inside a crossing are the
  // crossing's, wider.
  std::vector<float> body(dlos.size(), 0);
  for (size_t e = 0; e < dlos.size(); ++e)
    if (!dlos[e].radius.empty()) body[e] = median(dlos[e].radius);
  // Extends the last end of DLO `d`, if it stops short of a stub.
  const auto reach_tail = [&](size_t d) {
    Dlo& dlo = dlos[d];
    const int n = static_cast<int>(dlo.centerline.size());
    const cv::Point2f end(dlo.centerline.back());
    const cv::Point2f chord = end - cv::Point2f(dlo.centerline[n - 1 - back]);
    const float len = std::hypot(chord.x, chord.y);
    if (len < 1) return false;
    const cv::Point2f dir = chord * (1.0f / len);
    // Centerline pixels near the end, but this DLO's own last 2 * back pixels.
    std::vector<BodyPixel> others;
    for (size_t e = 0; e < dlos.size(); ++e) {
      const std::vector<cv::Point>& line = dlos[e].centerline;
      const size_t m = e == d ? line.size() - std::min(line.size(), static_cast<size_t>(2 * back)) : line.size();
      for (size_t k = 0; k < m; ++k) {
        if (std::abs(line[k].x - end.x) > window || std::abs(line[k].y - end.y) > window) continue;
        const size_t lo = k >= 3 ? k - 3 : 0, hi = std::min(line.size() - 1, k + 3);
        others.push_back({line[k], body[e], unit(cv::Point2f(line[hi] - line[lo]))});
      }
    }
    const float tip_radius = dlo.radius.back();
    // The stub may bend away from the chord: rays fan out up to 30 degrees either side,
    // and the one reaching furthest into a stub wins (the straightest of equals).
    std::optional<StubRay> stub;
    cv::Point2f stub_dir = dir;
    for (int turn : {0, 1, -1, 2, -2, 3, -3, 4, -4}) {
      const float a = static_cast<float>(turn * 7.5 * M_PI / 180);
      const cv::Point2f ray(dir.x * std::cos(a) - dir.y * std::sin(a), dir.x * std::sin(a) + dir.y * std::cos(a));
      const auto s = stub_past(end, ray, dir, max_steps, std::max(3.0f, tip_radius / 2), tip_radius,
                               kMinStubCrossingAngle, mask, others);
      if (s && (!stub || s->stub > stub->stub)) stub = s, stub_dir = ray;
    }
    if (!stub) return false;
    for (int k = 1; k <= stub->steps; ++k) append_connected(dlo.centerline, cv::Point(end + stub_dir * static_cast<float>(k)));
    dlo.radius.resize(dlo.centerline.size(), tip_radius);
    return true;
  };
  int extended = 0;
  for (size_t d = 0; d < dlos.size(); ++d) {
    Dlo& dlo = dlos[d];
    if (dlo.closed || static_cast<int>(dlo.centerline.size()) <= back) continue;
    for (int pass = 0; pass < 2; ++pass) {  // the first end, then the last
      reverse(dlo);
      extended += reach_tail(d);
    }
  }
  return extended;
}

void extend_ends(std::vector<Dlo>& dlos, const cv::Mat& mask, float r) {
  for (Dlo& dlo : dlos) {
    if (dlo.closed || dlo.centerline.size() < 3) continue;
    extend_tail(dlo.centerline, dlo.radius, mask, r);
    reverse(dlo);
    extend_tail(dlo.centerline, dlo.radius, mask, r);
    reverse(dlo);
  }
}

}  // namespace mbest

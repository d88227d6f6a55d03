#include "mbest/core/detector.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "mbest/core/bending.h"
#include "mbest/core/crossing_order.h"
#include "mbest/core/geometry.h"
#include "mbest/core/instance_mask.h"
#include "mbest/core/junctions.h"
#include "mbest/core/keypoints.h"
#include "mbest/core/median.h"
#include "mbest/core/prune.h"
#include "mbest/core/skeleton.h"
#include "mbest/core/strands.h"
#include "mbest/core/traverse.h"

namespace mbest {
namespace {

// Colour labels (refine_labels_by_colour): a pixel goes to a DLO only when its colour lies
// within this many times colour_label_margin of that DLO's (farther, it is glare or
// background blended in). 3 until 2026-12-06; once colours were read as a 3 x 3 median,
// 4.5, 5 and 6 scored alike on the nine synthetic seed sets (`stress` pairing failures
// 2878 -> 2804, 2781, 2769; strict DICE +0.16-0.18 points; outside `stress` unchanged
// within one crossing) and 10 broke two crossings at 20-45 degrees on the held-out pair
// (all with colour_label_margin 10; with its default of 8 since, the reach is 40 units).
constexpr double kColourLabelReach = 5;

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

// Do two paths cross or touch? Each is a chain of pixels; the polylines through their
// centres are tested segment against segment, exactly, in integers.
bool paths_meet(const std::vector<cv::Point>& a, const std::vector<cv::Point>& b) {
  if (a.empty() || b.empty()) return false;
  const cv::Rect box_a = cv::boundingRect(a), box_b = cv::boundingRect(b);
  if ((box_a & cv::Rect(box_b.x - 1, box_b.y - 1, box_b.width + 2, box_b.height + 2)).empty()) return false;
  const auto side = [](cv::Point o, cv::Point p, cv::Point q) {  // sign of (p - o) x (q - o)
    const long long c = static_cast<long long>(p.x - o.x) * (q.y - o.y) -
                        static_cast<long long>(p.y - o.y) * (q.x - o.x);
    return (c > 0) - (c < 0);
  };
  const auto within = [](cv::Point o, cv::Point p, cv::Point q) {  // q on segment o-p, if collinear
    return std::min(o.x, p.x) <= q.x && q.x <= std::max(o.x, p.x) && std::min(o.y, p.y) <= q.y &&
           q.y <= std::max(o.y, p.y);
  };
  const auto segments_meet = [&](cv::Point p1, cv::Point p2, cv::Point q1, cv::Point q2) {
    const int d1 = side(q1, q2, p1), d2 = side(q1, q2, p2), d3 = side(p1, p2, q1), d4 = side(p1, p2, q2);
    if (d1 * d2 < 0 && d3 * d4 < 0) return true;  // a proper crossing
    return (d1 == 0 && within(q1, q2, p1)) || (d2 == 0 && within(q1, q2, p2)) ||
           (d3 == 0 && within(p1, p2, q1)) || (d4 == 0 && within(p1, p2, q2));
  };
  const size_t na = std::max<size_t>(a.size(), 2) - 1, nb = std::max<size_t>(b.size(), 2) - 1;
  for (size_t i = 0; i < na; ++i) {
    const cv::Point a1 = a[i], a2 = a[std::min(i + 1, a.size() - 1)];
    for (size_t j = 0; j < nb; ++j)
      if (segments_meet(a1, a2, b[j], b[std::min(j + 1, b.size() - 1)])) return true;
  }
  return false;
}

// The index of the pixel of `path` nearest to `at` (the first of equals), and, when asked
// for, its squared distance.
size_t nearest_pixel(const std::vector<cv::Point>& path, cv::Point2f at, float* distance_squared = nullptr) {
  size_t k = 0;
  float best = std::numeric_limits<float>::max();
  for (size_t i = 0; i < path.size(); ++i) {
    const cv::Point2f d = cv::Point2f(path[i]) - at;
    const float d2 = d.dot(d);
    if (d2 < best) best = d2, k = i;
  }
  if (distance_squared) *distance_squared = best;
  return k;
}

// A path's direction at its pixel k: from `reach` pixels before it to `reach` after.
cv::Point path_direction(const std::vector<cv::Point>& path, size_t k, size_t reach) {
  return path[std::min(k + reach, path.size() - 1)] - path[k >= reach ? k - reach : 0];
}

// Which side of `path` is `p` on: +1 or -1 (the path's direction near its point closest
// to p, crossed with the way from there to p), or 0 within `margin` px of it. Past either
// end of the path this is the side of its end direction, extended.
int side_of_path(const std::vector<cv::Point>& path, cv::Point p, double margin = 0) {
  float d2 = 0;
  const size_t k = nearest_pixel(path, p, &d2);
  if (d2 == 0 || d2 < margin * margin) return 0;
  const cv::Point dir = path_direction(path, k, 3), to = p - path[k];
  const long long c = static_cast<long long>(dir.x) * to.y - static_cast<long long>(dir.y) * to.x;
  return (c > 0) - (c < 0);
}

// Where path `b` goes over to the other side of path `a`, leaving a pixel's margin so that
// two paths touching side by side do not count: one point per change of side.
std::vector<cv::Point2f> side_changes(const std::vector<cv::Point>& a, const std::vector<cv::Point>& b) {
  constexpr double kMargin = 1;
  std::vector<cv::Point2f> at;
  int last = 0;
  cv::Point last_point;
  for (const cv::Point& p : b) {
    const int s = side_of_path(a, p, kMargin);
    if (s == 0) continue;
    if (last != 0 && s != last) at.push_back((cv::Point2f(p) + cv::Point2f(last_point)) * 0.5f);
    last = s;
    last_point = p;
  }
  return at;
}

// A path's direction at its pixel nearest to `at`, over a few pixels either side.
cv::Point2f direction_near(const std::vector<cv::Point>& path, cv::Point2f at) {
  return cv::Point2f(path_direction(path, nearest_pixel(path, at), kDirectionSpan));
}

struct CrossingPoint {
  cv::Point2f at;
  double angle_deg;
};

// How many times two strands whose paths meet cross each other, where and at what angle:
// - once if each path's ends lie on the two sides of the other (they swap sides), at their
//   closest approach, at the angle between their fitted tangents;
// - twice if they do not, yet each path goes over to the other's far side and back (a
//   near-parallel pair twisted once round the other inside one crossing region), where they
//   change sides, at the angle of their paths there (their tangents are nearly parallel);
// - not at all otherwise, as when they touch and go on as they were, however their drawn
//   pixels happen to touch.
std::vector<CrossingPoint> crossings_between(const Passage& a, const Passage& b, cv::Point2f centre) {
  if (a.path.size() < 2 || b.path.size() < 2) return {};
  if (side_of_path(a.path, b.path.front()) * side_of_path(a.path, b.path.back()) < 0 &&
      side_of_path(b.path, a.path.front()) * side_of_path(b.path, a.path.back()) < 0)
    return {{closest_approach(a.path, b.path, centre), line_angle_deg(direction(a), direction(b))}};
  const std::vector<cv::Point2f> b_over = side_changes(a.path, b.path), a_over = side_changes(b.path, a.path);
  if (b_over.size() < 2 || a_over.size() < 2) return {};
  std::vector<CrossingPoint> out;
  for (const cv::Point2f& at : {b_over.front(), b_over.back()})
    out.push_back({at, line_angle_deg(direction_near(a.path, at), direction_near(b.path, at))});
  return out;
}

// Per crossing region, the exits where a kept DLO ends (exits no passage takes: a T's
// ending strand, a strand left alone at an odd region).
std::vector<std::vector<BranchEnd>> ending_exits(const SkeletonGraph& g, const std::vector<CrossingRegion>& regions,
                                                 const std::vector<Passage>& passages, const Traversal& tr) {
  std::vector<bool> paired(2 * g.branches.size(), false);  // per branch end
  for (const Passage& p : passages)
    for (const BranchEnd& e : {p.from, p.to}) paired[2 * e.branch + e.side] = true;
  std::vector<std::vector<BranchEnd>> out(regions.size());
  for (size_t k = 0; k < regions.size(); ++k)
    for (const BranchEnd& e : regions[k].exits)
      if (!paired[2 * e.branch + e.side] && tr.branch_dlo[e.branch] >= 0) out[k].push_back(e);
  return out;
}

// A DLO that ends at a crossing region (a T) and whose end runs on over or under a strand
// through it, its tip past that strand's path: a crossing of the two, as the truth of a
// rod ending across another has it.
struct EndCrossing {
  int crossing = -1;  // index into Detection::crossings
  int dlo = -1;       // the DLO that ends there
  bool at_front = false;  // at its centerline's first pixel (else its last)
  int passage = -1;   // the strand it crosses
};

// The shortest run of a DLO's own labels past a strand it ends across that counts as its
// stub there, in px.
constexpr float kMinStub = 2.0f;
// How far past its own strand's far side a DLO's tip must reach to be listed as crossing it
// (px). Over the nine seed sets' 6000 outside `stress` scenes and 3000 `stress` ones, the
// tips measured past it by more than 1 px were 18 true self-crossings and 4 not (all in
// `stress`, tips of merged rods); T's touching their own rod measured -0.7 to +0.4 px, and
// true crossings from +0.1 px. At 2 px, 4 of the 18 were lost. The measure moves by about a
// pixel with the image's orientation (a tip at its strand's axis: 0.39 px, and 1.38 px
// flipped), so a tip near the margin may be listed in one orientation only.
constexpr float kSelfTipMargin = 1.0f;

// Adds to det.crossings each crossing of an open DLO's end with a strand through the region
// where that DLO ends (at an exit no passage takes): where its last 6 r px of centerline
// meet the strand's path and its tip lies past it. The centerline's tip says little there:
// extend_ends runs it on through the other strand to the mask's edge. The labels say more:
// the DLO's own pixels (its colour, where it lies on top; its stub, where it ends just
// past the other) reach beyond the crossing by more than its radius when its tip is past
// the other's axis (a round tip lies a radius past its centerline's end). Their order is
// left to settle_tops_by_labels.
std::vector<EndCrossing> crossings_at_ends(Detection& det, const SkeletonGraph& g,
                                           const std::vector<Passage>& passages,
                                           const std::vector<CrossingRegion>& regions,
                                           const std::vector<std::vector<BranchEnd>>& ending,
                                           const Traversal& tr, const cv::Mat& labels, float r) {
  std::vector<std::vector<int>> in_region(regions.size());
  for (size_t i = 0; i < passages.size(); ++i)
    if (tr.passage_dlo[i] >= 0) in_region[passages[i].region].push_back(static_cast<int>(i));
  const size_t reach = static_cast<size_t>(std::max(4.0f, std::ceil(6 * r)));
  const cv::Rect image(0, 0, labels.cols, labels.rows);
  std::vector<EndCrossing> out;
  for (size_t k = 0; k < regions.size(); ++k) {
    if (in_region[k].empty()) continue;
    for (const BranchEnd& e : ending[k]) {
      const int d = tr.branch_dlo[e.branch];
      const Dlo& dlo = det.dlos[d];
      const Branch& b = g.branches[e.branch];
      if (dlo.closed || dlo.centerline.size() < 3 || b.pixels.empty()) continue;
      // The end of the DLO nearer the exit's pixel next to the region.
      const cv::Point2f at(e.side == 0 ? b.pixels.front() : b.pixels.back());
      const cv::Point2f d_front = cv::Point2f(dlo.centerline.front()) - at;
      const cv::Point2f d_back = cv::Point2f(dlo.centerline.back()) - at;
      const bool at_front = d_front.dot(d_front) < d_back.dot(d_back);
      const size_t n = std::min(reach, dlo.centerline.size());
      std::vector<cv::Point> tail(n);  // towards the tip
      std::vector<float> tail_radius(n);
      for (size_t i = 0; i < n; ++i) {
        const size_t j = at_front ? n - 1 - i : dlo.centerline.size() - n + i;
        tail[i] = dlo.centerline[j];
        tail_radius[i] = dlo.radius[j];
      }
      const float own_radius = middle_value(tail_radius);
      const cv::Point2f ahead = unit(cv::Point2f(tail.back() - tail.front()));
      for (int p : in_region[k]) {
        const Passage& ps = passages[p];
        if (!paths_meet(tail, ps.path)) continue;
        if (side_of_path(ps.path, tail.front()) * side_of_path(ps.path, tail.back()) >= 0) continue;
        const cv::Point2f x = closest_approach(tail, ps.path, regions[k].centre);
        const cv::Point2f across = unit(direction_near(ps.path, x));
        // How far the DLO's own pixels reach ahead of the crossing, within the mask: to the
        // end of its last run of them there, the one from the crossing or, beyond the other
        // strand, its stub (a run at least kMinStub long, or cut short by the image's border:
        // not a stray pixel of its label at the other's edge).
        float reached = 0, run_start = -1;
        for (float t = 0; t <= 8 * r; t += 0.5f) {
          const cv::Point2f q = x + ahead * t;
          const cv::Point c(static_cast<int>(std::lround(q.x)), static_cast<int>(std::lround(q.y)));
          if (!image.contains(c)) {
            if (run_start >= 0) reached = t - 0.5f;
            break;
          }
          const uint16_t label = labels.at<uint16_t>(c);
          if (label == 0) break;
          if (label != d + 1) {
            run_start = -1;
            continue;
          }
          if (run_start < 0) run_start = t;
          if (run_start == 0 || t - run_start >= kMinStub) reached = t;
        }
        // The DLO's tip on its own strand (a loop closing at its end): one label, so the run
        // holds the strand's pixels too, reaching its far side (own_radius / sin of the
        // angle along `ahead`). Past it by kSelfTipMargin, the tip pokes through: its
        // centerline ends past the strand's. (A tip that leaves the image before that is not
        // listed: where the strand runs along the border its far side is not seen.)
        const bool self = tr.passage_dlo[p] == d;
        const float sine = std::abs(ahead.cross(across));
        const float needed = self ? own_radius / std::max(sine, 0.25f) + kSelfTipMargin : own_radius;
        if (reached <= needed) continue;
        Crossing c;
        c.location = x;
        c.angle_deg = line_angle_deg(ahead, across);
        c.dlos = {tr.passage_dlo[p], d};
        out.push_back({static_cast<int>(det.crossings.size()), d, at_front, p});
        det.crossings.push_back(std::move(c));
      }
    }
  }
  return out;
}

// Dlo::crossings: per DLO, those of its passages in traversal order (crossings_of, per
// passage), with the crossings at its ends first and last and those of other DLOs' ends
// after the passage they cross.
void list_dlo_crossings(Detection& det, const Traversal& tr, const std::vector<std::vector<int>>& crossings_of,
                        const std::vector<EndCrossing>& at_ends) {
  for (size_t d = 0; d < det.dlos.size(); ++d) {
    std::vector<int>& list = det.dlos[d].crossings;
    for (const EndCrossing& x : at_ends)
      if (x.dlo == static_cast<int>(d) && x.at_front) list.push_back(x.crossing);
    for (int p : tr.dlo_passages[d]) {
      list.insert(list.end(), crossings_of[p].begin(), crossings_of[p].end());
      for (const EndCrossing& x : at_ends)
        if (x.passage == p) list.push_back(x.crossing);
    }
    for (const EndCrossing& x : at_ends)
      if (x.dlo == static_cast<int>(d) && !x.at_front) list.push_back(x.crossing);
  }
}

// Fills Detection::crossings and, per passage, the crossings it takes part in
// (`crossings_of`), and lists the strands to draw on top. A crossing is two strands whose
// paths through a crossing region meet and cross over
// (crossings_between): a region where three strands cross (a triple point) holds three, one
// where two strands touch without crossing holds none, and one where two twist once round
// each other holds two. So the crossings found do not depend on how nearby junctions were
// grouped into regions. Within a region the order is the region's (top first), until
// settle_tops_by_labels reads each crossing's top from the labels.
std::vector<TopStrand> record_crossings(Detection& det, const std::vector<Passage>& passages,
                                        const std::vector<CrossingRegion>& regions,
                                        const Traversal& tr,
                                        const std::vector<std::vector<int>>& ordered,
                                        std::vector<std::vector<int>>& crossings_of) {
  std::vector<TopStrand> tops;
  crossings_of.assign(passages.size(), {});
  // A passage routed round a loop meets the region's other strands along its loop only.
  std::vector<Passage> loop_part(passages.size());
  for (size_t p = 0; p < passages.size(); ++p) {
    const Passage& ps = passages[p];
    if (ps.loop_begin < 0) continue;
    loop_part[p] = ps;
    loop_part[p].path.assign(ps.path.begin() + ps.loop_begin, ps.path.begin() + ps.loop_end + 1);
    loop_part[p].from_tangent.direction = -start_direction(loop_part[p].path, kDirectionSpan);
    loop_part[p].to_tangent.direction = end_direction(loop_part[p].path, kDirectionSpan);
  }
  const auto strand = [&](int p) -> const Passage& {
    return passages[p].loop_begin >= 0 ? loop_part[p] : passages[p];
  };
  for (const std::vector<int>& list : ordered) {
    std::vector<int> strands;
    for (int p : list)
      if (tr.passage_dlo[p] >= 0) strands.push_back(p);
    for (int p : strands) {
      if (passages[p].loop_begin < 0) continue;
      // The rod's crossing with itself: where its way in and way out come closest.
      const Passage& ps = passages[p];
      const std::vector<cv::Point> way_in(ps.path.begin(), ps.path.begin() + ps.loop_begin + 1),
          way_out(ps.path.begin() + ps.loop_end, ps.path.end());
      Crossing c;
      c.location = closest_approach(way_in, way_out, regions[ps.region].centre);
      c.angle_deg = line_angle_deg(direction_near(way_in, c.location), direction_near(way_out, c.location));
      c.dlos = {tr.passage_dlo[p], tr.passage_dlo[p]};
      crossings_of[p].push_back(static_cast<int>(det.crossings.size()));
      det.crossings.push_back(std::move(c));
    }
    if (strands.size() < 2) continue;
    const cv::Point2f centre = regions[passages[strands[0]].region].centre;
    for (size_t i = 0; i < strands.size(); ++i)
      for (size_t j = i + 1; j < strands.size(); ++j) {
        const Passage &top = strand(strands[i]), &under = strand(strands[j]);
        if (!paths_meet(top.path, under.path)) continue;
        for (const CrossingPoint& x : crossings_between(top, under, centre)) {
          Crossing c;
          c.location = x.at;
          c.angle_deg = x.angle_deg;
          c.dlos = {tr.passage_dlo[strands[i]], tr.passage_dlo[strands[j]]};
          for (int p : {strands[i], strands[j]}) crossings_of[p].push_back(static_cast<int>(det.crossings.size()));
          det.crossings.push_back(std::move(c));
        }
      }
    for (size_t i = strands.size() - 1; i-- > 0;) {  // bottom to top, the bottom one not drawn
      const Passage& p = passages[strands[i]];
      tops.push_back({tr.passage_dlo[strands[i]], p.path, p.radius});
    }
  }
  // A loop's own crossing is met on the way in and again on the way out.
  for (size_t p = 0; p < passages.size(); ++p)
    if (passages[p].loop_begin >= 0 && !crossings_of[p].empty())
      crossings_of[p].push_back(crossings_of[p].front());
  return tops;
}

// A strand that ends at a crossing region (exit `e`, tangent `t`) may run on along a strand
// leaving the region straight ahead of it, lying at its side or half under it (a shallow
// crossing, then the two side by side). Its pixels there show its colour, but they are
// nearer the other strand's centerline. So a colour zone with the region's colours (added
// to `zones`) runs along the other DLO's centerline from the region, up to `max_length` px,
// while the mask there is at least as wide as the ending strand: where it is narrower the
// ending strand cannot lie alongside, and after a gap of 4 of its radii it has ended or
// lies wholly under the other. The zone relabels only pixels of the region's DLOs: a DLO
// from elsewhere, of one of their colours, may lie across or along the band (relabelling
// those too broke more crossings on held-out scenes than it mended).
void zones_along_bands(std::vector<ColourZone>& zones, const SkeletonGraph& g, const std::vector<Passage>& passages,
                       const Detection& det, const Traversal& tr, const BranchEnd& e,
                       const BranchTangent& t, int region, double max_length) {
  const Branch& own = g.branches[e.branch];
  if (own.radius.empty()) return;
  const float single = middle_value(own.radius);
  const int max_gap = static_cast<int>(std::lround(4 * single));
  for (size_t i = 0; i < passages.size(); ++i) {
    const Passage& p = passages[i];
    if (p.region != region || tr.passage_dlo[i] < 0) continue;
    const Dlo& other = det.dlos[tr.passage_dlo[i]];
    const int n = static_cast<int>(other.centerline.size());
    if (n < 2) continue;
    for (const BranchTangent* ahead : {&p.from_tangent, &p.to_tangent}) {
      if (ahead->direction.dot(t.direction) > -0.5f) continue;  // turns 60 degrees or more off
      ColourZone z;
      z.colours = zones[region].colours;  // the ending DLO's among them
      z.own_pixels_only = true;
      // From the other DLO's centerline pixel nearest where it leaves the region, outwards.
      const int from = static_cast<int>(nearest_pixel(other.centerline, ahead->point));
      const int step =
          from + 1 < n && cv::Point2f(other.centerline[from + 1] - other.centerline[from]).dot(ahead->direction) > 0 ? 1 : -1;
      int gap = 0;
      for (int k = from, walked = 0; k >= 0 && k < n && gap <= max_gap && walked <= max_length; k += step, ++walked) {
        if (other.radius[k] < single) {
          ++gap;
          continue;
        }
        gap = 0;
        z.discs.push_back({other.centerline[k], other.radius[k]});
      }
      zones.push_back(std::move(z));
    }
  }
}

// One colour zone per crossing region (refine_labels_by_colour skips those fewer than two
// DLOs meet in): discs over its inner branches and junctions (radius: the mask's half width
// there) and over the paths drawn through it, and each DLO's colour at the exits it takes
// or ends at. A DLO ending at a crossing (a T) most often ends on top of the strand there
// or just past it: where its colour shows over the other's, those pixels are its own.
// Where it runs on alongside a strand leaving the region, a zone with the region's colours
// runs along that strand (zones_along_bands).
std::vector<ColourZone> colour_zones(const SkeletonGraph& g, const std::vector<CrossingRegion>& regions,
                                     const std::vector<Passage>& passages,
                                     const std::vector<std::vector<BranchEnd>>& ending, const Detection& det,
                                     const Traversal& tr, TangentCache& tangents, double max_band_length) {
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
    for (const BranchEnd& e : ending[r]) {
      const BranchTangent t = tangents.of({e})[0];
      if (t.has_colour) z.colours.push_back({tr.branch_dlo[e.branch], t.colour});
    }
    for (int b : regions[r].inner_branches) {
      const Branch& br = g.branches[b];
      for (size_t k = 0; k < br.pixels.size(); k += 2) z.discs.push_back({br.pixels[k], br.radius[k]});
    }
    float widest = 0;
    for (const auto& [c, radius] : z.discs) widest = std::max(widest, radius);
    for (int n : regions[r].nodes) z.discs.push_back({cv::Point(g.nodes[n].centre), widest});
  }
  for (size_t r = 0; r < regions.size(); ++r)
    for (const BranchEnd& e : ending[r]) {
      const BranchTangent t = tangents.of({e})[0];
      if (t.has_colour) zones_along_bands(zones, g, passages, det, tr, e, t, static_cast<int>(r), max_band_length);
    }
  return zones;
}

// The crossing list says which strand is on top as the labels show it: at each crossing of
// two DLOs, the one whose label holds more of the disc of radius r / 2 around it goes first.
// The order a crossing region gives all its strands is a coarser cue: the labels are
// refined by colour pixel by pixel, and of two strands crossing twice in one region each may
// be on top once (a twisted pair).
void settle_tops_by_labels(std::vector<Crossing>& crossings, const cv::Mat& labels, float r) {
  const int k = std::max(1, static_cast<int>(std::lround(r / 2)));
  for (Crossing& c : crossings) {
    if (c.dlos.size() != 2 || c.dlos[0] == c.dlos[1]) continue;
    const cv::Point at(static_cast<int>(std::lround(c.location.x)), static_cast<int>(std::lround(c.location.y)));
    int first = 0, second = 0;
    for (int y = std::max(0, at.y - k); y <= std::min(labels.rows - 1, at.y + k); ++y) {
      const uint16_t* row = labels.ptr<uint16_t>(y);
      for (int x = std::max(0, at.x - k); x <= std::min(labels.cols - 1, at.x + k); ++x) {
        if ((x - at.x) * (x - at.x) + (y - at.y) * (y - at.y) > k * k) continue;
        first += row[x] == c.dlos[0] + 1;
        second += row[x] == c.dlos[1] + 1;
      }
    }
    if (second > first) std::swap(c.dlos[0], c.dlos[1]);
  }
}

// Every DetectorConfig field with its accepted range: one table for the JSON reader and for
// detect()'s own check.
struct ConfigField {
  const char* name;
  double DetectorConfig::*member;
  double lo, hi;
};
constexpr ConfigField kConfigFields[] = {
    {"radius_cap", &DetectorConfig::radius_cap, 0, 100},
    {"min_dlo_length_radii", &DetectorConfig::min_dlo_length_radii, 0, 1000},
    {"cut_radii", &DetectorConfig::cut_radii, 0, 100},
    {"fit_radii", &DetectorConfig::fit_radii, 0.5, 100},
    {"merge_radii", &DetectorConfig::merge_radii, 0, 100},
    {"epsilon_radii", &DetectorConfig::epsilon_radii, 0, 1000},
    {"wide_radii", &DetectorConfig::wide_radii, 0, 1000},
    {"through_radii", &DetectorConfig::through_radii, 0, 1000},
    {"colour_weight", &DetectorConfig::colour_weight, 0, 100},
    {"width_weight", &DetectorConfig::width_weight, 0, 100},
    {"loop_closing_cost", &DetectorConfig::loop_closing_cost, 0, 1000},
    {"loop_reopen_cost", &DetectorConfig::loop_reopen_cost, 0, 1000},
    {"loop_reopen_own_colour_cost", &DetectorConfig::loop_reopen_own_colour_cost, 0, 1000},
    {"loop_cross_margin", &DetectorConfig::loop_cross_margin, 0, 1000},
    {"small_loop_radii", &DetectorConfig::small_loop_radii, 0, 1000},
    {"loop_route_radii", &DetectorConfig::loop_route_radii, 0, 1000},
    {"merge_gain", &DetectorConfig::merge_gain, 0, 1000},
    {"lone_y_cost", &DetectorConfig::lone_y_cost, 0, 1000},
    {"fold_energy", &DetectorConfig::fold_energy, 0, 1000},
    {"unlike_end_energy", &DetectorConfig::unlike_end_energy, 0, 1000},
    {"border_fold_energy", &DetectorConfig::border_fold_energy, 0, 1000},
    {"colour_fold_energy", &DetectorConfig::colour_fold_energy, 0, 1000},
    {"colour_label_margin", &DetectorConfig::colour_label_margin, 0, 1000},
    {"side_by_side_radii", &DetectorConfig::side_by_side_radii, 0, 1000},
    {"route_min_exits", &DetectorConfig::route_min_exits, 0, 1000},
    {"route_weight", &DetectorConfig::route_weight, 0, 100},
    {"cluster_lightness", &DetectorConfig::cluster_lightness, 0, 100}};

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

// The share of the skeleton's length whose radius bounds r (DetectorConfig::radius_cap).
constexpr double kTypicalShare = 0.95;

// How many pixels in a row a passage's Hermite curve may run off the mask before it is
// re-routed along the mask (keep_passages_on_mask): a curve through an ordinary crossing
// may shave an edge by a pixel or two. Over the nine seed sets (centre weight 4), 2 mended
// the most `stress` crossings (3378 -> 3228 failures; a radius: 3260; 10 px: 3263), the
// other presets alike.
constexpr float kMaxOffMask = 2.f;

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
    r = measure_radii(g, mask);
    if (config.radius_cap > 0) {
      const float typical = length_quantile_radius(g, kTypicalShare);
      if (typical > 0) r = std::min(r, static_cast<float>(config.radius_cap) * typical);
    }
    r = std::max(1.0f, r);
    return g;
  });
  const ColourSource colour{config.colour_weight > 0 ? bgr : cv::Mat(), r};
  const double spur_length = 2 * r;  // the paper's delta: split ends, and forked tips' prongs
  stage("prune", [&] {
    return prune_split_ends(graph, spur_length, mask.size(), colour) +
           cut_folds_at_border(graph, config.fit_radii * r, mask.size(), config.border_fold_energy) +
           cut_folds_between_colours(graph, config.fit_radii * r, colour, config.colour_fold_energy);
  });
  stage("strands", [&] { return split_side_by_side(graph, mask, config.side_by_side_radii * r); });
  // Exit tangents and colours depend on their own branch only: computed once, on demand,
  // for junction grouping and pairing alike.
  const PairingSetup pairing{config.cut_radii * r, config.fit_radii * r, bgr,
                             {config.colour_weight, config.width_weight, config.loop_closing_cost}};
  TangentCache tangents(graph, pairing);
  auto regions = stage("junctions", [&] {
    return group_junctions(graph, config.merge_radii * r, config.epsilon_radii * r,
                           config.wide_radii * r, config.through_radii * r,
                           [&](const std::vector<BranchEnd>& exits) { return tangents.least_cost(exits); },
                           config.small_loop_radii);
  });
  auto passages = stage("bending", [&] {
    const auto join_ys = [&](bool short_links) {
      return pair_lone_ys(graph, regions, tangents, config.epsilon_radii * r, config.lone_y_cost,
                          config.merge_gain, short_links);
    };
    const auto merge = [&] {
      return merge_regions_by_pairing_cost(graph, regions, tangents, config.epsilon_radii * r,
                                           config.merge_gain, config.wide_radii * r, spur_length);
    };
    join_ys(false);
    merge();
    // Merging a Y with an X leaves a region of odd exit count that the Ys' pass did not see
    // (a rod's end lying hidden along another from a Y to a crossing with a third strand),
    // and that pass joins each region once: the Ys' pass once more, and the merging its
    // joins allow. This pass takes links within epsilon too: merging leaves two odd regions
    // alone however short their link, and Y-pair matching ran before it.
    if (join_ys(true) > 0) merge();
    auto built = build_passages(regions, tangents, config.fold_energy, config.unlike_end_energy,
                                config.colour_fold_energy,
                                {static_cast<int>(config.route_min_exits), config.route_weight,
                                 static_cast<float>(config.cluster_lightness)},
                                config.loop_cross_margin);
    if (config.loop_route_radii > 0)
      route_round_inner_loops(built, regions, tangents, config.loop_route_radii * r);
    keep_passages_on_mask(built, mask, r, kMaxOffMask);
    return built;
  });
  Traversal traversal = stage("traverse", [&] {
    Traversal t = traverse(graph, passages, config.min_dlo_length_radii * r);
    // Each re-pairing makes one closed DLO part of an open one.
    for (size_t k = t.dlos.size();
         k > 0 && open_closed_loops(passages, t, pairing.weights, config.loop_reopen_cost,
                                     config.loop_reopen_own_colour_cost);
         --k) {
      keep_passages_on_mask(passages, mask, r, kMaxOffMask);
      t = traverse(graph, passages, config.min_dlo_length_radii * r);
    }
    return t;
  });
  stage("extend_ends", [&] {
    extend_ends(traversal.dlos, mask, r);
    return reach_past_crossings(traversal.dlos, mask, r);
  });
  auto ordered = stage("crossing_order", [&] {
    return order_crossings(passages, static_cast<int>(regions.size()), bgr);
  });
  det.dlos = std::move(traversal.dlos);
  std::vector<std::vector<int>> crossings_of;  // per passage
  auto tops = record_crossings(det, passages, regions, traversal, ordered, crossings_of);
  const std::vector<std::vector<BranchEnd>> ending = ending_exits(graph, regions, passages, traversal);
  det.labels = stage("instance_mask", [&] {
    cv::Mat labels = instance_labels(mask, det.dlos, tops);
    if (!bgr.empty() && config.colour_weight > 0 && config.colour_label_margin > 0)
      refine_labels_by_colour(labels, mask, bgr, colour_zones(graph, regions, passages, ending, det, traversal, tangents,
                                                                config.wide_radii * r),
                              config.colour_label_margin, kColourLabelReach * config.colour_label_margin);
    list_dlo_crossings(det, traversal, crossings_of,
                       crossings_at_ends(det, graph, passages, regions, ending, traversal, labels, r));
    settle_tops_by_labels(det.crossings, labels, r);
    return labels;
  });
  return det;
}

}  // namespace mbest

#include "mbest/synth/scene.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include <opencv2/imgproc.hpp>

#include "mbest/synth/rod.h"

namespace mbest::synth {
namespace {

constexpr double kDeg = M_PI / 180;

double draw(Rng& rng, const Range& r) { return rng.uniform(r.lo, r.hi); }

// A guide curve sampled every 1 px: heading[i] is the direction from pts[i] to pts[i+1].
struct Guide {
  std::vector<double> heading;
  std::vector<cv::Point2d> pts;
  std::vector<Pin> pins;  // constraints beyond the evenly spaced position pins
  double length() const { return static_cast<double>(heading.size()); }
};

void integrate(Guide& g, cv::Point2d start) {
  g.pts.assign(1, start);
  for (double h : g.heading) g.pts.push_back(g.pts.back() + cv::Point2d(std::cos(h), std::sin(h)));
}

void transform(Guide& g, double rotate, cv::Point2d anchor_from, cv::Point2d anchor_to) {
  const double c = std::cos(rotate), s = std::sin(rotate);
  auto map = [&](cv::Point2d p) {
    const cv::Point2d d = p - anchor_from;
    return anchor_to + cv::Point2d(c * d.x - s * d.y, s * d.x + c * d.y);
  };
  for (double& h : g.heading) h += rotate;
  for (cv::Point2d& p : g.pts) p = map(p);
  for (Pin& pin : g.pins) {
    if (pin.has_position) pin.position = map(pin.position);
    if (pin.has_heading) pin.heading += rotate;
  }
}

// A smooth random heading function of n steps: a few sine modes whose number and
// amplitude grow with complexity, plus half the natural curvature's steady turning.
std::vector<double> random_heading(Rng& rng, int n, double complexity, double k0) {
  const int modes = 1 + static_cast<int>(std::lround(complexity * 4));
  std::vector<double> amp(modes), freq(modes), phase(modes);
  const double cycles_per_px = 1.0 / 700;  // a wave per ~700 px at the top mode
  for (int m = 0; m < modes; ++m) {
    freq[m] = 2 * M_PI * cycles_per_px * (m + 1) * rng.uniform(0.6, 1.4);
    amp[m] = rng.normal(0, (0.2 + 0.8 * complexity) / (m + 1.0));
    phase[m] = rng.uniform(0, 2 * M_PI);
  }
  std::vector<double> h(n);
  for (int i = 0; i < n; ++i) {
    double v = 0.5 * k0 * i;
    for (int m = 0; m < modes; ++m) v += amp[m] * std::sin(freq[m] * i + phase[m]);
    h[i] = v;
  }
  return h;
}

// Adds a loop (the planar elastica's loop: heading 4 atan(exp(s / lambda))) at step `at`,
// and pins its ends' positions and headings so the solved rod keeps it.
void add_loop(Guide& g, int at, double lambda, int sign) {
  for (size_t i = 0; i < g.heading.size(); ++i) {
    const double t = (static_cast<double>(i) - at) / lambda;
    g.heading[i] += sign * 4 * std::atan(std::exp(t));
  }
}

void pin_loop(Guide& g, int at, double lambda) {
  for (double k : {-3.0, 0.0, 3.0}) {
    const int i = std::clamp(at + static_cast<int>(k * lambda), 1, static_cast<int>(g.heading.size()) - 1);
    Pin p;
    p.s = i;
    p.has_position = true;
    p.position = g.pts[i];
    p.has_heading = true;
    p.heading = 0.5 * (g.heading[i - 1] + g.heading[i]);
    g.pins.push_back(p);
  }
}

Pin pin_at(const Guide& g, int i, bool heading) {
  Pin p;
  i = std::clamp(i, 0, static_cast<int>(g.heading.size()));
  p.s = i;
  p.has_position = true;
  p.position = g.pts[i];
  if (heading) {
    const int a = std::max(i - 1, 0), b = std::min<int>(i, g.heading.size() - 1);
    p.has_heading = true;
    p.heading = 0.5 * (g.heading[a] + g.heading[b]);
  }
  return p;
}

// Solves the elastic rod that follows the guide's pins; the guide itself satisfies every
// pin, so the constraints are feasible and the solve only removes bending.
SceneRod solve_guided(const Guide& g, double complexity, double k0, bool closed, double width) {
  RodProblem p;
  p.length = g.length();
  p.segments = std::clamp(static_cast<int>(p.length / 12), 24, 110);
  p.natural_curvature = k0;
  p.closed = closed;
  const double h = p.length / p.segments;
  for (int k = 0; k < p.segments; ++k) {
    const int i = std::clamp(static_cast<int>((k + 0.5) * h), 0, static_cast<int>(g.heading.size()) - 1);
    p.initial_heading.push_back(g.heading[i]);
  }
  p.initial_start = g.pts.front();
  // Evenly spaced position pins: more of them for a more complex rod.
  const int n_pins = 2 + static_cast<int>(std::lround(complexity * 6 * p.length / 1000));
  for (int k = 0; k < n_pins && !closed; ++k) {
    p.pins.push_back(pin_at(g, static_cast<int>(std::lround(k * p.length / (n_pins - 1))), false));
  }
  if (closed) {
    for (int k = 0; k < 4; ++k) p.pins.push_back(pin_at(g, static_cast<int>(k * p.length / 4), false));
  }
  p.pins.insert(p.pins.end(), g.pins.begin(), g.pins.end());
  const RodShape shape = solve_rod(p);
  SceneRod rod;
  rod.width = width;
  rod.closed = closed;
  rod.natural_curvature = k0;
  rod.bending_energy = bending_energy(shape, k0);
  rod.centerline = sample_centerline(shape, 1.0);
  return rod;
}

struct RodDraw {
  double width, length, complexity, k0;
};

RodDraw draw_rod(const SceneConfig& sc, Rng& rng) {
  RodDraw d;
  d.width = draw(rng, sc.width_px);
  d.length = draw(rng, sc.length_px);
  d.complexity = draw(rng, sc.complexity);
  d.k0 = draw(rng, sc.natural_curvature) * (rng.chance(0.5) ? 1 : -1);
  return d;
}

// A free guide of the drawn length, with a loop at random (config.self_loop).
Guide free_guide(const SceneConfig& sc, const RodDraw& d, Rng& rng) {
  Guide g;
  const int n = std::max(4, static_cast<int>(std::lround(d.length)));
  g.heading = random_heading(rng, n, d.complexity, d.k0);
  const double phi0 = rng.uniform(0, 2 * M_PI);
  for (double& h : g.heading) h += phi0;
  int loop_at = -1;
  double lambda = 0;
  if (rng.chance(sc.self_loop) && n > 200) {
    lambda = rng.uniform(std::max(10.0, sc.loop_size.lo * d.width), std::max(14.0, sc.loop_size.hi * d.width));
    loop_at = static_cast<int>(n * rng.uniform(0.25, 0.75));
    add_loop(g, loop_at, lambda, rng.chance(0.5) ? 1 : -1);
  }
  integrate(g, {0, 0});
  if (loop_at >= 0) pin_loop(g, loop_at, lambda);
  return g;
}

bool inside(cv::Point2d p, int w, int h) { return p.x >= 0 && p.y >= 0 && p.x < w && p.y < h; }

double inside_fraction(const std::vector<cv::Point2d>& pts, int w, int h) {
  int in = 0;
  for (const auto& p : pts) in += inside(p, w, h);
  return pts.empty() ? 0 : static_cast<double>(in) / pts.size();
}

// Places a free guide: its middle at a random point, rotated at random, leaving the
// image or not as drawn (best effort for rods too long to fit).
void place_free(Guide& g, const SceneConfig& sc, Rng& rng) {
  const bool leave = rng.chance(sc.leave_image);
  const cv::Point2d mid = g.pts[g.pts.size() / 2];
  for (int attempt = 0; attempt < 16; ++attempt) {
    const cv::Point2d to(rng.uniform(0.1, 0.9) * sc.width, rng.uniform(0.1, 0.9) * sc.height);
    Guide t = g;
    transform(t, rng.uniform(0, 2 * M_PI), mid, to);
    const double f = inside_fraction(t.pts, sc.width, sc.height);
    const bool leaves = f < 1;
    if (f > 0.6 && leaves == leave) {
      g = std::move(t);
      return;
    }
    if (attempt == 15) g = std::move(t);
  }
}

// Rotates and moves the guide so that its step `at` lies at `point` with heading `theta`,
// and pins it there.
void anchor(Guide& g, int at, cv::Point2d point, double theta) {
  transform(g, theta - g.heading[at], g.pts[at], point);
  g.pins.push_back(pin_at(g, at, true));
}

// A guide that runs beside `other` (1 px centerline) at centre distance `offset` for
// `stretch` px, then goes its own way at both ends; the shared stretch is pinned densely.
Guide parallel_guide(const SceneConfig& sc, const SceneRod& other, const RodDraw& d,
                     double offset, Rng& rng) {
  const int n_other = static_cast<int>(other.centerline.size());
  int len = static_cast<int>(std::min(draw(rng, sc.parallel_length_px), 0.6 * n_other));
  len = std::max(len, 10);
  // Prefer a stretch inside the image.
  int i0 = 0;
  for (int attempt = 0; attempt < 20; ++attempt) {
    i0 = rng.uniform_int(2, std::max(2, n_other - len - 3));
    if (inside(other.centerline[i0], sc.width, sc.height) &&
        inside(other.centerline[std::min(i0 + len, n_other - 1)], sc.width, sc.height)) break;
  }
  const int side = rng.chance(0.5) ? 1 : -1;
  std::vector<cv::Point2d> q;
  for (int i = i0; i <= std::min(i0 + len, n_other - 2); ++i) {
    cv::Point2d t = other.centerline[i + 1] - other.centerline[i - 1];
    t /= std::max(1e-9, cv::norm(t));
    q.push_back(other.centerline[i] + side * offset * cv::Point2d(-t.y, t.x));
  }
  // Headings of the offset stretch at 1 px steps (unwrapped).
  std::vector<double> stretch;
  std::vector<cv::Point2d> stretch_pts{q.front()};
  double carry = 0;
  for (size_t i = 0; i + 1 < q.size(); ++i) {
    cv::Point2d seg = q[i + 1] - q[i];
    double l = cv::norm(seg) + carry;
    const double h = std::atan2(seg.y, seg.x);
    while (l >= 1) {
      double u = stretch.empty() ? h : stretch.back() + std::remainder(h - stretch.back(), 2 * M_PI);
      stretch.push_back(u);
      l -= 1;
    }
    carry = l;
  }
  if (stretch.empty()) stretch.push_back(0);
  const double total = std::max(d.length, stretch.size() + 100.0);
  const int pre = static_cast<int>((total - stretch.size()) * rng.uniform(0.2, 0.8));
  const int post = static_cast<int>(total - stretch.size()) - pre;
  std::vector<double> a = random_heading(rng, pre + 1, d.complexity, 0);
  std::vector<double> b = random_heading(rng, post + 1, d.complexity, 0);
  Guide g;
  for (int i = 0; i < pre; ++i) g.heading.push_back(stretch.front() + a[i] - a[pre]);
  g.heading.insert(g.heading.end(), stretch.begin(), stretch.end());
  for (int i = 1; i <= post; ++i) g.heading.push_back(stretch.back() + b[i] - b[0]);
  integrate(g, {0, 0});
  transform(g, 0, g.pts[pre], q.front());
  for (int i = pre; i <= pre + static_cast<int>(stretch.size()); i += 20) g.pins.push_back(pin_at(g, i, true));
  g.pins.push_back(pin_at(g, pre + static_cast<int>(stretch.size()), true));
  return g;
}

Guide ring_guide(const SceneConfig& sc, const RodDraw& d, Rng& rng) {
  const double diameter = draw(rng, sc.ring_diameter_px);
  const int n = std::max(12, static_cast<int>(std::lround(M_PI * diameter)));
  Guide g;
  const double phi0 = rng.uniform(0, 2 * M_PI);
  const double a2 = rng.normal(0, 0.15 + 0.3 * d.complexity), p2 = rng.uniform(0, 2 * M_PI);
  const double a3 = rng.normal(0, 0.1 + 0.2 * d.complexity), p3 = rng.uniform(0, 2 * M_PI);
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * i / n;
    g.heading.push_back(phi0 + t + a2 * std::sin(2 * t + p2) + a3 * std::sin(3 * t + p3));
  }
  integrate(g, {0, 0});
  const cv::Point2d centre(rng.uniform(0.2, 0.8) * sc.width, rng.uniform(0.2, 0.8) * sc.height);
  cv::Point2d mean(0, 0);
  for (const auto& p : g.pts) mean += p;
  mean /= static_cast<double>(g.pts.size());
  transform(g, 0, mean, centre);
  return g;
}

const std::vector<cv::Vec3b>& palette_colors(const std::string& palette) {
  // The three tube colours of the real dev set (pink, yellow-green, teal) and S1's salmon
  // tube, RGB: the mean colour of the tubes' cores measured on mbest-real (S1-S3), divided
  // by 1.12, the gain of the tube shading at the core, so rendered cores match.
  static const std::vector<cv::Vec3b> real = {{161, 82, 89}, {138, 150, 82}, {79, 131, 105}, {170, 125, 112}};
  static const std::vector<cv::Vec3b> cables = {
      {30, 30, 34},  {225, 225, 220}, {128, 128, 128}, {175, 35, 35}, {35, 70, 170},
      {215, 185, 45}, {40, 135, 65},  {225, 115, 35},  {110, 72, 42}};
  return palette == "cables" ? cables : real;
}

cv::Vec3b jitter(const cv::Vec3b& c, Rng& rng, double amount) {
  cv::Vec3b out;
  const double gain = rng.uniform(1 - amount, 1 + amount);
  for (int k = 0; k < 3; ++k) out[k] = cv::saturate_cast<uchar>(c[k] * gain + rng.normal(0, 4));
  return out;
}

std::vector<cv::Vec3b> draw_colors(const std::string& palette, int n, Rng& rng) {
  std::vector<cv::Vec3b> out;
  if (palette == "random") {
    for (int i = 0; i < n; ++i) {
      cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(rng.uniform_int(0, 179), rng.uniform_int(90, 255),
                                             rng.uniform_int(110, 255)));
      cv::Mat rgb;
      cv::cvtColor(hsv, rgb, cv::COLOR_HSV2RGB);
      out.push_back(rgb.at<cv::Vec3b>(0, 0));
    }
    return out;
  }
  std::vector<cv::Vec3b> pool = palette_colors(palette);
  // The real set's first three colours are distinct per scene; past the pool, reuse.
  const int distinct = palette == "real" ? 3 : static_cast<int>(pool.size());
  std::vector<int> order(distinct);
  for (int i = 0; i < distinct; ++i) order[i] = i;
  for (int i = distinct - 1; i > 0; --i) std::swap(order[i], order[rng.uniform_int(0, i)]);
  for (int i = 0; i < n; ++i) {
    int k = order[i % distinct];
    if (palette == "real" && n == 1 && rng.chance(0.4)) k = 3;  // the salmon tube of S1
    // The real tubes' brightness varies by about +-15 % between scenes (the lights).
    out.push_back(jitter(pool[k], rng, palette == "real" ? 0.15 : 0.06));
  }
  return out;
}

std::vector<SceneRod> compose_rods(const SceneConfig& sc, Rng& rng) {
  const int n = rng.uniform_int(static_cast<int>(sc.rods.lo), static_cast<int>(sc.rods.hi));
  std::vector<SceneRod> rods;
  auto solve = [&](Guide g, const RodDraw& d, bool closed) {
    rods.push_back(solve_guided(g, d.complexity, d.k0, closed, d.width));
  };
  for (int t = 0; t < sc.triple_points && static_cast<int>(rods.size()) + 3 <= n; ++t) {
    const cv::Point2d p(rng.uniform(0.25, 0.75) * sc.width, rng.uniform(0.25, 0.75) * sc.height);
    const double base = rng.uniform(0, M_PI);
    for (int k = 0; k < 3; ++k) {
      const RodDraw d = draw_rod(sc, rng);
      Guide g = free_guide(sc, d, rng);
      const int at = static_cast<int>(g.length() * rng.uniform(0.3, 0.7));
      anchor(g, at, p, base + k * 60 * kDeg + rng.normal(0, 5 * kDeg));
      solve(g, d, false);
    }
  }
  for (int r = 0; r < sc.rings && static_cast<int>(rods.size()) < n; ++r) {
    const RodDraw d = draw_rod(sc, rng);
    solve(ring_guide(sc, d, rng), d, true);
  }
  auto open_rod = [&]() -> int {
    std::vector<int> open;
    for (size_t i = 0; i < rods.size(); ++i) {
      if (!rods[i].closed && rods[i].centerline.size() > 60) open.push_back(static_cast<int>(i));
    }
    return open.empty() ? -1 : open[rng.uniform_int(0, static_cast<int>(open.size()) - 1)];
  };
  auto free_rod = [&]() {
    const RodDraw d = draw_rod(sc, rng);
    Guide g = free_guide(sc, d, rng);
    place_free(g, sc, rng);
    solve(g, d, false);
  };
  for (int p = 0; p < sc.parallel_strands && static_cast<int>(rods.size()) < n; ++p) {
    int other = open_rod();
    if (other < 0) {
      free_rod();
      if (static_cast<int>(rods.size()) >= n) break;
      other = static_cast<int>(rods.size()) - 1;
    }
    const RodDraw d = draw_rod(sc, rng);
    const double offset = 0.5 * (rods[other].width + d.width) + draw(rng, sc.parallel_gap_px);
    solve(parallel_guide(sc, rods[other], d, offset, rng), d, false);
  }
  for (int c = 0; c < sc.planned_crossings && static_cast<int>(rods.size()) < n; ++c) {
    int other = open_rod();
    if (other < 0) {
      free_rod();
      if (static_cast<int>(rods.size()) >= n) break;
      other = static_cast<int>(rods.size()) - 1;
    }
    const auto& line = rods[other].centerline;
    int i = 1;
    for (int attempt = 0; attempt < 20; ++attempt) {
      i = rng.uniform_int(1, static_cast<int>(line.size()) - 2);
      const cv::Point2d q = line[i];
      if (q.x > 40 && q.y > 40 && q.x < sc.width - 40 && q.y < sc.height - 40) break;
    }
    const cv::Point2d t = line[i + 1] - line[i - 1];
    const double angle = draw(rng, sc.crossing_angle_deg) * kDeg * (rng.chance(0.5) ? 1 : -1);
    const RodDraw d = draw_rod(sc, rng);
    Guide g = free_guide(sc, d, rng);
    const int at = static_cast<int>(g.length() * rng.uniform(0.3, 0.7));
    anchor(g, at, line[i], std::atan2(t.y, t.x) + angle + (rng.chance(0.5) ? M_PI : 0));
    solve(g, d, false);
  }
  while (static_cast<int>(rods.size()) < n) free_rod();
  return rods;
}

}  // namespace

std::vector<CrossingAnnotation> find_crossings(const std::vector<SceneRod>& rods, int width,
                                               int height) {
  struct Seg {
    int rod, index;
  };
  constexpr double kCell = 16;
  const int gw = static_cast<int>(std::ceil(width / kCell)) + 2;
  std::unordered_map<long long, std::vector<Seg>> grid;
  auto segment = [&](const Seg& s, cv::Point2d* a, cv::Point2d* b) {
    const auto& c = rods[s.rod].centerline;
    *a = c[s.index];
    *b = c[(s.index + 1) % c.size()];
  };
  for (size_t r = 0; r < rods.size(); ++r) {
    const auto& c = rods[r].centerline;
    const int n_seg = static_cast<int>(c.size()) - (rods[r].closed ? 0 : 1);
    for (int i = 0; i < n_seg; ++i) {
      cv::Point2d a, b;
      segment({static_cast<int>(r), i}, &a, &b);
      if (std::max(a.x, b.x) < -1 || std::max(a.y, b.y) < -1 || std::min(a.x, b.x) > width ||
          std::min(a.y, b.y) > height) {
        continue;
      }
      const int x0 = static_cast<int>(std::floor(std::min(a.x, b.x) / kCell)) + 1;
      const int x1 = static_cast<int>(std::floor(std::max(a.x, b.x) / kCell)) + 1;
      const int y0 = static_cast<int>(std::floor(std::min(a.y, b.y) / kCell)) + 1;
      const int y1 = static_cast<int>(std::floor(std::max(a.y, b.y) / kCell)) + 1;
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) grid[static_cast<long long>(y) * gw + x].push_back({static_cast<int>(r), i});
    }
  }
  std::map<std::tuple<int, int, int, int>, CrossingAnnotation> found;
  for (const auto& [cell, segs] : grid) {
    for (size_t p = 0; p < segs.size(); ++p) {
      for (size_t q = p + 1; q < segs.size(); ++q) {
        Seg s = segs[p], t = segs[q];
        if (std::make_pair(s.rod, s.index) > std::make_pair(t.rod, t.index)) std::swap(s, t);
        if (s.rod == t.rod) {
          const int n = static_cast<int>(rods[s.rod].centerline.size());
          int gap = t.index - s.index;
          if (rods[s.rod].closed) gap = std::min(gap, n - gap);
          if (gap <= 3) continue;
        }
        cv::Point2d a, b, c, d;
        segment(s, &a, &b);
        segment(t, &c, &d);
        const cv::Point2d u = b - a, v = d - c, w = c - a;
        const double den = u.x * v.y - u.y * v.x;
        if (std::abs(den) < 1e-12) continue;
        const double tu = (w.x * v.y - w.y * v.x) / den;
        const double tv = (w.x * u.y - w.y * u.x) / den;
        // Half-open on the segment end, so a crossing at a shared vertex counts once.
        if (tu < 0 || tu >= 1 || tv < 0 || tv >= 1) continue;
        const cv::Point2d x = a + tu * u;
        if (x.x < -0.5 || x.y < -0.5 || x.x > width - 0.5 || x.y > height - 0.5) continue;
        CrossingAnnotation ca;
        ca.location = x;
        const double cosang = std::abs(u.dot(v)) / (cv::norm(u) * cv::norm(v));
        ca.angle_deg = std::acos(std::min(1.0, cosang)) / kDeg;
        ca.rod_a = s.rod + 1;
        ca.rod_b = t.rod + 1;
        const int na = static_cast<int>(rods[s.rod].centerline.size());
        const int nb = static_cast<int>(rods[t.rod].centerline.size());
        ca.arc_index_a = (s.index + (tu >= 0.5 ? 1 : 0)) % na;
        ca.arc_index_b = (t.index + (tv >= 0.5 ? 1 : 0)) % nb;
        ca.top_arc_index = ca.arc_index_a;
        found[{s.rod, s.index, t.rod, t.index}] = ca;
      }
    }
  }
  std::vector<CrossingAnnotation> out;
  for (auto& [key, c] : found) out.push_back(c);
  return out;
}

namespace {

// A rod that leaves the picture and comes back shows as two pieces no detector can join,
// yet its label would count them as one instance. Each open rod keeps only its longest
// stretch that can be seen (its disc, half a width around the centerline, touching the
// picture), so every visible rod is one connected piece. Returns false when nothing of the
// rod can be seen.
bool keep_longest_visible_run(SceneRod& rod, int width, int height) {
  const double margin = rod.width / 2 + 1;
  auto visible = [&](const cv::Point2d& p) {
    return p.x >= -margin && p.y >= -margin && p.x <= width - 1 + margin && p.y <= height - 1 + margin;
  };
  const auto& c = rod.centerline;
  size_t best_start = 0, best_len = 0;
  for (size_t i = 0; i < c.size();) {
    if (!visible(c[i])) {
      ++i;
      continue;
    }
    size_t j = i;
    while (j < c.size() && visible(c[j])) ++j;
    if (j - i > best_len) {
      best_start = i;
      best_len = j - i;
    }
    i = j;
  }
  if (best_len == 0) return false;
  if (best_len < c.size())
    rod.centerline = std::vector<cv::Point2d>(c.begin() + static_cast<long>(best_start),
                                              c.begin() + static_cast<long>(best_start + best_len));
  return true;
}

}  // namespace

Scene compose_scene(const SynthConfig& config, Rng& rng) {
  const SceneConfig& sc = config.scene;
  Scene best;
  int best_miss = -1;
  for (int attempt = 0; attempt < 12; ++attempt) {
    Scene s;
    s.width = sc.width;
    s.height = sc.height;
    s.rods = compose_rods(sc, rng);
    for (SceneRod& rod : s.rods)
      if (!rod.closed) keep_longest_visible_run(rod, s.width, s.height);
    s.crossings = find_crossings(s.rods, s.width, s.height);
    const int n = static_cast<int>(s.crossings.size());
    const int miss = n < sc.crossings.lo ? int(sc.crossings.lo) - n
                                          : (n > sc.crossings.hi ? n - int(sc.crossings.hi) : 0);
    if (best_miss < 0 || miss < best_miss) {
      best = std::move(s);
      best_miss = miss;
    }
    if (miss == 0) break;
  }
  const std::vector<cv::Vec3b> colors = draw_colors(config.render.palette, best.rods.size(), rng);
  for (size_t i = 0; i < best.rods.size(); ++i) best.rods[i].color_rgb = colors[i];
  best.base_order.resize(best.rods.size());
  for (size_t i = 0; i < best.rods.size(); ++i) best.base_order[i] = static_cast<int>(i);
  for (int i = static_cast<int>(best.rods.size()) - 1; i > 0; --i) {
    std::swap(best.base_order[i], best.base_order[rng.uniform_int(0, i)]);
  }
  for (CrossingAnnotation& c : best.crossings) {
    const bool a_on_top = rng.chance(0.5);
    c.top = a_on_top ? c.rod_a : c.rod_b;
    c.top_arc_index = a_on_top ? c.arc_index_a : c.arc_index_b;
  }
  return best;
}

}  // namespace mbest::synth

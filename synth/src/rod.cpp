#include "mbest/synth/rod.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace mbest::synth {
namespace {

// Penalty weights: position error in px and heading error in rad, against bending energy
// of order 0.01-1. Large enough that feasible pins are met to a fraction of a pixel.
constexpr double kPositionWeight = 3.0;
constexpr double kHeadingWeight = 6.0;
constexpr double kClosureWeight = 10.0;

struct Residuals {
  Eigen::VectorXd r;  // every residual: the M - 1 bending rows first
  Eigen::MatrixXd J;  // the Jacobian of the rows after the bending rows only (pins, closure);
                      // the bending rows' is constant and tridiagonal, used directly
};

// Variables: [x0, y0, phi_0 .. phi_{M-1}]. Node j (0..M) is x0 + h sum_{k<j} u(phi_k).
Residuals evaluate(const RodProblem& p, const Eigen::VectorXd& v) {
  const int m = p.segments;
  const double h = p.length / m;
  const double sqrt_h = std::sqrt(h);
  int rows = m - 1 + (p.closed ? 3 : 0);
  for (const Pin& pin : p.pins) rows += (pin.has_position ? 2 : 0) + (pin.has_heading ? 1 : 0);
  const int bend_rows = m - 1;
  Residuals out{Eigen::VectorXd::Zero(rows), Eigen::MatrixXd::Zero(rows - bend_rows, m + 2)};
  int row = 0;
  for (int k = 0; k + 1 < m; ++k, ++row) {
    out.r(row) = (v(k + 3) - v(k + 2) - h * p.natural_curvature) / sqrt_h;
  }
  // Jacobian rows are numbered from the first row after the bending rows.
  auto J = [&](int r, int c) -> double& { return out.J(r - bend_rows, c); };
  // Prefix sums of the unit tangents give every node.
  std::vector<double> cx(m + 1, 0.0), cy(m + 1, 0.0), cos_v(m), sin_v(m);
  for (int k = 0; k < m; ++k) {
    cos_v[k] = std::cos(v(k + 2));
    sin_v[k] = std::sin(v(k + 2));
    cx[k + 1] = cx[k] + h * cos_v[k];
    cy[k + 1] = cy[k] + h * sin_v[k];
  }
  for (const Pin& pin : p.pins) {
    // The pin's point on the segment polyline: segment j at fraction f.
    const int j = std::clamp(static_cast<int>(std::floor(pin.s / h)), 0, m - 1);
    const double f = std::clamp(pin.s / h - j, 0.0, 1.0);
    if (pin.has_position) {
      const double cj = cos_v[j], sj = sin_v[j];
      out.r(row) = kPositionWeight * (v(0) + cx[j] + f * h * cj - pin.position.x);
      out.r(row + 1) = kPositionWeight * (v(1) + cy[j] + f * h * sj - pin.position.y);
      J(row, 0) = kPositionWeight;
      J(row + 1, 1) = kPositionWeight;
      for (int k = 0; k < j; ++k) {
        J(row, k + 2) = -kPositionWeight * h * sin_v[k];
        J(row + 1, k + 2) = kPositionWeight * h * cos_v[k];
      }
      J(row, j + 2) = -kPositionWeight * f * h * sj;
      J(row + 1, j + 2) = kPositionWeight * f * h * cj;
      row += 2;
    }
    if (pin.has_heading) {
      // Heading linear between segment midpoints, as in sample_centerline.
      const double t = std::clamp(pin.s / h - 0.5, 0.0, m - 1.0);
      const int a = std::min(static_cast<int>(std::floor(t)), m - 1), b = std::min(a + 1, m - 1);
      const double g = t - a;
      out.r(row) = kHeadingWeight * ((1 - g) * v(a + 2) + g * v(b + 2) - pin.heading);
      J(row, a + 2) += (1 - g) * kHeadingWeight;
      J(row, b + 2) += g * kHeadingWeight;
      ++row;
    }
  }
  if (p.closed) {
    out.r(row) = (v(2) + 2 * M_PI - v(m + 1) - h * p.natural_curvature) / sqrt_h;
    J(row, 2) = 1 / sqrt_h;
    J(row, m + 1) = -1 / sqrt_h;
    out.r(row + 1) = kClosureWeight * cx[m];
    out.r(row + 2) = kClosureWeight * cy[m];
    for (int k = 0; k < m; ++k) {
      J(row + 1, k + 2) = -kClosureWeight * h * sin_v[k];
      J(row + 2, k + 2) = kClosureWeight * h * cos_v[k];
    }
  }
  return out;
}

}  // namespace

RodShape solve_rod(const RodProblem& p) {
  const int m = p.segments;
  Eigen::VectorXd v(m + 2);
  v(0) = p.initial_start.x;
  v(1) = p.initial_start.y;
  for (int k = 0; k < m; ++k) v(k + 2) = p.initial_heading.at(k);

  Residuals res = evaluate(p, v);
  double cost = res.r.squaredNorm();
  double lambda = 1e-3;
  const int bend_rows = m - 1;
  for (int iter = 0; iter < 25; ++iter) {
    // J^T J: the bending rows are a tridiagonal block, added directly; only the few pin
    // and closure rows go through a dense product.
    // Only the lower triangle of J^T J is formed: the Cholesky factorisation reads no more.
    const Eigen::MatrixXd& pin_rows = res.J;
    Eigen::MatrixXd jtj = Eigen::MatrixXd::Zero(m + 2, m + 2);
    jtj.selfadjointView<Eigen::Lower>().rankUpdate(pin_rows.transpose());
    Eigen::VectorXd g = pin_rows.transpose() * res.r.tail(res.r.size() - bend_rows);
    const double h = p.length / m;
    for (int k = 0; k < bend_rows; ++k) {
      jtj(k + 2, k + 2) += 1 / h;
      jtj(k + 3, k + 3) += 1 / h;
      jtj(k + 2, k + 3) -= 1 / h;
      jtj(k + 3, k + 2) -= 1 / h;
      const double rk = res.r(k) / std::sqrt(h);
      g(k + 3) += rk;
      g(k + 2) -= rk;
    }
    Eigen::MatrixXd a = jtj;
    a.diagonal().array() += lambda * (jtj.diagonal().array() + 1e-6);
    const Eigen::VectorXd step = a.llt().solve(-g);
    const Eigen::VectorXd trial = v + step;
    Residuals trial_res = evaluate(p, trial);
    const double trial_cost = trial_res.r.squaredNorm();
    if (trial_cost < cost) {
      const double gain = cost - trial_cost;
      v = trial;
      res = std::move(trial_res);
      cost = trial_cost;
      lambda = std::max(lambda * 0.3, 1e-7);
      if (gain < 1e-7 * (1 + cost)) break;
    } else {
      lambda *= 10;
      if (lambda > 1e8) break;
    }
  }
  RodShape shape;
  shape.length = p.length;
  shape.start = {v(0), v(1)};
  shape.closed = p.closed;
  shape.heading.assign(v.data() + 2, v.data() + 2 + m);
  return shape;
}

double bending_energy(const RodShape& shape, double k0) {
  const int m = static_cast<int>(shape.heading.size());
  const double h = shape.length / m;
  double e = 0;
  for (int k = 0; k + 1 < m; ++k) {
    const double d = shape.heading[k + 1] - shape.heading[k] - h * k0;
    e += d * d / h;
  }
  if (shape.closed) {
    const double d = shape.heading[0] + 2 * M_PI - shape.heading[m - 1] - h * k0;
    e += d * d / h;
  }
  return e;
}

std::vector<cv::Point2d> sample_centerline(const RodShape& shape, double step) {
  const int m = static_cast<int>(shape.heading.size());
  const double h = shape.length / m;
  // Heading at arc s: linear between segment midpoints (s = (k + 0.5) h).
  auto heading_at = [&](double s) {
    const double t = s / h - 0.5;
    if (shape.closed) {
      const double wraps = std::floor(t / m);
      const double tt = t - wraps * m;
      const int k = static_cast<int>(std::floor(tt)) % m;
      const double f = tt - std::floor(tt);
      const double a = shape.heading[k];
      double b = k + 1 < m ? shape.heading[k + 1] : shape.heading[0] + 2 * M_PI;
      return a + f * (b - a) + wraps * 2 * M_PI;
    }
    if (t <= 0) return shape.heading.front();
    if (t >= m - 1) return shape.heading.back();
    const int k = static_cast<int>(std::floor(t));
    const double f = t - k;
    return shape.heading[k] + f * (shape.heading[k + 1] - shape.heading[k]);
  };
  const int n = shape.closed ? std::max(3, static_cast<int>(std::lround(shape.length / step)))
                             : static_cast<int>(std::floor(shape.length / step)) + 1;
  const double ds = shape.closed ? shape.length / n : step;
  std::vector<cv::Point2d> pts;
  pts.reserve(n + 1);
  cv::Point2d x = shape.start;
  pts.push_back(x);
  const int steps = shape.closed ? n : n - 1;
  for (int i = 0; i < steps; ++i) {
    // Midpoint rule over each small step.
    const double phi = heading_at((i + 0.5) * ds);
    x += cv::Point2d(std::cos(phi), std::sin(phi)) * ds;
    pts.push_back(x);
  }
  if (shape.closed) {
    // Spread the small closure gap left by the penalty over the ring, then drop the
    // repeated start.
    const cv::Point2d gap = pts.back() - pts.front();
    for (int i = 0; i <= n; ++i) pts[i] -= gap * (static_cast<double>(i) / n);
    pts.pop_back();
  }
  return pts;
}

Complexity complexity(const std::vector<cv::Point2d>& c, double width, bool closed) {
  Complexity out;
  const int n = static_cast<int>(c.size());
  if (n < 3) return out;
  std::vector<double> kappa;
  double length = 0;
  for (int i = 0; i + 1 < n; ++i) length += cv::norm(c[i + 1] - c[i]);
  if (closed) length += cv::norm(c[0] - c[n - 1]);
  const int first = closed ? 0 : 1, last = closed ? n : n - 1;
  for (int i = first; i < last; ++i) {
    const cv::Point2d a = c[(i - 1 + n) % n], b = c[i], d = c[(i + 1) % n];
    const cv::Point2d u = b - a, w = d - b;
    const double turn = std::atan2(u.x * w.y - u.y * w.x, u.x * w.x + u.y * w.y);
    const double ds = 0.5 * (cv::norm(u) + cv::norm(w));
    kappa.push_back(ds > 0 ? turn / ds : 0);
    out.total_turning_rad += std::abs(turn);
  }
  double sum = 0, sum_sq = 0, energy = 0;
  for (double k : kappa) {
    sum += std::abs(k);
    sum_sq += k * k;
    energy += k * k;  // ds = 1 px
  }
  const double count = static_cast<double>(kappa.size());
  out.mean_abs_curvature = sum / count;
  double mean = 0;
  for (double k : kappa) mean += k;
  mean /= count;
  out.curvature_std_x_width = std::sqrt(std::max(0.0, sum_sq / count - mean * mean)) * width;
  out.normalised_bending_energy = length * energy;
  // Inflections: sign changes of curvature, ignoring near-straight stretches
  // (|k| < 1e-3 / px, a radius over 1000 px) so sampling noise does not count.
  int sign = 0;
  for (double k : kappa) {
    if (std::abs(k) < 1e-3) continue;
    const int s = k > 0 ? 1 : -1;
    if (sign != 0 && s != sign) ++out.inflections;
    sign = s;
  }
  return out;
}

}  // namespace mbest::synth

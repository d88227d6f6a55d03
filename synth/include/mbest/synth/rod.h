// Elastic rod: a discrete planar inextensible rod whose shape minimises bending energy
// (sum over joints of (turning angle - h * natural curvature)^2 / h) under pin constraints.
// The rod is stored as M segments of equal length h = length / M, each with a heading
// (radians, unwrapped, so a loop shows as a 2*pi change), starting at `start`.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "mbest/synth/annotation.h"

namespace mbest::synth {

// A constraint at arc length s (px from the start): the rod passes through `position`
// and/or has tangent direction `heading` there. Penalised, so infeasible pins are met as
// nearly as the rod's fixed length allows.
struct Pin {
  double s = 0;
  bool has_position = false;
  cv::Point2d position;
  bool has_heading = false;
  double heading = 0;  // radians, unwrapped consistently with the initial guess
};

struct RodProblem {
  double length = 0;             // px, kept exactly
  int segments = 64;             // M
  double natural_curvature = 0;  // 1/px, signed; 0 for a straight rest shape
  bool closed = false;           // a ring: the end meets the start, heading + 2*pi
  std::vector<Pin> pins;
  // Initial guess: M headings and the start point (a guide curve sampled per segment).
  std::vector<double> initial_heading;
  cv::Point2d initial_start;
};

struct RodShape {
  double length = 0;
  cv::Point2d start;
  std::vector<double> heading;  // M segment headings
  bool closed = false;
};

// Minimises bending energy + pin penalties by Levenberg-Marquardt over (start, headings).
RodShape solve_rod(const RodProblem& problem);

// Discrete bending energy sum_j (phi_{j+1} - phi_j - h k0)^2 / h (closing joint included
// for a ring). Units 1/px.
double bending_energy(const RodShape& shape, double natural_curvature);

// The centerline sampled every `step` px along the arc (heading interpolated linearly
// between segment midpoints, so curvature is piecewise constant). A ring's last sample is
// not repeated. Returns floor(length / step) + 1 points (open) or round(length/step) (ring).
std::vector<cv::Point2d> sample_centerline(const RodShape& shape, double step = 1.0);

// Complexity figures of a centerline sampled ~1 px apart (see annotation.h).
Complexity complexity(const std::vector<cv::Point2d>& centerline, double width, bool closed);

}  // namespace mbest::synth

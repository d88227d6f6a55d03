#include "mbest/synth/rod.h"

#include <cmath>

#include <gtest/gtest.h>

namespace mbest::synth {
namespace {

double polyline_length(const std::vector<cv::Point2d>& c) {
  double l = 0;
  for (size_t i = 0; i + 1 < c.size(); ++i) l += cv::norm(c[i + 1] - c[i]);
  return l;
}

// A wavy guess: headings of a sine, start at the origin.
RodProblem wavy_problem(double length, int segments) {
  RodProblem p;
  p.length = length;
  p.segments = segments;
  for (int k = 0; k < segments; ++k) p.initial_heading.push_back(0.8 * std::sin(6.0 * k / segments));
  p.initial_start = {0, 0};
  return p;
}

RodShape as_shape(const RodProblem& p) {
  RodShape s;
  s.length = p.length;
  s.start = p.initial_start;
  s.heading = p.initial_heading;
  return s;
}

TEST(Rod, PinnedEndsAtFullLengthGiveAStraightRod) {
  RodProblem p = wavy_problem(300, 30);
  Pin a, b;
  a.s = 0, a.has_position = true, a.position = {0, 0};
  b.s = 300, b.has_position = true, b.position = {300, 0};
  p.pins = {a, b};
  const RodShape shape = solve_rod(p);
  EXPECT_LT(bending_energy(shape, 0), 1e-3);
  for (const cv::Point2d& q : sample_centerline(shape)) EXPECT_NEAR(q.y, 0, 0.5);
}

TEST(Rod, SolvingLowersBendingEnergyAndMeetsFeasiblePins) {
  RodProblem p = wavy_problem(600, 50);
  const RodShape guess = as_shape(p);
  // Pins taken from the guess's own segment polyline: feasible.
  for (int s : {0, 200, 400, 599}) {
    const double h = p.length / p.segments;
    const int j = static_cast<int>(s / h);
    cv::Point2d x = p.initial_start;
    for (int k = 0; k < j; ++k) x += h * cv::Point2d(std::cos(p.initial_heading[k]), std::sin(p.initial_heading[k]));
    x += (s - j * h) * cv::Point2d(std::cos(p.initial_heading[j]), std::sin(p.initial_heading[j]));
    Pin pin;
    pin.s = s;
    pin.has_position = true;
    pin.position = x;
    p.pins.push_back(pin);
  }
  const RodShape shape = solve_rod(p);
  EXPECT_LT(bending_energy(shape, 0), 0.95 * bending_energy(guess, 0));
  const std::vector<cv::Point2d> line = sample_centerline(shape);
  ASSERT_EQ(line.size(), 601u);
  EXPECT_NEAR(polyline_length(line), 600, 1e-6);  // inextensible
  for (const Pin& pin : p.pins) EXPECT_LT(cv::norm(line[static_cast<int>(pin.s)] - pin.position), 1.0);
}

TEST(Rod, FreeRodTakesItsNaturalCurvature) {
  RodProblem p = wavy_problem(400, 40);
  p.natural_curvature = 0.01;
  const RodShape shape = solve_rod(p);
  EXPECT_LT(bending_energy(shape, 0.01), 1e-6);
  const Complexity c = complexity(sample_centerline(shape), 10, false);
  EXPECT_NEAR(c.mean_abs_curvature, 0.01, 5e-4);
  EXPECT_EQ(c.inflections, 0);
}

TEST(Rod, RingWithoutPinsIsACircle) {
  RodProblem p;
  p.length = 2 * M_PI * 50;
  p.segments = 40;
  p.closed = true;
  for (int k = 0; k < p.segments; ++k) {
    const double t = 2 * M_PI * (k + 0.5) / p.segments;
    p.initial_heading.push_back(t + 0.3 * std::sin(2 * t));
  }
  const RodShape shape = solve_rod(p);
  const std::vector<cv::Point2d> ring = sample_centerline(shape);
  cv::Point2d centre(0, 0);
  for (const auto& q : ring) centre += q;
  centre /= static_cast<double>(ring.size());
  for (const auto& q : ring) EXPECT_NEAR(cv::norm(q - centre), 50, 1.0);
}

TEST(Complexity, SCurveHasOneInflectionAndKnownTurning) {
  // Two quarter circles of radius 100 turning opposite ways.
  std::vector<cv::Point2d> c;
  double heading = 0;
  cv::Point2d x(0, 0);
  const int quarter = static_cast<int>(std::lround(M_PI / 2 * 100));
  for (int i = 0; i < 2 * quarter; ++i) {
    c.push_back(x);
    heading += (i < quarter ? 1 : -1) / 100.0;
    x += cv::Point2d(std::cos(heading), std::sin(heading));
  }
  const Complexity k = complexity(c, 10, false);
  EXPECT_EQ(k.inflections, 1);
  EXPECT_NEAR(k.total_turning_rad, M_PI, 0.05);
  EXPECT_NEAR(k.mean_abs_curvature, 0.01, 5e-4);
  EXPECT_NEAR(k.normalised_bending_energy, (2 * quarter) * (2 * quarter) * 1e-4, 0.5);
}

}  // namespace
}  // namespace mbest::synth

#include "mbest/core/bending.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <initializer_list>
#include <set>

#include <gtest/gtest.h>

#include "mbest/core/detector.h"
#include "mbest/core/geometry.h"
#include "mbest/core/prune.h"
#include "mbest/core/traverse.h"
#include "scenes.h"

namespace mbest {
namespace {

cv::Point2f dir(double deg) {
  return {static_cast<float>(std::cos(deg * M_PI / 180)), static_cast<float>(std::sin(deg * M_PI / 180))};
}

// An exit `dist` px from the origin at angle `deg`, pointing away from it.
BranchTangent exit_at(double deg, double dist = 12) {
  BranchTangent t;
  t.direction = dir(deg);
  t.point = t.direction * static_cast<float>(dist);
  return t;
}

Passage passage_along(const std::vector<cv::Point>& path, float radius) {
  Passage p;
  p.path = path;
  p.radius.assign(path.size(), radius);
  return p;
}

TEST(Bending, APassageCuttingOverTheBackgroundIsRoutedAlongTheMask) {
  // A U: two arms joined at the bottom. A curve from the top of one arm to the top of the
  // other cuts straight over the gap between them; one down an arm stays on the mask.
  cv::Mat mask = cv::Mat::zeros(120, 100, CV_8UC1);
  mask(cv::Rect(10, 10, 10, 100)).setTo(255);
  mask(cv::Rect(80, 10, 10, 100)).setTo(255);
  mask(cv::Rect(10, 100, 80, 10)).setTo(255);
  std::vector<cv::Point> across, down;
  for (int x = 15; x <= 85; ++x) across.emplace_back(x, 15);
  for (int y = 15; y <= 60; ++y) down.emplace_back(15, y);
  std::vector<Passage> passages = {passage_along(across, 5), passage_along(down, 5)};
  passages[0].radius.back() = 4;
  EXPECT_EQ(keep_passages_on_mask(passages, mask, 5, 2), 1);
  const Passage& routed = passages[0];
  EXPECT_EQ(routed.path.front(), cv::Point(15, 15));
  EXPECT_EQ(routed.path.back(), cv::Point(85, 15));
  ASSERT_EQ(routed.radius.size(), routed.path.size());
  EXPECT_FLOAT_EQ(routed.radius.front(), 5);
  EXPECT_FLOAT_EQ(routed.radius.back(), 4);
  for (size_t k = 0; k < routed.path.size(); ++k) {
    EXPECT_NE(mask.at<uchar>(routed.path[k]), 0) << routed.path[k];
    if (k > 0) {
      EXPECT_TRUE(eight_adjacent(routed.path[k - 1], routed.path[k]));
    }
  }
  EXPECT_GT(routed.path.size(), 150u);  // down, across the bottom and up again
  EXPECT_EQ(passages[1].path, down);
}

TEST(Bending, APassageMayShaveTheMasksEdgeButNotLeaveTheImage) {
  cv::Mat mask = cv::Mat::zeros(40, 100, CV_8UC1);
  mask(cv::Rect(0, 0, 100, 10)).setTo(255);
  // Off the mask for two pixels in a row: kept. Off for three: routed.
  std::vector<cv::Point> shaving, off;
  for (int x = 10; x <= 90; ++x) shaving.emplace_back(x, x >= 50 && x < 52 ? 11 : 5);
  for (int x = 10; x <= 90; ++x) off.emplace_back(x, x >= 50 && x < 53 ? 11 : 5);
  std::vector<Passage> passages = {passage_along(shaving, 3), passage_along(off, 3)};
  EXPECT_EQ(keep_passages_on_mask(passages, mask, 3, 2), 1);
  EXPECT_EQ(passages[0].path, shaving);
  for (const cv::Point& p : passages[1].path) EXPECT_NE(mask.at<uchar>(p), 0) << p;
  // A curve bulging past the image's top edge, though the mask runs along it.
  std::vector<cv::Point> outside;
  for (int x = 10; x <= 90; ++x) outside.emplace_back(x, x >= 40 && x < 60 ? -1 : 1);
  passages = {passage_along(outside, 3)};
  EXPECT_EQ(keep_passages_on_mask(passages, mask, 3, 2), 1);
  for (const cv::Point& p : passages[0].path) EXPECT_GE(p.y, 0);
}

TEST(Bending, DiscreteCurvatureIsTwiceTheTangentOfHalfTheTurn) {
  EXPECT_NEAR(discrete_curvature(dir(0), dir(0)), 0, 1e-9);
  for (double turn : {10.0, 45.0, 90.0, 150.0})
    EXPECT_NEAR(discrete_curvature(dir(0), dir(turn)), 2 * std::tan(turn * M_PI / 360), 1e-5);
  // Turning back is the worst case, not 0/0.
  EXPECT_GT(discrete_curvature(dir(0), dir(180)), 1000);
}

// A path through a crossing starts where it attaches to a branch; on a curved branch it
// must leave along the strand's tangent there, not along the chord of the fitted stretch,
// or it veers off the strand and the instance mask beside the crossing goes to the wrong DLO.
TEST(Bending, PathLeavesACurvedBranchAlongItsTangentAtTheAttachment) {
  const cv::Point2d c(60, 100);
  const double radius = 40;  // a bend of about 13 DLO radii, common in the synthetic presets
  SkeletonGraph g;
  Node junction, end;
  junction.kind = Node::Kind::junction;
  junction.pixels = {cv::Point(100, 100)};
  junction.centre = cv::Point2f(100, 100);
  end.kind = Node::Kind::end;
  Branch b;
  for (int k = 1; k <= 400; ++k) {  // from the junction (angle 0) round to 1.4 rad
    const double a = 1.4 * k / 400;
    const cv::Point p(static_cast<int>(std::lround(c.x + radius * std::cos(a))),
                      static_cast<int>(std::lround(c.y + radius * std::sin(a))));
    if (p != junction.pixels[0] && (b.pixels.empty() || p != b.pixels.back())) b.pixels.push_back(p);
  }
  b.radius.assign(b.pixels.size(), 3.5f);
  end.pixels = {b.pixels.back()};
  end.centre = cv::Point2f(b.pixels.back());
  b.node[0] = 0;
  b.node[1] = 1;
  b.length = chain_length(b.pixels);
  g.nodes = {junction, end};
  g.branches = {b};

  const BranchTangent t = fit_branch_tangent(g, {0, 0}, 4, 12, false);
  const double phi = std::atan2(t.point.y - c.y, t.point.x - c.x);
  const cv::Point2f truth(static_cast<float>(-std::sin(phi)), static_cast<float>(std::cos(phi)));
  const auto degrees_off = [&](cv::Point2f d) {
    return std::acos(std::clamp(static_cast<double>(d.dot(truth)), -1.0, 1.0)) * 180 / M_PI;
  };
  EXPECT_LT(degrees_off(t.path_direction), 3.0);
  // The chord of the fitted stretch (the pairing tangent) is the tangent further along.
  EXPECT_GT(degrees_off(t.direction), 5.0);
  EXPECT_GT(t.direction.dot(truth), 0.9f) << "both point away from the crossing";
}

TEST(Bending, XCrossingPairsStraightThrough) {
  for (double angle : {90.0, 45.0, 20.0, 10.0}) {
    const std::vector<BranchTangent> exits{exit_at(0), exit_at(angle), exit_at(180), exit_at(180 + angle)};
    auto pairs = min_energy_pairing(exits);
    ASSERT_EQ(pairs.size(), 2u);
    for (auto [a, b] : pairs) EXPECT_EQ(std::abs(a - b), 2) << "angle " << angle;
  }
}

TEST(Bending, NearParallelStrandsAreTellApartByTheirOffset) {
  // Two strands crossing at 6 degrees, exits far along a long overlap.
  const double a = 3;
  std::vector<BranchTangent> exits{exit_at(a, 60), exit_at(-a, 60), exit_at(180 + a, 60), exit_at(180 - a, 60)};
  auto pairs = min_energy_pairing(exits);
  ASSERT_EQ(pairs.size(), 2u);
  for (auto [i, j] : pairs) EXPECT_EQ(std::abs(i - j), 2);
}

TEST(Bending, SixExitsOfThreeStrandsThroughOnePoint) {
  std::vector<BranchTangent> exits;
  for (double d : {0.0, 60.0, 120.0, 180.0, 240.0, 300.0}) exits.push_back(exit_at(d));
  auto pairs = min_energy_pairing(exits);
  ASSERT_EQ(pairs.size(), 3u);
  for (auto [i, j] : pairs) EXPECT_EQ(std::abs(i - j), 3);
}

// The least total cost over every pairing of `left` (one may stay unpaired when `singles`),
// by plain enumeration.
double brute_force_cost(const std::vector<BranchTangent>& t, std::vector<int> left, int singles) {
  if (left.empty()) return 0;
  const int a = left.back();
  left.pop_back();
  double best = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < left.size(); ++k) {
    std::vector<int> rest = left;
    rest.erase(rest.begin() + static_cast<long>(k));
    best = std::min(best, pair_cost(t[a], t[left[k]], {}) + brute_force_cost(t, rest, singles));
  }
  if (singles) best = std::min(best, brute_force_cost(t, left, 0));
  return best;
}

TEST(Bending, PairingOfManyExitsIsTheLeastCostOne) {
  // A tangle of 11 to 13 exits with random directions and positions: the pairing costs as
  // little as any (a greedy pairing, cheapest pair first, often costs more).
  cv::RNG rng(20261202);
  int greedy_worse = 0;
  for (int trial = 0; trial < 9; ++trial) {
    const int n = 11 + trial % 3;
    std::vector<BranchTangent> exits;
    for (int k = 0; k < n; ++k) exits.push_back(exit_at(rng.uniform(0.0, 360.0), rng.uniform(5.0, 30.0)));
    std::vector<int> all(n);
    for (int k = 0; k < n; ++k) all[k] = k;
    const double least = brute_force_cost(exits, all, n % 2);
    const auto pairs = min_energy_pairing(exits);
    EXPECT_EQ(pairs.size(), static_cast<size_t>(n / 2));
    EXPECT_NEAR(pairing_cost(exits, pairs, {}), least, 1e-9) << "trial " << trial;
    std::vector<std::pair<double, std::pair<int, int>>> by_cost;
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b) by_cost.push_back({pair_cost(exits[a], exits[b], {}), {a, b}});
    std::sort(by_cost.begin(), by_cost.end());
    std::vector<bool> used(n, false);
    double greedy = 0;
    for (const auto& [c, p] : by_cost)
      if (!used[p.first] && !used[p.second]) {
        used[p.first] = used[p.second] = true;
        greedy += c;
      }
    greedy_worse += greedy > least + 1e-9;
  }
  EXPECT_GT(greedy_worse, 0) << "the tangles should be ones a greedy pairing gets wrong";
}

TEST(Bending, OddExitCountLeavesTheEndingStrandUnpaired) {
  // A T: a strand ends on another that runs straight through.
  const std::vector<BranchTangent> exits{exit_at(0), exit_at(180), exit_at(90)};
  auto pairs = min_energy_pairing(exits);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(std::min(pairs[0].first, pairs[0].second), 0);
  EXPECT_EQ(std::max(pairs[0].first, pairs[0].second), 1);
}

BranchTangent coloured(BranchTangent t, cv::Vec3f lab) {
  t.has_colour = true;
  t.colour = lab;
  return t;
}

TEST(Bending, ColourPenaltyIgnoresSmallDifferencesAndMissingColour) {
  const BranchTangent red = coloured(exit_at(0), {50, 60, 40});
  EXPECT_EQ(colour_penalty(red, red), 0);
  EXPECT_EQ(colour_penalty(red, exit_at(90)), 0) << "no colour on one side: geometry alone";
  // Lightness counts half: shading along one DLO changes it more than hue.
  EXPECT_EQ(colour_penalty(red, coloured(exit_at(0), {50 + 2 * kColourTolerance, 60, 40})), 0);
  EXPECT_EQ(colour_penalty(red, coloured(exit_at(0), {50, 60 + kColourTolerance, 40})), 0);
  const double half = colour_penalty(red, coloured(exit_at(0), {50, 60 + 2 * kColourTolerance, 40}));
  EXPECT_NEAR(half, kColourPenaltyMax / 2, 1e-4);
  const BranchTangent blue = coloured(exit_at(0), {40, 10, -50});
  EXPECT_EQ(colour_penalty(red, blue), kColourPenaltyMax) << "capped";
}

TEST(Bending, ColourDecidesBetweenPairingsGeometryCannotTellApart) {
  // Three exits nearly evenly spread plus one: by bending alone the red strand turning
  // 100 degrees and the blue one turning 80 are close calls; colour settles them.
  const cv::Vec3f red{50, 60, 40}, blue{40, 10, -50};
  const std::vector<BranchTangent> exits{coloured(exit_at(0), red), coloured(exit_at(100), blue),
                                         coloured(exit_at(180), blue), coloured(exit_at(260), red)};
  // Geometry alone pairs 0 with 2 (straight on).
  auto plain = min_energy_pairing(exits);
  ASSERT_EQ(plain.size(), 2u);
  for (auto [a, b] : plain) EXPECT_EQ(std::abs(a - b), 2);
  auto with_colour = min_energy_pairing(exits, {2.0});
  ASSERT_EQ(with_colour.size(), 2u);
  for (auto [a, b] : with_colour) EXPECT_EQ(exits[a].colour, exits[b].colour) << a << "-" << b;
  // Same colour everywhere: colour changes nothing.
  std::vector<BranchTangent> grey = exits;
  for (BranchTangent& t : grey) t.colour = {50, 0, 0};
  EXPECT_EQ(min_energy_pairing(grey, {2.0}), plain);
}

TEST(Bending, TheTwoEndsOfOneBranchCloseIntoARingOnlyAtACost) {
  // A self-loop lying along its own rod: exits 0 and 1 are the two ends of the loop's
  // branch, 2 and 3 the rod's ways in and out, 10 degrees off the loop's. By bending alone
  // the loop closes straight through the crossing and the rod runs straight on beside it.
  const std::vector<BranchTangent> exits{exit_at(0), exit_at(180), exit_at(10), exit_at(190)};
  const std::vector<BranchEnd> ends{{7, 0}, {7, 1}, {3, 0}, {4, 1}};
  const auto closes = [](const std::vector<std::pair<int, int>>& pairs) {
    return std::any_of(pairs.begin(), pairs.end(), [](auto p) { return std::min(p.first, p.second) == 0 &&
                                                                       std::max(p.first, p.second) == 1; });
  };
  ASSERT_TRUE(closes(min_energy_pairing(exits)));
  ASSERT_TRUE(closes(min_energy_pairing(exits, ends, {})));
  PairWeights loop;
  loop.loop = 10;
  EXPECT_FALSE(closes(min_energy_pairing(exits, ends, loop))) << "the rod runs through its loop";
  // Exits of different branches pay nothing: the same exits on four branches pair as before.
  EXPECT_TRUE(closes(min_energy_pairing(exits, {{7, 0}, {8, 1}, {3, 0}, {4, 1}}, loop)));
  // A loop whose colour no other exit shares is a ring of its own: it closes.
  const cv::Vec3f red{50, 60, 40}, blue{40, 10, -50};
  std::vector<BranchTangent> ring{coloured(exits[0], red), coloured(exits[1], red),
                                  coloured(exits[2], blue), coloured(exits[3], blue)};
  loop.colour = 4;
  EXPECT_TRUE(closes(min_energy_pairing(ring, ends, loop)));
  // One of the rod's exits of the loop's colour: the loop may be the rod's.
  ring[3].colour = red;
  EXPECT_FALSE(closes(min_energy_pairing(ring, ends, loop)));
  // The cost counts in the cache's pair costs too, which junction grouping compares.
  std::vector<std::vector<double>> costs(4, std::vector<double>(4, 1.0));
  add_loop_closing_costs(costs, exits, ends, 10);
  EXPECT_EQ(costs[0][1], 11.0);
  EXPECT_EQ(costs[1][0], 11.0);
  EXPECT_EQ(costs[2][3], 1.0);
  EXPECT_EQ(costs[0][2], 1.0);
}

TEST(Bending, ALoopAtItsOwnCrossingIsTheRodsWhenEitherEndSharesItsColour) {
  // A tight loop is lit unevenly: one of its ends may read a shade off the rod while the
  // other matches it. Exits 0 and 1 are the loop's ends (branch 7), 2 and 3 the rod's.
  const std::vector<BranchEnd> ends{{7, 0}, {7, 1}, {3, 0}, {4, 1}};
  const cv::Vec3f rod{40, 10, -50}, off{40, 22, -58}, near{42, 14, -52};  // 14.4 and 4.6 units
  const auto exit = [](double deg, cv::Vec3f lab, float radius) {
    BranchTangent t = coloured(exit_at(deg), lab);
    t.radius = radius;
    return t;
  };
  const auto loop_cost = [&](const std::vector<BranchTangent>& exits, const std::vector<BranchEnd>& e) {
    std::vector<std::vector<double>> costs(exits.size(), std::vector<double>(exits.size(), 1.0));
    add_loop_closing_costs(costs, exits, e, 10);
    EXPECT_EQ(costs[0][1], costs[1][0]);
    return costs[0][1] - 1.0;
  };
  // The loop narrower than the rod by a pixel: the plain tolerance (10 units) holds.
  std::vector<BranchTangent> exits{exit(0, off, 3), exit(180, near, 3), exit(10, rod, 4), exit(190, rod, 4)};
  EXPECT_EQ(loop_cost(exits, ends), 10.0) << "the second end matches the rod: the rod's loop";
  exits[1].colour = off;
  EXPECT_EQ(loop_cost(exits, ends), 0.0) << "both ends off: a ring of its own";
  exits[0].colour = near;
  EXPECT_EQ(loop_cost(exits, ends), 10.0) << "either end, whichever is listed first";
  // In a larger region (a cluster of six exits) only the first end's colour is read: a
  // short branch there is as likely a stretch between two crossings as a loop.
  exits[0].colour = off;
  exits[1].colour = near;
  exits.push_back(exit(90, {70, -40, 30}, 4));
  exits.push_back(exit(270, {70, -40, 30}, 4));
  std::vector<BranchEnd> six = ends;
  six.push_back({5, 0});
  six.push_back({6, 1});
  EXPECT_EQ(loop_cost(exits, six), 0.0);
}

TEST(Bending, RadiiWithinHalfAPixelAreOneWidthForALoopsColour) {
  // A loop 13 units off its rod's colour (both ends) is the rod's only at the rod's width,
  // where the tolerance is kSameWidthColourTolerance times wider. Radii are distance-transform
  // values: 3.16 and 3.61 are neighbours on that grid, one width, though 14 % apart.
  const cv::Vec3f rod{43, 32, -70}, loop{50, 24, -62};
  ASSERT_GT(colour_distance(rod, loop), kColourTolerance);
  ASSERT_LT(colour_distance(rod, loop), kSameWidthColourTolerance * kColourTolerance);
  const auto cost_at = [&](float loop_radius) {
    std::vector<BranchTangent> exits{coloured(exit_at(0), loop), coloured(exit_at(180), loop),
                                     coloured(exit_at(10), rod), coloured(exit_at(190), rod)};
    exits[0].radius = exits[1].radius = loop_radius;
    exits[2].radius = exits[3].radius = 3.16f;
    std::vector<std::vector<double>> costs(4, std::vector<double>(4, 0.0));
    add_loop_closing_costs(costs, exits, {{7, 0}, {7, 1}, {3, 0}, {4, 1}}, 10);
    return costs[0][1];
  };
  EXPECT_EQ(cost_at(3.61f), 10.0) << "one grain wider: the rod's own loop";
  EXPECT_EQ(cost_at(4.5f), 0.0) << "a width of its own and a colour of its own: a ring";
}

TEST(Bending, AClosedDloJoinsAnOpenOneWhereReRoutingCostsLittle) {
  // One crossing region, two passages: the closed DLO 0 turns a right angle from exit A to
  // exit B, the open DLO 1 from C to D; straight on, A-C and B-D, costs less.
  const BranchEnd a{1, 0}, b{1, 1}, c{2, 0}, d{3, 1};
  const BranchTangent ta = exit_at(0), tb = exit_at(90), tc = exit_at(180), td = exit_at(270);
  const auto setup = [&](const BranchTangent& ta_, const BranchTangent& tb_, int open_region) {
    std::vector<Passage> passages{make_passage(0, a, ta_, b, tb_), make_passage(open_region, c, tc, d, td)};
    return passages;
  };
  Traversal t;
  t.dlos.resize(2);
  t.dlos[0].closed = true;
  t.dlo_passages = {{0}, {1}};
  t.passage_dlo = {0, 1};
  const auto joins = [](const Passage& p, BranchEnd x, BranchEnd y) {
    return (p.from == x && p.to == y) || (p.from == y && p.to == x);
  };
  std::vector<Passage> passages = setup(ta, tb, 0);
  ASSERT_TRUE(open_closed_loops(passages, t, {}, 1.0));
  EXPECT_TRUE(joins(passages[0], a, c) || joins(passages[0], a, d));
  EXPECT_TRUE(joins(passages[1], b, d) || joins(passages[1], b, c));
  EXPECT_TRUE(joins(passages[0], a, c)) << "straight on is the cheaper way round";
  EXPECT_FALSE(open_closed_loops(passages = setup(ta, tb, 0), t, {}, 0)) << "0 turns it off";
  EXPECT_FALSE(open_closed_loops(passages = setup(ta, tb, 1), t, {}, 1.0)) << "another region";
  // A loop whose colour is far from both of the open DLO's exits is a ring of its own.
  const cv::Vec3f red{50, 60, 40}, blue{40, 10, -50};
  passages = {make_passage(0, a, coloured(ta, red), b, coloured(tb, red)),
              make_passage(0, c, coloured(tc, blue), d, coloured(td, blue))};
  EXPECT_FALSE(open_closed_loops(passages, t, {}, 1.0));
  passages[1].to_tangent.colour = red;
  EXPECT_TRUE(open_closed_loops(passages, t, {}, 1.0)) << "one of the open DLO's exits shares it";
  // Where the loop already runs straight through, re-routing costs more than 1 allows.
  passages = {make_passage(0, a, ta, b, tc), make_passage(0, c, tb, d, td)};
  EXPECT_FALSE(open_closed_loops(passages, t, {}, 1.0));
  EXPECT_TRUE(open_closed_loops(passages, t, {}, 100.0));
  // Re-routing a loop turning 90 degrees with a DLO running straight through at 60
  // degrees to its first exit costs about 1.4: more than 1 allows, but where all four exits
  // are of one colour the loop is most likely the rod's own, and own_colour_cost allows it.
  const BranchTangent te = exit_at(240), tf = exit_at(60);
  const auto tinted = [&](cv::Vec3f loop, cv::Vec3f rod) {
    return std::vector<Passage>{make_passage(0, a, coloured(ta, loop), b, coloured(tb, loop)),
                                make_passage(0, c, coloured(te, rod), d, coloured(tf, rod))};
  };
  const cv::Vec3f green{60, -40, 30}, greenish{60, -33, 30};  // 7 Lab units apart
  EXPECT_FALSE(open_closed_loops(passages = tinted(green, green), t, {}, 1.0));
  EXPECT_TRUE(open_closed_loops(passages = tinted(green, green), t, {}, 1.0, 2.0)) << "one colour";
  EXPECT_FALSE(open_closed_loops(passages = tinted(green, greenish), t, {}, 1.0, 2.0))
      << "a ring of a like colour (within kColourTolerance, not half of it)";
  EXPECT_FALSE(open_closed_loops(passages = {make_passage(0, a, ta, b, tb), make_passage(0, c, te, d, tf)}, t, {},
                                 1.0, 2.0))
      << "no colours (a mask alone): 1 allows no more";
  EXPECT_FALSE(open_closed_loops(passages = tinted(green, green), t, {}, 0, 2.0)) << "0 turns it off";
  // With no open DLO in the region there is nothing to join.
  t.dlos[1].closed = true;
  EXPECT_FALSE(open_closed_loops(passages = setup(ta, tb, 0), t, {}, 1.0));
}

BranchTangent with_radius(BranchTangent t, float radius) {
  t.radius = radius;
  return t;
}

TEST(Bending, WidthPenaltyGrowsWithTheWidthRatioUpToTwoStrands) {
  const BranchTangent thin = with_radius(exit_at(0), 3);
  EXPECT_EQ(width_penalty(thin, with_radius(exit_at(180), 3)), 0);
  EXPECT_EQ(width_penalty(thin, with_radius(exit_at(180), 3.25f)), 0) << "within the scatter of one DLO";
  EXPECT_NEAR(width_penalty(thin, with_radius(exit_at(180), 4.5f)), 1.5 - kWidthTolerance, 1e-6);
  EXPECT_NEAR(width_penalty(with_radius(exit_at(180), 4.5f), thin), 1.5 - kWidthTolerance, 1e-6)
      << "symmetric";
  EXPECT_EQ(width_penalty(thin, with_radius(exit_at(180), 6)), 0)
      << "twice as wide: two strands side by side, one of which runs on";
  EXPECT_EQ(width_penalty(thin, exit_at(180)), 0) << "no radius measured on one side";
  // In pair_cost, weighed by PairWeights::width only.
  const BranchTangent thick = with_radius(exit_at(180), 4.5f);
  EXPECT_NEAR(pair_cost(thin, thick, {0, 4}) - pair_cost(thin, thick, {}), 4 * (1.5 - kWidthTolerance), 1e-6);
}

TEST(Bending, WidthKeepsAThinAndAThickDloApartAtAShallowCrossing) {
  // A 6 px and a 9 px wide DLO crossing at 10 degrees, each bending 10 degrees through the
  // crossing: by bending alone the straight swap (thin in, thick out) wins; widths do not
  // change at a crossing.
  const std::vector<BranchTangent> exits{with_radius(exit_at(0), 3), with_radius(exit_at(10), 4.5f),
                                         with_radius(exit_at(190), 3), with_radius(exit_at(180), 4.5f)};
  const auto plain = min_energy_pairing(exits);
  ASSERT_EQ(plain.size(), 2u);
  for (auto [a, b] : plain) EXPECT_NE(exits[a].radius, exits[b].radius) << a << "-" << b;
  const auto with_width = min_energy_pairing(exits, {0, 4});
  ASSERT_EQ(with_width.size(), 2u);
  for (auto [a, b] : with_width) EXPECT_EQ(exits[a].radius, exits[b].radius) << a << "-" << b;
}

// A strand through a crossing, as the two exit branches it joins (lower index first).
using Strand = std::pair<int, int>;
Strand strand(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

// The strands `region`'s least-cost pairing makes.
std::set<Strand> strands_of(const CrossingRegion& region, TangentCache& cache) {
  std::set<Strand> out;
  for (const auto& [i, j] : min_energy_pairing(cache.of(region.exits), cache.setup().weights))
    out.insert(strand(region.exits[i].branch, region.exits[j].branch));
  return out;
}

// A skeleton graph drawn by hand: nodes at points, straight or bent branches between them
// (radius 3), each branch also drawn 5 px wide in its colour into `bgr` when that is set.
struct HandGraph {
  SkeletonGraph graph;
  cv::Mat bgr;

  int node(cv::Point p, Node::Kind kind) {
    Node n;
    n.kind = kind;
    n.pixels = {p};
    n.centre = cv::Point2f(p);
    graph.nodes.push_back(n);
    return static_cast<int>(graph.nodes.size()) - 1;
  }
  int branch(int from, int to, const cv::Scalar& colour = cv::Scalar()) {
    return branch_via(from, {}, to, colour);
  }
  // A branch bent at `via` (none: straight).
  int branch_via(int from, std::vector<cv::Point> via, int to, const cv::Scalar& colour = cv::Scalar()) {
    Branch br;
    const cv::Point p = graph.nodes[from].pixels[0], q = graph.nodes[to].pixels[0];
    std::vector<cv::Point> corners{p};
    corners.insert(corners.end(), via.begin(), via.end());
    corners.push_back(q);
    for (size_t c = 0; c + 1 < corners.size(); ++c) {
      cv::LineIterator it(corners[c], corners[c + 1], 8);
      // Not the nodes; a corner once, as the last pixel of the segment before it.
      for (int k = 0; k < it.count; ++k, ++it)
        if (k > 0 && !(c + 2 == corners.size() && k == it.count - 1)) br.pixels.push_back(it.pos());
      if (!bgr.empty()) cv::line(bgr, corners[c], corners[c + 1], colour, 5);
    }
    br.radius.assign(br.pixels.size(), 3.0f);
    br.node[0] = from;
    br.node[1] = to;
    br.length = chain_length(br.pixels) + 2;
    graph.branches.push_back(br);
    const int i = static_cast<int>(graph.branches.size()) - 1;
    graph.nodes[from].branch_ends.push_back({i, 0});
    graph.nodes[to].branch_ends.push_back({i, 1});
    return i;
  }
  // Each of `junctions` as a crossing region of its own.
  std::vector<CrossingRegion> regions_of(std::initializer_list<int> junctions) const {
    std::vector<CrossingRegion> regions;
    for (int j : junctions) {
      CrossingRegion r;
      r.nodes = {j};
      r.exits = graph.nodes[j].branch_ends;
      r.centre = graph.nodes[j].centre;
      regions.push_back(r);
    }
    return regions;
  }
};

// A hand-made graph: junctions J1 (100, 100) and J2 (140, 100) joined by a red link; a
// red rod runs left-right through both, a blue one from the upper left of J1 to the lower
// right of J2 and a green one from the lower left of J1 to the upper right of J2, all three
// lying along the link. Each junction alone can only pair blue with green; together the
// three strands run straight through.
struct Bundle {
  SkeletonGraph graph;
  std::vector<CrossingRegion> regions;
  cv::Mat bgr;
};
// Three strands (red, blue, green) crossing near two junctions 40 px apart; with `yellow_end`
// a yellow DLO also ends at the left one.
Bundle bundle(bool yellow_end = false) {
  HandGraph h;
  h.bgr = cv::Mat(200, 240, CV_8UC3, cv::Scalar(0, 0, 0));
  const cv::Scalar red(40, 40, 200), blue(200, 90, 30), green(40, 200, 60);
  const int j1 = h.node({100, 100}, Node::Kind::junction), j2 = h.node({140, 100}, Node::Kind::junction);
  h.branch(h.node({30, 100}, Node::Kind::end), j1, red);
  h.branch(h.node({50, 50}, Node::Kind::end), j1, blue);
  h.branch(h.node({50, 150}, Node::Kind::end), j1, green);
  h.branch(j2, h.node({210, 100}, Node::Kind::end), red);
  h.branch(j2, h.node({190, 150}, Node::Kind::end), blue);
  h.branch(j2, h.node({190, 50}, Node::Kind::end), green);
  if (yellow_end) h.branch(h.node({100, 20}, Node::Kind::end), j1, cv::Scalar(30, 210, 230));
  h.branch(j1, j2, red);  // drawn last: the link shows the top strand's colour
  Bundle b;
  b.regions = h.regions_of({j1, j2});
  b.graph = std::move(h.graph);
  b.bgr = h.bgr;
  return b;
}

TEST(Bending, RegionsThatPairBetterTogetherAreMerged) {
  Bundle b = bundle();
  const PairingSetup setup{2, 8, b.bgr, {2.0}};
  Bundle kept = b;
  TangentCache kept_tangents(kept.graph, setup), tangents(b.graph, setup);
  EXPECT_EQ(merge_regions_by_pairing_cost(kept.graph, kept.regions, kept_tangents, 60, 1000), 0)
      << "no merge gains that much";
  EXPECT_EQ(merge_regions_by_pairing_cost(b.graph, b.regions, tangents, 30, 1.0), 0)
      << "the link is longer than max_link";
  ASSERT_EQ(merge_regions_by_pairing_cost(b.graph, b.regions, tangents, 60, 1.0), 1);
  ASSERT_EQ(b.regions.size(), 1u);
  const CrossingRegion& r = b.regions[0];
  ASSERT_EQ(r.exits.size(), 6u);
  ASSERT_EQ(r.inner_branches.size(), 1u);
  EXPECT_FALSE(b.graph.branches[r.inner_branches[0]].alive) << "the link is inside the crossing";
  const std::vector<BranchTangent> t = exit_tangents(b.graph, r.exits, setup);
  for (const auto& [i, j] : min_energy_pairing(t, setup.weights)) {
    EXPECT_LT(t[i].direction.dot(t[j].direction), -0.95) << "strands run straight through";
    EXPECT_EQ(colour_penalty(t[i], t[j]), 0);
  }
}

// A cluster of two junctions, J1 (100, 100) and J2 (160, 160), joined by an S-shaped inner
// branch that leaves J1 heading right and arrives at J2 heading right. At J1 a rod comes in
// from the left and one leaves upwards; at J2 one leaves to the right and one downwards.
struct SCluster {
  SkeletonGraph graph;
  CrossingRegion region;
  int left = -1, up = -1, right = -1, down = -1;  // indices into region.exits
};
SCluster s_cluster() {
  HandGraph h;
  const int j1 = h.node({100, 100}, Node::Kind::junction), j2 = h.node({160, 160}, Node::Kind::junction);
  const int link = h.branch_via(j1, {{125, 100}, {135, 160}}, j2);
  const int left = h.branch(h.node({30, 100}, Node::Kind::end), j1);
  const int up = h.branch(j1, h.node({100, 30}, Node::Kind::end));
  const int right = h.branch(j2, h.node({230, 160}, Node::Kind::end));
  const int down = h.branch(j2, h.node({160, 230}, Node::Kind::end));
  SCluster c;
  c.region.nodes = {j1, j2};
  c.region.inner_branches = {link};
  h.graph.branches[link].alive = false;
  for (const BranchEnd& e : {BranchEnd{left, 1}, BranchEnd{up, 0}, BranchEnd{right, 0}, BranchEnd{down, 0}})
    c.region.exits.push_back(e);
  c.left = 0, c.up = 1, c.right = 2, c.down = 3;
  c.graph = std::move(h.graph);
  return c;
}

TEST(Bending, ARouteThroughAClusterPaysForTheTurnsAlongItsInnerBranches) {
  const SCluster c = s_cluster();
  const PairingSetup setup{2, 8, cv::Mat(), {}};
  const std::vector<BranchTangent> t = exit_tangents(c.graph, c.region.exits, setup);
  const auto route = inner_route_bending(c.graph, c.region, t, setup.cut_length, setup.fit_length);
  ASSERT_EQ(route.size(), 4u);
  // Left to right runs straight along the S: no turn, where the Hermite curve between the
  // two exits, 60 px apart sideways, bends.
  EXPECT_LT(route[c.left][c.right], 0.05);
  EXPECT_GT(pair_cost(t[c.left], t[c.right], {}), 1.0);
  // Left to down turns a right angle at J2 (2 tan 45 degrees, squared); up to down turns two.
  EXPECT_NEAR(route[c.left][c.down], 4.0, 0.3);
  EXPECT_NEAR(route[c.up][c.down], 8.0, 0.6);
  // Two exits at one node have no route through the inside; the costs are symmetric.
  EXPECT_TRUE(std::isinf(route[c.left][c.up]));
  EXPECT_TRUE(std::isinf(route[c.right][c.down]));
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) EXPECT_EQ(route[a][b], route[b][a]);
  // Without the inner branch there is no route at all.
  SCluster bare = s_cluster();
  bare.region.inner_branches.clear();
  const auto none = inner_route_bending(bare.graph, bare.region, t, setup.cut_length, setup.fit_length);
  EXPECT_TRUE(std::isinf(none[c.left][c.right]));
}

// Two strands crossing twice, J1 (100, 100) and J2 (200, 100), between them an eye of two
// inner branches, over (100, 100) - (150, 70) - (200, 100) and under through (150, 130). One
// strand comes from the lower left, runs over the top and leaves to the lower right; the
// other from the upper left along the bottom to the upper right. Every pair of exits across
// the eye shares the chord J1-J2, so their Hermite energies add up nearly alike for either
// pairing (the wrong one a little cheaper): only the inside tells which way each runs.
TEST(Bending, AClusterPairsTheStrandsThatFollowItsInside) {
  HandGraph h;
  const int j1 = h.node({100, 100}, Node::Kind::junction), j2 = h.node({200, 100}, Node::Kind::junction);
  const int over = h.branch_via(j1, {{150, 70}}, j2), under = h.branch_via(j1, {{150, 130}}, j2);
  const int lower_left = h.branch(h.node({50, 130}, Node::Kind::end), j1);
  const int upper_left = h.branch(h.node({50, 70}, Node::Kind::end), j1);
  const int lower_right = h.branch(j2, h.node({250, 130}, Node::Kind::end));
  const int upper_right = h.branch(j2, h.node({250, 70}, Node::Kind::end));
  CrossingRegion region;
  region.nodes = {j1, j2};
  region.inner_branches = {over, under};
  region.exits = {{lower_left, 1}, {upper_left, 1}, {lower_right, 0}, {upper_right, 0}};
  SkeletonGraph graph = std::move(h.graph);
  graph.branches[over].alive = graph.branches[under].alive = false;
  const PairingSetup setup{2, 8, cv::Mat(), {}};
  const std::vector<BranchTangent> t = exit_tangents(graph, region.exits, setup);
  const double along = pair_cost(t[0], t[2], {}) + pair_cost(t[1], t[3], {});
  const double across = pair_cost(t[0], t[3], {}) + pair_cost(t[1], t[2], {});
  EXPECT_LT(across, along) << "by Hermite energy alone the wrong pairing is the cheaper";
  EXPECT_LT(along - across, 0.3) << "but only by what the attachment points add";
  TangentCache cache(graph, setup);
  const auto pairs_of = [&](RouteCosts route) {
    std::set<std::pair<int, int>> pairs;
    const double never = std::numeric_limits<double>::infinity();
    for (const Passage& p : build_passages({region}, cache, never, never, never, route)) {
      const auto index = [&](BranchEnd e) {
        return static_cast<int>(std::find(region.exits.begin(), region.exits.end(), e) - region.exits.begin());
      };
      pairs.insert(std::minmax(index(p.from), index(p.to)));
    }
    return pairs;
  };
  const std::set<std::pair<int, int>> strands{{0, 2}, {1, 3}};
  EXPECT_EQ(pairs_of({4, 0.35}), strands);
  EXPECT_EQ(pairs_of({5, 0.35}), pairs_of({0, 0.35})) << "fewer exits than min_exits: as without";
  EXPECT_NE(pairs_of({0, 0.35}), strands) << "the tie went the strands' way without the route: "
                                            "this scene no longer shows what the route adds";
}

// A Y where a green DLO ends lying along a yellow one: the yellow comes in from the lower
// left and bends 30 degrees into the exit to the right, the green comes in from the left
// bending 10, and lies on top of the yellow for the exit's first 40 px, where the exit is
// wide (two strands side by side) and shows green. Past that it is the yellow alone.
// `wide` = false draws the exit one DLO wide all along.
struct EndAlongRod {
  SkeletonGraph graph;
  std::vector<CrossingRegion> regions;
  cv::Mat bgr;
  int yellow = -1, green = -1, exit = -1;
};
EndAlongRod end_along_rod(bool wide) {
  HandGraph h;
  h.bgr = cv::Mat(200, 260, CV_8UC3, cv::Scalar(0, 0, 0));
  const cv::Scalar yellow(30, 210, 230), green(40, 200, 60);
  const int j = h.node({100, 100}, Node::Kind::junction);
  EndAlongRod s;
  s.yellow = h.branch(h.node({100 - 70, 100 + 40}, Node::Kind::end), j, yellow);  // 150 deg
  s.green = h.branch(h.node({100 - 79, 100 - 14}, Node::Kind::end), j, green);    // 190 deg
  s.exit = h.branch(j, h.node({230, 100}, Node::Kind::end), yellow);
  cv::line(h.bgr, {100, 100}, {140, 100}, green, 5);
  if (wide) {
    Branch& b = h.graph.branches[s.exit];
    for (size_t k = 0; k < b.pixels.size() && b.pixels[k].x < 140; ++k) b.radius[k] = 5.0f;
  }
  s.regions = h.regions_of({j});
  s.graph = std::move(h.graph);
  s.bgr = h.bgr;
  return s;
}

TEST(Bending, AWideExitOfAYTakesItsColourPastWhereItNarrows) {
  for (const bool wide : {true, false}) {
    EndAlongRod s = end_along_rod(wide);
    const PairingSetup setup{2, 8, s.bgr, {2.0}};
    TangentCache tangents(s.graph, setup);
    const std::vector<Passage> passages = build_passages(s.regions, tangents);
    ASSERT_EQ(passages.size(), 1u) << "a Y: one strand through, one ending";
    const int through = passages[0].from.branch == s.exit ? passages[0].to.branch : passages[0].from.branch;
    // Wide, the exit carries the green end beside the yellow strand, which runs on: the
    // yellow goes through. One DLO wide, the exit is the green DLO's own continuation.
    EXPECT_EQ(through, wide ? s.yellow : s.green) << (wide ? "wide exit" : "narrow exit");
  }
}

// Past max_link, up to long_link, the joint pairing must gain three times min_gain, however
// wide the link is.
TEST(Bending, RegionsJoinedByALongLinkMergeForThreeTimesTheGain) {
  // The bundle's link is about 40 px long: beyond max_link = 30 here.
  const auto merges = [](double max_link, double min_gain, double long_link) {
    Bundle b = bundle();
    const PairingSetup setup{2, 8, b.bgr, {2.0}};
    TangentCache tangents(b.graph, setup);
    return merge_regions_by_pairing_cost(b.graph, b.regions, tangents, max_link, min_gain, long_link);
  };
  Bundle b = bundle();
  const PairingSetup setup{2, 8, b.bgr, {2.0}};
  TangentCache tangents(b.graph, setup);
  // Joined, the exits are both regions' but the link's two ends (the branch joining the
  // two junctions).
  std::vector<BranchEnd> joined;
  for (const CrossingRegion& r : b.regions)
    for (const BranchEnd& e : r.exits) {
      const Branch& br = b.graph.branches[e.branch];
      if (b.graph.nodes[br.node[0]].kind != Node::Kind::junction ||
          b.graph.nodes[br.node[1]].kind != Node::Kind::junction)
        joined.push_back(e);
    }
  ASSERT_EQ(joined.size(), 6u);
  const double gain = tangents.least_cost(b.regions[0].exits) + tangents.least_cost(b.regions[1].exits) -
                      tangents.least_cost(joined);
  ASSERT_GT(gain, 3.0) << "each region alone pairs two strands wrongly";
  EXPECT_EQ(merges(30, 0.9 * gain / 3, 60), 1) << "long, gaining over three times min_gain: merged";
  EXPECT_EQ(merges(30, 1.1 * gain / 3, 60), 0) << "long, gaining under three times min_gain: not merged";
  EXPECT_EQ(merges(60, 1.1 * gain / 3, 60), 1) << "the same gain merges within max_link";
  EXPECT_EQ(merges(30, 0.9 * gain / 3, 35), 0) << "longer than long_link: not merged";
  EXPECT_EQ(merges(30, 0.9 * gain / 3, 0), 0) << "long links off by default";
}

// Three regions in a row, A - M - C, along a red DLO: a green one crosses it at M; a blue
// one comes in at A, lies hidden under the red up to C and leaves there; a purple one ends
// at A. A alone must pair blue with purple (a turn and a change of colour), joined to M it
// still must, and M with C pair well alone: only the three together let blue run through
// and purple end.
TEST(Bending, ThreeRegionsInARowMergeWhenOnlyTogetherTheyPairWell) {
  const auto run = [](double min_gain, int* merges) {
    HandGraph h;
    h.bgr = cv::Mat(200, 280, CV_8UC3, cv::Scalar(0, 0, 0));
    const cv::Scalar red(40, 40, 200), blue(200, 90, 30), green(40, 200, 60), purple(160, 40, 140);
    const int a = h.node({100, 100}, Node::Kind::junction), m = h.node({140, 100}, Node::Kind::junction),
              c = h.node({180, 100}, Node::Kind::junction);
    h.branch(h.node({30, 100}, Node::Kind::end), a, red);
    const int blue_in = h.branch(h.node({60, 60}, Node::Kind::end), a, blue);
    const int purple_end = h.branch(h.node({60, 140}, Node::Kind::end), a, purple);
    h.branch(h.node({140, 30}, Node::Kind::end), m, green);
    h.branch(m, h.node({140, 170}, Node::Kind::end), green);
    h.branch(c, h.node({250, 100}, Node::Kind::end), red);
    const int blue_out = h.branch(c, h.node({220, 140}, Node::Kind::end), blue);
    h.branch(a, m, red);  // the red lies over the blue
    h.branch(m, c, red);
    std::vector<CrossingRegion> regions = h.regions_of({a, m, c});
    const PairingSetup setup{2, 8, h.bgr, {2.0}};
    TangentCache tangents(h.graph, setup);
    *merges = merge_regions_by_pairing_cost(h.graph, regions, tangents, 60, min_gain);
    std::pair<int, int> blue_pair{-1, -1};
    if (regions.size() == 1) {
      const std::vector<BranchTangent> t = exit_tangents(h.graph, regions[0].exits, setup);
      for (const auto& [i, j] : min_energy_pairing(t, setup.weights)) {
        const int x = regions[0].exits[i].branch, y = regions[0].exits[j].branch;
        if (x == blue_in || y == blue_in) blue_pair = {std::min(x, y), std::max(x, y)};
        EXPECT_NE(x, purple_end) << "purple ends";
        EXPECT_NE(y, purple_end) << "purple ends";
      }
    }
    return blue_pair == std::pair<int, int>{std::min(blue_in, blue_out), std::max(blue_in, blue_out)};
  };
  int merges = 0;
  EXPECT_TRUE(run(1.0, &merges)) << "blue runs through A, M and C";
  EXPECT_EQ(merges, 2);
  EXPECT_FALSE(run(5.0, &merges)) << "three times min_gain is more than the three gain together";
  EXPECT_EQ(merges, 0);
}

// A black DLO ends with its tip lying along an orange one: thinning runs the black strand
// along the orange for a few px, and the orange's skeleton meets it at a second junction.
// That one has two exits, forced to pair orange with black; merged with the Y beside it,
// the orange runs straight through and the black ends there.
TEST(Bending, BendJoiningTwoColoursBesideAYMergesIntoIt) {
  HandGraph h;
  h.bgr = cv::Mat(200, 240, CV_8UC3, cv::Scalar(0, 0, 0));
  const cv::Scalar orange(0, 140, 255), black(20, 20, 20);
  const int j1 = h.node({100, 100}, Node::Kind::junction), j2 = h.node({124, 100}, Node::Kind::junction);
  const int left = h.branch(h.node({30, 100}, Node::Kind::end), j1, orange);
  const int right = h.branch(j2, h.node({210, 100}, Node::Kind::end), orange);
  h.branch(j2, h.node({170, 150}, Node::Kind::end), black);
  h.branch(j1, j2, black);  // the black tip, drawn over the orange
  std::vector<CrossingRegion> regions = h.regions_of({j1, j2});
  ASSERT_EQ(regions[0].exits.size(), 2u);
  const PairingSetup setup{2, 8, h.bgr, {2.0}};
  TangentCache tangents(h.graph, setup);
  ASSERT_EQ(merge_regions_by_pairing_cost(h.graph, regions, tangents, 60, 1.0), 1);
  ASSERT_EQ(regions.size(), 1u);
  ASSERT_EQ(regions[0].exits.size(), 3u);
  const std::vector<BranchTangent> t = exit_tangents(h.graph, regions[0].exits, setup);
  const auto pairs = min_energy_pairing(t, setup.weights);
  ASSERT_EQ(pairs.size(), 1u);
  const int a = regions[0].exits[pairs[0].first].branch, b = regions[0].exits[pairs[0].second].branch;
  EXPECT_EQ(std::min(a, b), std::min(left, right)) << "the orange runs through";
  EXPECT_EQ(std::max(a, b), std::max(left, right)) << "the orange runs through";
}

// Where a DLO also ends at one of the two regions, that region has an odd exit count; the
// merge leaves one exit unpaired either way, so the comparison still holds.
TEST(Bending, RegionWhereAStrandEndsMergesToo) {
  Bundle b = bundle(/*yellow_end=*/true);
  ASSERT_EQ(b.regions[0].exits.size(), 5u);
  const PairingSetup setup{2, 8, b.bgr, {2.0}};
  TangentCache tangents(b.graph, setup);
  ASSERT_EQ(merge_regions_by_pairing_cost(b.graph, b.regions, tangents, 60, 1.0), 1);
  ASSERT_EQ(b.regions.size(), 1u);
  const CrossingRegion& r = b.regions[0];
  ASSERT_EQ(r.exits.size(), 7u);
  const std::vector<BranchTangent> t = exit_tangents(b.graph, r.exits, setup);
  const auto pairs = min_energy_pairing(t, setup.weights);
  ASSERT_EQ(pairs.size(), 3u);
  std::vector<bool> paired(r.exits.size(), false);
  for (const auto& [i, j] : pairs) {
    paired[i] = paired[j] = true;
    EXPECT_LT(t[i].direction.dot(t[j].direction), -0.95) << "strands run straight through";
  }
  for (size_t k = 0; k < r.exits.size(); ++k) {
    if (paired[k]) continue;
    EXPECT_EQ(b.graph.nodes[b.graph.branches[r.exits[k].branch].node[0]].centre,
              cv::Point2f(100, 20)) << "the yellow DLO ends here";
  }
}

// A shallow crossing whose overlap is long enough to split it into two Ys joined by a
// branch: strand A from the upper left to the lower right, B from the lower left to the
// upper right. Each Y alone pairs the strand closer to the link's direction with it and
// leaves the other ending; here those are B at the left Y and A at the right one, which do
// not continue each other. Both strands still run through, so the Ys are one crossing.
TEST(Bending, TwoYsWhoseStrandsBothRunThroughAreOneCrossing) {
  HandGraph h;
  const int y1 = h.node({100, 100}, Node::Kind::junction), y2 = h.node({160, 100}, Node::Kind::junction);
  const int a_in = h.branch(h.node({40, 85}, Node::Kind::end), y1);    // 14 deg off the link
  const int b_in = h.branch(h.node({40, 120}, Node::Kind::end), y1);   // 18 deg
  const int b_out = h.branch(y2, h.node({220, 85}, Node::Kind::end));  // 14 deg
  const int a_out = h.branch(y2, h.node({220, 120}, Node::Kind::end)); // 18 deg
  h.branch(y1, y2);
  SkeletonGraph& g = h.graph;
  std::vector<CrossingRegion> regions = h.regions_of({y1, y2});
  const PairingSetup setup{2, 8, cv::Mat(), {0.0}};
  TangentCache cache(g, setup);
  // Alone, each Y leaves the strand farther from the link's direction ending.
  for (const auto& [y, ending] : {std::pair{0, b_in}, std::pair{1, a_out}}) {
    const std::vector<BranchTangent> t = cache.of(regions[y].exits);
    const auto pairs = min_energy_pairing(t);
    ASSERT_EQ(pairs.size(), 1u);
    for (int k : {pairs[0].first, pairs[0].second}) EXPECT_NE(regions[y].exits[k].branch, ending);
  }
  ASSERT_EQ(pair_lone_ys(g, regions, cache, 30, 2.0), 1);
  ASSERT_EQ(regions.size(), 1u);
  ASSERT_EQ(regions[0].exits.size(), 4u);
  const std::vector<BranchTangent> t = cache.of(regions[0].exits);
  for (const auto& [i, j] : min_energy_pairing(t)) {
    const int bi = regions[0].exits[i].branch, bj = regions[0].exits[j].branch;
    EXPECT_TRUE((bi == a_in && bj == a_out) || (bi == a_out && bj == a_in) ||
                (bi == b_in && bj == b_out) || (bi == b_out && bj == b_in))
        << "branches " << bi << " and " << bj;
  }
}

// The same two Ys with a link no longer than min_link: Y-pair matching's case, left alone
// unless short links are asked for (after region merging, when two regions of odd exit
// count joined by a short link are left to this pass).
TEST(Bending, YsJoinedByAShortLinkArePairedOnlyWithShortLinks) {
  HandGraph h;
  const int y1 = h.node({100, 100}, Node::Kind::junction), y2 = h.node({160, 100}, Node::Kind::junction);
  h.branch(h.node({40, 85}, Node::Kind::end), y1);
  h.branch(h.node({40, 120}, Node::Kind::end), y1);
  h.branch(y2, h.node({220, 85}, Node::Kind::end));
  h.branch(y2, h.node({220, 120}, Node::Kind::end));
  h.branch(y1, y2);  // 60 px
  const PairingSetup setup{2, 8, cv::Mat(), {0.0}};
  {
    SkeletonGraph g = h.graph;
    TangentCache cache(g, setup);
    std::vector<CrossingRegion> regions = h.regions_of({y1, y2});
    EXPECT_EQ(pair_lone_ys(g, regions, cache, 80, 2.0), 0);
    EXPECT_EQ(regions.size(), 2u);
  }
  TangentCache cache(h.graph, setup);
  std::vector<CrossingRegion> regions = h.regions_of({y1, y2});
  EXPECT_EQ(pair_lone_ys(h.graph, regions, cache, 80, 2.0, 1.0, true), 1);
  ASSERT_EQ(regions.size(), 1u);
  EXPECT_EQ(regions[0].exits.size(), 4u);
}

// Two strands crossing at a shallow angle, lying along each other between two junctions:
// the branch joining them shows a colour between the two (purple between red and blue), and
// a white DLO crosses at the left junction. Red runs straight along the link at the left and
// turns off at the right, blue the other way round, so each junction alone pairs the link
// with the straighter strand, at the price of the colour change, and leaves the other ending:
// blue at the left, red at the right. Those two do not continue each other (their colours
// differ), and the left junction is no plain Y; pairing all exits together is still far
// cheaper, with every strand keeping its colour, so the junctions are one crossing.
TEST(Bending, RegionsEachPairingTheLinkDearlyAreOneCrossing) {
  HandGraph h;
  h.bgr = cv::Mat(200, 260, CV_8UC3, cv::Scalar(0, 0, 0));
  const cv::Scalar red(40, 40, 200), blue(200, 90, 30), white(230, 230, 230), purple(120, 65, 115);
  const int a = h.node({100, 100}, Node::Kind::junction), c = h.node({160, 100}, Node::Kind::junction);
  h.branch(h.node({100, 40}, Node::Kind::end), a, white);
  h.branch(a, h.node({100, 160}, Node::Kind::end), white);
  const int red_in = h.branch(h.node({40, 100}, Node::Kind::end), a, red);
  const int blue_in = h.branch(h.node({50, 135}, Node::Kind::end), a, blue);
  const int blue_out = h.branch(c, h.node({220, 100}, Node::Kind::end), blue);
  const int red_out = h.branch(c, h.node({210, 65}, Node::Kind::end), red);
  h.branch(a, c, purple);
  SkeletonGraph& g = h.graph;
  SkeletonGraph untouched = g;  // pair_lone_ys changes a graph only where it joins
  const PairingSetup setup{2, 8, h.bgr, {4.0}};
  // Alone, the left junction leaves blue ending and the right one red.
  {
    TangentCache cache(untouched, setup);
    std::vector<CrossingRegion> regions = h.regions_of({a, c});
    for (const auto& [r, ending] : {std::pair{0, blue_in}, std::pair{1, red_out}}) {
      const std::vector<BranchTangent> t = cache.of(regions[r].exits);
      std::vector<bool> paired(t.size(), false);
      for (const auto& [i, j] : min_energy_pairing(t, setup.weights)) paired[i] = paired[j] = true;
      for (size_t k = 0; k < t.size(); ++k)
        EXPECT_EQ(!paired[k], regions[r].exits[k].branch == ending) << "region " << r << ", exit " << k;
    }
    EXPECT_EQ(pair_lone_ys(untouched, regions, cache, 30, 4.0), 0)
        << "the strands left ending do not continue each other: without a gain, not joined";
    EXPECT_EQ(pair_lone_ys(untouched, regions, cache, 30, 4.0, 1000.0), 0)
        << "a gain larger than joining brings: not joined";
  }
  TangentCache cache(g, setup);
  std::vector<CrossingRegion> regions = h.regions_of({a, c});
  ASSERT_EQ(pair_lone_ys(g, regions, cache, 30, 4.0, 1.0), 1);
  ASSERT_EQ(regions.size(), 1u);
  ASSERT_EQ(regions[0].exits.size(), 6u);
  const std::vector<BranchTangent> t = cache.of(regions[0].exits);
  const auto pairs = min_energy_pairing(t, setup.weights);
  ASSERT_EQ(pairs.size(), 3u);
  for (const auto& [i, j] : pairs) {
    EXPECT_EQ(colour_penalty(t[i], t[j]), 0) << "every strand keeps its colour";
    const int bi = regions[0].exits[i].branch, bj = regions[0].exits[j].branch;
    for (const auto& [x, y] : {std::pair{red_in, red_out}, std::pair{blue_in, blue_out}})
      if (bi == x || bj == x) {
        EXPECT_TRUE(bi == y || bj == y) << "branches " << bi << " and " << bj;
      }
  }
}

// Two strands lie along each other from one Y to another (a twisted pair, or two strands
// overlapping at a shallow angle), and a white DLO crosses both on the way: between the Ys
// is a crossing of four exits, linked to each. Neither Y is linked to the other, so neither
// the Y-pair rule nor a merge of two regions applies, and each Y alone leaves a strand
// ending. Joined, all three pair each Y's strand with its continuation at the other and the
// white with itself: one crossing.
TEST(Bending, TwoYsWithACrossingBetweenThemAreOneCrossing) {
  HandGraph h;
  h.bgr = cv::Mat(200, 320, CV_8UC3, cv::Scalar(0, 0, 0));
  const cv::Scalar red(40, 40, 200), blue(200, 90, 30), white(230, 230, 230), purple(120, 65, 115);
  const int y1 = h.node({100, 100}, Node::Kind::junction), m = h.node({160, 100}, Node::Kind::junction),
            y2 = h.node({220, 100}, Node::Kind::junction);
  const int red_in = h.branch(h.node({40, 85}, Node::Kind::end), y1, red);
  const int blue_in = h.branch(h.node({40, 120}, Node::Kind::end), y1, blue);
  const int blue_out = h.branch(y2, h.node({280, 85}, Node::Kind::end), blue);
  const int red_out = h.branch(y2, h.node({280, 120}, Node::Kind::end), red);
  h.branch(y1, m, purple);  // both strands, side by side or overlapping
  h.branch(m, y2, purple);
  const int white_in = h.branch(h.node({160, 30}, Node::Kind::end), m, white);
  const int white_out = h.branch(m, h.node({160, 170}, Node::Kind::end), white);
  SkeletonGraph& g = h.graph;
  const PairingSetup setup{2, 8, h.bgr, {4.0}};
  {
    SkeletonGraph untouched = g;
    TangentCache cache(untouched, setup);
    std::vector<CrossingRegion> regions = h.regions_of({y1, m, y2});
    EXPECT_EQ(pair_lone_ys(untouched, regions, cache, 30, 1e-3), 0)
        << "strands that cannot continue each other at so low a cost: not joined";
    EXPECT_EQ(pair_lone_ys(untouched, regions, cache, 70, 4.0), 0)
        << "links no longer than min_link are the Y-pair rule's: not joined";
  }
  TangentCache cache(g, setup);
  std::vector<CrossingRegion> regions = h.regions_of({y1, m, y2});
  ASSERT_EQ(pair_lone_ys(g, regions, cache, 30, 4.0), 2);
  ASSERT_EQ(regions.size(), 1u);
  EXPECT_EQ(strands_of(regions[0], cache),
            (std::set<Strand>{strand(red_in, red_out), strand(blue_in, blue_out), strand(white_in, white_out)}));
}

// Two strands crossing twice a few radii apart, with an eye between the crossings: each
// crossing is a region of four exits, and the eye's two sides are two short links between
// them. Both sides show a mix of the strands' colours (each covers part of the other), so
// each region alone pays a colour change whichever side it pairs a strand with. Joined
// through both links at once, every strand keeps its colour. The same holds where the two
// sides are twins (a band of two strands split in two between two Ys, which became these
// crossings): but only while both are short, as any link.
struct Eye {
  HandGraph h;
  int upper, lower, red_in, blue_in, red_out, blue_out;
  std::vector<CrossingRegion> regions;
  explicit Eye(bool twins) {
    h.bgr = cv::Mat(200, 260, CV_8UC3, cv::Scalar(0, 0, 0));
    const cv::Scalar red(40, 40, 200), blue(200, 90, 30), purple(120, 65, 115);
    const int a = h.node({100, 100}, Node::Kind::junction), b = h.node({150, 100}, Node::Kind::junction);
    upper = h.branch_via(a, {{125, 90}}, b, purple);
    lower = h.branch_via(a, {{125, 110}}, b, purple);
    if (twins) {
      h.graph.branches[upper].twin = lower;
      h.graph.branches[lower].twin = upper;
    }
    red_in = h.branch(h.node({40, 70}, Node::Kind::end), a, red);
    blue_in = h.branch(h.node({40, 130}, Node::Kind::end), a, blue);
    red_out = h.branch(b, h.node({210, 130}, Node::Kind::end), red);
    blue_out = h.branch(b, h.node({210, 70}, Node::Kind::end), blue);
    regions = h.regions_of({a, b});
  }
};

TEST(Bending, RegionsJoinedByTwoShortLinksMergeThroughBoth) {
  for (const bool twins : {false, true}) {
    Eye eye(twins);
    const double length = std::max(eye.h.graph.branches[eye.upper].length, eye.h.graph.branches[eye.lower].length);
    ASSERT_LT(length, 60);
    const PairingSetup setup{2, 8, eye.h.bgr, {4.0}};
    if (twins) {
      SkeletonGraph untouched = eye.h.graph;
      std::vector<CrossingRegion> regions = eye.regions;
      TangentCache tangents(untouched, setup);
      EXPECT_EQ(merge_regions_by_pairing_cost(untouched, regions, tangents, length - 1, 1.0, 200), 0)
          << "twins longer than max_link are no links, even up to long_link";
    }
    SkeletonGraph& g = eye.h.graph;
    TangentCache tangents(g, setup);
    std::vector<CrossingRegion>& regions = eye.regions;
    ASSERT_EQ(merge_regions_by_pairing_cost(g, regions, tangents, 60, 1.0), 1) << "twins " << twins;
    ASSERT_EQ(regions.size(), 1u);
    ASSERT_EQ(regions[0].exits.size(), 4u) << "both links are inside the crossing";
    EXPECT_FALSE(g.branches[eye.upper].alive);
    EXPECT_FALSE(g.branches[eye.lower].alive);
    EXPECT_EQ(strands_of(regions[0], tangents),
              (std::set<Strand>{strand(eye.red_in, eye.red_out), strand(eye.blue_in, eye.blue_out)}))
        << "twins " << twins;
  }
}

constexpr double kOff = std::numeric_limits<double>::infinity();

// A red rod runs left to right through a junction where two more DLOs end, coming in at
// `first` and `second` degrees (image angles, y down) in the colours given; `stub` makes
// the second one a stub of 11 px, shorter than a tangent fit (20 px here).
struct TwoEnds {
  SkeletonGraph graph;
  std::vector<CrossingRegion> regions;
  cv::Mat bgr;
  int first = -1, second = -1;
};
TwoEnds two_ends_on_a_rod(double first, double second, const cv::Scalar& first_colour,
                          const cv::Scalar& second_colour, bool stub = false) {
  HandGraph h;
  h.bgr = cv::Mat(200, 200, CV_8UC3, cv::Scalar(0, 0, 0));
  const cv::Scalar red(40, 40, 200);
  const cv::Point c(100, 100);
  const auto at = [&](double deg, double dist) {
    return c + cv::Point(cvRound(dist * std::cos(deg * M_PI / 180)), cvRound(dist * std::sin(deg * M_PI / 180)));
  };
  const int j = h.node(c, Node::Kind::junction);
  TwoEnds s;
  s.first = h.branch(h.node(at(first, 70), Node::Kind::end), j, first_colour);
  s.second = h.branch(h.node(at(second, stub ? 12 : 70), Node::Kind::end), j, second_colour);
  h.branch(h.node({20, 100}, Node::Kind::end), j, red);
  h.branch(j, h.node({180, 100}, Node::Kind::end), red);  // drawn last: the rod on top
  s.regions = h.regions_of({j});
  s.graph = std::move(h.graph);
  s.bgr = h.bgr;
  return s;
}

// Tangents fitted over 20 px with colour: the stub is shorter than a fit.
PairingSetup two_ends_setup(const TwoEnds& s) { return {2, 20, s.bgr, {2.0}}; }

// Whether build_passages joins the two DLOs ending at the junction into one strand.
bool ends_joined(const TwoEnds& s, double unlike_energy) {
  const PairingSetup setup = two_ends_setup(s);
  TangentCache tangents(s.graph, setup);
  for (const Passage& p : build_passages(s.regions, tangents, kOff, unlike_energy))
    if (strand(p.from.branch, p.to.branch) == strand(s.first, s.second)) return true;
  return false;
}

TEST(Bending, TwoDLOsOfDifferentColoursEndingInACrossingAreNotJoined) {
  const cv::Scalar blue(200, 90, 30), green(40, 200, 60);
  // Both come from above, 30 degrees apart: a path through would turn 150 degrees.
  const TwoEnds sharp = two_ends_on_a_rod(-75, -105, blue, green);
  {
    const PairingSetup setup = two_ends_setup(sharp);
    TangentCache tangents(sharp.graph, setup);
    const std::vector<BranchTangent> t = tangents.of(sharp.regions[0].exits);
    ASSERT_EQ(strands_of(sharp.regions[0], tangents).count(strand(sharp.first, sharp.second)), 1u)
        << "the least-cost pairing joins them";
    ASSERT_EQ(colour_penalty(t[0], t[1]), kColourPenaltyMax);
    ASSERT_GE(pair_cost(t[0], t[1], {}), 4.0);
  }
  EXPECT_FALSE(ends_joined(sharp, 4.0)) << "unlike colours, sharp bend: two DLOs ending";
  EXPECT_TRUE(ends_joined(sharp, kOff)) << "the rule turned off";
  EXPECT_TRUE(ends_joined(two_ends_on_a_rod(-75, -105, blue, blue), 4.0))
      << "one colour: one DLO bending sharply";
  EXPECT_FALSE(ends_joined(two_ends_on_a_rod(-75, -105, blue, green, /*stub=*/true), 4.0))
      << "a stub's colour is evidence too (once it was not: that lost crossings in clutter)";
  // Nearly straight on (a 20 degree turn): a DLO whose colour changes, say under glare.
  EXPECT_TRUE(ends_joined(two_ends_on_a_rod(-80, 120, blue, green), 4.0)) << "a gentle bend";
}

// The default threshold parts them from a turn of about 78 degrees on: two ends 80 degrees
// apart (a path through them would turn 100 degrees) are two DLOs ending, as two rods of
// different colours are on generated scenes far more often than one rod changing colour
// while folding.
TEST(Bending, ByDefaultTwoColoursEndingInACrossingAtA100DegreeTurnAreNotJoined) {
  const cv::Scalar blue(200, 90, 30), green(40, 200, 60);
  const double energy = DetectorConfig{}.unlike_end_energy;
  const TwoEnds folding = two_ends_on_a_rod(-50, -130, blue, green);
  {
    const PairingSetup setup = two_ends_setup(folding);
    TangentCache tangents(folding.graph, setup);
    const std::vector<BranchTangent> t = tangents.of(folding.regions[0].exits);
    ASSERT_EQ(strands_of(folding.regions[0], tangents).count(strand(folding.first, folding.second)), 1u);
    const double bend = pair_cost(t[0], t[1], {});
    ASSERT_GT(bend, 1.0);
    ASSERT_LT(bend, 4.0) << "a turn the first threshold (4) let through";
  }
  EXPECT_FALSE(ends_joined(folding, energy)) << "two colours turning 100 degrees: two DLOs ending";
  EXPECT_TRUE(ends_joined(two_ends_on_a_rod(-50, -130, blue, blue), energy)) << "one colour: one DLO";
  EXPECT_TRUE(ends_joined(two_ends_on_a_rod(-60, 150, blue, green), energy))
      << "a 30 degree turn: one DLO whose colour changes";
}

// Two DLOs whose ends touch, meeting at `turn` degrees: a junction left with just their two
// exits, in the colours given. Does build_passages join them into one strand?
bool two_exits_joined(double turn, const cv::Scalar& a, const cv::Scalar& b, double unlike_fold_energy) {
  HandGraph h;
  h.bgr = cv::Mat(200, 200, CV_8UC3, cv::Scalar(0, 0, 0));
  const cv::Point c(100, 100);
  const int j = h.node(c, Node::Kind::junction);
  const double out = turn * M_PI / 180;  // the second branch's direction, off straight on
  h.branch(h.node({30, 100}, Node::Kind::end), j, a);
  h.branch(j, h.node(c + cv::Point(cvRound(70 * std::cos(out)), cvRound(-70 * std::sin(out))), Node::Kind::end), b);
  const std::vector<CrossingRegion> regions = h.regions_of({j});
  const PairingSetup setup{2, 20, h.bgr, {2.0}};
  TangentCache tangents(h.graph, setup);
  return !build_passages(regions, tangents, 4.0, 4.0, unlike_fold_energy).empty();
}

TEST(Bending, TwoExitsOfDifferentColoursArePartedAtAFold) {
  const cv::Scalar blue(200, 90, 30), green(40, 200, 60);
  // A 100 degree turn: below fold_energy (4, about 140 degrees), above 1 (about 78).
  EXPECT_FALSE(two_exits_joined(100, blue, green, 1.0)) << "two colours folding: two DLOs whose ends touch";
  EXPECT_TRUE(two_exits_joined(100, blue, green, kOff)) << "the rule turned off";
  EXPECT_TRUE(two_exits_joined(100, blue, blue, 1.0)) << "one colour: one DLO bending sharply";
  EXPECT_TRUE(two_exits_joined(30, blue, green, 1.0)) << "a gentle bend: a DLO whose colour changes, say under glare";
}

}  // namespace
}  // namespace mbest

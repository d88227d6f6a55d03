// Scenes of the generated data sets where the detector once went wrong, regenerated in
// memory from their preset, seed and index: plain tests of what a user sees there (the
// property suites' shrunk cases live in fixtures/regressions/ instead).
#include <algorithm>
#include <limits>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "mbest/core/bending.h"
#include "mbest/core/detector.h"
#include "mbest/synth/config.h"
#include "mbest/synth/dataset.h"
#include "mbest/validate/centerline_error.h"
#include "mbest/validate/crossing_list.h"
#include "mbest/validate/dice.h"

namespace mbest {
namespace {

synth::GeneratedScene scene(const std::string& preset, std::uint64_t seed, int index) {
  Result<synth::SynthConfig> config = synth::make_config(preset, nlohmann::json::object(), "test");
  EXPECT_TRUE(config.ok());
  Result<synth::GeneratedScene> s = synth::generate_scene(config.value(), seed, index);
  EXPECT_TRUE(s.ok()) << s.error().message;
  return std::move(s).value();
}

// The detector's result on the scene's ground-truth mask and picture.
Detection detected(const synth::GeneratedScene& s, const DetectorConfig& config = DetectorConfig()) {
  Result<Detection> d = detect(s.render.labels > 0, s.render.image, config);
  EXPECT_TRUE(d.ok()) << (d.ok() ? "" : d.error().message);
  return d.ok() ? std::move(d).value() : Detection();
}

// Strict matched DICE of the detection against the scene's labels (0 if it cannot be scored).
double strict_dice(const synth::GeneratedScene& s, const Detection& d) {
  const Result<validate::DiceScore> dice = validate::matched_dice(s.render.labels, d.labels);
  EXPECT_TRUE(dice.ok()) << (dice.ok() ? "" : dice.error().message);
  return dice.ok() ? dice.value().strict : 0.0;
}

// The scene has `rods` rods, and the detector finds as many DLOs, at a strict matched DICE
// of at least `min_strict`.
void expect_as_many_dlos_as_rods(const synth::GeneratedScene& s, size_t rods, double min_strict) {
  ASSERT_EQ(s.annotation.rods.size(), rods);
  const Detection d = detected(s);
  EXPECT_EQ(d.dlos.size(), rods);
  EXPECT_GE(strict_dice(s, d), min_strict);
}

int closed_dlos(const Detection& d) {
  int n = 0;
  for (const Dlo& dlo : d.dlos) n += dlo.closed;
  return n;
}

// Every rod of the scene is one open DLO, found whole (matched DICE at least 0.97).
void expect_each_rod_one_open_dlo(const synth::GeneratedScene& s, const Detection& d) {
  ASSERT_EQ(d.dlos.size(), s.annotation.rods.size());
  EXPECT_EQ(closed_dlos(d), 0);
  const Result<validate::DiceScore> dice = validate::matched_dice(s.render.labels, d.labels);
  ASSERT_TRUE(dice.ok());
  for (double v : dice.value().matched_dice) EXPECT_GE(v, 0.97);
}

// `accuracy-suite.sh out/fresh-17000 200 17000`, s2 scene 000156: a rod crosses another,
// then makes a self-loop that lies along itself where it crosses itself at 41 degrees.
// Pairing the loop's two ends with each other and the rod's way in with its way out bent
// about as little as the rod's own path, and the loop came out a ring of its own.
TEST(SuiteScenes, ASelfLoopLyingAlongItsRodStaysPartOfTheRod) {
  const synth::GeneratedScene s = scene("s2", 17002, 156);
  ASSERT_EQ(s.annotation.rods.size(), 2u);
  expect_each_rod_one_open_dlo(s, detected(s));
  // Without the cost of closing a loop (nor re-pairing closed DLOs after), the loop is a
  // ring: the case this test is for.
  DetectorConfig no_loop_cost;
  no_loop_cost.loop_closing_cost = 0;
  no_loop_cost.loop_reopen_cost = 0;
  no_loop_cost.route_min_exits = 10;  // as when this test was written: the region has six
  EXPECT_EQ(detected(s, no_loop_cost).dlos.size(), 3u);
}

// The self-crossings a DLO crosses near `at` (within 8 px).
int self_crossings_near(const Detection& d, cv::Point2f at) {
  int n = 0;
  for (const Crossing& c : d.crossings)
    n += c.dlos.size() == 2 && c.dlos[0] == c.dlos[1] && cv::norm(c.location - at) <= 8;
  return n;
}

// A loop crossing itself at `at` is listed as crossing there, and only thanks to
// loop_cross_margin: with a margin of `short_margin` (0: none, the omega pairing) the same
// DLOs and labels within 0.2 % of strict DICE, but no self-crossing there. `omega` holds
// the other constants of that run (those of when the test was written, where they differ).
void expect_loop_crossing_from_margin(const synth::GeneratedScene& s, cv::Point2f at,
                                      double short_margin = 0, DetectorConfig omega = DetectorConfig()) {
  const Detection d = detected(s);
  EXPECT_EQ(d.dlos.size(), s.annotation.rods.size());
  EXPECT_EQ(self_crossings_near(d, at), 1);
  omega.loop_cross_margin = short_margin;
  const Detection o = detected(s, omega);
  EXPECT_EQ(o.dlos.size(), d.dlos.size());
  EXPECT_EQ(self_crossings_near(o, at), 0);
  EXPECT_NEAR(strict_dice(s, d), strict_dice(s, o), 0.002);
}

// `accuracy-suite.sh`'s seed set 7000, `cables` scene 000069 (seed 7004): a thin cable makes
// a loop about 10 widths round and crosses itself at 51 degrees at (668, 444). The ends'
// tangents bend with the tight loop, and pairing the way in with the loop's near side (an
// omega, no crossing) cost 7.32 against 7.78 for the crossing: one DLO either way, but no
// self-crossing listed. Since radius_cap the scene's r is 5.8 px rather than 7.0 (1.3
// times the 4.47 px that 95 % of the skeleton stays within), and the crossing is listed
// without the margin too; with the paper's r it is not.
TEST(SuiteScenes, ATightLoopCrossesItsRod) {
  DetectorConfig paper_r;
  paper_r.radius_cap = 0;
  expect_loop_crossing_from_margin(scene("cables", 7004, 69), {668, 444}, 0, paper_r);
}

// `accuracy-suite.sh`'s seed set 11000, `cables` scene 000157 (seed 11004): a green cable's
// loop closes on a yellow cable, crossing itself at 72 degrees at (618, 282), in one region
// with the yellow cable's crossing (six exits). The loop's ends leave it side by side, and
// pairing them without crossing (an omega) cost 1.86 against 2.21: no self-crossing listed.
// The swap is taken there too since the four exits share a colour no other exit has.
// Since cluster_lightness (its six exits make a cluster) the yellow cable's lightness keeps
// the loop's ends off it without the margin too: the omega run counts lightness half.
TEST(SuiteScenes, ALoopClosingOnAnotherRodCrossesItself) {
  DetectorConfig omega;
  omega.cluster_lightness = kLightnessWeight;
  expect_loop_crossing_from_margin(scene("cables", 11004, 157), {618, 282}, 0, omega);
}

// The detection's crossing list scored against the scene's crossings (validate's matching:
// the right two DLOs, within two widths).
validate::CrossingListScore listed_crossings(const synth::GeneratedScene& s, const Detection& d) {
  const Result<validate::DiceScore> dice = validate::matched_dice(s.render.labels, d.labels);
  EXPECT_TRUE(dice.ok());
  if (!dice.ok()) return {};
  std::vector<validate::DetectedCrossing> listed;
  for (const Crossing& c : d.crossings)
    listed.push_back({c.location, c.angle_deg, c.dlos[0] + 1, c.dlos[1] + 1});
  return validate::match_crossing_list(s.annotation, dice.value(), listed);
}

// `accuracy-suite.sh`'s seed set 15000, `s2` scene 000117 (seed 15002): a teal tube loops
// round a yellow one, which passes through the loop: the teal crosses itself at 65 degrees
// at (387, 504) and the yellow three times within 70 px, all in one region of six exits.
// Paired by the Hermite energies between its exits, the region listed one crossing; paired
// along its inner branches too (DetectorConfig::route_min_exits from six exits), all four,
// each between the right DLOs.
TEST(SuiteScenes, ARodThroughALoopCrossesItThreeTimes) {
  const synth::GeneratedScene s = scene("s2", 15002, 117);
  ASSERT_EQ(s.annotation.rods.size(), 2u);
  ASSERT_EQ(s.annotation.crossings.size(), 4u);
  const Detection d = detected(s);
  expect_each_rod_one_open_dlo(s, d);
  const validate::CrossingListScore listed = listed_crossings(s, d);
  EXPECT_EQ(listed.detected, 4);
  EXPECT_EQ(listed.matches.size(), 4u);
  // The route alone lists them: with the loop swap's margin as small as it was (3), from
  // six exits all four, from ten (as before) fewer.
  DetectorConfig small_margin;
  small_margin.loop_cross_margin = 3;
  EXPECT_EQ(listed_crossings(s, detected(s, small_margin)).matches.size(), 4u);
  DetectorConfig large_regions_only = small_margin;
  large_regions_only.route_min_exits = 10;
  EXPECT_LT(listed_crossings(s, detected(s, large_regions_only)).matches.size(), 4u)
      << "this scene no longer shows what the route adds in small regions";
}

// `accuracy-suite.sh`'s seed set 1000, `cables` scene 000038 (seed 1004): a thin blue cable
// makes a loop about three widths across, lit lighter than the cable, crossing itself at 48
// degrees at (222, 94). The omega (the way in paired with the way out, the loop closed on
// itself) cost between 3 and 6 less than the crossing: with loop_cross_margin 3, as before
// 2026-12-07, no crossing was listed in the scene.
TEST(SuiteScenes, ASmallLitLoopOfAThinCableCrossesItself) {
  expect_loop_crossing_from_margin(scene("cables", 1004, 38), {222, 94}, 3);
}

// The scene with its picture as a data set holds it: `cables` scenes are written as JPEG
// (quality 88), whose artefacts shift the colours and tangents the detector reads.
synth::GeneratedScene as_written(synth::GeneratedScene s) {
  std::vector<uchar> jpeg;
  EXPECT_TRUE(cv::imencode(".jpg", s.render.image, jpeg, {cv::IMWRITE_JPEG_QUALITY, 88}));
  s.render.image = cv::imdecode(jpeg, cv::IMREAD_COLOR);
  return s;
}

// `scripts/demo.sh`'s `cables` set (seed 2026), scene 000005: a green cable's small loop
// lies in one region of six exits with a blue cable's crossing. Paired along the region's
// inside, the short route between the loop's two ends made closing it cheap, and it came
// out a ring of its own (strict DICE 0.80); a loop's ends are not paired by that route
// below 10 exits.
TEST(SuiteScenes, ASmallLoopBesideACrossingIsNoRing) {
  const synth::GeneratedScene s = as_written(scene("cables", 2026, 5));
  const Detection d = detected(s);
  EXPECT_EQ(d.dlos.size(), s.annotation.rods.size());
  EXPECT_EQ(closed_dlos(d), 0);
  EXPECT_GE(strict_dice(s, d), 0.97);  // 0.98; 0.80 with the loop closed into a ring
}

// `accuracy-suite.sh out/fresh-27000 200 27000`, `cables` scene 000035 (seed 27004): a green
// cable makes a small loop where a black and a red cable cross it, runs off into a wide
// loop that a fourth cable crosses, and comes back to end under the black one. Its two
// strands into the wide loop both run to that second crossing; paired along the first
// region's inside, a U-turn route between them got its weight's discount and closed the
// wide loop into a ring (strict DICE 0.86; 0.99 before the route was used from six exits).
TEST(SuiteScenes, ALoopThroughASecondCrossingIsNoRing) {
  const synth::GeneratedScene s = as_written(scene("cables", 27004, 35));
  const Detection d = detected(s);
  EXPECT_EQ(d.dlos.size(), s.annotation.rods.size());
  EXPECT_EQ(closed_dlos(d), 0);
  EXPECT_GE(strict_dice(s, d), 0.97);  // 0.99; 0.86 with the ring
}

// How far the detected centerlines leave the ground truth's near `at`: the largest distance
// from a true centerline point within `reach` px of `at` to the nearest detected centerline
// (validate's centerline error, over every DLO).
double farthest_truth_near(const synth::GeneratedScene& s, const Detection& d, cv::Point2f at,
                           double reach) {
  std::vector<cv::Point2d> near;
  for (const auto& rod : s.annotation.rods)
    for (const cv::Point2d& p : rod.centerline)
      if (cv::norm(cv::Point2f(p) - at) <= reach) near.push_back(p);
  std::vector<double> nearest(near.size(), std::numeric_limits<double>::infinity());
  for (const Dlo& dlo : d.dlos) {
    validate::Polyline line{{dlo.centerline.begin(), dlo.centerline.end()}, dlo.closed};
    const std::vector<double> to_dlo = validate::distances_to_polyline(near, line);
    for (size_t k = 0; k < near.size(); ++k) nearest[k] = std::min(nearest[k], to_dlo[k]);
  }
  return nearest.empty() ? 0 : *std::max_element(nearest.begin(), nearest.end());
}

// With the default constants the loop of `s` crossing itself at `at` is on a DLO's
// centerline and its crossing listed, once; with `without` (the rule that keeps it turned
// off) the centerline runs more than 6 px off it and nothing is listed there, for the
// same strict DICE within 0.005.
void expect_loop_on_centerline(const synth::GeneratedScene& s, cv::Point2f at, const DetectorConfig& without) {
  const Detection d = detected(s);
  EXPECT_EQ(d.dlos.size(), s.annotation.rods.size());
  EXPECT_EQ(self_crossings_near(d, at), 1);
  EXPECT_LE(farthest_truth_near(s, d, at, 25), 2.5);
  const Detection h = detected(s, without);
  EXPECT_EQ(self_crossings_near(h, at), 0);
  EXPECT_GT(farthest_truth_near(s, h, at, 25), 6);
  EXPECT_NEAR(strict_dice(s, d), strict_dice(s, h), 0.005);
}

// `accuracy-suite.sh`'s seed set 7000, `cables` scene 000191 (seed 7004): a thin cable
// (4 px wide) makes a loop about 13 px across, crossing itself at (154, 189). The loop's
// skeleton, 40 px long, leaves and re-enters one junction, like the strips round a hole
// in the mask, and was dropped: the centerline ran straight past the loop and no
// self-crossing was listed. The loop is as wide as the cable and 18 of its radii long.
TEST(SuiteScenes, ASmallLoopIsPartOfTheCenterlineNotAHole) {
  DetectorConfig holes_only;
  holes_only.small_loop_radii = 0;
  expect_loop_on_centerline(scene("cables", 7004, 191), {154, 189}, holes_only);
}

// `accuracy-suite.sh`'s default seed set, `cables` scene 000020 (seed 1004): a blue cable
// makes a loop about 25 px across that lies against a yellow cable. The loop's crossing with
// itself and its touch with the yellow cable became one crossing region, the loop's two
// halves inner branches of it, and the blue passage ran straight from its way in to its
// way out: the loop was off the centerline and the self-crossing at (297, 475) unlisted.
TEST(SuiteScenes, ALoopAgainstAnotherRodIsPartOfTheCenterline) {
  DetectorConfig straight;
  straight.loop_route_radii = 0;
  expect_loop_on_centerline(scene("cables", 1004, 20), {297, 475}, straight);
}

// `accuracy-suite.sh`'s default seed set, `stress` scene 000061 (seed 1005): a light purple
// rod makes a small loop where a dark purple ring crosses it, the ring's strand lying along
// one half of the loop as one band. The ring's passage runs from one group of the region's
// nodes to the other, which kept the loop from being routed round: the loop was off the
// rod's centerline, labelled as the ring, and the rod's crossing with itself at
// (349.7, 436.3) went unlisted.
TEST(SuiteScenes, ALoopWithAnotherRodAlongOneHalfIsPartOfTheCenterline) {
  const synth::GeneratedScene s = scene("stress", 1005, 61);
  const cv::Point2f at(349.7f, 436.3f);
  const int rod = 6;  // the light purple rod
  const auto rod_dice = [&](const Detection& d) {
    const Result<validate::DiceScore> dice = validate::matched_dice(s.render.labels, d.labels);
    EXPECT_TRUE(dice.ok());
    return dice.ok() ? dice.value().matched_dice[dice.value().instance_of(rod)] : 0.0;
  };
  const Detection d = detected(s);
  EXPECT_EQ(self_crossings_near(d, at), 1);
  // Where the band carries both strands its skeleton runs between them: within half a width.
  EXPECT_LE(farthest_truth_near(s, d, at, 25), 5);
  EXPECT_GE(rod_dice(d), 0.97);
  DetectorConfig straight;
  straight.loop_route_radii = 0;
  const Detection h = detected(s, straight);
  EXPECT_EQ(self_crossings_near(h, at), 0);
  EXPECT_GT(farthest_truth_near(s, h, at, 25), 6);
  EXPECT_LT(rod_dice(h), 0.95);
}

// `accuracy-suite.sh`'s default seed set, `stress` scene 000034 (seed 1005): a purple rod
// curls into a small loop where a green and a light blue rod cross it side by side, under a
// dark blue one. The bands they make measured the paper's r (the widest branch's median
// radius) at 14.9 px, 2.2 times the widest rod's half width (6.7 px): merge and crossing
// lengths grew with it, the green rod was lost in the others (four DLOs for five rods,
// strict DICE 0.74). Capped at 1.3 times the 95 % radius (radius_cap), r is 12.3 px.
TEST(SuiteScenes, SideBySideBandsDoNotInflateTheScale) {
  const synth::GeneratedScene s = scene("stress", 1005, 34);
  ASSERT_EQ(s.annotation.rods.size(), 5u);
  const Detection d = detected(s);
  EXPECT_EQ(d.dlos.size(), 5u);
  const Result<validate::DiceScore> dice = validate::matched_dice(s.render.labels, d.labels);
  ASSERT_TRUE(dice.ok());
  for (double v : dice.value().matched_dice) EXPECT_GE(v, 0.97);
  DetectorConfig paper_r;
  paper_r.radius_cap = 0;
  const Detection p = detected(s, paper_r);
  EXPECT_EQ(p.dlos.size(), 4u);
  EXPECT_LT(strict_dice(s, p), 0.8);
}

// `accuracy-suite.sh out/set-13000 200 13000`, s3 scene 000115: a yellow rod crosses a
// green one at a shallow angle just below a red rod's crossing, and lies along it for about
// 10 r. Its two Ys were 83.9 px apart for an epsilon of 83.5 (r 8.35 px): two crossings,
// one holding the red rod's crossing too. Joined they pair right, for a gain of 0.9, less
// than the merge_gain of 1 asked of links past epsilon until the gain asked grew from
// nothing at epsilon (pair_lone_ys); the yellow rod was traversed twice, 4 DLOs for 3
// rods, strict DICE 0.66. (With the paper's r, 8.53 px, the Ys were within epsilon.)
TEST(SuiteScenes, YsJustPastEpsilonJoinOnTheirGain) {
  const synth::GeneratedScene s = scene("s3", 13003, 115);
  ASSERT_EQ(s.annotation.rods.size(), 3u);
  expect_each_rod_one_open_dlo(s, detected(s));
}

// `accuracy-suite.sh out/set-29000 200 29000`, s2 scene 000153: a yellow rod's end lies
// hidden along a green rod from a Y to where the yellow rod's small loop crosses it, 19 r
// further on. There the loop's crossing and the yellow rod's way out were an X and a Y,
// merged into one region of five exits after the Ys' pass had run: the Y at the hidden
// end found no odd region to pair with, and the yellow rod came out as two DLOs (strict
// DICE 0.62). The Ys' pass runs again after merging.
TEST(SuiteScenes, ARodsEndHiddenAlongAnotherUpToAMergedCrossingIsOneDlo) {
  const synth::GeneratedScene s = scene("s2", 29002, 153);
  expect_as_many_dlos_as_rods(s, 2, 0.95);
}

// `accuracy-suite.sh out/set-29000 200 29000`, cables scene 000038: an orange cable runs
// into a yellow one and along it through a blue one's crossing. Merging left two regions
// of five exits each joined by two links of 2.3 and 2.7 r, within epsilon, which Y-pair
// matching had run before them and no later pass looked at: a cable split in two (8 DLOs
// for 7, strict DICE 0.82). The Ys' second pass weighs short links too.
TEST(SuiteScenes, OddRegionsLeftByMergingWithAShortLinkAreOneCrossing) {
  expect_as_many_dlos_as_rods(scene("cables", 29004, 38), 7, 0.95);
}

// `accuracy-suite.sh out/set-19000 200 19000`, s2 scene 000127: a red rod and a green one
// twist along each other, lying on each other for 49 r between two Ys. The Ys' pass took
// links up to wide_radii (40 r) only: the two Ys stayed apart and the rods came out as
// three DLOs (strict DICE 0.57). It takes links of any length.
TEST(SuiteScenes, RodsLyingOnEachOtherFarPastWideRadiiAreTwoDlos) {
  expect_as_many_dlos_as_rods(scene("s2", 19002, 127), 2, 0.95);
}

// `accuracy-suite.sh out/set-11000 200 11000`, cables scene 000139: a grey cable ends beside
// a black one, its forked tip 3 to 5 prongs (6-10 r) from the black one's crossing with a
// white cable. Merged into that crossing (tips were, through links up to epsilon), the
// tip's shaded prong paired with the black cable's way on: the black cable was cut and
// the grey one carried on along it (strict DICE 0.85). Tips merge within three prongs.
TEST(SuiteScenes, ACablesEndBesideACrossingIsNotPartOfIt) {
  expect_as_many_dlos_as_rods(scene("cables", 11004, 139), 6, 0.95);
}

// `accuracy-suite.sh out/set-17000 200 17000`, stress scene 000199: a light blue rod ties
// itself into a knot of three loops across a dark blue rod and a teal one, all merged into
// one cluster of 16 exits. With lightness counted half, the two blues were close enough in
// colour to pair through the knot: the light blue rod came out in two pieces, one of them
// joined to the dark blue rod (6 DLOs for 5 rods, strict DICE 0.785, 12 crossings paired
// wrong). In a cluster lightness counts in full (DetectorConfig::cluster_lightness).
TEST(SuiteScenes, TwoRodsOfOneHueStayApartThroughAKnot) {
  const synth::GeneratedScene s = scene("stress", 17005, 199);
  expect_as_many_dlos_as_rods(s, 5, 0.95);
  DetectorConfig half;
  half.cluster_lightness = kLightnessWeight;
  EXPECT_EQ(detected(s, half).dlos.size(), 6u);
}

// `accuracy-suite.sh out/fresh-15000 200 15000`, stress scene 000071: a ring of its own
// colour touches the other rods at one crossing cluster only. Its colour, which no other
// exit there shares, keeps it closed.
TEST(SuiteScenes, ARingOfItsOwnColourTouchingOneCrossingStaysARing) {
  const synth::GeneratedScene s = scene("stress", 15005, 71);
  int rings = 0;
  for (const auto& rod : s.annotation.rods) rings += rod.closed;
  ASSERT_EQ(rings, 1);
  const Detection d = detected(s);
  EXPECT_EQ(closed_dlos(d), 1);
  EXPECT_EQ(d.dlos.size(), s.annotation.rods.size());
}

// `accuracy-suite.sh out/fresh-9000 200 9000`, s1 scene 000138: a lone rod makes a loop
// through which it passes, crossing itself twice. The pairing of each crossing alone closed
// the loop into a ring, the rod running on straight through it.
TEST(SuiteScenes, ALoneRodsLoopThroughWhichItPassesIsNoRing) {
  const synth::GeneratedScene s = scene("s1", 9001, 138);
  ASSERT_EQ(s.annotation.rods.size(), 1u);
  expect_each_rod_one_open_dlo(s, detected(s));
  DetectorConfig no_reopening;
  no_reopening.loop_reopen_cost = 0;
  EXPECT_EQ(detected(s, no_reopening).dlos.size(), 2u);
}

// `accuracy-suite.sh out/fresh-15000 200 15000`, s3 scene 000197: a rod's large self-loop
// closes where the rod crosses itself beside another rod's crossing. Re-pairing the loop
// into the rod there costs about 1.4, more than loop_reopen_cost allows, and the loop came
// out as a ring; all four exits there are of the rod's colour, and
// loop_reopen_own_colour_cost allows it.
TEST(SuiteScenes, ASelfLoopOfTheRodsOwnColourIsTheRods) {
  const synth::GeneratedScene s = scene("s3", 15003, 197);
  ASSERT_EQ(s.annotation.rods.size(), 3u);
  expect_each_rod_one_open_dlo(s, detected(s));
  DetectorConfig one_allowance;
  one_allowance.loop_reopen_own_colour_cost = 0;
  EXPECT_EQ(closed_dlos(detected(s, one_allowance)), 1);
}

// `accuracy-suite.sh out/fresh-9000 200 9000`, stress scene 000052: a ring of nearly the
// colour of a rod it crosses twice (RGB 24, 113, 86 and 32, 120, 94). Joining the ring to
// a DLO it crosses costs more than loop_reopen_cost allows; a larger allowance merges it.
TEST(SuiteScenes, ARingOfARodsColourLyingAcrossItStaysARing) {
  const synth::GeneratedScene s = scene("stress", 9005, 52);
  ASSERT_EQ(s.annotation.rods.size(), 4u);
  ASSERT_TRUE(s.annotation.rods[3].closed);
  EXPECT_EQ(closed_dlos(detected(s)), 1);
  DetectorConfig lenient;
  lenient.loop_reopen_cost = 10;
  EXPECT_EQ(closed_dlos(detected(s, lenient)), 0);
}

// `accuracy-suite.sh out/fresh-7000 200 7000`, stress scene 000169: seven rods, several
// lying along each other through one cluster of crossings. One region of it had grown to
// kMaxExactExits (24) exits, and two beside it (6 exits each) could not join it; kept
// apart, each paired its exits wrongly and two rods came out as one (6 DLOs, strict DICE
// 0.59). Joined, costed past 24 exits by the greedy pairing, all seven are found (0.86;
// 0.81 since the cluster is paired along its inner branches too, AClusterIsPairedAlongItsInside:
// one strand of it goes the other way).
TEST(SuiteScenes, AClusterTooLargeToPairExactlyIsStillPairedAsOne) {
  const synth::GeneratedScene s = scene("stress", 7005, 169);
  expect_as_many_dlos_as_rods(s, 7, 0.78);
}

// `accuracy-suite.sh out/set-13000 200 13000`, stress scene 000011: five rods, strands of
// several lying along each other through one cluster of crossings of more than ten exits.
// Paired by the Hermite energies between its exits alone, five of its crossings went wrong
// and two rods swapped halves (strict DICE 0.64); paired along its inner branches too
// (DetectorConfig::route_min_exits), all are right (0.996).
TEST(SuiteScenes, AClusterIsPairedAlongItsInside) {
  const synth::GeneratedScene s = scene("stress", 13005, 11);
  expect_as_many_dlos_as_rods(s, 5, 0.95);
  DetectorConfig hermite_only;
  hermite_only.route_min_exits = 0;
  EXPECT_LT(strict_dice(s, detected(s, hermite_only)), 0.7) << "this scene no longer shows what the route adds";
}

}  // namespace
}  // namespace mbest

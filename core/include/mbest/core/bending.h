// Minimal bending energy pairing. At a crossing, each exit branch is summarised by a
// tangent; the strands through the crossing are the pairing of exits whose connecting
// paths bend least (the paper's Sec. III-F, extended from 4 exits to any number).
#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <unordered_map>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "mbest/core/junctions.h"
#include "mbest/core/keypoints.h"

namespace mbest {

// Where a path through a crossing leaves a branch, and the branch's direction there.
struct BranchTangent {
  cv::Point2f point;      // the branch pixel where the path through the crossing attaches
  cv::Point2f direction;  // unit, pointing away from the crossing
  // The branch's tangent at `point` itself (unit, away from the crossing): the line fitted
  // for `direction` follows the chord of a curved branch, which turns off the strand's
  // tangent at the attachment point. Paths through the crossing start along this one;
  // pairing keeps the line (steadier, and the better pairing cue on the dev scenes).
  cv::Point2f path_direction;
  int cut = 0;            // pixels of the branch (from the crossing side) the path replaces
  int last = 0;           // the last fitted pixel, counted like `cut`
  int reach = 0;          // the last pixel a fit may use (half a branch shared with a crossing)
  float radius = 0;       // median radius of the fitted stretch
  // The branch's colour over the fitted stretch (CIE Lab, L in [0, 100]), when an image was
  // given: strands keep their colour through a crossing, so it is a pairing cue.
  bool has_colour = false;
  cv::Vec3f colour;
};

// Fits the tangent of `end`'s branch: the skeleton near a junction bends towards it, so
// the first `cut_length` px are skipped and a line is fitted (total least squares) to the
// next `fit_length` px, never using more than half of a branch that ends in another
// crossing (`shared` = true). path_direction comes from a quadratic in arc length fitted
// over twice that stretch, differentiated at `point` (the line's direction where the
// stretch is too short or the fit disagrees with it by more than 60 degrees).
BranchTangent fit_branch_tangent(const SkeletonGraph& graph, BranchEnd end, double cut_length,
                                 double fit_length, bool shared);

// The discrete curvature of the paper, kappa = 2 |t1 x t2| / (1 + t1 . t2), for unit
// tangents t1 (in) and t2 (out); it grows without bound as the path turns back.
double discrete_curvature(cv::Point2f t1, cv::Point2f t2);

// Bending energy of the path that enters the crossing along `in` and leaves along `out`:
// a discrete rod through in.point and out.point, with the chord between them as its middle
// edge, bending kappa_in at in.point and kappa_out at out.point; energy = kappa_in^2 +
// kappa_out^2. It accounts for both the turn and the sideways offset of the two branches.
double bending_energy(const BranchTangent& in, const BranchTangent& out);

// Samples `bgr` along `stretch` px of the branch from where `t` attaches (t->cut, never
// past t->reach), at the skeleton pixels and half a radius to either side of them
// (highlights sit in the middle of a tube), and stores the per-channel median in CIE Lab in
// t->colour. A long stretch outvotes the overlap next to a shallow crossing, where the top
// strand's colour covers the branch.
void sample_branch_colour(const SkeletonGraph& graph, BranchEnd end, const cv::Mat& bgr,
                          BranchTangent* t, int stretch);
// build_passages samples this many tangent-fit lengths (4 x 3 r = 12 r): 3 r and 6 r let
// the overlap of a 25-35 degree crossing decide a branch's colour.
inline constexpr double kColourStretchFits = 4.0;

// What pairing two exits of different colour costs, in units of bending energy: 0 up to a
// colour difference of `kColourTolerance` (Lab units, lightness counted half: shading and
// highlights change lightness along one DLO more than hue), then growing linearly to
// `kColourPenaltyMax` at three tolerances. 0 when either exit has no colour. `lightness`
// weighs the squared lightness difference (kLightnessWeight: counted half).
inline constexpr double kColourTolerance = 10.0;
inline constexpr double kColourPenaltyMax = 4.0;
inline constexpr float kLightnessWeight = 0.25f;
double colour_penalty(const BranchTangent& a, const BranchTangent& b, float lightness = kLightnessWeight);
// The colour difference colour_penalty measures: Euclidean in CIE Lab, lightness weighted
// by `lightness` (counted half by default); and its square, for comparisons in a hot loop.
inline float colour_distance_squared(const cv::Vec3f& a, const cv::Vec3f& b,
                                     float lightness = kLightnessWeight) {
  const cv::Vec3f d = a - b;
  return lightness * d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}
double colour_distance(const cv::Vec3f& a, const cv::Vec3f& b, float lightness = kLightnessWeight);

// What pairing two exits of unlike width costs, in units of bending energy, per unit of
// width ratio: the wider exit's radius over the narrower's, less `kWidthTolerance` (room
// for the scatter of radii measured on one DLO's mask, in distance-transform steps of a
// few px; of 1.0-1.45 tried on generated scenes, 1.1 paired best). 0 when the ratio is
// `kTwoStrandRatio` or more: a branch that wide may carry two strands lying side by side,
// and one of them running on from it is no change of width. 0 when either exit has no
// radius. A DLO keeps its width through a crossing, while DLOs differ: up to 2.25 times in
// the generator's `cables` preset, 2 times in `stress`.
inline constexpr double kWidthTolerance = 1.1;
inline constexpr double kTwoStrandRatio = 1.9;
double width_penalty(const BranchTangent& a, const BranchTangent& b);

// What pairing two exits costs beyond their bending energy: `colour` times the colour
// penalty and `width` times the width penalty.
struct PairWeights {
  double colour = 0;
  double width = 0;
  // What pairing the two ends of one branch costs (a strand that leaves a crossing and
  // comes back to it: the pair closes it into a ring), added to their cost, unless colour
  // says the branch is a DLO of its own (loop_closing_cost). Only where the pairing knows
  // its exits' branches (the overload of min_energy_pairing with `ends`, TangentCache).
  double loop = 0;
  // How much lightness counts in the colour penalty (its `lightness`).
  float lightness = kLightnessWeight;
};

// What closing a loop at a crossing costs: a rod that crosses itself leaves the crossing
// and comes back to it along one branch, as does a ring touching other DLOs at one crossing
// only; when the crossing is shallow or its strands lie along each other for a stretch,
// pairing the branch's two ends with each other (a ring) and the rod's two other exits
// with each other bends hardly more than the rod's true path. Rings are the rarer, and
// coloured ones show it: `weight` is added to the cost of pairing the two ends of a branch
// unless the branch has a colour and no exit of another branch shares it (within
// kColourTolerance, or kSameWidthColourTolerance times that for an exit of the branch's
// width, within kSameWidth or kRadiusGrain: a rod's own loop, lit lighter or darker than
// the rod beside it); where the region has at most four exits, unless neither of the
// branch's ends shares a colour with another exit. Adds to `costs` (the pair costs of
// `exits`, symmetric).
// Added 2026-12-07, the wider tolerance at the same width: the loop property's only failures
// (a `cables` loop 11-13 Lab units from its rod coming out as a ring) 9 stored -> 3, its
// failing seeds of 12 (300 cases each) 6 -> 2; on the nine seed sets one `stress` crossing
// broken, on 2000 fresh scenes one `stress` scene mended (0.66 -> 0.78). Twice the
// tolerance merged two `stress` rings of their own into rods (0.95 -> 0.62).
inline constexpr double kSameWidth = 0.1;
// Radii are distance-transform values, on a grid with steps of up to about half a pixel at
// thin DLOs' radii (2, 2.24, ..., 3.16, 3.61, 4): two radii this close are one width
// whatever kSameWidth says. Added 2026-12-07 with the both-ends test above: the loop
// property's failures (a thin `cables` loop a shade apart from its rod, out as a ring) 6
// stored known -> 0, and the 4 new ones found that day (campaign seed 138, and seeds
// 300-331 of the loop property, 300 cases each: 3 of 32 failing -> 0) mended; the 15000
// scenes of the fifteen seed sets detect the same. The both-ends test in regions of any
// size broke 3 `stress` scenes (one 0.99 -> 0.80: a short branch of a 12-exit cluster).
inline constexpr double kRadiusGrain = 0.5;
inline constexpr double kSameWidthColourTolerance = 1.5;
void add_loop_closing_costs(std::vector<std::vector<double>>& costs,
                            const std::vector<BranchTangent>& tangents,
                            const std::vector<BranchEnd>& exits, double weight);

// The pairing of exits (indices into `exits`) with the least total cost: bending energy
// plus the weighted colour and width penalties. With an odd number of exits one is left
// unpaired (the strand that ends there). Up to kMaxExactExits exits, by branch and bound:
// exact, but for a tangle so even in its costs that the search runs out of steps (it keeps
// the best pairing found, the greedy one at worst); greedy (cheapest pair first) beyond.
inline constexpr int kMaxExactExits = 24;
std::vector<std::pair<int, int>> min_energy_pairing(const std::vector<BranchTangent>& exits,
                                                    PairWeights weights = {});
// The same, `ends` naming each exit's branch end (weights.loop counts).
std::vector<std::pair<int, int>> min_energy_pairing(const std::vector<BranchTangent>& exits,
                                                    const std::vector<BranchEnd>& ends,
                                                    PairWeights weights);

}  // namespace mbest

namespace mbest {

// A strand through a crossing: the path joining two paired exits of one crossing region.
struct Passage {
  int region = -1;                // index into the crossing regions
  BranchEnd from, to;             // the paired exits
  BranchTangent from_tangent, to_tangent;
  std::vector<cv::Point> path;    // 8-connected, from from_tangent.point to to_tangent.point
  std::vector<float> radius;      // per path pixel, interpolated between the two exits
  double energy = 0;              // bending energy of the path
  // A passage routed round a loop inside its region (route_round_inner_loops): the path
  // index where its way in ends and the loop begins, and where the loop ends and its way
  // out begins; the way in and the way out cross (the rod's crossing with itself). -1
  // otherwise.
  int loop_begin = -1, loop_end = -1;
};

// How exits are summarised and paired: tangents skip `cut_length` px next to the crossing
// and are fitted over the next `fit_length` px; with an image (`bgr` not empty, the mask's
// size) and `weights.colour` > 0, exits of different colour are paired reluctantly
// (colour_penalty); with `weights.width` > 0, so are exits of unlike width (width_penalty).
struct PairingSetup {
  double cut_length = 0, fit_length = 0;
  cv::Mat bgr;
  PairWeights weights;
};

// The cost of pairing two exits: their mean bending energy both ways plus the weighted
// colour and width penalties; and the total over a pairing.
double pair_cost(const BranchTangent& a, const BranchTangent& b, PairWeights weights);
double pairing_cost(const std::vector<BranchTangent>& exits,
                    const std::vector<std::pair<int, int>>& pairs, PairWeights weights);

// The tangents (and colours) of a crossing's exits under `setup`.
std::vector<BranchTangent> exit_tangents(const SkeletonGraph& graph,
                                         const std::vector<BranchEnd>& exits,
                                         const PairingSetup& setup);

// exit_tangents, each exit computed once per graph: an exit's tangent and colour depend on
// its own branch only, however the crossings around it are grouped. Holds references to
// both arguments; the graph may lose branches (alive = false) but not gain any.
class TangentCache {
 public:
  TangentCache(const SkeletonGraph& graph, const PairingSetup& setup);
  std::vector<BranchTangent> of(const std::vector<BranchEnd>& exits);
  // The cost of the least-cost pairing of `exits` (min_energy_pairing, pairing_cost), once
  // per set of exits: junction grouping and region merging ask for the same sets again.
  double least_cost(const std::vector<BranchEnd>& exits);
  // A lower bound of least_cost, in O(n^2): every exit pays at least half its cheapest pair
  // (but one, when their count is odd).
  double least_cost_bound(const std::vector<BranchEnd>& exits);
  const PairingSetup& setup() const { return setup_; }
  const SkeletonGraph& graph() const { return graph_; }

 private:
  const SkeletonGraph& graph_;
  const PairingSetup& setup_;
  std::vector<BranchTangent> tangents_;
  std::vector<bool> done_;
  std::map<std::vector<int>, double> least_costs_;  // by sorted 2 * branch + side
  std::unordered_map<uint64_t, double> pair_costs_;  // by the pair's two 2 * branch + side
  // pair_cost of every two of `exits`, each pair computed once.
  std::vector<std::vector<double>> pair_costs(const std::vector<BranchEnd>& exits);
};

// Two regions with odd exit counts (each leaves one strand ending there) joined by a branch
// longer than `min_link` (Y-pair matching took the shorter ones), however long: one
// crossing when the two strands left alone continue each other (they pair together in
// the joined region's minimal energy pairing, at a cost of at most `max_cost`). Such a pair
// is a thin DLO passing under or over a wide one at a shallow angle: where it lies within
// the wide one's width, the mask shows one DLO with a thin branch on either side. Two plain
// Ys (three exits each) are also one crossing when both strands run through: the joined
// pairing joins each exit of one Y to one of the other, each pair at most `max_cost` (a
// shallow crossing with a long overlap, where which strand each Y alone leaves ending is
// a near tie). Or, whatever the strands left ending, when pairing the exits of both
// together costs less than pairing each region alone (as merge_regions_by_pairing_cost,
// though joined the two strands left ending pair too), by at least `min_gain` times the
// share of `min_link` by which the link is longer than `min_link` (at most all of it, and
// more than nothing): a shallow crossing whose Ys each paired a strand with the link
// between them because the link's colour mixes both strands. (Asking the full `min_gain`
// just past `min_link`, the paper's epsilon, left two Ys 10.0 r apart as two crossings
// that joined would pair right: their gain was 0.9, suite `s3` seed 13003 scene 115, one
// rod traversed twice.) With `short_links`, links up to `min_link` are weighed alike: run
// after merge_regions_by_pairing_cost, which leaves two regions of odd exit count alone
// (their case is this one) and can make them out of Ys that Y-pair matching had already
// used, a strand lying along another through a knot of three (suite `cables` seed 29004
// scene 38: two regions of five exits joined by two links of 2.3 and 2.7 r). No link is too
// long: what joins two regions is how their strands pair, not how far apart they are, and
// two rods lying on each other can do so for any length (bounded at 40 r, suite `s2` seed
// 19002 scene 127, two rods twisting along each other for 49 r, came out as three DLOs).
// Also two plain Ys each linked as above (longer than `min_link`) to a region of even
// exit count between them (a third DLO crossing two strands that lie along each other
// from one Y to the other): the three are one crossing when the joined least-cost pairing
// joins each exit of one Y to one of the other, at most `max_cost` each, and the middle
// region's exits among themselves. Cheapest first (a gain counting as its negative cost),
// each region once. Returns the joins made (two for a Y, a crossing and a Y).
int pair_lone_ys(SkeletonGraph& graph, std::vector<CrossingRegion>& regions, TangentCache& cache,
                 double min_link, double max_cost,
                 double min_gain = std::numeric_limits<double>::infinity(), bool short_links = false);

// Junction grouping decides by distance; where three strands cross near one point the
// skeleton may split the crossing into two regions a few radii apart, and each alone can
// only pair its exits wrongly. Two regions joined by a branch no longer than `max_link`
// become one when pairing their exits together costs at least `min_gain` less than pairing
// each alone (the link becomes inner and is marked dead); best gain first, repeated while
// one qualifies, from three exits (a DLO's tip lying along another thins into a bend with
// two exits, forced to pair the two DLOs, beside the Y where it ends) to any number: past
// kMaxExactExits a set of exits is costed by its greedy pairing (min_energy_pairing), which
// costs no less than the least, so a joined tangle that size shows at most its own gain.
// Capping the joined region at kMaxExactExits exits left clusters of strands lying along
// each other split into regions that each paired wrongly (nine seed sets: `stress` pairing
// failures 2619 -> 2591 without the cap, strict DICE +0.05, the other presets unchanged;
// a cap of 8 or 12 exits: 6458 and 4616). A link longer than `max_link`, up to
// `long_link`, qualifies too if the gain is
// three times `min_gain`: two strands crossing at a shallow angle overlap along it, or a
// twisted pair's two strands lie side by side along it, and one region alone must pair a
// strand with the link that carries both (whether the mask shows the link wider than its
// neighbours or not: a thin DLO over a wide one does not widen it). At most one of the two
// may have an odd exit count (a DLO ends there, e.g. on the crossing of two others): the
// joined region then leaves one exit unpaired too, so the costs compare like with like;
// two odd ones are pair_lone_ys's case. Where two or more links up to `max_link` join the
// same two regions (a rod through a small loop of another, or two strands crossing twice
// a few radii apart), the two are weighed through all of them at once, and all become
// inner: merged through one, the others would be left as exits of the joined region on
// both sides, which the pairing treats as strands. When no two qualify, three in a row
// (two links, each as above) become one if joined they gain three times `min_gain` (plus
// twice `min_gain` per long link): a thin DLO hidden under a wide one from one region to
// the next but one, across a third DLO's crossing, where neither end region gains enough
// joined to the middle one alone. A DLO's forked tip (one prong pruned, the other, shorter
// than `tip_prong`, left as an exit of a two-exit region) is no crossing: it is merged
// through no link longer than three prongs, nor than `max_link` (the prong's shaded colour
// pairs cheaply with any other tip's, or a strand's, however far; a tip next to a crossing
// may still be part of it). Returns the merges made (two for three regions).
int merge_regions_by_pairing_cost(SkeletonGraph& graph, std::vector<CrossingRegion>& regions,
                                  TangentCache& tangents, double max_link, double min_gain,
                                  double long_link = 0, double tip_prong = 0);

// The bending stage: for every crossing region, the tangents of its exits (from the graph
// `tangents` was made for) and the pairing of least total cost; one Passage per pair. A
// region with two exits (a bend the skeleton made into a junction) gets its single forced
// passage unless it folds back with a bending energy above `fold_energy`: then both
// strands end there. Nor does any region join two exits whose colours differ by the
// colour penalty's cap (three tolerances) and whose path bends with an energy (without
// colour) of at least `unlike_energy`: those are two DLOs that end inside the crossing,
// whose ends the least-cost pairing joins because it pairs every exit it can. This holds
// for an exit too short for a full tangent fit (a stub between two crossings) as well:
// asking for a full fit (90 % of fit_length) on both lost 121 more `stress` crossings on
// 1800 scenes than it saved, and 4 on 7200 scenes of the other presets for none saved.
// A region with two such exits (no other pairing to choose) parts them at the lower
// `unlike_fold_energy`: one rod neither folds nor changes colour at a point, and two DLOs
// of different colours whose ends touch leave a junction with just their two exits.
//
// A cluster (a region of at least `route.min_exits` exits and at most 64, with inner
// branches: strands lying along each other, merged into one region by the stages before)
// is paired along its inside too: a pair of exits at two different nodes of it costs the
// lesser of its bending energy and `route.weight` times the bending of the strand's
// cheapest route between them through the inner branches (inner_route_bending). All pairs
// across a cluster share one chord, so their Hermite energies add up alike for any
// pairing; the skeleton inside shows how each strand runs. There colour weighs lightness by
// `route.lightness` (DetectorConfig::cluster_lightness) instead of weights.lightness. Below
// 10 exits the route is not used between a loop's two ends (one branch leaving and
// re-entering the region), nor, where it bends more than their own pairing, between two
// exits whose strands both run into one other region (a loop through a second crossing).
// min_exits 0: never.
//
// A loop's two ends paired with two exits of other branches within 1.5 times the loop's
// width without crossing (the rod running into the loop and out of it on one side, an
// omega) are paired crossing instead when that costs at most `loop_cross_margin` more: a rod
// that makes a loop crosses itself, and the tangents of a tight loop's ends bend with it.
// In a region with further exits (the loop closing on another rod) only when the four are
// alike in colour and no other exit there is of their colour. 0: never.
struct RouteCosts {
  int min_exits = 0;
  double weight = 1;
  float lightness = kLightnessWeight;
};
std::vector<Passage> build_passages(const std::vector<CrossingRegion>& regions,
                                    TangentCache& tangents,
                                    double fold_energy = std::numeric_limits<double>::infinity(),
                                    double unlike_energy = std::numeric_limits<double>::infinity(),
                                    double unlike_fold_energy = std::numeric_limits<double>::infinity(),
                                    RouteCosts route = {}, double loop_cross_margin = 0);

// For every two exits of `region` (tangents `exits`, in the order of region.exits) at two
// different nodes of it, the bending of the cheapest route between them through its inner
// branches: a path that enters along one exit, follows inner branches from node to node and
// leaves along the other pays the squared discrete curvature of every turn, from the exit
// into the first inner branch, along each inner branch (from its tangent leaving one node
// to its tangent arriving at the other, fitted as exits are, over `cut_length` and
// `fit_length`), from branch to branch at each node and into the far exit. Infinity for
// two exits at one node or with no such route. Symmetric.
std::vector<std::vector<double>> inner_route_bending(const SkeletonGraph& graph,
                                                     const CrossingRegion& region,
                                                     const std::vector<BranchTangent>& exits,
                                                     double cut_length, double fit_length);

// The passage joining exit `from` to exit `to` of crossing region `region`: a Hermite curve
// between the two attachment points, along their path directions, radii interpolated.
Passage make_passage(int region, BranchEnd from, const BranchTangent& from_tangent, BranchEnd to,
                     const BranchTangent& to_tangent);

// A rod's loop inside a crossing region: where a rod makes a small loop that lies on or
// against another DLO, the loop's own crossing and the one it makes with that DLO are
// grouped into one region (Y-pairs, merges), the loop's two halves become inner branches,
// and the rod's passage runs straight from its way in to its way out, leaving the loop off
// its centerline and its crossing with itself unlisted. For each region whose nodes fall
// into two groups joined by exactly two inner branches (each at least `min_half_length`
// long, not twins), one passage with both exits in one group and the others' exits in the
// other group, and both branches of that passage's colour (within 1.5 kColourTolerance of
// one of its exits, and nearer than to any other passage's exits): the passage is routed
// from its way in along one branch, across the other group, back along the other branch
// and out, the order bending the least where it joins them. Where no two branches of a
// region qualify so, passages with an exit in each group (another rod lying across the
// loop, often along one of its halves where the two merge into one band) are let be,
// counted in neither group but still in the colour test. Needs colours (an image).
// Returns the passages routed.
int route_round_inner_loops(std::vector<Passage>& passages, const std::vector<CrossingRegion>& regions,
                            TangentCache& tangents, double min_half_length);

// Keeps each passage's path on the mask. build_passages draws a passage as a Hermite curve
// between its two exits, which is the strand's course through an ordinary crossing; but
// across a long region (Y-pairs, regions merged through links up to wide_radii, and Ys
// joined by pair_lone_ys through links of any length) the curve can cut over the
// background, or leave the image at its border, leaving the DLO's centerline and labels off
// its pixels. Where the curve runs off the mask for more than
// `max_off` px in a row, or leaves the image, its path becomes the cheapest chain of mask
// pixels between the two exits that keeps to the middle of the strands and, where the mask
// allows, near the curve (path_through_mask; the radii are interpolated along it). An exit
// point off the mask (an exit attached a pixel or two outside it, at the image border where
// the mask thins) is joined to the nearest mask pixel within max(2 px, r), where the chain
// starts. Returns how many paths were replaced.
int keep_passages_on_mask(std::vector<Passage>& passages, const cv::Mat& mask, float r,
                          float max_off);

}  // namespace mbest

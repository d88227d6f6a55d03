// The mBEST detector: binary mask (and optionally the colour image) in, ordered DLO
// centerlines, crossings and an instance label image out.
// Coordinates are pixels, x to the right, y down; cv::Point(x, y).
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mbest/core/result.h"

namespace mbest {

// One crossing: where two strands pass over each other (their paths through a crossing
// region meet). Three strands through one point are three crossings, one per pair.
// Two strands that cross over (once; a pair twisted once round the other inside one
// crossing region is two crossings). Strands that only touch are none. A DLO that ends at
// a crossing region with its tip past a strand through it (over it, or under it with a stub
// showing beyond) crosses that strand too.
struct Crossing {
  cv::Point2f location;  // where the two paths come closest (or change sides), pixels
  double angle_deg = 0;  // angle between the strands' tangents, in [0, 90]
  // DLO indices of the two strands, top first (the one the labels show there). A
  // self-crossing lists the same DLO twice.
  std::vector<int> dlos;
};

// One deformable linear object.
struct Dlo {
  // Ordered 8-connected pixels from one end to the other. For a closed DLO (a ring) the
  // last pixel is 8-adjacent to the first and no pixel is repeated at the seam.
  std::vector<cv::Point> centerline;
  std::vector<float> radius;  // radius in pixels at each centerline pixel (same length)
  bool closed = false;
  // Indices into Detection::crossings, in traversal order (by index where one passage
  // through a region takes part in several).
  std::vector<int> crossings;
};

struct StageTime {
  std::string stage;
  double ms = 0;
};

struct Detection {
  std::vector<Dlo> dlos;
  std::vector<Crossing> crossings;
  // CV_16UC1, the mask's size: 0 = background, i + 1 = dlos[i]. Every mask pixel reached
  // from a centerline belongs to one DLO; crossing pixels belong to the DLO on top.
  cv::Mat labels;
  std::vector<StageTime> timings;  // one entry per pipeline stage, in order
  double total_ms() const;
};

// Every length is in units of r, the widest DLO's radius, measured on the mask (but
// small_loop_radii, in a loop's own radius): the detector has no hyperparameter in pixels.
// JSON field names are the member names.
struct DetectorConfig {
  // r is the paper's: the largest median radius of a skeleton branch (keypoints.h,
  // measure_radii), but at most this many times the radius 95 % of the skeleton's length
  // stays within (length_quantile_radius). Where rods lie side by side, or knot, the mask
  // makes short branches far wider than any rod: in `stress` the paper's r came out 1.5
  // times the widest rod's half width (median over scenes; 1.15 in `cables`, 1.2 in `s3`),
  // and every length below grew with it. Added 2026-12-07: the 95 % radius is 0.92-1.55
  // times the widest rod's half width on 180 suite scenes (`cables`, `s3`, `stress`). On
  // the nine seed sets (9000 scenes) with 1.3, `stress` pairing failures 1763 -> 1754 (dev)
  // and 564 -> 554 (held-out), its strict DICE +0.23 points (dev), crossing-list recall
  // 54.44 -> 56.71 % at precision 89.98 -> 90.84 %; outside `stress` failures at 10
  // degrees and above 74 -> 68 (dev) and 27 -> 23 (held-out), but 46 -> 52 on the six
  // unseen sets of seeds 23000-33000 (whose `stress` failures fell 1446 -> 1372). 1.2, 1.25
  // and 1.4 broke more crossings at 45-90 degrees outside `stress` (dev: 39, 35 and 35
  // failures against 33). 0 turns it off: the paper's r.
  double radius_cap = 1.3;
  double min_dlo_length_radii = 3.0;  // shorter traversals are mask noise, not DLOs
  double cut_radii = 1.0;    // skeleton next to a crossing replaced by the path through it
  double fit_radii = 3.0;    // stretch of branch a crossing tangent is fitted to
  double merge_radii = 2.0;  // junctions joined by a shorter branch are one crossing
  double epsilon_radii = 10.0;  // Ys joined by a shorter branch are one crossing (paper)
  double wide_radii = 40.0;  // ... or by a branch up to this long, if it is wider than a DLO
  // Ys joined through other crossings by a path up to this long are one crossing with them
  // (junctions.h, step 4).
  double through_radii = 30.0;
  // With the colour image: how much a colour change between two exits of a crossing weighs
  // against pairing them (bending.h, colour_penalty). 0 = geometry alone, as in the paper.
  // At 4, pairing two exits of clearly different colours (30 Lab units apart) costs 16,
  // more than a path turning 150 degrees (about 5): on fresh generated scenes 4 paired
  // better than 2 at every angle of 20 degrees and above, and 3 to 6 alike.
  double colour_weight = 4.0;
  // How much a change of width between two exits of a crossing weighs against pairing them,
  // per unit of width ratio beyond 1.1 (bending.h, width_penalty; exits nearly twice as
  // wide as the other, which may carry two strands side by side, cost nothing). Works on
  // the mask alone. At 4, pairing a 6 px wide exit with a 9 px one costs 1.6, about a 100
  // degree turn. Added 2026-12-06: on the 9000 generated scenes of seeds 1000-21000 it
  // cut `stress` pairing failures from 3197 to 2906 and raised `stress` strict DICE by
  // 0.3-0.4 points; in `s2`, `s3` and `cables` at 10 degrees and above 137 failures
  // became 125.
  // 0 turns it off.
  double width_weight = 4.0;
  // What pairing the two ends of one skeleton branch at a crossing costs, in bending energy
  // units, when colour does not mark the branch as a DLO of its own (bending.h,
  // add_loop_closing_costs): a rod's self-loop lying along the rod at a shallow self-crossing
  // otherwise came out as a ring beside an uncrossed rod. 10 is about two 150 degree turns.
  // Added 2026-12-06: on the 9000 generated scenes of seeds 1000-21000 failures outside
  // `stress` at 10 degrees and above went from 121 to 116, `stress` failures from 2660 to
  // 2651 (with no colour gate 10 broke coloured rings touching one crossing: `stress` DICE
  // -0.06); 3 mended 1 crossing, 30 alike but with no gate. 0 turns it off (scenes of
  // rings, rubber bands, of one colour).
  double loop_closing_cost = 10.0;
  // A closed DLO that runs through crossings becomes part of an open DLO crossing it when
  // re-pairing one of its passages with one of that DLO's costs at most this much more
  // (bending energy units), unless colour marks it a ring of its own (traverse.h,
  // open_closed_loops): a rod's self-loop closed where it crosses the rod or another DLO.
  // Added 2026-12-06: on the 9000 generated scenes of seeds 1000-21000 it mended 9
  // crossings in 3 scenes outside `stress` (a lone rod's loop among them) and broke none
  // (failures at 10 degrees and above 116 -> 108), and `stress` failures went from 2651 to
  // 2619; 0.5 alike; 2 and 10 mended more (101 and 95) but merged rings of a rod's colour
  // into it (`stress` strict DICE -0.25 and -0.3 points on the held-out pair). 0 turns it
  // off.
  double loop_reopen_cost = 1.0;
  // ... and at most this much more where the four exits of the two passages are all of one
  // colour (within half kColourTolerance: most likely one rod and its own loop), with the
  // image's colours only. Added 2026-12-06: on the seven dev sets (7000 scenes) failures
  // outside `stress` at 10 degrees and above 81 -> 74 (an `s3` and a `cables` scene), one
  // `stress` scene mended and one broken (a ring of a rod's colour), `stress` figures
  // otherwise unchanged; the held-out pair and 2000 fresh scenes (seeds 23000, 25000)
  // unchanged. 2 without the colour test merged rings into rods (above); 3 with it mended
  // 6 more crossings but merged a ring of a rod's near colour in `stress`. Below
  // loop_reopen_cost it does nothing.
  double loop_reopen_own_colour_cost = 2.0;
  // A loop through a crossing region of four exits (its two ends and two exits of like
  // width) is paired crossing rather than as an omega (the rod running into the loop and out
  // on one side) when that costs at most this much more (bending.h, build_passages): the
  // DLO and its labels are the same either way, but only the crossing pairing lists the
  // self-crossing and runs the centerline across it. Added 2026-12-06: on the nine seed
  // sets (9000 scenes) the crossing list's recall on `cables`, whose loops are 5-15 widths
  // round, went from 89.41 to 90.02 % (images with the right count 62.3 -> 65.2 %), `stress`
  // 51.94 -> 52.29 %, precision and pairing unchanged, one `stress` scene's strict DICE
  // -0.013; on 2000 fresh scenes (seeds 23000, 25000) `cables` recall +0.6 points, right
  // count +3 and +4 points. 6 alike; 100 (always) listed a false crossing in `s1`. 0 turns
  // it off. 3 until 2026-12-07, then 10 (after route_min_exits 6): nine seed sets, recall
  // `cables` 90.51 -> 90.85 %, `stress` 52.62 -> 52.96 %, precision the same or higher,
  // pairing the same but at one `stress` crossing; 20 traded a true crossing for two false
  // in `cables`, 30 listed a false one in `s1`. 4000 further scenes: `cables` recall +0.4.
  double loop_cross_margin = 10.0;
  // A skeleton branch leaving and re-entering one crossing within 4 merge_radii is taken for
  // the strips round a hole in the mask and dropped (junctions.h, step 2), unless it is a
  // rod's small self-loop: the crossing's only other exits are the rod's way in and out,
  // the loop is about as wide as they are, and it is at least this many times its own
  // radius long (a hole's strips are narrower, and shorter). `cables` loops of 2-3 widths
  // across were dropped from the centerline, their self-crossing unlisted. Added
  // 2026-12-07: on the nine seed sets (9000 scenes) `cables` crossing-list recall 90.02 ->
  // 90.21 % (29 more of its 1466 self-crossings at 40-90 degrees listed, right count 65.2 ->
  // 65.8 %), centerline error truth -> prediction 0.854 -> 0.847 px; DICE and pairing
  // outside `stress` unchanged, `stress` failures 1779 -> 1774 and 566 -> 566. Without the
  // two-exit test (loops on another rod's crossing too) `cables` recall +0.23 points, but
  // `stress` rods merged through such loops (held-out failures 566 -> 578); with neither
  // that nor the length test, holes at shallow crossings became loops (seven `cables`, an
  // `s2` and an `s3` scene broken). One suite `stress` scene fell 0.95 -> 0.81 (the loop's
  // crossing merged with its neighbour by pairing cost). 0 turns it off.
  double small_loop_radii = 9.0;
  // A rod's loop lying on or against another DLO: its own crossing and the one with that
  // DLO are grouped into one region, the loop's two halves inside it, and the rod's passage
  // ran straight from its way in to its way out, the loop off its centerline and its
  // crossing with itself unlisted. Where two inner branches at least this many radii long
  // are all that joins the region's two groups of nodes, one group holding the rod's
  // passage alone and both branches of its colour, the passage is routed round them and
  // its crossing with itself listed (bending.h, route_round_inner_loops; where no two
  // branches qualify so, other strands may run from one group to the other). Added 2026-12-07:
  // on the nine seed sets (9000 scenes), strict DICE better by more than 0.002 on 16 scenes
  // (four `cables`, up to 0.986 -> 0.996) and worse on one `stress` scene (0.993 -> 0.988),
  // one `stress` pairing failure fewer, nothing else changed; crossing-list recall `cables`
  // 90.87 -> 91.69 % (dev) and 90.80 -> 91.50 % (held-out), `s2` +0.30 and +0.53 points,
  // `s3` +0.39 and +0.49, `stress` +0.98 and +0.97; 131 more crossings matched in `cables`
  // for 18 more listed wrongly (precision 98.33 -> 98.23 and 97.79 -> 97.69 %), 402 for 50
  // in `stress`, 27 for 2 in `s3`, 9 for 0 in `s2`, 0 for 1 in `s1`. At 3 radii: 80 for 12
  // in `cables`; at 0: 140 for 28. Needs the colour image. 0 turns it off.
  double loop_route_radii = 1.5;
  // Two crossing regions joined by a branch up to epsilon_radii long become one when
  // pairing their exits together costs this much less (bending energy units) than pairing
  // each alone (bending.h, merge_regions_by_pairing_cost), and by a branch up to wide_radii
  // when it costs three times this much less, as do three regions in a row; so do two
  // regions each leaving a strand ending, joined by a branch of any length past
  // 2 epsilon_radii (pair_lone_ys; less is asked from epsilon_radii up). Large values turn
  // it off.
  double merge_gain = 1.0;
  // Two Ys joined by a branch longer than epsilon_radii (of any length), each leaving
  // a strand ending there, are one crossing when those two strands continue each other at
  // a pairing cost (bending energy plus colour) of at most this (bending.h, pair_lone_ys):
  // a thin DLO passing along a wide one at a shallow angle; or when both strands run
  // through the two Ys, each pair at most this. 0 turns it off.
  double lone_y_cost = 4.0;
  // A junction left with two exits (a bend the skeleton made into a junction, a split end
  // pruned) joins them into one strand unless that path folds back with more bending energy
  // than this (about a 140 degree turn): an elastic rod does not fold at a point, but two
  // DLOs touching end to end, or leaving the image side by side, meet that way
  // (bending.h, build_passages). Large values turn it off.
  double fold_energy = 4.0;
  // With the colour image and colour_weight > 0: two exits of a crossing region whose
  // colours differ by 30 Lab units or more (colour_penalty at its cap) are not joined when
  // their path bends with at least this energy, though the least-cost pairing pairs them:
  // two DLOs that both end inside one crossing cluster (bending.h, build_passages). 1 is a
  // turn of about 78 degrees (energies as for colour_fold_energy below, whose 0.7 is about
  // 66). It was 4 until 2026-12-05; on the 9000 scenes of seeds 1000-21000, 1 mended 4
  // crossings outside `stress` (at 20-90 degrees) and broke none, cut `stress` failures from
  // 3540 to 3502 and raised strict DICE on `cables` by 0.04-0.11 points and on `stress` by
  // 0.23; 0.5 broke a `cables` scene.
  // Large values turn it off.
  double unlike_end_energy = 1.0;
  // Two DLOs leaving the image side by side touch where they leave, and thinning may run
  // one branch round the V they make there. A branch that turns sharper than this (bending
  // energy of the turn between 3 r chords before and after a pixel within a radius of the
  // border; 1 is about 78 degrees) is cut there, when both arms run straight (within 30
  // degrees) up to it: a smooth bend or a hairpin turns as much along its arms (prune.h,
  // cut_folds_at_border). Large values turn it off.
  double border_fold_energy = 1.0;
  // With the colour image: two DLOs whose tips touch make a V the skeleton runs round. A
  // branch that turns sharper than this (measured as for border_fold_energy, arms running
  // straight up to the turn) where its two arms differ in colour by 30 Lab units or more is
  // cut there, anywhere in the image (prune.h, cut_folds_between_colours): a rod neither
  // folds at a point nor changes colour. Likewise a junction left with two exits of such
  // colours does not join them when their path bends with more than this (bending.h,
  // build_passages), though less than fold_energy. Both were found by the property
  // campaign (three rods through a point, two touching tip to tip; two rods ending together
  // at the border, bending 3.99); on 9000 generated scenes of seeds 1000-21000 the cut
  // changed no label and the junction rule mended two scenes' count errors and broke none.
  // First 1 (about 78 degrees); 0.7 (about 66) since 2026-12-05: on the same scenes it
  // mended two more count errors (`cables` strict DICE 79 -> 99.7 %), a crossing at 55
  // degrees and three in `stress`, and lowered no scene's DICE; 0.5 broke 7 in `stress`.
  // Large values turn both off.
  double colour_fold_energy = 0.7;
  // With the colour image and colour_weight > 0: inside a crossing region, a mask pixel goes
  // to the DLO whose colour it shows when that DLO's colour is nearer by at least this (Lab
  // units, lightness counted half) than the colour of the DLO the pixel was drawn for, and
  // within five times this (instance_mask.h, refine_labels_by_colour). 0 turns it off.
  // 10 until 2026-12-06 (7 then lowered strict DICE by 0.3 points on `stress`); once the
  // colours were read as a 3 x 3 median, 8 cost 0.05 points there and 0.01 on `cables`, but
  // over the nine synthetic seed sets `stress` pairing failures fell 2781 -> 2660, at 20-45
  // degrees outside `stress` 50 -> 48 (10-20 23 -> 22, 45-90 51 -> 52), real S2 and S3 rose.
  double colour_label_margin = 8.0;
  // A branch carrying two strands side by side over at least this long (two DLOs lying
  // along each other, or one ending along another) is split into one branch per strand
  // (strands.h, split_side_by_side). Large values turn it off.
  double side_by_side_radii = 3.0;
  // A crossing region of at least route_min_exits exits (a cluster of strands lying along
  // each other) pairs an exit with one at another of its nodes at the lesser of their
  // bending energy and route_weight times the bending of the route between them through
  // the region's inner branches (bending.h, RouteCosts). 0 turns it off. Over the nine
  // synthetic seed sets (2026-12-06), `stress` pairing failures 2591 -> 2345 and strict
  // DICE +0.32 (seven dev sets) and +0.61 points (held-out pair); outside `stress` one
  // crossing mended and one broken, in one `cables` scene. Weights 0.2 and 0.5: 2344 and
  // 2410 failures; 1 (a route's turns counted in full): 2484. From 10 exits at first; 6
  // since 2026-12-07: a rod through another's loop or a loop round another rod makes a
  // region of six exits whose inside shows which strand goes where (`s2` 15002 scene 117:
  // one of four crossings listed, then all four). Over the nine seed sets, pairing outside
  // `stress` the same crossing by crossing; `stress` failures 1776 -> 1762 (dev) and 567 ->
  // 560 (held-out), 13 scenes better and 4 worse; crossing-list recall `cables` 90.36 ->
  // 90.51 %, `s2` 95.72 -> 95.95 %, `s3` 94.76 -> 95.00 %, precision the same or higher.
  // From 5 exits alike; from 7 or 8 as many `stress` crossings mended but no more listed
  // (the loops' regions have six); from 4 (every X) two `cables` crossings at 45-90
  // degrees broken; weights 0.25 (from 5) and 0.5 (from 6) made 28 and 18 scenes worse.
  // On 4000 scenes not used to choose it, one `cables` scene broken (three crossings).
  // Below 10 exits the route is not used between a loop's two ends (bending.cpp,
  // kClusterExits): it closed a cable's small loop into a ring (the demo's `cables` scene
  // 5); `stress` failures then 1765 and 564. Nor, where it bends more than the pair's own
  // bending, between two exits whose strands run into one other region: that mended the
  // `cables` scene above (a loop through a second crossing), changing nothing else.
  double route_min_exits = 6;
  double route_weight = 0.35;
  // With the colour image: in such a cluster, how much lightness counts in the colour
  // difference of two exits, as the weight of its square (Lab units; elsewhere 0.25, counted
  // half, because shading and highlights change lightness along one DLO more than hue;
  // bending.h, colour_penalty). In a cluster a DLO's exits are a few radii apart under one
  // light, while the DLOs tangled together often share a hue and differ in lightness (a
  // dark and a light blue rod, a brown and a peach one). Added 2026-12-08: over the nine
  // synthetic seed sets, `stress` pairing failures 1665 -> 1568 (seven dev sets) and
  // 541 -> 531 (held-out pair), strict DICE +0.12 and +0.04 points; outside `stress` on
  // the seven 16 -> 15 failures at 20-45 degrees and 32 -> 31 at 45-90 (3 crossings mended,
  // 1 broken), the pair unchanged. 0.5: 1609 and 536. Lightness in full in every pairing
  // did about as well in `stress` (1591 and 518) but cut cables where shading changes their
  // lightness (a cable's end past its own crossing came out as a DLO of its own): outside
  // `stress` 72 scenes worse and 26 better over the fifteen seed sets.
  double cluster_lightness = 1.0;
};

// Reads a DetectorConfig from a JSON object of the fields above (all optional). Unknown
// fields, non-numbers and out-of-range values are errors naming the field.
Result<DetectorConfig> parse_detector_config(const std::string& json_text);

// Runs the whole pipeline on `mask` (CV_8UC1, non-zero = DLO). `bgr` (CV_8UC3, same size)
// is used for crossing order; without it, the straighter strand is taken as on top.
// Errors (wrong type, size mismatch, empty image) name the offending argument.
Result<Detection> detect(const cv::Mat& mask, const cv::Mat& bgr = cv::Mat(),
                         const DetectorConfig& config = DetectorConfig());

}  // namespace mbest

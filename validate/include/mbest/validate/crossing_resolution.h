// Crossing resolution on synthetic data (../shared/docs/metrics.md): for each ground-truth
// crossing, is the pairing of strands right (no switch) and is the right rod on top?
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mbest/synth/annotation.h"
#include "mbest/validate/dice.h"

namespace mbest::validate {

struct CrossingOptions {
  // A strand is sampled where it is clear of the crossing: at least this many rod widths of
  // arc from the crossing, its centre at least (w_a + w_b) / 2 + 1 px from the other strand,
  // visible in the ground truth (no third rod on top) and overlapped by no other rod's body
  // (where two bodies overlap the label shows the order there, not this pairing; the votes
  // of the disc below skip such pixels too). The walk gives up after
  // max_walk_widths widths of arc: the crossing is then not assessed.
  double offset_widths = 1.5;
  double max_walk_widths = 40;
  // Radius, in widths of the rod sampled, of the disc whose majority predicted label is read.
  double disc_radius_widths = 0.25;
  // A crossing's neighbours are the other ground-truth crossings of the scene within this
  // many widths (of its wider rod) of it: how crowded the place is (CrossingResolution::
  // neighbours). Beyond metrics.md. Four widths is about where a detector's view of one
  // crossing (the junction cluster, the strands' directions a width or two out) takes in
  // the next.
  double crowding_radius_widths = 4;
};

struct CrossingResolution {
  int index = 0;  // into SceneAnnotation::crossings
  int rod_a = 0, rod_b = 0, top = 0;  // ground-truth rod ids (rod_a == rod_b: self-crossing)
  double angle_deg = 0;
  cv::Point2d location;   // pixels, from the annotation
  double width_px = 0;    // the wider rod's width
  double complexity = 0;  // max total_turning_rad of the rods involved
  int neighbours = 0;     // other crossings within crowding_radius_widths (CrossingOptions)
  // Majority predicted label on each strand just before / after the crossing (0 = background
  // or not sampled) and at the crossing itself.
  int a_before = 0, a_after = 0, b_before = 0, b_after = 0, at_crossing = 0;
  // Pairing: each strand keeps one non-zero label across the crossing, and two different rods
  // keep different labels (a self-crossing keeps one label on all four sides, unless the loop
  // between its two passes leaves the image: the picture then shows two pieces, which may
  // keep two labels).
  bool pairing_assessed = false, pairing_correct = false;
  // Order: the label at the crossing is the one matched (matched DICE) to the top rod. Not
  // assessed for a self-crossing (a label image cannot show which strand of one rod is on
  // top), nor where the ground truth's label at the crossing is a third rod's (one lying over
  // both: no label image shows their order there).
  bool order_assessed = false, order_correct = false;
  std::string note;  // why something was not assessed; empty otherwise
};

// scene: the ground truth; gt_labels: its label image (value = rod id); pred_labels: the
// prediction (CV_8UC1 or CV_16UC1, the same size); dice: matched_dice(gt_labels, pred_labels),
// which gives the predicted label matched to each rod. One entry per scene.crossings entry.
std::vector<CrossingResolution> crossing_resolution(const synth::SceneAnnotation& scene,
                                                    const cv::Mat& gt_labels,
                                                    const cv::Mat& pred_labels,
                                                    const DiceScore& dice,
                                                    const CrossingOptions& options = {});

}  // namespace mbest::validate

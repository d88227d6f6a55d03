// Split-end pruning: a jagged mask makes the skeleton sprout short spurs that end near a
// junction they created. A branch from an end that reaches a junction within `delta` px
// (the paper's delta = 2 r, the widest DLO's diameter) is such a split end.
#pragma once

#include "mbest/core/keypoints.h"

namespace mbest {

// The colour image for colour-aware decisions: `bgr` (empty = none), `radius` = the widest
// DLO's radius in pixels.
struct ColourSource {
  cv::Mat bgr;
  double radius = 1;
};

// Is branch `branch` of `graph` a spur: alive, shorter than `delta`, from a junction to an
// end? Split ends are such spurs; of two at a DLO's forked tip, one stays.
bool is_spur(const SkeletonGraph& graph, int branch, double delta);

// Removes split ends from `graph`, shortest first; a junction keeps at least two branches
// (of two spurs at a real end, the longer one stays as the DLO's end). Left alone: branches
// joining two ends (short isolated pieces); branches whose end is as close to the border
// of an image of size `image` as to the mask's edge (a DLO leaving the image, whose stub
// beyond a crossing near the border may be short); and the stub of a DLO ending just past
// a crossing: a branch from a junction of four or more branches that runs straight on
// (within 35 degrees) from another branch there. With a colour image (`colour`), also the
// end of a DLO lying on another: a short branch at a junction whose other branches differ
// in colour. Returns the number removed.
int prune_split_ends(SkeletonGraph& graph, double delta, cv::Size image,
                     const ColourSource& colour = ColourSource());

// Two DLOs that leave the image side by side touch where they leave: the mask joins them
// there into a V whose tip is on the border, and thinning runs one branch round the tip.
// A branch is cut at a pixel within its radius plus two pixels of the border of an image of
// size `image` (thinning leaves the tip a pixel nearer some borders than others) where it
// turns back sharper than `fold_energy` and its arms run straight up
// to that pixel. The turn is that between the chords `reach` px before and after the
// pixel, scored as the bending energy of a turn at a point, 8 tan^2(turn / 4) (1 is about
// 78 degrees, 4 about 140); straight arms turn less than 30 degrees between the chords
// from 2 `reach` to `reach` px and from `reach` px to the pixel. A smooth bend turns as
// much along its arms as at any pixel, and a hairpin whose bend is about `reach` long
// turns 50 degrees or more along them: neither is cut. Where the two leave the image a
// little apart, thinning runs the branch along the border between them: failing a pixel,
// a stretch of up to 4 `reach` px within a radius of the border is taken whole, the chords
// taken before its first pixel and after its last, when it turns more than 3 times as much
// as its arms, bending at their own rate (the larger turn between their two chords, per
// `reach` px), would over `reach` px plus its length; a bend that leaves the image and comes
// back turns at the border no faster than beside it. An arm that reaches a junction (a
// crossing just past the border) sooner than 2 `reach` px from the turn is measured with
// chords of half its length, down to `reach` / 2. The pieces end at the pixels before and
// after the cut. Returns the number of cuts.
int cut_folds_at_border(SkeletonGraph& graph, double reach, cv::Size image, double fold_energy);

// Two DLOs whose tips touch: the mask joins them into a V and thinning runs one branch
// round its tip, so the two would be traversed as one. An elastic rod neither folds at a
// point nor changes colour there: a branch is cut at its sharpest pixel, anywhere in the
// image, when it turns back there sharper than `fold_energy` (measured as in
// cut_folds_at_border, arms running straight up to it) and its two arms, sampled over the
// chords before and after that pixel (clear of the tips, which blend where they touch),
// differ in colour by at least 3 kColourTolerance (colour_penalty at its cap). Without an
// image (`colour.bgr` empty) nothing is cut: a hairpin bent as tightly as a rod can lies
// on both arms of one colour. Returns the number of cuts.
int cut_folds_between_colours(SkeletonGraph& graph, double reach, const ColourSource& colour,
                              double fold_energy);

}  // namespace mbest

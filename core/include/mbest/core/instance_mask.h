// Instance masks. The mask already holds the exact DLO pixels, so instead of drawing discs
// along each centerline, every mask pixel is given to the DLO whose centerline is nearest
// inside the mask (a multi-source breadth-first search from all centerlines), after the
// band of each top strand through a crossing has been given to that strand.
#pragma once

#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "mbest/core/detector.h"

namespace mbest {

// A strand drawn over the others at a crossing.
struct TopStrand {
  int dlo = -1;
  std::vector<cv::Point> path;
  std::vector<float> radius;  // per path pixel
};

// mask: CV_8UC1 (non-zero = DLO). `tops` are painted in order, so later ones cover earlier
// ones (give them bottom to top). Returns CV_16UC1: 0 outside the mask and on mask pixels no
// centerline reaches, otherwise DLO index + 1. The result is a view into a buffer with a
// one-pixel border (so not continuous; rows are reached with ptr()), which saves a copy.
cv::Mat instance_labels(const cv::Mat& mask, const std::vector<Dlo>& dlos,
                        const std::vector<TopStrand>& tops);

// Where strands cross or lie side by side, the paths drawn through a crossing region are a
// guess, but which DLO a pixel shows is plain in its colour. A colour zone covers one
// crossing region (the union of `discs`, centre and radius) and lists the colour of each
// DLO through it (CIE Lab as in BranchTangent::colour; a DLO may have several, one per exit).
struct ColourZone {
  std::vector<std::pair<cv::Point, float>> discs;
  std::vector<std::pair<int, cv::Vec3f>> colours;  // (DLO index, colour)
  // Relabel only pixels already labelled with one of the zone's DLOs: a zone running along
  // strands lying side by side may cross a DLO from elsewhere of one of their colours.
  bool own_pixels_only = false;
};

// Relabels each mask pixel inside a zone to the DLO whose colour is nearest the pixel's
// (colour_distance) when that is at most `max_distance` and nearer by at least `margin`
// than the DLO the pixel is labelled with (a pixel labelled with no DLO of the zone: than
// every other DLO of the zone, or not at all with `own_pixels_only`). The drawn label is
// the rival to beat, not every DLO of the zone: a grey strand hidden under a red one is
// told apart from it plainly, even where the grey is near the white of a third DLO there.
// Other pixels keep their label: glare, edges blended with the background, DLOs of one
// colour, and a DLO paired wrongly through the crossing (it carries both strands' colours,
// so neither wins). A pixel's colour is read as the median of its 3 x 3 neighbourhood, and
// a few relabelled pixels cut off from the rest of their new DLO are given back (noise, or a
// blend of two DLOs' colours nearest a third). `labels` as instance_labels returns it; `bgr`
// CV_8UC3 of the mask's size (nothing happens when it is empty).
void refine_labels_by_colour(cv::Mat& labels, const cv::Mat& mask, const cv::Mat& bgr,
                             const std::vector<ColourZone>& zones, double margin,
                             double max_distance);

}  // namespace mbest

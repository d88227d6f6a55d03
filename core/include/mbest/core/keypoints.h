// Key points of a skeleton (ends and junctions) and the skeleton as a graph of them.
// Ends are pixels with one skeleton neighbour, junction pixels have three or more;
// junction pixels within 2 px of each other form one junction (the paper's DBSCAN, eps 2).
#pragma once

#include <algorithm>
#include <vector>

#include <opencv2/core.hpp>

#include "mbest/core/skeleton.h"

namespace mbest {

// One end of a branch: `side` 0 is the end at branch.pixels.front(), 1 at .back().
struct BranchEnd {
  int branch = -1;
  int side = 0;
  bool operator==(const BranchEnd& o) const { return branch == o.branch && side == o.side; }
};

struct Node {
  enum class Kind { end, junction };
  Kind kind = Kind::end;
  std::vector<cv::Point> pixels;  // one pixel for an end, the cluster for a junction
  cv::Point2f centre;             // mean of pixels
  std::vector<BranchEnd> branch_ends;  // the branches that leave this node
  bool alive = true;
  int degree() const { return static_cast<int>(branch_ends.size()); }
};

struct Branch {
  // Ordered pixels strictly between the two nodes (no node pixel). May be empty when
  // two nodes touch.
  std::vector<cv::Point> pixels;
  std::vector<float> radius;  // local radius (px) at each pixel, filled by measure_radii
  int node[2] = {-1, -1};     // node at side 0 (before pixels.front()) and side 1
  bool alive = true;
  double length = 0;  // arc length in px from node to node
  // The branch lying beside this one between the same two nodes, where one branch carrying
  // two strands side by side was split in two (strands.h); -1 otherwise. Twins are never
  // the link that makes two crossings one: each carries its own strand from one to the other.
  int twin = -1;
};

struct SkeletonGraph {
  std::vector<Node> nodes;
  std::vector<Branch> branches;
  std::vector<std::vector<cv::Point>> rings;  // closed chains with no node, ordered
  std::vector<std::vector<float>> ring_radius;
};

// The ends and junction pixels of a skeleton, by the neighbour count.
struct Keypoints {
  std::vector<cv::Point> ends;
  std::vector<cv::Point> junction_pixels;
};
Keypoints detect_keypoints(const Skeleton& skeleton);

// Builds the graph of the skeleton. `skeleton.image` is used as scratch and left as it was.
SkeletonGraph build_skeleton_graph(Skeleton& skeleton, const Keypoints& keypoints);

// Euclidean distance from `p` to the nearest zero pixel of `mask` (CV_8UC1), pixels outside
// the image counting as zero: the L2 distance transform, evaluated at one pixel.
float distance_to_background(const cv::Mat& mask, cv::Point p);

// Fills Branch::radius and SkeletonGraph::ring_radius (measured every `stride` pixels,
// linearly interpolated between) and returns the radius of the widest DLO: the largest
// per-branch median radius over branches of at least 5 px (junctions, where the mask is
// wider than any DLO, do not inflate it). Returns 0 for an empty graph.
float measure_radii(SkeletonGraph& graph, const cv::Mat& mask, int stride = 4);

// The radius that a fraction `share` (0-1] of the skeleton's length stays within: branches
// of at least 5 px and rings, each at its median radius, weighed by its length (call after
// measure_radii). Junction blobs and strands lying side by side make short wide branches
// that inflate measure_radii's widest radius; this one stays near the widest DLO's radius
// where they cover less than 1 - share of the length. Returns 0 for an empty graph.
float length_quantile_radius(const SkeletonGraph& graph, double share);

// Radius along a pixel chain: distance_to_background every `stride` pixels (and at the
// last), linearly interpolated between.
std::vector<float> sample_radius(const std::vector<cv::Point>& chain, const cv::Mat& mask, int stride);

// Distance in pixels from `p` to just outside the nearest border of an image of size `image`.
inline int distance_to_border(cv::Point p, cv::Size image) {
  return 1 + std::min(std::min(p.x, p.y), std::min(image.width - 1 - p.x, image.height - 1 - p.y));
}

// Does branch `b` run out of an image of size `image` at its end `side`: is the border no
// farther from its end node than the mask's edge (the radius there, plus a pixel)?
bool leaves_image(const SkeletonGraph& graph, const Branch& b, int side, cv::Size image);

// Arc length of an 8-connected pixel chain (1 per straight step, sqrt 2 per diagonal).
double chain_length(const std::vector<cv::Point>& pixels);

// Branch::length for `pixels`: the chain plus a step from each node onto it (one step
// between two adjacent nodes when the chain is empty).
inline double branch_length(const std::vector<cv::Point>& pixels) {
  return chain_length(pixels) + (pixels.empty() ? 1.0 : 2.0);
}

}  // namespace mbest

#include "mbest/core/strands.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "mbest/core/geometry.h"
#include "mbest/core/median.h"

namespace mbest {
namespace {

float cross(cv::Point2f a, cv::Point2f b) { return a.x * b.y - a.y * b.x; }

// A branch seen from one of its ends: pixel and radius k counted from that end.
struct BranchFrom {
  const Branch& b;
  int side;
  int size() const { return static_cast<int>(b.pixels.size()); }
  int index(int k) const { return side == 0 ? k : size() - 1 - k; }
  cv::Point pixel(int k) const { return b.pixels[index(std::clamp(k, 0, size() - 1))]; }
  float radius(int k) const { return b.radius[index(std::clamp(k, 0, size() - 1))]; }
  // The middle radius over pixels [from, from + count), clipped to the branch.
  float radius_over(int from, int count) const {
    std::vector<float> r;
    for (int k = from; k < std::min(size(), from + count); ++k) r.push_back(radius(k));
    return middle_value(r);
  }
};

// One of the three branches at a Y, as seen from the Y.
struct Arm {
  BranchEnd end;
  float radius = 0;   // next to the Y, past its bulge
  cv::Point2f point;  // a pixel there
};

// The strand of a side-by-side band on one side of its middle pixels from[0 .. count):
// each moved along the left normal by `sign` times (the band's half width there less
// `radius`), tapered to no offset over the last `taper` pixels, and kept inside `mask`.
std::vector<cv::Point> offset_strand(const BranchFrom& from, int count, float radius, int sign,
                                     int taper, int reach, const cv::Mat& mask) {
  std::vector<cv::Point> out;
  const cv::Rect image(0, 0, mask.cols, mask.rows);
  float held = 0;  // the offset last measured clear of the image border
  for (int k = 0; k < count; ++k) {
    const cv::Point2f t = unit(cv::Point2f(from.pixel(k + reach) - from.pixel(k - reach)));
    const cv::Point2f normal(-t.y, t.x);
    // Within a radius of the border the measured radius is the distance to the border, not
    // the band's half width: keep the offset from before.
    if (distance_to_border(from.pixel(k), mask.size()) > from.radius(k) + 1)
      held = std::max(0.0f, from.radius(k) - radius);
    float offset = held;
    if (taper > 0 && count - k < taper) offset *= static_cast<float>(count - k) / static_cast<float>(taper);
    const cv::Point2f middle(from.pixel(k));
    cv::Point q = middle;
    for (; offset > 0; offset -= 0.5f) {
      const cv::Point2f moved = middle + normal * (static_cast<float>(sign) * offset);
      const cv::Point c(static_cast<int>(std::lround(moved.x)), static_cast<int>(std::lround(moved.y)));
      if (image.contains(c) && mask.ptr<uint8_t>(c.y)[c.x]) {
        q = c;
        break;
      }
    }
    append_connected(out, q);
  }
  return out;
}

// Runs of up to this many pixels below or above a width threshold are noise.
constexpr int kNoisePixels = 2;

// How far a node's bulge reaches: the largest distance from a junction's pixels to the
// background (the branches next to it are wider than they are further on); 0 for an end.
// (Not from its centre: the mean of its pixels may fall in a notch of the mask.)
int bulge_of(const Node& node, const cv::Mat& mask) {
  if (node.kind != Node::Kind::junction) return 0;
  float widest = 0;
  for (const cv::Point& p : node.pixels) widest = std::max(widest, distance_to_background(mask, p));
  return static_cast<int>(std::ceil(widest));
}

// Is `node` a Y where two strands arriving side by side along branch `band` (travelling
// along `arriving`) part: two other branches, each running on within 60 degrees? Each is
// judged by its pixel `reach` px from the node.
bool strands_part(const SkeletonGraph& g, const Node& node, int band, cv::Point2f arriving, int reach) {
  int others = 0, running_on = 0;
  for (const BranchEnd& e : node.branch_ends) {
    const Branch& b = g.branches[e.branch];
    if (!b.alive || e.branch == band) continue;
    ++others;
    if (b.pixels.empty()) continue;
    const BranchFrom from{b, e.side};
    running_on += unit(cv::Point2f(from.pixel(reach)) - node.centre).dot(arriving) >= 0.5f;
  }
  return others == 2 && running_on == 2;
}

// Replaces `node`'s entry for branch end (branch, old_side) by (branch, new_side).
void rename_end(Node& node, int branch, int old_side, int new_side) {
  for (BranchEnd& e : node.branch_ends)
    if (e.branch == branch && e.side == old_side) {
      e.side = new_side;
      return;
    }
}

// A new end node at the last pixel of `chain`, which it takes off the chain, for the end
// `side` of branch `branch`.
int end_node_at(SkeletonGraph& g, std::vector<cv::Point>& chain, int branch, int side) {
  Node n;
  n.kind = Node::Kind::end;
  n.pixels = {chain.back()};
  n.centre = cv::Point2f(chain.back());
  n.branch_ends = {{branch, side}};
  chain.pop_back();
  g.nodes.push_back(std::move(n));
  return static_cast<int>(g.nodes.size()) - 1;
}

// A Y's widest branch where it carries two strands side by side.
struct Band {
  BranchEnd at_y;           // the band's branch, at its end at the Y
  int y = -1, far = -1;     // the Y and the node at the band's other end
  Arm left, right;          // the strands, looking into the band from the Y
  float thick = 0;          // the wider strand's radius
  int two = 0;              // pixels from the Y over which the band is two strands wide
  bool full = false;        // all the way to the far node
};

// The band out of node `y`, if it is a Y whose widest branch carries two strands side by
// side over at least `min_length` px, as split_side_by_side describes.
std::optional<Band> band_out_of(const SkeletonGraph& g, int y, const cv::Mat& mask, double min_length) {
  const Node& node = g.nodes[y];
  if (node.kind != Node::Kind::junction || !node.alive) return std::nullopt;
  std::vector<BranchEnd> ends;
  for (const BranchEnd& e : node.branch_ends)
    if (g.branches[e.branch].alive) ends.push_back(e);
  if (ends.size() != 3) return std::nullopt;
  const cv::Point2f centre = node.centre;
  const int bulge = bulge_of(node, mask), span = std::max(4, 2 * bulge);
  Arm arms[3];
  for (int k = 0; k < 3; ++k) {
    const Branch& b = g.branches[ends[k].branch];
    const BranchFrom from{b, ends[k].side};
    if (b.node[0] == b.node[1] || b.twin >= 0 || from.size() <= bulge + 2) return std::nullopt;
    arms[k] = {ends[k], from.radius_over(bulge, span), cv::Point2f(from.pixel(bulge + span / 2))};
  }
  std::sort(arms, arms + 3, [](const Arm& a, const Arm& b) { return a.radius < b.radius; });
  const Arm &thin = arms[0], &thick = arms[1], &wide = arms[2];
  const float threshold = thick.radius + static_cast<float>(kSideBySideShare) * thin.radius;
  if (wide.radius < threshold || wide.radius > 1.2f * (thin.radius + thick.radius) + 1) return std::nullopt;
  // Both narrow branches run on into the band, within 60 degrees.
  const cv::Point2f into = unit(wide.point - centre);
  if (unit(centre - thin.point).dot(into) < 0.5f || unit(centre - thick.point).dot(into) < 0.5f)
    return std::nullopt;

  // The band's own pixels lie between the two nodes' bulges. It is two strands wide from
  // the Y up to the first run of more than a couple of pixels below the threshold.
  const Branch& w = g.branches[wide.end.branch];
  const BranchFrom from{w, wide.end.side};
  const int n = from.size(), far = w.node[1 - wide.end.side];
  const Node& q = g.nodes[far];
  const int last = n - bulge_of(q, mask);
  const auto run_from = [&](int start, bool two_wide) {  // where a run of such pixels begins
    for (int k = start, run = 0; k < last; ++k) {
      run = (from.radius(k) >= threshold) == two_wide ? run + 1 : 0;
      if (run > kNoisePixels) return k - run + 1;
    }
    return last;
  };
  Band band;
  band.two = run_from(bulge, false);
  if (band.two - bulge < min_length) return std::nullopt;
  band.full = band.two == last;
  const cv::Point2f arriving = unit(q.centre - cv::Point2f(from.pixel(last - 1 - span / 2)));
  const bool parts_again = q.kind == Node::Kind::junction &&
                           strands_part(g, q, wide.end.branch, arriving, n - last + span / 2);
  if (band.full) {
    // Two strands all along: they part again at a Y, or leave the image side by side.
    // Anything else (a crossing with further strands, an end in the mask) is left alone.
    if (q.kind == Node::Kind::end ? !leaves_image(g, w, 1 - wide.end.side, mask.size()) : !parts_again)
      return std::nullopt;
  } else if (run_from(band.two, true) < last || last - band.two < 6 * thick.radius || parts_again) {
    // Narrowed: one strand ended there, and the other runs on alone, well past it, to
    // something other than a Y where the two part. Narrowing and widening again, or
    // parting at a Y just past the narrowing (its bulge hides the widening), is where the
    // two cross: two Ys that junctions.h pairs.
    return std::nullopt;
  }
  const bool thin_left = cross(into, thin.point - centre) > cross(into, thick.point - centre);
  band.at_y = wide.end;
  band.y = y;
  band.far = far;
  band.left = thin_left ? thin : thick;
  band.right = thin_left ? thick : thin;
  band.thick = thick.radius;
  return band;
}

// The band's branch, whose pixels now run from the Y to the far node, takes the Y as its
// side 0.
void orient_from_y(SkeletonGraph& g, const Band& band) {
  if (band.at_y.side == 0) return;
  Branch& w = g.branches[band.at_y.branch];
  std::swap(w.node[0], w.node[1]);
  rename_end(g.nodes[band.y], band.at_y.branch, 1, 0);
  rename_end(g.nodes[band.far], band.at_y.branch, 0, 1);
}

// Splits `band` (full) into two twin branches from the Y to the far node, or, where that is
// an end at the image border, to an end each.
bool split_full(SkeletonGraph& g, const Band& band, const cv::Mat& mask) {
  const BranchFrom from{g.branches[band.at_y.branch], band.at_y.side};
  const int reach = std::max(2, static_cast<int>(std::lround(band.thick)));
  std::vector<cv::Point> left = offset_strand(from, from.size(), band.left.radius, +1, 0, reach, mask);
  std::vector<cv::Point> right = offset_strand(from, from.size(), band.right.radius, -1, 0, reach, mask);
  if (left.size() < 2 || right.size() < 2) return false;
  const int wi = band.at_y.branch, nb = static_cast<int>(g.branches.size());
  Branch beside;
  beside.node[0] = band.y;
  beside.twin = wi;
  if (g.nodes[band.far].kind == Node::Kind::end) {
    // Both strands leave the image: the old end moves to the left strand's last pixel.
    Node& end = g.nodes[band.far];
    end.pixels = {left.back()};
    end.centre = cv::Point2f(left.back());
    left.pop_back();
    beside.node[1] = end_node_at(g, right, nb, 1);
  } else {
    beside.node[1] = band.far;
    g.nodes[band.far].branch_ends.push_back({nb, 1});
  }
  beside.pixels = std::move(right);
  beside.radius.assign(beside.pixels.size(), band.right.radius);
  Branch& w = g.branches[wi];
  w.pixels = std::move(left);
  w.radius.assign(w.pixels.size(), band.left.radius);
  w.twin = nb;
  orient_from_y(g, band);
  g.nodes[band.y].branch_ends.push_back({nb, 0});
  g.branches.push_back(std::move(beside));
  return true;
}

// Splits `band` (one strand ending where it narrows) into the strand running on, along the
// old pixels past the narrowing, and a new branch from the Y to an end there.
bool split_partial(SkeletonGraph& g, const Band& band, const cv::Mat& mask) {
  const BranchFrom from{g.branches[band.at_y.branch], band.at_y.side};
  const int n = from.size(), two = band.two;
  const int reach = std::max(2, static_cast<int>(std::lround(band.thick)));
  // Past the narrowing the old pixels are the middle of the strand running on: off the
  // band's middle, towards that strand's side.
  const cv::Point2f before = cv::Point2f(from.pixel(two - 1)) - cv::Point2f(from.pixel(two - 1 - 2 * reach));
  const cv::Point2f after = cv::Point2f(from.pixel(std::min(n - 1, two + 2 * reach))) - cv::Point2f(from.pixel(two - 1));
  const float lateral = cross(unit(before), after);
  if (std::abs(lateral) < 0.5f) return false;  // cannot tell which strand runs on
  const int on_side = lateral > 0 ? +1 : -1;
  const Arm& on = on_side > 0 ? band.left : band.right;
  const Arm& ending = on_side > 0 ? band.right : band.left;
  // The strand running on comes back to the old pixels over its last 2 r before the narrowing.
  std::vector<cv::Point> run_on = offset_strand(from, two, on.radius, on_side, 2 * reach, reach, mask);
  std::vector<cv::Point> ends = offset_strand(from, two, ending.radius, -on_side, 0, reach, mask);
  if (ends.size() < 3) return false;
  std::vector<float> radius(run_on.size(), on.radius);
  for (int k = two; k < n; ++k) {
    append_connected(run_on, from.pixel(k));
    radius.resize(run_on.size(), from.radius(k));
  }
  const int wi = band.at_y.branch, nb = static_cast<int>(g.branches.size());
  Branch beside;
  beside.node[0] = band.y;
  beside.node[1] = end_node_at(g, ends, nb, 1);
  beside.pixels = std::move(ends);
  beside.radius.assign(beside.pixels.size(), ending.radius);
  Branch& w = g.branches[wi];
  w.pixels = std::move(run_on);
  w.radius = std::move(radius);
  orient_from_y(g, band);
  g.nodes[band.y].branch_ends.push_back({nb, 0});
  g.branches.push_back(std::move(beside));
  return true;
}

}  // namespace

int split_side_by_side(SkeletonGraph& g, const cv::Mat& mask, double min_length) {
  int splits = 0;
  const int n_nodes = static_cast<int>(g.nodes.size());
  for (int y = 0; y < n_nodes; ++y) {
    const std::optional<Band> band = band_out_of(g, y, mask, min_length);
    if (!band) continue;
    if (!(band->full ? split_full(g, *band, mask) : split_partial(g, *band, mask))) continue;
    for (Branch* b : {&g.branches[band->at_y.branch], &g.branches.back()})
      b->length = branch_length(b->pixels);
    ++splits;
  }
  return splits;
}

}  // namespace mbest

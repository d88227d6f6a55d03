#include "mbest/core/strands.h"

#include <gtest/gtest.h>

#include "mbest/core/prune.h"
#include "scenes.h"

namespace mbest {
namespace {

// The skeleton graph of `mask` as the detector has it when strands are split.
struct Graph {
  SkeletonGraph g;
  float r = 0;
};
Graph graph_of(const cv::Mat& mask) {
  Skeleton s = skeletonize(mask);
  Graph out{build_skeleton_graph(s, detect_keypoints(s)), 0};
  out.r = measure_radii(out.g, mask);
  prune_split_ends(out.g, 2 * out.r, mask.size());
  return out;
}

int alive_branches(const SkeletonGraph& g) {
  int n = 0;
  for (const Branch& b : g.branches) n += b.alive;
  return n;
}

cv::Mat drawn(cv::Size size, const std::vector<std::vector<cv::Point>>& rods, std::vector<int> widths) {
  cv::Mat mask = cv::Mat::zeros(size, CV_8UC1);
  for (size_t k = 0; k < rods.size(); ++k) test::draw_rod(mask, rods[k], widths[k]);
  return mask;
}

TEST(Strands, RodsTouchingSideBySideBecomeTwinBranches) {
  for (int width : {9, 13}) {
    const test::SideBySide rods = test::side_by_side(width, width);
    const cv::Mat mask = drawn({420, 300}, {rods.a, rods.b}, {width, width});
    Graph gr = graph_of(mask);
    const int before = alive_branches(gr.g);
    ASSERT_EQ(split_side_by_side(gr.g, mask, 3 * gr.r), 1) << "width " << width;
    EXPECT_EQ(alive_branches(gr.g), before + 1);
    int twins = 0;
    for (const Branch& b : gr.g.branches) {
      if (b.twin < 0) continue;
      ++twins;
      const Branch& t = gr.g.branches[b.twin];
      EXPECT_EQ(t.twin, &b - gr.g.branches.data());
      EXPECT_EQ(std::min(b.node[0], b.node[1]), std::min(t.node[0], t.node[1]));
      EXPECT_EQ(std::max(b.node[0], b.node[1]), std::max(t.node[0], t.node[1]));
      // Each strand runs along its own rod: within its half width of that rod's middle.
      const cv::Point mid = b.pixels[b.pixels.size() / 2], other = t.pixels[t.pixels.size() / 2];
      EXPECT_GT(cv::norm(mid - other), 0.6 * width) << "the twins lie apart";
      EXPECT_NEAR(b.radius[b.pixels.size() / 2], width / 2.0 + 0.5, 1.5);
    }
    EXPECT_EQ(twins, 2);
  }
}

TEST(Strands, RodEndingAlongAnotherLeavesAStrandEndingWhereTheBandNarrows) {
  const test::SideBySide rods = test::side_by_side(11, 11, 250);
  const cv::Mat mask = drawn({420, 300}, {rods.a, rods.b}, {11, 11});
  Graph gr = graph_of(mask);
  const size_t nodes = gr.g.nodes.size();
  ASSERT_EQ(split_side_by_side(gr.g, mask, 3 * gr.r), 1);
  ASSERT_EQ(gr.g.nodes.size(), nodes + 1);
  const Node& end = gr.g.nodes.back();
  EXPECT_EQ(end.kind, Node::Kind::end);
  // Near rod b's tip (x = 250 on its side of the band), within a rod's width.
  EXPECT_LT(cv::norm(end.centre - cv::Point2f(rods.b.back())), 12) << end.centre;
}

TEST(Strands, RodsLeavingTheImageSideBySideEndAtTheBorderApart) {
  std::vector<cv::Point> a, b;
  for (int x = 20; x <= 430; x += 4) {
    const double apart = x < 200 ? (200 - x) * 0.5 : 0;
    a.emplace_back(x, static_cast<int>(std::lround(144.5 - apart)));
    b.emplace_back(x, static_cast<int>(std::lround(155.5 + apart)));
  }
  const cv::Mat mask = drawn({420, 300}, {a, b}, {11, 11});
  Graph gr = graph_of(mask);
  const size_t nodes = gr.g.nodes.size();
  ASSERT_EQ(split_side_by_side(gr.g, mask, 3 * gr.r), 1);
  ASSERT_EQ(gr.g.nodes.size(), nodes + 1);
  int at_border = 0;
  std::vector<float> ys;
  for (const Node& n : gr.g.nodes)
    if (n.kind == Node::Kind::end && n.centre.x > 405) ++at_border, ys.push_back(n.centre.y);
  ASSERT_EQ(at_border, 2);
  EXPECT_GT(std::abs(ys[0] - ys[1]), 8) << "one end per strand, each on its rod (11 px apart)";
}

TEST(Strands, CrossingsAndTeesAreNotSideBySide) {
  // Two rods crossing at a shallow or a steep angle overlap fully where they cross: the
  // band between their Ys narrows to one rod there. A thin rod ending on a thick one makes
  // a Y whose wide branch is the thick rod, as wide as its other side.
  for (double angle : {10.0, 15.0, 25.0, 50.0}) {
    const cv::Mat mask = drawn({500, 300}, {test::line_through({250, 150}, 0, 460),
                                            test::line_through({250, 150}, angle, 460)}, {11, 11});
    Graph gr = graph_of(mask);
    EXPECT_EQ(split_side_by_side(gr.g, mask, 3 * gr.r), 0) << "angle " << angle;
  }
  const cv::Mat tee = drawn({400, 200}, {{{20, 100}, {380, 100}}, {{200, 100}, {200, 10}}}, {17, 7});
  Graph gr = graph_of(tee);
  EXPECT_EQ(split_side_by_side(gr.g, tee, 3 * gr.r), 0);
}

}  // namespace
}  // namespace mbest

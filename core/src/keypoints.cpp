#include "mbest/core/keypoints.h"
#include "mbest/core/median.h"

#include <algorithm>
#include <bitset>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>
#include <unordered_map>

namespace mbest {
namespace {

int find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

constexpr uint8_t kNodePixel = 2;  // scratch marks in the skeleton image
constexpr uint8_t kVisited = 4;

}  // namespace

bool leaves_image(const SkeletonGraph& g, const Branch& b, int side, cv::Size image) {
  const float r = b.radius.empty() ? 1.0f : (side == 0 ? b.radius.front() : b.radius.back());
  return distance_to_border(g.nodes[b.node[side]].pixels.front(), image) <= r + 1.5f;
}

double chain_length(const std::vector<cv::Point>& pixels) {
  double len = 0;
  for (size_t i = 1; i < pixels.size(); ++i)
    len += (pixels[i].x != pixels[i - 1].x && pixels[i].y != pixels[i - 1].y) ? M_SQRT2 : 1.0;
  return len;
}

Keypoints detect_keypoints(const Skeleton& skeleton) {
  Keypoints kp;
  const size_t step = skeleton.image.step;
  for (const cv::Point& p : skeleton.pixels) {
    const int n = static_cast<int>(
        std::bitset<8>(neighbour_code(skeleton.image.ptr<uint8_t>(p.y) + p.x, step)).count());
    if (n == 1) kp.ends.push_back(p);
    if (n >= 3) kp.junction_pixels.push_back(p);
  }
  return kp;
}

SkeletonGraph build_skeleton_graph(Skeleton& skeleton, const Keypoints& kp) {
  SkeletonGraph g;
  cv::Mat& img = skeleton.image;
  auto at = [&](cv::Point p) -> uint8_t& { return img.ptr<uint8_t>(p.y)[p.x]; };

  // Junction clusters: pixels within 2 px of each other (sorted by row, so the inner loop
  // stops after two rows).
  const auto& jp = kp.junction_pixels;
  std::vector<int> parent(jp.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (size_t i = 0; i < jp.size(); ++i)
    for (size_t j = i + 1; j < jp.size() && jp[j].y - jp[i].y <= 2; ++j) {
      const int dx = jp[j].x - jp[i].x, dy = jp[j].y - jp[i].y;
      if (dx * dx + dy * dy <= 4) parent[find(parent, static_cast<int>(i))] = find(parent, static_cast<int>(j));
    }

  std::unordered_map<long long, int> node_of;  // pixel key -> node index
  auto key = [](cv::Point p) { return (static_cast<long long>(p.y) << 32) | static_cast<unsigned>(p.x); };
  std::unordered_map<int, int> cluster_node;
  for (size_t i = 0; i < jp.size(); ++i) {
    const int root = find(parent, static_cast<int>(i));
    auto it = cluster_node.find(root);
    if (it == cluster_node.end()) {
      it = cluster_node.emplace(root, static_cast<int>(g.nodes.size())).first;
      g.nodes.emplace_back();
      g.nodes.back().kind = Node::Kind::junction;
    }
    g.nodes[it->second].pixels.push_back(jp[i]);
    node_of[key(jp[i])] = it->second;
  }
  for (const cv::Point& e : kp.ends) {
    node_of[key(e)] = static_cast<int>(g.nodes.size());
    g.nodes.emplace_back();
    g.nodes.back().kind = Node::Kind::end;
    g.nodes.back().pixels.push_back(e);
  }
  for (Node& n : g.nodes) {
    cv::Point2f c(0, 0);
    for (const cv::Point& p : n.pixels) {
      c += cv::Point2f(static_cast<float>(p.x), static_cast<float>(p.y));
      at(p) |= kNodePixel;
    }
    n.centre = c * (1.0f / static_cast<float>(n.pixels.size()));
  }

  auto add_branch = [&](Branch&& b) {
    const int id = static_cast<int>(g.branches.size());
    b.length = branch_length(b.pixels);
    g.nodes[b.node[0]].branch_ends.push_back({id, 0});
    g.nodes[b.node[1]].branch_ends.push_back({id, 1});
    g.branches.push_back(std::move(b));
  };

  // Trace every chain that leaves a node. A non-node pixel has at most two skeleton
  // neighbours, so each walk is unambiguous.
  std::set<std::pair<int, int>> touching;  // nodes joined without pixels between them
  for (int n = 0; n < static_cast<int>(g.nodes.size()); ++n) {
    for (const cv::Point q : std::vector<cv::Point>(g.nodes[n].pixels)) {
      for (int k = 0; k < 8; ++k) {
        const cv::Point t(q.x + kNeighbourDx[k], q.y + kNeighbourDy[k]);
        const uint8_t v = at(t);
        if (!v) continue;
        if (v & kNodePixel) {
          const int m = node_of[key(t)];
          if (m != n && touching.insert({std::min(n, m), std::max(n, m)}).second) {
            Branch b;
            b.node[0] = n;
            b.node[1] = m;
            add_branch(std::move(b));
          }
          continue;
        }
        if (v & kVisited) continue;
        Branch b;
        b.node[0] = n;
        cv::Point prev = q, cur = t;
        at(cur) |= kVisited;
        b.pixels.push_back(cur);
        while (b.node[1] < 0) {
          // A plain pixel has at most two skeleton neighbours: `prev` and the next one.
          cv::Point next(-1, -1);
          for (int j = 0; j < 8 && next.x < 0; ++j) {
            const cv::Point u(cur.x + kNeighbourDx[j], cur.y + kNeighbourDy[j]);
            const uint8_t w = at(u);
            if (w && u != prev && ((w & kNodePixel) || !(w & kVisited))) next = u;
          }
          if (next.x < 0) {  // a dead end that was not classed as an end: make it one
            const int e = static_cast<int>(g.nodes.size());
            g.nodes.emplace_back();
            g.nodes.back().pixels.push_back(cur);
            g.nodes.back().centre = cv::Point2f(static_cast<float>(cur.x), static_cast<float>(cur.y));
            b.pixels.pop_back();
            node_of[key(cur)] = e;
            at(cur) |= kNodePixel;
            b.node[1] = e;
          } else if (at(next) & kNodePixel) {
            b.node[1] = node_of[key(next)];
          } else {
            prev = cur;
            cur = next;
            at(cur) |= kVisited;
            b.pixels.push_back(cur);
          }
        }
        add_branch(std::move(b));
      }
    }
  }

  // What is left unvisited are closed chains with no node: rings.
  for (const cv::Point& s : skeleton.pixels) {
    if (at(s) & (kVisited | kNodePixel)) continue;
    std::vector<cv::Point> ring{s};
    at(s) |= kVisited;
    cv::Point cur = s;
    for (;;) {
      cv::Point next(-1, -1);
      for (int j = 0; j < 8 && next.x < 0; ++j) {
        const cv::Point u(cur.x + kNeighbourDx[j], cur.y + kNeighbourDy[j]);
        if (at(u) && !(at(u) & kVisited)) next = u;
      }
      if (next.x < 0) break;
      at(next) |= kVisited;
      ring.push_back(next);
      cur = next;
    }
    if (ring.size() >= 3) g.rings.push_back(std::move(ring));
  }

  for (const cv::Point& p : skeleton.pixels) at(p) = 1;
  return g;
}

float distance_to_background(const cv::Mat& mask, cv::Point p) {
  const int rows = mask.rows, cols = mask.cols;
  if (p.x < 0 || p.y < 0 || p.x >= cols || p.y >= rows || !mask.ptr<uint8_t>(p.y)[p.x]) return 0;
  const size_t step = mask.step;
  const uint8_t* c = mask.ptr<uint8_t>(p.y) + p.x;
  int best = std::numeric_limits<int>::max();
  // Square rings of growing radius k; a zero at ring k is at least k away, so stop once
  // k * k reaches the best squared distance found.
  for (int k = 1; k * k < best; ++k) {
    const bool inside = p.x - k >= 0 && p.y - k >= 0 && p.x + k < cols && p.y + k < rows;
    if (!inside) {  // outside the image counts as background
      const int border = std::min({p.x + 1, p.y + 1, cols - p.x, rows - p.y});
      best = std::min(best, border * border);
    }
    for (int i = -k; i <= k; ++i) {
      const int d = k * k + i * i;
      if (d >= best) continue;
      auto zero = [&](int dx, int dy) {
        const int x = p.x + dx, y = p.y + dy;
        if (inside) return c[static_cast<ptrdiff_t>(dy) * static_cast<ptrdiff_t>(step) + dx] == 0;
        return x >= 0 && y >= 0 && x < cols && y < rows && mask.ptr<uint8_t>(y)[x] == 0;
      };
      if (zero(i, -k) || zero(i, k) || zero(-k, i) || zero(k, i)) best = d;
    }
  }
  return std::sqrt(static_cast<float>(best));
}

std::vector<float> sample_radius(const std::vector<cv::Point>& px, const cv::Mat& mask, int stride) {
  std::vector<float> r(px.size());
  if (px.empty()) return r;
  std::vector<size_t> at;
  for (size_t i = 0; i < px.size(); i += stride) at.push_back(i);
  if (at.back() != px.size() - 1) at.push_back(px.size() - 1);
  for (size_t i : at) r[i] = distance_to_background(mask, px[i]);
  for (size_t k = 0; k + 1 < at.size(); ++k)
    for (size_t i = at[k] + 1; i < at[k + 1]; ++i) {
      const float t = static_cast<float>(i - at[k]) / static_cast<float>(at[k + 1] - at[k]);
      r[i] = r[at[k]] * (1 - t) + r[at[k + 1]] * t;
    }
  return r;
}

// Branches shorter than this (px) are junction stubs: their radius is the junction's.
constexpr size_t kMeasuredBranch = 5;

float measure_radii(SkeletonGraph& graph, const cv::Mat& mask, int stride) {
  float widest = 0;
  for (Branch& b : graph.branches) {
    b.radius = sample_radius(b.pixels, mask, stride);
    if (b.pixels.size() >= kMeasuredBranch) widest = std::max(widest, middle_value(b.radius));
  }
  graph.ring_radius.clear();
  for (const auto& ring : graph.rings) {
    graph.ring_radius.push_back(sample_radius(ring, mask, stride));
    widest = std::max(widest, middle_value(graph.ring_radius.back()));
  }
  if (widest == 0) {  // only tiny pieces: fall back to any measured pixel
    for (const Branch& b : graph.branches)
      for (float r : b.radius) widest = std::max(widest, r);
    for (const Node& n : graph.nodes)
      for (const cv::Point& p : n.pixels) widest = std::max(widest, distance_to_background(mask, p));
  }
  return widest;
}

float length_quantile_radius(const SkeletonGraph& graph, double share) {
  std::vector<std::pair<float, size_t>> pieces;  // median radius, length in pixels
  size_t total = 0;
  for (const Branch& b : graph.branches)
    if (b.alive && b.pixels.size() >= kMeasuredBranch && b.radius.size() == b.pixels.size()) {
      pieces.emplace_back(middle_value(b.radius), b.pixels.size());
      total += b.pixels.size();
    }
  for (size_t i = 0; i < graph.rings.size() && i < graph.ring_radius.size(); ++i)
    if (!graph.ring_radius[i].empty()) {
      pieces.emplace_back(middle_value(graph.ring_radius[i]), graph.rings[i].size());
      total += graph.rings[i].size();
    }
  std::sort(pieces.begin(), pieces.end());
  size_t covered = 0;
  for (const auto& [radius, length] : pieces) {
    covered += length;
    if (static_cast<double>(covered) >= share * static_cast<double>(total)) return radius;
  }
  return 0;
}

}  // namespace mbest

#include "mbest/core/skeleton.h"

#include <algorithm>
#include <array>
#include <bitset>

#include <opencv2/imgproc.hpp>

namespace mbest {
namespace {

bool bit(int code, int i) { return (code >> i) & 1; }

// Zhang-Suen deletion rules as a table: bit 0 = removable in the first sub-iteration,
// bit 1 = removable in the second.
std::array<uint8_t, 256> zhang_suen_table() {
  std::array<uint8_t, 256> lut{};
  for (int c = 0; c < 256; ++c) {
    const int b = static_cast<int>(std::bitset<8>(c).count());
    int a = 0;  // 0 -> 1 transitions around the ring N, NE, ..., NW, N
    for (int i = 0; i < 8; ++i) a += !bit(c, i) && bit(c, (i + 1) % 8);
    if (b < 2 || b > 6 || a != 1) continue;
    const bool n = bit(c, 0), e = bit(c, 2), s = bit(c, 4), w = bit(c, 6);
    if (!(n && e && s) && !(e && s && w)) lut[c] |= 1;
    if (!(n && e && w) && !(n && s && w)) lut[c] |= 2;
  }
  return lut;
}

// A pixel can go without changing 8-connectivity when its neighbours form exactly one
// 8-connected group (Yokoi's connectivity number equals 1).
int yokoi_8(int c) {
  int n = 0;
  for (int k = 0; k < 8; k += 2) {
    const bool xk = !bit(c, k), xk1 = !bit(c, k + 1), xk2 = !bit(c, (k + 2) % 8);
    n += xk - (xk && xk1 && xk2);
  }
  return n;
}

// Staircase corner: two orthogonal 4-neighbours (N-E, E-S, S-W, W-N) both set.
bool is_corner(int c) {
  const bool n = bit(c, 0), e = bit(c, 2), s = bit(c, 4), w = bit(c, 6);
  return (n && e) || (e && s) || (s && w) || (w && n);
}

std::array<uint8_t, 256> staircase_table() {
  std::array<uint8_t, 256> lut{};
  for (int c = 0; c < 256; ++c)
    lut[c] = std::bitset<8>(c).count() >= 2 && yokoi_8(c) == 1 && is_corner(c);
  return lut;
}

constexpr uint8_t kQueued = 2;  // marks a foreground pixel already in the candidate list

}  // namespace

Skeleton skeletonize(const cv::Mat& mask) {
  static const std::array<uint8_t, 256> kZhangSuen = zhang_suen_table();
  static const std::array<uint8_t, 256> kStaircase = staircase_table();
  CV_Assert(mask.type() == CV_8UC1);

  Skeleton sk;
  sk.buffer = cv::Mat::zeros(mask.rows + 2, mask.cols + 2, CV_8UC1);
  sk.image = sk.buffer(cv::Rect(1, 1, mask.cols, mask.rows));
  cv::threshold(mask, sk.image, 0, 1, cv::THRESH_BINARY);

  uint8_t* data = sk.buffer.data;
  const size_t step = sk.buffer.step;
  const ptrdiff_t offs[8] = {-static_cast<ptrdiff_t>(step), -static_cast<ptrdiff_t>(step) + 1, 1,
                             static_cast<ptrdiff_t>(step) + 1, static_cast<ptrdiff_t>(step),
                             static_cast<ptrdiff_t>(step) - 1, -1, -static_cast<ptrdiff_t>(step) - 1};

  // Only pixels on the boundary can be deleted; start with them and, after each
  // sub-iteration, add the foreground neighbours of what was deleted.
  std::vector<ptrdiff_t> candidates;
  for (int y = 1; y <= mask.rows; ++y) {
    uint8_t* row = data + y * step;
    for (int x = 1; x <= mask.cols; ++x) {
      if (row[x] && neighbour_code(row + x, step) != 0xFF) {
        row[x] |= kQueued;
        candidates.push_back(y * static_cast<ptrdiff_t>(step) + x);
      }
    }
  }

  std::vector<ptrdiff_t> removed, kept;
  bool changed = true;
  while (changed) {
    changed = false;
    for (int pass = 0; pass < 2; ++pass) {
      removed.clear();
      for (ptrdiff_t i : candidates)
        if (kZhangSuen[neighbour_code(data + i, step)] & (1 << pass)) removed.push_back(i);
      if (removed.empty()) continue;
      changed = true;
      for (ptrdiff_t i : removed) data[i] = 0;
      kept.clear();
      for (ptrdiff_t i : candidates)
        if (data[i]) kept.push_back(i);
      for (ptrdiff_t i : removed)
        for (ptrdiff_t o : offs)
          if (data[i + o] == 1) {
            data[i + o] |= kQueued;
            kept.push_back(i + o);
          }
      candidates.swap(kept);
    }
  }

  // Every remaining pixel is in the candidate list (it touches the background).
  std::sort(candidates.begin(), candidates.end());
  for (ptrdiff_t i : candidates)
    if (kStaircase[neighbour_code(data + i, step)]) data[i] = 0;

  sk.pixels.reserve(candidates.size());
  for (ptrdiff_t i : candidates) {
    if (!data[i]) continue;
    data[i] = 1;
    sk.pixels.emplace_back(static_cast<int>(i % step) - 1, static_cast<int>(i / step) - 1);
  }
  return sk;
}

}  // namespace mbest

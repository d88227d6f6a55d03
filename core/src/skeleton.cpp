#include "mbest/core/skeleton.h"

#include <algorithm>
#include <array>
#include <bitset>
#include <cstring>

#include <opencv2/imgproc.hpp>

namespace mbest {
namespace {

bool bit(int code, int i) { return (code >> i) & 1; }

// Zhang-Suen deletion rules as a table: bit 0 = removable in the first sub-iteration,
// bit 1 = removable in the second. With Lu and Wang's correction: at least 3 neighbours
// (not 2), without which a 2-pixel-thick diagonal line is eaten from its end (a straight
// rod at 46 degrees lost 70 px of skeleton); the staircase pass thins what it leaves.
std::array<uint8_t, 256> zhang_suen_table() {
  std::array<uint8_t, 256> lut{};
  for (int c = 0; c < 256; ++c) {
    const int b = static_cast<int>(std::bitset<8>(c).count());
    int a = 0;  // 0 -> 1 transitions around the ring N, NE, ..., NW, N
    for (int i = 0; i < 8; ++i) a += !bit(c, i) && bit(c, (i + 1) % 8);
    if (b < 3 || b > 6 || a != 1) continue;
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

// Marks kept in the image beside the foreground bit 1.
constexpr uint8_t kQueued = 2;  // in the candidate list
// Evaluated for sub-iteration 1 / 2 (kSettled << pass) and found to stay; cleared when a
// neighbour goes, since a pixel's fate depends only on its 8 neighbours.
constexpr uint8_t kSettled = 4;
constexpr uint8_t kBothSettled = kSettled | kSettled << 1;

}  // namespace

Skeleton skeletonize(const cv::Mat& mask) {
  static const std::array<uint8_t, 256> kZhangSuen = zhang_suen_table();
  static const std::array<uint8_t, 256> kStaircase = staircase_table();
  CV_Assert(mask.type() == CV_8UC1);

  Skeleton sk;
  sk.buffer.create(mask.rows + 2, mask.cols + 2, CV_8UC1);
  uint8_t* data = sk.buffer.data;
  const size_t step = sk.buffer.step;
  std::memset(data, 0, step);  // only the border needs zeroing; the inside is overwritten
  std::memset(data + (mask.rows + 1) * step, 0, step);
  for (int y = 1; y <= mask.rows; ++y) data[y * step] = data[y * step + mask.cols + 1] = 0;
  sk.image = sk.buffer(cv::Rect(1, 1, mask.cols, mask.rows));
  cv::threshold(mask, sk.image, 0, 1, cv::THRESH_BINARY);

  const ptrdiff_t s = static_cast<ptrdiff_t>(step);
  const ptrdiff_t offs[8] = {-s, -s + 1, 1, s + 1, s, s - 1, -1, -s - 1};

  // Only pixels on the boundary can be deleted; start with them and, after each
  // sub-iteration, add the foreground neighbours of what was deleted. A pixel is on the
  // boundary when it is set and not all of its 8 neighbours are: one AND over three rows,
  // which the compiler vectorises, then a pass that skips empty stretches 8 bytes at a time.
  std::vector<ptrdiff_t> candidates;
  std::vector<uint8_t> boundary(static_cast<size_t>(mask.cols) + 9, 0);
  for (int y = 1; y <= mask.rows; ++y) {
    const uint8_t* a = data + (y - 1) * step;
    uint8_t* b = data + y * step;
    const uint8_t* c = data + (y + 1) * step;
    uint8_t* out = boundary.data();
    for (int x = 1; x <= mask.cols; ++x) {
      const uint8_t all = a[x - 1] & a[x] & a[x + 1] & b[x - 1] & b[x + 1] & c[x - 1] & c[x] & c[x + 1];
      out[x] = static_cast<uint8_t>(b[x] & ~all & 1);
    }
    for (int x = 1; x <= mask.cols; x += 8) {
      uint64_t word;
      std::memcpy(&word, out + x, sizeof word);
      if (word == 0) continue;
      for (int k = x; k < x + 8 && k <= mask.cols; ++k)
        if (out[k]) {
          b[k] |= kQueued;
          candidates.push_back(y * s + k);
        }
    }
  }

  std::vector<ptrdiff_t> removed, resting;  // resting: left the list, settled for both passes
  bool changed = true;
  while (changed) {
    changed = false;
    for (int pass = 0; pass < 2; ++pass) {
      const uint8_t settled = static_cast<uint8_t>(kSettled << pass);
      removed.clear();
      size_t kept = 0;
      for (ptrdiff_t i : candidates) {
        uint8_t& v = data[i];
        if (!v) continue;  // deleted in the previous sub-iteration
        if ((v & kBothSettled) == kBothSettled) {  // stays until a neighbour goes
          v &= static_cast<uint8_t>(~kQueued);
          resting.push_back(i);
          continue;
        }
        candidates[kept++] = i;
        if (v & settled) continue;
        if (kZhangSuen[neighbour_code(data + i, step)] & (1 << pass))
          removed.push_back(i);
        else
          v |= settled;
      }
      candidates.resize(kept);
      if (removed.empty()) continue;
      changed = true;
      for (ptrdiff_t i : removed) data[i] = 0;
      for (ptrdiff_t i : removed)
        for (ptrdiff_t o : offs) {
          uint8_t& v = data[i + o];
          if (!v) continue;
          v &= static_cast<uint8_t>(~kBothSettled);
          if (!(v & kQueued)) {
            v |= kQueued;
            candidates.push_back(i + o);
          }
        }
    }
  }

  // Every remaining pixel touches the background, so it is in the list or resting.
  candidates.insert(candidates.end(), resting.begin(), resting.end());
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  for (ptrdiff_t i : candidates)
    if (data[i] && kStaircase[neighbour_code(data + i, step)]) data[i] = 0;

  sk.pixels.reserve(candidates.size());
  for (ptrdiff_t i : candidates) {
    if (!data[i]) continue;
    data[i] = 1;
    sk.pixels.emplace_back(static_cast<int>(i % step) - 1, static_cast<int>(i / step) - 1);
  }
  return sk;
}

}  // namespace mbest

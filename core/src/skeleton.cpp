#include "mbest/core/skeleton.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace mbest {
namespace {

constexpr bool bit(int code, int i) { return (code >> i) & 1; }

constexpr int popcount8(int c) {
  int n = 0;
  for (int i = 0; i < 8; ++i) n += bit(c, i);
  return n;
}

// Zhang-Suen deletion rule for the 8-neighbourhood code `c` (bit order of neighbour_code) in
// sub-iteration `pass` (0 or 1). With Lu and Wang's correction: at least 3 neighbours (not
// 2), without which a 2-pixel-thick diagonal line is eaten from its end (a straight rod at 46
// degrees lost 70 px of skeleton); the staircase pass thins what it leaves.
constexpr bool zhang_suen_removable(int c, int pass) {
  const int b = popcount8(c);
  int a = 0;  // 0 -> 1 transitions around the ring N, NE, ..., NW, N
  for (int i = 0; i < 8; ++i) a += !bit(c, i) && bit(c, (i + 1) % 8);
  if (b < 3 || b > 6 || a != 1) return false;
  const bool n = bit(c, 0), e = bit(c, 2), s = bit(c, 4), w = bit(c, 6);
  return pass == 0 ? !(n && e && s) && !(e && s && w) : !(n && e && w) && !(n && s && w);
}

// The same rule evaluated for 64 pixels at once: p[k] holds neighbour k (bit order of
// neighbour_code) of each pixel of a word. Bit-sliced, the count and transition conditions
// become: A == 1 (exactly one 0 -> 1 transition around the ring) makes the ones and the zeros
// each one circular run, so B >= 3 is "three ones in a row somewhere on the ring" and B <= 6
// is "two zeros in a row somewhere".
constexpr uint64_t zhang_suen_removable(const uint64_t (&p)[8], int pass) {
  uint64_t seen = 0, twice = 0, three_ones = 0, all_pairs_hit = ~uint64_t{0};
  for (int k = 0; k < 8; ++k) {
    const uint64_t a = p[k], b = p[(k + 1) % 8], c = p[(k + 2) % 8];
    const uint64_t rise = ~a & b;
    twice |= seen & rise;
    seen |= rise;
    three_ones |= a & b & c;
    all_pairs_hit &= a | b;
  }
  const uint64_t n = p[0], e = p[2], s = p[4], w = p[6];
  const uint64_t rule = pass == 0 ? ~(n & e & s) & ~(e & s & w) : ~(n & e & w) & ~(n & s & w);
  return seen & ~twice & three_ones & ~all_pairs_hit & rule;
}

// Checks, at compile time, the bit-sliced form against the rule for all 256 codes.
constexpr bool bit_sliced_rule_matches() {
  for (int c = 0; c < 256; ++c)
    for (int pass = 0; pass < 2; ++pass) {
      uint64_t p[8] = {};
      for (int k = 0; k < 8; ++k) p[k] = bit(c, k) ? 1 : 0;
      if ((zhang_suen_removable(p, pass) & 1) != zhang_suen_removable(c, pass)) return false;
    }
  return true;
}
static_assert(bit_sliced_rule_matches(), "bit-sliced Zhang-Suen rule differs from the table");

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
    lut[c] = popcount8(c) >= 2 && yokoi_8(c) == 1 && is_corner(c);
  return lut;
}

// The mask as bits in 8 x 8 tiles, one 64-bit word a tile: pixel (x, y) is bit
// 8 (y % 8) + x % 8 of tile (x / 8 + 1, y / 8 + 1) of a grid `stride` tiles wide, whose
// outermost ring of tiles is zero, so all 8 neighbour tiles of a mask tile are readable
// without checks. A thin DLO covers about as many tiles per pixel of length at any angle;
// rows of 64 pixels cost one word per row a near-vertical DLO crosses.
struct TileImage {
  int stride = 0;
  std::vector<uint64_t> tiles;
};

constexpr uint64_t kColumn0 = 0x0101010101010101ULL;  // pixel x % 8 == 0 of every row
constexpr uint64_t kColumn7 = kColumn0 << 7;
constexpr uint64_t kRow0 = 0xFFULL, kRow7 = kRow0 << 56;

// The bits of each pixel's east (x + 1) and west (x - 1) neighbour, given the tile `t` and
// the tile to its right or left.
constexpr uint64_t east_of(uint64_t t, uint64_t right) {
  return ((t >> 1) & ~kColumn7) | ((right & kColumn0) << 7);
}
constexpr uint64_t west_of(uint64_t t, uint64_t left) {
  return ((t << 1) & ~kColumn0) | ((left & kColumn7) >> 7);
}
// The same for the north (y - 1) and south (y + 1) neighbour, given the tile above or below.
constexpr uint64_t north_of(uint64_t t, uint64_t up) { return (t << 8) | (up >> 56); }
constexpr uint64_t south_of(uint64_t t, uint64_t down) { return (t >> 8) | (down << 56); }

TileImage pack(const cv::Mat& mask) {
  TileImage b;
  const int cols = mask.cols;
  b.stride = (cols + 7) / 8 + 2;
  b.tiles.assign(static_cast<size_t>((mask.rows + 7) / 8 + 2) * b.stride, 0);
  for (int y = 0; y < mask.rows; ++y) {
    const uint8_t* m = mask.ptr<uint8_t>(y);
    uint64_t* out = b.tiles.data() + static_cast<size_t>(y / 8 + 1) * b.stride + 1;
    const int shift = 8 * (y % 8);
    int x = 0;
#ifdef __SSE2__
    // 16 pixels per compare: the sign bits of (byte == 0), inverted, are the foreground bits.
    const __m128i zero = _mm_setzero_si128();
    for (; x + 16 <= cols; x += 16) {
      const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(m + x));
      const unsigned bits = ~static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(v, zero))) & 0xFFFFu;
      out[x / 8] |= static_cast<uint64_t>(bits & 0xFFu) << shift;
      out[x / 8 + 1] |= static_cast<uint64_t>(bits >> 8) << shift;
    }
#endif
    for (; x < cols; ++x) out[x / 8] |= static_cast<uint64_t>(m[x] != 0) << (shift + x % 8);
  }
  return b;
}

}  // namespace

Skeleton skeletonize(const cv::Mat& mask) {
  static const std::array<uint8_t, 256> kStaircase = staircase_table();
  CV_Assert(mask.type() == CV_8UC1);

  // Zhang-Suen on the tiled bit image: the rule is evaluated for a whole tile at once (see
  // zhang_suen_removable), so a sub-iteration costs about as much per 64 pixels as the byte
  // version did per pixel. Only tiles whose 3x3 tile neighbourhood changed since their last
  // evaluation in that sub-iteration are evaluated again: a pixel's fate depends on its 8
  // neighbours only, so the others would find nothing to delete. dirty[i] bit `pass` says
  // tile i is in todo[pass].
  TileImage b = pack(mask);
  uint64_t* w = b.tiles.data();
  const ptrdiff_t stride = b.stride;
  std::vector<uint8_t> dirty(b.tiles.size(), 0);
  std::vector<int> todo[2], current;
  for (size_t i = 0; i < b.tiles.size(); ++i)
    if (w[i]) {
      dirty[i] = 3;
      todo[0].push_back(static_cast<int>(i));
      todo[1].push_back(static_cast<int>(i));
    }
  auto mark = [&](ptrdiff_t i) {
    for (int pass = 0; pass < 2; ++pass)
      if (!(dirty[i] & (1 << pass))) {
        dirty[i] |= static_cast<uint8_t>(1 << pass);
        todo[pass].push_back(static_cast<int>(i));
      }
  };
  std::vector<std::pair<int, uint64_t>> removed;  // tile, bits to clear
  bool changed = true;
  while (changed) {
    changed = false;
    for (int pass = 0; pass < 2; ++pass) {
      // Every tile is judged on the image as it was before this sub-iteration: deletions
      // are collected first and applied after.
      current.swap(todo[pass]);
      todo[pass].clear();
      removed.clear();
      for (int i : current) {
        dirty[i] &= static_cast<uint8_t>(~(1 << pass));
        const uint64_t c = w[i];
        if (!c) continue;
        const uint64_t* up = w + i - stride;
        const uint64_t* down = w + i + stride;
        const uint64_t e = east_of(c, w[i + 1]), west = west_of(c, w[i - 1]);
        const uint64_t e_up = east_of(up[0], up[1]), e_down = east_of(down[0], down[1]);
        const uint64_t w_up = west_of(up[0], up[-1]), w_down = west_of(down[0], down[-1]);
        const uint64_t p[8] = {north_of(c, up[0]),   north_of(e, e_up),     e,
                               south_of(e, e_down),  south_of(c, down[0]),  south_of(west, w_down),
                               west,                 north_of(west, w_up)};  // N, NE, ..., NW
        const uint64_t del = c & zhang_suen_removable(p, pass);
        if (del) removed.emplace_back(i, del);
      }
      if (removed.empty()) continue;
      changed = true;
      for (const auto& [i, del] : removed) w[i] &= ~del;
      // What changes: this tile, and a neighbour tile only where a deleted pixel lies on the
      // edge or corner facing it.
      for (const auto& [i, del] : removed) {
        mark(i);
        const bool n = del & kRow0, s = del & kRow7, west = del & kColumn0, e = del & kColumn7;
        if (n) mark(i - stride);
        if (s) mark(i + stride);
        if (west) mark(i - 1);
        if (e) mark(i + 1);
        if (del & kRow0 & kColumn0) mark(i - stride - 1);
        if (del & kRow0 & kColumn7) mark(i - stride + 1);
        if (del & kRow7 & kColumn0) mark(i + stride - 1);
        if (del & kRow7 & kColumn7) mark(i + stride + 1);
      }
    }
  }

  // Back to bytes, with a zero border: only the few remaining pixels need writing. Each row
  // of tiles is scanned once for its non-empty tiles, whose eight pixel rows are then read
  // in raster order (scanning all tiles again for every pixel row cost more than the rest of
  // the conversion).
  Skeleton sk;
  sk.buffer = cv::Mat::zeros(mask.rows + 2, mask.cols + 2, CV_8UC1);
  sk.image = sk.buffer(cv::Rect(1, 1, mask.cols, mask.rows));
  uint8_t* data = sk.buffer.data;
  const size_t step = sk.buffer.step;
  std::vector<ptrdiff_t> remaining;  // in raster order
  std::vector<int> occupied;         // non-empty tiles of one row of tiles
  for (int ty = 0; 8 * ty < mask.rows; ++ty) {
    const uint64_t* row = w + static_cast<size_t>(ty + 1) * stride + 1;
    occupied.clear();
    for (int k = 0; k < stride - 2; ++k)
      if (row[k]) occupied.push_back(k);
    for (int y = 8 * ty; y < std::min(8 * ty + 8, mask.rows) && !occupied.empty(); ++y) {
      const int shift = 8 * (y % 8);
      for (int k : occupied)
        for (unsigned bits = static_cast<unsigned>(row[k] >> shift) & 0xFFu; bits; bits &= bits - 1) {
          const int x = 8 * k + __builtin_ctz(bits);
          const ptrdiff_t i = static_cast<ptrdiff_t>((y + 1) * step + x + 1);
          data[i] = 1;
          remaining.push_back(i);
        }
    }
  }

  // Staircase corners go one by one in raster order, each seeing the deletions before it.
  for (ptrdiff_t i : remaining)
    if (kStaircase[neighbour_code(data + i, step)]) data[i] = 0;

  sk.pixels.reserve(remaining.size());
  for (ptrdiff_t i : remaining)
    if (data[i]) sk.pixels.emplace_back(static_cast<int>(i % step) - 1, static_cast<int>(i / step) - 1);
  return sk;
}

}  // namespace mbest

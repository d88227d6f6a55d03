#include "mbest/core/instance_mask.h"

#include <cmath>
#include <cstring>

namespace mbest {

namespace {
// One padded 16-bit array holds the mask and the labels together, so the search needs no
// bounds checks and touches one array: kOutside = background or border, 0 = mask pixel not
// yet reached, otherwise the DLO's id, with kBand set while it is reserved for a top strand.
constexpr uint16_t kOutside = 0xFFFF;
constexpr uint16_t kBand = 0x8000;
}  // namespace

cv::Mat instance_labels(const cv::Mat& mask, const std::vector<Dlo>& dlos,
                        const std::vector<TopStrand>& tops) {
  const int rows = mask.rows, cols = mask.cols, stride = cols + 2;
  cv::Mat buffer(rows + 2, stride, CV_16UC1);
  std::memset(buffer.ptr(0), 0xFF, buffer.step);  // 0xFFFF = kOutside
  std::memset(buffer.ptr(rows + 1), 0xFF, buffer.step);
  for (int y = 0; y < rows; ++y) {
    const uint8_t* m = mask.ptr<uint8_t>(y);
    uint16_t* b = buffer.ptr<uint16_t>(y + 1);
    b[0] = b[cols + 1] = kOutside;
    for (int x = 0; x < cols; ++x) b[x + 1] = m[x] ? 0 : kOutside;
  }
  uint16_t* lab = buffer.ptr<uint16_t>(0);
  auto index = [&](cv::Point p) { return (p.y + 1) * stride + p.x + 1; };
  auto in_image = [&](cv::Point p) { return p.x >= 0 && p.y >= 0 && p.x < cols && p.y < rows; };

  // The band of each strand on top is reserved for it: no other DLO's front may enter it.
  std::vector<int> band;
  for (const TopStrand& top : tops) {
    const uint16_t id = static_cast<uint16_t>(top.dlo + 1) | kBand;
    for (size_t k = 0; k < top.path.size(); ++k) {
      const cv::Point c = top.path[k];
      const float rr = top.radius[k] - 0.5f;  // radius is half the width + 0.5 px
      const int ri = static_cast<int>(std::ceil(rr));
      for (int dy = -ri; dy <= ri; ++dy)
        for (int dx = -ri; dx <= ri; ++dx) {
          const cv::Point q(c.x + dx, c.y + dy);
          if (dx * dx + dy * dy > rr * rr || !in_image(q)) continue;
          uint16_t& l = lab[index(q)];
          if (l == kOutside) continue;
          l = id;
          band.push_back(index(q));
        }
    }
  }

  // Breadth-first search inside the mask from every centerline at once: each pixel goes to
  // the DLO whose centerline front reaches it first. 4-connected fronts score as well as
  // 8-connected ones on the dev set (S2 99.76 vs 99.75 %, S3 99.66 both) at half the cost.
  std::vector<int> queue;
  auto claim = [&](int i, uint16_t id) {
    uint16_t& l = lab[i];
    if (l == 0 || l == (id | kBand)) {
      l = id;
      queue.push_back(i);
    }
  };
  for (size_t d = 0; d < dlos.size(); ++d)
    for (const cv::Point& p : dlos[d].centerline)
      if (in_image(p)) claim(index(p), static_cast<uint16_t>(d + 1));
  const int offs[4] = {-stride, -1, 1, stride};
  for (size_t head = 0; head < queue.size(); ++head) {
    const int i = queue[head];
    const uint16_t id = lab[i];
    for (int o : offs) claim(i + o, id);
  }

  // Band pixels no front reached (cut off from their strand) still belong to it.
  for (int i : band) lab[i] &= static_cast<uint16_t>(~kBand);
  cv::Mat labels(rows, cols, CV_16UC1);
  for (int y = 0; y < rows; ++y) {
    const uint16_t* src = buffer.ptr<uint16_t>(y + 1) + 1;
    uint16_t* dst = labels.ptr<uint16_t>(y);
    for (int x = 0; x < cols; ++x) dst[x] = src[x] == kOutside ? 0 : src[x];
  }
  return labels;
}

}  // namespace mbest

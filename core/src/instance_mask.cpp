#include "mbest/core/instance_mask.h"

#include <cmath>

namespace mbest {

namespace {
constexpr uint16_t kBand = 0x8000;  // pixel reserved for the strand on top, not yet reached
}

cv::Mat instance_labels(const cv::Mat& mask, const std::vector<Dlo>& dlos,
                        const std::vector<TopStrand>& tops) {
  const int rows = mask.rows, cols = mask.cols;
  cv::Mat labels = cv::Mat::zeros(rows, cols, CV_16UC1);
  auto inside = [&](int x, int y) { return x >= 0 && y >= 0 && x < cols && y < rows && mask.ptr<uint8_t>(y)[x]; };

  // The band of each strand on top is reserved for it: no other DLO's front may enter it.
  std::vector<int> band;
  for (const TopStrand& top : tops) {
    const uint16_t id = static_cast<uint16_t>(top.dlo + 1) | kBand;
    for (size_t k = 0; k < top.path.size(); ++k) {
      const cv::Point c = top.path[k];
      const float rr = top.radius[k] + 0.5f;
      const int ri = static_cast<int>(std::ceil(rr));
      for (int dy = -ri; dy <= ri; ++dy)
        for (int dx = -ri; dx <= ri; ++dx)
          if (dx * dx + dy * dy <= rr * rr && inside(c.x + dx, c.y + dy)) {
            labels.ptr<uint16_t>(c.y + dy)[c.x + dx] = id;
            band.push_back((c.y + dy) * cols + c.x + dx);
          }
    }
  }

  // Breadth-first search inside the mask from every centerline at once: each pixel goes to
  // the DLO whose centerline front reaches it first.
  std::vector<int> queue;
  auto claim = [&](int x, int y, uint16_t id) {
    uint16_t& l = labels.ptr<uint16_t>(y)[x];
    if (l == 0 || l == (id | kBand)) {
      l = id;
      queue.push_back(y * cols + x);
    }
  };
  for (size_t i = 0; i < dlos.size(); ++i)
    for (const cv::Point& p : dlos[i].centerline)
      if (inside(p.x, p.y)) claim(p.x, p.y, static_cast<uint16_t>(i + 1));
  for (size_t head = 0; head < queue.size(); ++head) {
    const int x = queue[head] % cols, y = queue[head] / cols;
    const uint16_t id = labels.ptr<uint16_t>(y)[x];
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (inside(x + dx, y + dy)) claim(x + dx, y + dy, id);
  }
  // Band pixels no front reached (cut off from their strand) still belong to it.
  for (int i : band) labels.ptr<uint16_t>(i / cols)[i % cols] &= static_cast<uint16_t>(~kBand);
  return labels;
}

}  // namespace mbest

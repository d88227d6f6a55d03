#include "mbest/core/instance_mask.h"

#include <cmath>

namespace mbest {

cv::Mat instance_labels(const cv::Mat& mask, const std::vector<Dlo>& dlos,
                        const std::vector<TopStrand>& tops) {
  const int rows = mask.rows, cols = mask.cols;
  cv::Mat labels = cv::Mat::zeros(rows, cols, CV_16UC1);
  auto inside = [&](int x, int y) { return x >= 0 && y >= 0 && x < cols && y < rows && mask.ptr<uint8_t>(y)[x]; };

  for (size_t i = 0; i < dlos.size(); ++i)
    for (const cv::Point& p : dlos[i].centerline)
      if (inside(p.x, p.y)) labels.ptr<uint16_t>(p.y)[p.x] = static_cast<uint16_t>(i + 1);

  for (const TopStrand& top : tops) {
    const uint16_t id = static_cast<uint16_t>(top.dlo + 1);
    for (size_t k = 0; k < top.path.size(); ++k) {
      const cv::Point c = top.path[k];
      const float rr = top.radius[k] + 0.5f;
      const int ri = static_cast<int>(std::ceil(rr));
      for (int dy = -ri; dy <= ri; ++dy)
        for (int dx = -ri; dx <= ri; ++dx)
          if (dx * dx + dy * dy <= rr * rr && inside(c.x + dx, c.y + dy))
            labels.ptr<uint16_t>(c.y + dy)[c.x + dx] = id;
    }
  }

  // Breadth-first search inside the mask from every labelled pixel.
  std::vector<int> queue;
  for (int y = 0; y < rows; ++y) {
    const uint16_t* row = labels.ptr<uint16_t>(y);
    for (int x = 0; x < cols; ++x)
      if (row[x]) queue.push_back(y * cols + x);
  }
  for (size_t head = 0; head < queue.size(); ++head) {
    const int x = queue[head] % cols, y = queue[head] / cols;
    const uint16_t id = labels.ptr<uint16_t>(y)[x];
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if (!inside(nx, ny)) continue;
        uint16_t& l = labels.ptr<uint16_t>(ny)[nx];
        if (l) continue;
        l = id;
        queue.push_back(ny * cols + nx);
      }
  }
  return labels;
}

}  // namespace mbest

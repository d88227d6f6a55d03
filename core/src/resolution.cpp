#include "mbest/core/resolution.h"

#include <algorithm>

#include "mbest/core/geometry.h"
#include "mbest/core/keypoints.h"

namespace mbest {
namespace {

// The block of half-resolution pixel p is 2p .. 2p + 1; its centre 2p + 0.5 is not a pixel,
// so take 2p + 1, clamped to the image.
cv::Point up(cv::Point p, cv::Size size) {
  return {std::min(2 * p.x + 1, size.width - 1), std::min(2 * p.y + 1, size.height - 1)};
}

std::vector<cv::Point> up_chain(const std::vector<cv::Point>& chain, cv::Size size) {
  std::vector<cv::Point> out;
  out.reserve(2 * chain.size());
  for (const cv::Point& p : chain) append_connected(out, up(p, size));
  return out;
}

}  // namespace

cv::Mat half_resolution(const cv::Mat& mask) {
  const int rows = (mask.rows + 1) / 2, cols = (mask.cols + 1) / 2;
  cv::Mat half(rows, cols, CV_8UC1);
  for (int y = 0; y < rows; ++y) {
    const uint8_t* a = mask.ptr<uint8_t>(2 * y);
    const uint8_t* b = 2 * y + 1 < mask.rows ? mask.ptr<uint8_t>(2 * y + 1) : nullptr;
    uint8_t* out = half.ptr<uint8_t>(y);
    const int full_pairs = mask.cols / 2;
    if (b) {
      for (int x = 0; x < full_pairs; ++x)
        out[x] = ((a[2 * x] != 0) + (a[2 * x + 1] != 0) + (b[2 * x] != 0) + (b[2 * x + 1] != 0)) >= 2;
    } else {
      for (int x = 0; x < full_pairs; ++x) out[x] = ((a[2 * x] != 0) + (a[2 * x + 1] != 0)) >= 1;
    }
    if (cols > full_pairs) {  // odd width: the last column's blocks are one pixel wide
      const int x = mask.cols - 1;
      out[cols - 1] = b ? ((a[x] != 0) + (b[x] != 0)) >= 1 : a[x] != 0;
    }
  }
  return half;
}

void to_full_resolution(Traversal& t, std::vector<Passage>& passages,
                        std::vector<CrossingRegion>& regions, const cv::Mat& mask) {
  const cv::Size size = mask.size();
  // A DLO's centre lies somewhere in the 2x2 block of its half-resolution pixel, and the
  // distance to the background peaks there: the radius is the block's largest distance.
  auto block_radius = [&](cv::Point p) {
    float r = 0;
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx)
        r = std::max(r, distance_to_background(mask, {std::min(2 * p.x + dx, size.width - 1),
                                                      std::min(2 * p.y + dy, size.height - 1)}));
    return r;
  };
  constexpr size_t kStride = 4;  // radius measured every kStride-th pixel, interpolated
  for (Dlo& dlo : t.dlos) {
    const std::vector<cv::Point> half_chain = std::move(dlo.centerline);
    const size_t n = half_chain.size();
    std::vector<float> half_radius(n);
    for (size_t a = 0; a < n; a += kStride) {
      const size_t b = std::min(a + kStride, n - 1);
      half_radius[a] = block_radius(half_chain[a]);
      half_radius[b] = block_radius(half_chain[b]);
      for (size_t i = a + 1; i < b; ++i) {
        const float f = static_cast<float>(i - a) / static_cast<float>(b - a);
        half_radius[i] = half_radius[a] * (1 - f) + half_radius[b] * f;
      }
    }
    dlo.centerline.clear();
    dlo.radius.clear();
    for (size_t i = 0; i < n; ++i) {
      append_connected(dlo.centerline, up(half_chain[i], size));
      dlo.radius.resize(dlo.centerline.size(), half_radius[i]);
    }
    if (dlo.closed && dlo.centerline.size() > 2) {  // close the seam again, without repeating
      const cv::Point first = dlo.centerline.front();
      append_connected(dlo.centerline, first);
      if (dlo.centerline.back() == first) dlo.centerline.pop_back();
      dlo.radius.resize(dlo.centerline.size(), dlo.radius.back());
    }
  }
  for (Passage& p : passages) {
    p.path = up_chain(p.path, size);
    for (BranchTangent* tangent : {&p.from_tangent, &p.to_tangent}) {
      tangent->radius = block_radius(cv::Point(tangent->point));
      tangent->point = cv::Point2f(up(cv::Point(tangent->point), size));
      tangent->cut *= 2;
    }
    const size_t n = p.path.size();
    p.radius.resize(n);
    for (size_t k = 0; k < n; ++k) {
      const float f = n > 1 ? static_cast<float>(k) / static_cast<float>(n - 1) : 0.f;
      p.radius[k] = p.from_tangent.radius * (1 - f) + p.to_tangent.radius * f;
    }
  }
  for (CrossingRegion& r : regions) r.centre = r.centre * 2.0f + cv::Point2f(0.5f, 0.5f);
}

}  // namespace mbest

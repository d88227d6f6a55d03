#include "mbest/synth/background.h"

#include <cmath>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace mbest::synth {
namespace {

cv::Scalar bgr(const cv::Vec3b& rgb, double gain = 1) {
  return cv::Scalar(rgb[2] * gain, rgb[1] * gain, rgb[0] * gain);
}

cv::Vec3b vary(const cv::Vec3b& rgb, Rng& rng, double spread) {
  cv::Vec3b out;
  for (int k = 0; k < 3; ++k) out[k] = cv::saturate_cast<uchar>(rgb[k] + rng.normal(0, spread));
  return out;
}

// Smooth value noise in [0, 1]: a coarse random grid (cells of `cell` px), bicubic upsampled.
cv::Mat smooth_noise(cv::Size size, double cell, Rng& rng) {
  const int gw = std::max(2, static_cast<int>(size.width / cell) + 2);
  const int gh = std::max(2, static_cast<int>(size.height / cell) + 2);
  cv::Mat g(gh, gw, CV_32F);
  for (int y = 0; y < gh; ++y)
    for (int x = 0; x < gw; ++x) g.at<float>(y, x) = static_cast<float>(rng.uniform());
  cv::Mat up;
  cv::resize(g, up, cv::Size(static_cast<int>(gw * cell), static_cast<int>(gh * cell)), 0, 0, cv::INTER_CUBIC);
  return up(cv::Rect(0, 0, size.width, size.height));  // a view: no copy of the frame
}

// Colour = base * (scale * field + offset + grain) in one pass over the frame: `field` is
// smooth noise (CV_32F), the grain a small random tile of sd `sigma`, repeated at a random
// offset (cheap, and the repeat is hidden under the coarser structure).
cv::Mat tint_grained(const cv::Mat& field, double scale, double offset, double sigma, const cv::Vec3b& rgb,
                     Rng& rng) {
  constexpr int kTile = 128;
  cv::Mat tile(kTile, kTile, CV_32F);
  cv::RNG cv_rng(rng.next());
  cv_rng.fill(tile, cv::RNG::NORMAL, 0, sigma);
  const int ox = rng.uniform_int(0, kTile - 1), oy = rng.uniform_int(0, kTile - 1);
  const float a = static_cast<float>(scale), b = static_cast<float>(offset);
  const float base[3] = {static_cast<float>(rgb[2]), static_cast<float>(rgb[1]), static_cast<float>(rgb[0])};
  cv::Mat out(field.size(), CV_8UC3);
  for (int y = 0; y < field.rows; ++y) {
    const float* f = field.ptr<float>(y);
    const float* t = tile.ptr<float>((y + oy) % kTile);
    uchar* o = out.ptr<uchar>(y);
    for (int x = 0; x < field.cols; ++x) {
      const float gain = a * f[x] + b + t[(x + ox) % kTile];
      for (int k = 0; k < 3; ++k) o[3 * x + k] = cv::saturate_cast<uchar>(base[k] * gain);
    }
  }
  return out;
}

// Colour = base * (gain field), gain field per pixel (CV_32F, ~1).
cv::Mat tint(const cv::Mat& gain, const cv::Vec3b& rgb) {
  const float base[3] = {static_cast<float>(rgb[2]), static_cast<float>(rgb[1]), static_cast<float>(rgb[0])};
  cv::Mat out(gain.size(), CV_8UC3);
  for (int y = 0; y < gain.rows; ++y) {
    const float* g = gain.ptr<float>(y);
    uchar* o = out.ptr<uchar>(y);
    for (int x = 0; x < gain.cols; ++x) {
      for (int k = 0; k < 3; ++k) o[3 * x + k] = cv::saturate_cast<uchar>(base[k] * g[x]);
    }
  }
  return out;
}

cv::Mat gradient(cv::Size size, const cv::Vec3b& base, Rng& rng) {
  const cv::Vec3b a = vary(base, rng, 25), b = vary(base, rng, 45);
  const double angle = rng.uniform(0, 2 * M_PI);
  const double cx = std::cos(angle), cy = std::sin(angle);
  const double span = std::abs(cx) * size.width + std::abs(cy) * size.height;
  cv::Mat out(size, CV_8UC3);
  for (int y = 0; y < size.height; ++y) {
    auto* row = out.ptr<cv::Vec3b>(y);
    for (int x = 0; x < size.width; ++x) {
      double t = ((x - size.width / 2.0) * cx + (y - size.height / 2.0) * cy) / span + 0.5;
      for (int k = 0; k < 3; ++k) row[x][k] = cv::saturate_cast<uchar>(a[2 - k] + t * (b[2 - k] - a[2 - k]));
    }
  }
  return out;
}

cv::Mat wood(cv::Size size, Rng& rng) {
  const cv::Vec3b light = vary({170, 125, 80}, rng, 15), dark = vary({110, 70, 40}, rng, 10);
  const cv::Mat warp = smooth_noise(size, rng.uniform(120, 260), rng);
  const cv::Mat fine = smooth_noise(size, 6, rng);
  const double freq = rng.uniform(0.04, 0.09), angle = rng.uniform(-0.3, 0.3);
  const double ca = std::cos(angle), sa = std::sin(angle);
  // sin from a table: this loop runs for every pixel.
  constexpr int kTable = 4096;
  std::vector<float> sine(kTable);
  for (int i = 0; i < kTable; ++i) sine[i] = static_cast<float>(std::sin(2 * M_PI * i / kTable));
  auto fast_sin = [&](double a) {
    const long i = std::lround(a * (kTable / (2 * M_PI)));
    return sine[static_cast<size_t>(((i % kTable) + kTable) % kTable)];
  };
  cv::Mat out(size, CV_8UC3);
  for (int y = 0; y < size.height; ++y) {
    auto* row = out.ptr<cv::Vec3b>(y);
    const float* w = warp.ptr<float>(y);
    const float* f = fine.ptr<float>(y);
    for (int x = 0; x < size.width; ++x) {
      const double v = -sa * x + ca * y;
      double t = 0.5 + 0.5 * fast_sin(freq * v + 9 * w[x]);
      t = t * t * t * 0.8 + 0.2 * f[x];
      for (int k = 0; k < 3; ++k) row[x][k] = cv::saturate_cast<uchar>(light[2 - k] + t * (dark[2 - k] - light[2 - k]));
    }
  }
  return out;
}

cv::Mat checker(cv::Size size, const cv::Vec3b& base, Rng& rng) {
  const cv::Vec3b a = vary(base, rng, 30), b = vary({230, 230, 225}, rng, 30);
  const int cell = rng.uniform_int(24, 90);
  const int ox = rng.uniform_int(0, cell), oy = rng.uniform_int(0, cell);
  cv::Mat out(size, CV_8UC3, bgr(a));
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x)
      if ((((x + ox) / cell) + ((y + oy) / cell)) % 2) out.at<cv::Vec3b>(y, x) = cv::Vec3b(b[2], b[1], b[0]);
  cv::GaussianBlur(out, out, cv::Size(0, 0), 0.7);
  return out;
}

// Distractors that are not rods: thin straight lines, short arcs and blobs.
cv::Mat clutter(cv::Size size, const cv::Vec3b& base, Rng& rng) {
  cv::Mat gain = smooth_noise(size, 200, rng) * 0.35 + 0.8;
  cv::Mat out = tint(gain, vary(base, rng, 20));
  const int blobs = rng.uniform_int(4, 12), lines = rng.uniform_int(4, 14);
  for (int i = 0; i < blobs; ++i) {
    const cv::Point c(rng.uniform_int(0, size.width), rng.uniform_int(0, size.height));
    const cv::Size axes(rng.uniform_int(10, 70), rng.uniform_int(8, 50));
    cv::ellipse(out, c, axes, rng.uniform(0, 180), 0, 360, bgr(vary(base, rng, 70)), cv::FILLED, cv::LINE_AA);
  }
  for (int i = 0; i < lines; ++i) {
    const cv::Point a(rng.uniform_int(0, size.width), rng.uniform_int(0, size.height));
    const cv::Point b(rng.uniform_int(0, size.width), rng.uniform_int(0, size.height));
    cv::line(out, a, b, bgr(vary(base, rng, 80)), rng.uniform_int(1, 3), cv::LINE_AA);
  }
  return out;
}

}  // namespace

Result<cv::Mat> make_background(const BackgroundConfig& config, cv::Size size, Rng& rng) {
  const std::string& type = config.types[rng.uniform_int(0, static_cast<int>(config.types.size()) - 1)];
  const cv::Vec3b base = config.color_rgb;
  if (type == "solid") return cv::Mat(size, CV_8UC3, bgr(base));
  if (type == "gradient") return gradient(size, base, rng);
  if (type == "noise") {
    const cv::Mat field = smooth_noise(size, rng.uniform(30, 150), rng);
    const cv::Vec3b colour = vary(base, rng, 15);
    return tint_grained(field, 0.5, 0.75, 0.04, colour, rng);
  }
  if (type == "paper") {
    const cv::Mat field = smooth_noise(size, 250, rng);
    const cv::Vec3b colour = vary({225, 220, 205}, rng, 10);
    return tint_grained(field, 0.08, 0.92, 0.025, colour, rng);
  }
  if (type == "wood") return wood(size, rng);
  if (type == "checker") return checker(size, base, rng);
  if (type == "clutter") return clutter(size, base, rng);
  // "folder": a random image, scaled to cover the frame, then a random crop.
  const std::string& file = config.folder_files[rng.uniform_int(0, static_cast<int>(config.folder_files.size()) - 1)];
  cv::Mat img = cv::imread(file, cv::IMREAD_COLOR);
  if (img.empty()) return Error{"cannot read background image " + file};
  const double scale = std::max(double(size.width) / img.cols, double(size.height) / img.rows);
  cv::resize(img, img, cv::Size(), scale * 1.0001, scale * 1.0001, cv::INTER_AREA);
  const int x = rng.uniform_int(0, std::max(0, img.cols - size.width));
  const int y = rng.uniform_int(0, std::max(0, img.rows - size.height));
  return img(cv::Rect(x, y, size.width, size.height)).clone();
}

}  // namespace mbest::synth

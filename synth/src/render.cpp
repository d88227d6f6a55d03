#include "mbest/synth/render.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <cairo.h>
#include <opencv2/imgproc.hpp>

#include "mbest/synth/background.h"

namespace mbest::synth {
namespace {

// Per-thread scratch memory reused from scene to scene: the per-rod buffers are as large
// as a rod's bounding box (often most of the frame), and allocating them afresh for every
// scene cost more in page faults than the work done in them. A Mat returned by scratch()
// views the slot's memory and stays valid until the same slot is requested again.
class Scratch {
 public:
  cv::Mat get(size_t slot, cv::Size size, int type) {
    if (slot >= slots_.size()) slots_.resize(slot + 1);
    std::vector<uchar>& bytes = slots_[slot];
    const size_t need = static_cast<size_t>(size.area()) * CV_ELEM_SIZE(type) + 64;
    if (bytes.size() < need) bytes.resize(need);
    return cv::Mat(size, type, bytes.data());
  }

 private:
  std::vector<std::vector<uchar>> slots_;
};

Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

// Slots of scratch(): fixed ones, then three per rod.
enum : size_t { kDist, kAlong, kArc, kPatchColour, kLayerCoverage0 };
size_t rod_slot(int rod, int k) { return 1000 + 3 * static_cast<size_t>(rod) + k; }

// A piece of one rod painted in one go: the whole rod (its base layer) or, at a crossing,
// the stretch of the strand that must be on top, painted again above.
struct Layer {
  int rod = 0;
  int from = 0, to = 0;  // centerline indices, inclusive; to may exceed n on a ring (wraps)
  bool whole = false;
  cv::Rect box;          // in the image
  cv::Mat coverage;      // CV_8UC1 over box, from Cairo
};

cv::Point2d point_at(const SceneRod& rod, int i) {
  const int n = static_cast<int>(rod.centerline.size());
  return rod.centerline[((i % n) + n) % n];
}

// Cairo coverage of the stroked piece, over its bounding box in the image.
void rasterise(Layer& layer, const SceneRod& rod, const cv::Rect& image, size_t slot) {
  double x0 = 1e18, y0 = 1e18, x1 = -1e18, y1 = -1e18;
  for (int i = layer.from; i <= layer.to; ++i) {
    const cv::Point2d p = point_at(rod, i);
    x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
  }
  const double pad = rod.width / 2 + 2;
  // Pixel centres at integer coordinates: pixel (x, y) spans [x - 0.5, x + 0.5].
  cv::Rect box(cv::Point(static_cast<int>(std::floor(x0 - pad)), static_cast<int>(std::floor(y0 - pad))),
               cv::Point(static_cast<int>(std::ceil(x1 + pad)) + 1, static_cast<int>(std::ceil(y1 + pad)) + 1));
  layer.box = box & image;
  if (layer.box.empty()) return;
  const int stride = cairo_format_stride_for_width(CAIRO_FORMAT_A8, layer.box.width);
  cv::Mat buffer = scratch().get(slot, cv::Size(stride, layer.box.height), CV_8UC1);
  buffer.setTo(0);
  cairo_surface_t* surface = cairo_image_surface_create_for_data(
      buffer.data, CAIRO_FORMAT_A8, layer.box.width, layer.box.height, stride);
  cairo_t* cr = cairo_create(surface);
  cairo_translate(cr, 0.5 - layer.box.x, 0.5 - layer.box.y);
  const cv::Point2d first = point_at(rod, layer.from);
  cairo_move_to(cr, first.x, first.y);
  // Every third centerline sample (and the last): the chords stray under 0.1 px from the
  // arc at the tightest bends drawn, and Cairo's stroker costs per segment. The shading
  // (shade) measures distances to the same 3 px polyline.
  constexpr int kPathStep = 3;
  for (int i = layer.from + kPathStep; i < layer.to; i += kPathStep) {
    const cv::Point2d p = point_at(rod, i);
    cairo_line_to(cr, p.x, p.y);
  }
  if (layer.to > layer.from) {
    const cv::Point2d last = point_at(rod, layer.to);
    cairo_line_to(cr, last.x, last.y);
  }
  if (layer.whole && rod.closed) cairo_close_path(cr);
  cairo_set_line_width(cr, rod.width);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_antialias(cr, CAIRO_ANTIALIAS_GOOD);
  cairo_stroke(cr);
  cairo_destroy(cr);
  cairo_surface_flush(surface);
  cairo_surface_destroy(surface);
  layer.coverage = buffer(cv::Rect(0, 0, layer.box.width, layer.box.height));
}

struct Light {
  cv::Vec3d l, h;  // light and half vectors, unit, z towards the camera
  double shading, glare;
};

// The colour of a rod's piece at each covered pixel of its box (BGR floats, 0..255; 0
// where the piece does not cover the pixel): a lit cylinder (darker rims, lighter core)
// with a specular streak whose strength varies along the rod. Only the band of pixels the
// piece covers is shaded; `colour` must be CV_32FC3 over layer.box.
void shade(const Layer& layer, const SceneRod& rod, const Light& light, double glare_phase,
           cv::Mat colour) {
  const cv::Rect& box = layer.box;
  cv::Mat dist = scratch().get(kDist, box.size(), CV_32F);
  cv::Mat along = scratch().get(kAlong, box.size(), CV_32FC3);  // (signed offset, normal x, normal y)
  cv::Mat arc = scratch().get(kArc, box.size(), CV_32F);
  dist.setTo(1e9f);
  const double half = rod.width / 2;
  constexpr int kStep = 3;  // distances to a 3 px polyline: well under a pixel of error
  for (int i = layer.from; i < layer.to; i += kStep) {
    const int j = std::min(i + kStep, layer.to);
    const cv::Point2d a = point_at(rod, i), b = point_at(rod, j);
    const cv::Point2d d = b - a;
    const double len2 = d.dot(d);
    if (len2 < 1e-12) continue;
    const double len = std::sqrt(len2);
    const float nx = static_cast<float>(-d.y / len), ny = static_cast<float>(d.x / len);
    const float dx = static_cast<float>(d.x), dy = static_cast<float>(d.y);
    const float inv_len2 = static_cast<float>(1 / len2);
    const int xa = std::max(box.x, static_cast<int>(std::floor(std::min(a.x, b.x) - half - 1)));
    const int xb = std::min(box.x + box.width - 1, static_cast<int>(std::ceil(std::max(a.x, b.x) + half + 1)));
    const int ya = std::max(box.y, static_cast<int>(std::floor(std::min(a.y, b.y) - half - 1)));
    const int yb = std::min(box.y + box.height - 1, static_cast<int>(std::ceil(std::max(a.y, b.y) + half + 1)));
    const float s0 = static_cast<float>(i), ds = static_cast<float>(j - i);
    for (int y = ya; y <= yb; ++y) {
      const uchar* cov = layer.coverage.ptr<uchar>(y - box.y) - box.x;
      float* drow = dist.ptr<float>(y - box.y) - box.x;
      cv::Vec3f* arow = along.ptr<cv::Vec3f>(y - box.y) - box.x;
      float* srow = arc.ptr<float>(y - box.y) - box.x;
      const float py = static_cast<float>(y - a.y);
      for (int x = xa; x <= xb; ++x) {
        if (!cov[x]) continue;  // only covered pixels are shaded
        const float px = static_cast<float>(x - a.x);
        const float t = std::clamp((px * dx + py * dy) * inv_len2, 0.f, 1.f);
        const float qx = px - t * dx, qy = py - t * dy;
        const float dd = qx * qx + qy * qy;
        if (dd < drow[x]) {
          drow[x] = dd;
          arow[x] = cv::Vec3f(px * nx + py * ny, nx, ny);
          srow[x] = s0 + t * ds;
        }
      }
    }
  }
  // The streak's strength along the arc, tabulated per centerline sample (it varies over
  // tens of px) and interpolated linearly.
  const int n_arc = layer.to - layer.from + 2;
  std::vector<float> streak(static_cast<size_t>(n_arc) + 1);
  for (int k = 0; k < n_arc + 1; ++k) {
    const double s = layer.from + k;
    streak[k] = static_cast<float>(std::max(0.0, std::sin(s / 57.0 + glare_phase) * 0.6 + std::sin(s / 23.0 + 2 * glare_phase) * 0.4));
  }
  const float base[3] = {static_cast<float>(rod.color_rgb[2]), static_cast<float>(rod.color_rgb[1]),
                         static_cast<float>(rod.color_rgb[0])};
  const float inv_half = static_cast<float>(1 / half);
  const float lx = static_cast<float>(light.l[0]), ly = static_cast<float>(light.l[1]), lz = static_cast<float>(light.l[2]);
  const float hx = static_cast<float>(light.h[0]), hy = static_cast<float>(light.h[1]), hz = static_cast<float>(light.h[2]);
  const float shading = static_cast<float>(light.shading), glare = static_cast<float>(255 * light.glare);
  for (int y = 0; y < box.height; ++y) {
    const uchar* cov = layer.coverage.ptr<uchar>(y);
    const float* drow = dist.ptr<float>(y);
    const cv::Vec3f* arow = along.ptr<cv::Vec3f>(y);
    const float* srow = arc.ptr<float>(y);
    cv::Vec3f* out = colour.ptr<cv::Vec3f>(y);
    for (int x = 0; x < box.width; ++x) {
      if (!cov[x] || drow[x] > 1e8f) {
        out[x] = cv::Vec3f(0, 0, 0);
        continue;
      }
      const float u = std::clamp(arow[x][0] * inv_half, -1.f, 1.f);
      const float w = std::sqrt(1 - u * u);
      const float n0 = u * arow[x][1], n1 = u * arow[x][2];
      const float diffuse = std::max(0.f, n0 * lx + n1 * ly + w * lz);
      float spec = std::max(0.f, n0 * hx + n1 * hy + w * hz);
      for (int k = 0; k < 5; ++k) spec *= spec;  // ^32: a narrow streak
      const float s = std::clamp(srow[x] - layer.from, 0.f, static_cast<float>(n_arc - 1));
      const int si = static_cast<int>(s);
      const float sf = s - si;
      const float st = streak[si] + sf * (streak[si + 1] - streak[si]);
      const float tone = 1 - shading + shading * (0.45f + 0.75f * diffuse);
      const float g = glare * spec * (0.35f + 0.65f * st);
      for (int k = 0; k < 3; ++k) out[x][k] = std::min(255.f, base[k] * tone + g);
    }
  }
}

struct RodBuffers {
  cv::Rect box;
  cv::Mat coverage;  // CV_8UC1, the whole rod (union of its pieces)
  cv::Mat colour;    // CV_32FC3
  cv::Mat depth;     // CV_32S: index of the topmost layer of this rod at the pixel
};

// Depth of a rod's strand (centerline index i) after the layers so far: the last layer
// of that rod whose range holds i.
int strand_depth(const std::vector<Layer>& layers, int rod, int i, int n) {
  int depth = -1;
  for (size_t k = 0; k < layers.size(); ++k) {
    const Layer& l = layers[k];
    if (l.rod != rod) continue;
    if (l.whole) {
      depth = static_cast<int>(k);
      continue;
    }
    for (int shift : {-n, 0, n}) {
      if (i + shift >= l.from && i + shift <= l.to) depth = static_cast<int>(k);
    }
  }
  return depth;
}

// The pieces to paint, bottom first: whole rods in base order, then one patch per
// crossing whose wanted top strand is not already above (always at a self-crossing).
std::vector<Layer> plan_layers(const Scene& scene) {
  std::vector<Layer> layers;
  for (int r : scene.base_order) {
    Layer l;
    l.rod = r;
    l.from = 0;
    const int n = static_cast<int>(scene.rods[r].centerline.size());
    l.to = n - 1 + (scene.rods[r].closed ? 1 : 0);
    l.whole = true;
    layers.push_back(l);
  }
  for (const CrossingAnnotation& c : scene.crossings) {
    const int top = c.top - 1;
    const bool a_top = c.top_arc_index == c.arc_index_a && c.top == c.rod_a;
    const int other = (a_top ? c.rod_b : c.rod_a) - 1;
    const int top_i = c.top_arc_index;
    const int other_i = a_top ? c.arc_index_b : c.arc_index_a;
    const int n_top = static_cast<int>(scene.rods[top].centerline.size());
    const int n_other = static_cast<int>(scene.rods[other].centerline.size());
    if (top != other &&
        strand_depth(layers, top, top_i, n_top) > strand_depth(layers, other, other_i, n_other)) {
      continue;
    }
    // Long enough to cover the overlap of the two tubes at this angle, plus a margin.
    const double sin_angle = std::max(std::sin(c.angle_deg * M_PI / 180), 0.03);
    const double overlap = 0.5 * (scene.rods[top].width + scene.rods[other].width) / sin_angle;
    const int half = static_cast<int>(std::min(overlap + scene.rods[top].width + 4, 0.45 * n_top));
    Layer l;
    l.rod = top;
    l.from = top_i - half;
    l.to = top_i + half;
    if (!scene.rods[top].closed) {
      l.from = std::max(l.from, 0);
      l.to = std::min(l.to, n_top - 1);
    }
    layers.push_back(l);
  }
  return layers;
}

// Quantiles of the standard normal at (i + 0.5) / 65536, i = 0..65535 (|z| < 4.2), by
// Acklam's rational approximation (relative error < 1.2e-9), computed once.
const std::vector<float>& normal_quantiles() {
  static const std::vector<float> table = [] {
    static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                               1.383577518672690e+02, -3.066479806614716e+01, 2.506628277459239e+00};
    static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                               6.680131188771972e+01, -1.328068155288572e+01};
    static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                               -2.549732539343734e+00, 4.374664141464968e+00, 2.938163982698783e+00};
    static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                               3.754408661907416e+00};
    std::vector<float> t(65536);
    for (int i = 0; i < 65536; ++i) {
      const double p = (i + 0.5) / 65536;
      double z;
      if (p < 0.02425 || p > 1 - 0.02425) {
        const double r = std::sqrt(-2 * std::log(p < 0.5 ? p : 1 - p));
        z = (((((c[0] * r + c[1]) * r + c[2]) * r + c[3]) * r + c[4]) * r + c[5]) /
            ((((d[0] * r + d[1]) * r + d[2]) * r + d[3]) * r + 1);
        if (p > 0.5) z = -z;
      } else {
        const double u = p - 0.5, r = u * u;
        z = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * u /
            (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
      }
      t[i] = static_cast<float>(z);
    }
    return t;
  }();
  return table;
}

void apply_camera(const CameraConfig& camera, Rng& rng, cv::Mat* image) {
  const double exposure = rng.uniform(camera.exposure.lo, camera.exposure.hi);
  const double blur = rng.uniform(camera.blur_sigma.lo, camera.blur_sigma.hi);
  const double noise = rng.uniform(camera.noise_sigma.lo, camera.noise_sigma.hi);
  const std::uint64_t noise_seed = rng.next();
  if (std::abs(exposure - 1) > 1e-6) image->convertTo(*image, CV_8UC3, exposure);
  if (blur > 0.05) cv::GaussianBlur(*image, *image, cv::Size(0, 0), blur);
  if (noise > 0.05) {
    // Gaussian, from the generator's own stream: each 16 bits of it index a table of the
    // standard normal's quantiles, scaled and rounded once per scene, then added in
    // integers. Fast and identical everywhere.
    Rng noise_rng(noise_seed);
    const std::vector<float>& q = normal_quantiles();
    std::vector<std::int16_t> offset(q.size());
    for (size_t i = 0; i < q.size(); ++i) offset[i] = static_cast<std::int16_t>(std::lround(q[i] * noise));
    for (int y = 0; y < image->rows; ++y) {
      uchar* row = image->ptr<uchar>(y);
      const int n = image->cols * image->channels();
      for (int i = 0; i < n; i += 4) {
        const std::uint64_t bits = noise_rng.next();
        const int k_end = std::min(4, n - i);
        for (int k = 0; k < k_end; ++k) {
          row[i + k] = static_cast<uchar>(std::clamp(row[i + k] + offset[(bits >> (16 * k)) & 0xffff], 0, 255));
        }
      }
    }
  }
}

}  // namespace

Result<RenderedScene> render_scene(const Scene& scene, const SynthConfig& config, Rng& rng) {
  const RenderConfig& rc = config.render;
  const cv::Size size(scene.width, scene.height);
  const cv::Rect image_rect(cv::Point(0, 0), size);
  Result<cv::Mat> background = make_background(rc.background, size, rng);
  if (!background) return background.error();
  cv::Mat picture = std::move(background).value();

  // Light from the upper left, a little above the table.
  const double azimuth = rng.uniform(-2.6, -1.9);
  const cv::Vec3d l = cv::normalize(cv::Vec3d(0.55 * std::cos(azimuth), 0.55 * std::sin(azimuth), 1.0));
  const Light light{l, cv::normalize(l + cv::Vec3d(0, 0, 1)), rc.shading, rc.glare};

  std::vector<Layer> layers = plan_layers(scene);
  const int n_rods = static_cast<int>(scene.rods.size());
  std::vector<RodBuffers> rods(n_rods);
  std::vector<double> glare_phase(n_rods);
  for (double& p : glare_phase) p = rng.uniform(0, 2 * M_PI);
  for (size_t k = 0; k < layers.size(); ++k) {
    Layer& layer = layers[k];
    const SceneRod& rod = scene.rods[layer.rod];
    rasterise(layer, rod, image_rect, layer.whole ? rod_slot(layer.rod, 0) : kLayerCoverage0);
    if (layer.box.empty()) continue;
    cv::Mat colour = scratch().get(layer.whole ? rod_slot(layer.rod, 1) : kPatchColour, layer.box.size(), CV_32FC3);
    shade(layer, rod, light, glare_phase[layer.rod], colour);
    RodBuffers& b = rods[layer.rod];
    if (layer.whole) {
      b.box = layer.box;
      b.coverage = layer.coverage;
      b.colour = colour;
      b.depth = scratch().get(rod_slot(layer.rod, 2), layer.box.size(), CV_32S);
      for (int y = 0; y < b.box.height; ++y) {
        const uchar* cov = b.coverage.ptr<uchar>(y);
        int* depth = b.depth.ptr<int>(y);
        for (int x = 0; x < b.box.width; ++x) depth[x] = cov[x] ? static_cast<int>(k) : -1;
      }
      continue;
    }
    // A patch lies inside its rod's box; paint it over the rod's own colour.
    const cv::Rect in_rod = layer.box - b.box.tl();
    for (int y = 0; y < layer.box.height; ++y) {
      const uchar* cov = layer.coverage.ptr<uchar>(y);
      const cv::Vec3f* src = colour.ptr<cv::Vec3f>(y);
      cv::Vec3f* dst = b.colour.ptr<cv::Vec3f>(y + in_rod.y) + in_rod.x;
      int* depth = b.depth.ptr<int>(y + in_rod.y) + in_rod.x;
      for (int x = 0; x < layer.box.width; ++x) {
        if (!cov[x]) continue;
        const float a = cov[x] / 255.f;
        dst[x] = a * src[x] + (1 - a) * dst[x];
        depth[x] = static_cast<int>(k);
      }
    }
  }

  if (rc.shadow > 0) {
    // Soft, so a quarter-resolution mask is enough: max coverage, shifted, blurred.
    constexpr int kScale = 4;
    const cv::Size small((size.width + kScale - 1) / kScale, (size.height + kScale - 1) / kScale);
    cv::Mat mask(small, CV_32F, cv::Scalar(0));
    const cv::Point2d offset(rng.uniform(2, 6), rng.uniform(2, 6));
    for (const RodBuffers& b : rods) {
      if (b.box.empty()) continue;
      for (int y = 0; y < b.box.height; ++y) {
        const uchar* cov = b.coverage.ptr<uchar>(y);
        const int sy = static_cast<int>((y + b.box.y + offset.y) / kScale);
        if (sy >= small.height) break;
        float* row = mask.ptr<float>(sy);
        for (int x = 0; x < b.box.width; ++x) {
          const int sx = static_cast<int>((x + b.box.x + offset.x) / kScale);
          if (sx < small.width) row[sx] = std::max(row[sx], cov[x] / 255.f);
        }
      }
    }
    const double sigma = rng.uniform(2.5, 5) / kScale + 0.5;
    cv::GaussianBlur(mask, mask, cv::Size(0, 0), sigma);
    cv::Mat gain;
    mask.convertTo(gain, CV_8U, -255 * 0.6 * rc.shadow, 255);
    cv::resize(gain, gain, size, 0, 0, cv::INTER_LINEAR);
    // The shadow can only darken near the rods: their boxes, shifted, widened by the blur
    // kernel's reach (OpenCV's kernel is at most 8 sigma + 1 wide) and the upsampling.
    cv::Rect reach;
    const int margin = kScale * (static_cast<int>(std::ceil(4 * sigma)) + 3) + 8;
    for (const RodBuffers& b : rods) {
      if (b.box.empty()) continue;
      const cv::Rect r(b.box.x - margin, b.box.y - margin, b.box.width + 2 * margin, b.box.height + 2 * margin);
      reach = reach.empty() ? r : (reach | r);
    }
    reach &= image_rect;
    for (int y = reach.y; y < reach.y + reach.height; ++y) {
      cv::Vec3b* row = picture.ptr<cv::Vec3b>(y);
      const uchar* g = gain.ptr<uchar>(y);
      for (int x = reach.x; x < reach.x + reach.width; ++x) {
        if (g[x] == 255) continue;
        for (int k = 0; k < 3; ++k) row[x][k] = static_cast<uchar>((row[x][k] * g[x] + 127) / 255);
      }
    }
  }

  RenderedScene out;
  out.labels = cv::Mat(size, CV_16UC1, cv::Scalar(0));
  struct Present {
    int depth, rod;
    float coverage;
  };
  // How many rods cover each pixel: where one does (most pixels), composite at once;
  // where several do, stack them in their local order below.
  cv::Mat count(size, CV_8UC1, cv::Scalar(0));
  std::vector<cv::Point> shared;
  for (const RodBuffers& b : rods) {
    for (int y = 0; !b.box.empty() && y < b.box.height; ++y) {
      const uchar* cov = b.coverage.ptr<uchar>(y);
      uchar* c = count.ptr<uchar>(y + b.box.y) + b.box.x;
      for (int x = 0; x < b.box.width; ++x) {
        if (cov[x] && ++c[x] == 2) shared.emplace_back(x + b.box.x, y + b.box.y);
      }
    }
  }
  auto composite = [&](const Present* present, int n, int x, int y) {
    // Top down: each rod shows through what the ones above leave uncovered.
    float remaining = 1;
    cv::Vec3f sum(0, 0, 0);
    ushort label = 0;
    for (int i = 0; i < n; ++i) {
      const RodBuffers& b = rods[present[i].rod];
      const float visible = present[i].coverage * remaining;
      sum += visible * b.colour.at<cv::Vec3f>(y - b.box.y, x - b.box.x);
      if (255 * visible >= 127.5f) label = static_cast<ushort>(present[i].rod + 1);
      remaining -= visible;
    }
    cv::Vec3b& p = picture.at<cv::Vec3b>(y, x);
    for (int k = 0; k < 3; ++k) p[k] = cv::saturate_cast<uchar>(sum[k] + remaining * p[k]);
    out.labels.at<ushort>(y, x) = label;
  };
  for (int r = 0; r < n_rods; ++r) {
    const RodBuffers& b = rods[r];
    for (int y = 0; !b.box.empty() && y < b.box.height; ++y) {
      const uchar* cov = b.coverage.ptr<uchar>(y);
      const uchar* c = count.ptr<uchar>(y + b.box.y) + b.box.x;
      for (int x = 0; x < b.box.width; ++x) {
        if (!cov[x] || c[x] != 1) continue;
        const Present one{0, r, cov[x] / 255.f};
        composite(&one, 1, x + b.box.x, y + b.box.y);
      }
    }
  }
  for (const cv::Point& p : shared) {
    Present present[12];
    int n = 0;
    for (int r = 0; r < n_rods; ++r) {
      const RodBuffers& b = rods[r];
      if (b.box.empty() || !b.box.contains(p)) continue;
      const uchar c = b.coverage.at<uchar>(p.y - b.box.y, p.x - b.box.x);
      if (c) present[n++] = {b.depth.at<int>(p.y - b.box.y, p.x - b.box.x), r, c / 255.f};
    }
    for (int i = 1; i < n; ++i) {  // insertion sort, topmost first
      for (int j = i; j > 0 && present[j].depth > present[j - 1].depth; --j) std::swap(present[j], present[j - 1]);
    }
    composite(present, n, p.x, p.y);
  }

  for (int r = 0; r < n_rods; ++r) {
    cv::Mat m(size, CV_8UC1, cv::Scalar(0));
    if (!rods[r].box.empty()) {
      cv::Mat roi = m(rods[r].box);
      cv::compare(rods[r].coverage, 128, roi, cv::CMP_GE);
    }
    out.amodal.push_back(m);
  }

  // What the picture shows at each crossing: between two rods, the one whose pieces are
  // on top at the crossing pixel; at a self-crossing, the strand of the last piece.
  out.crossings = scene.crossings;
  for (CrossingAnnotation& c : out.crossings) {
    const int a = c.rod_a - 1, b = c.rod_b - 1;
    if (a == b) {
      const int n = static_cast<int>(scene.rods[a].centerline.size());
      const int da = strand_depth(layers, a, c.arc_index_a, n);
      const int db = strand_depth(layers, a, c.arc_index_b, n);
      c.top = c.rod_a;
      c.top_arc_index = da >= db ? c.arc_index_a : c.arc_index_b;
      continue;
    }
    const cv::Point p(std::clamp(static_cast<int>(std::lround(c.location.x)), 0, size.width - 1),
                      std::clamp(static_cast<int>(std::lround(c.location.y)), 0, size.height - 1));
    auto depth_at = [&](int r) {
      const RodBuffers& rb = rods[r];
      if (rb.box.empty() || !rb.box.contains(p)) return -1;
      return rb.depth.at<int>(p.y - rb.box.y, p.x - rb.box.x);
    };
    const bool a_top = depth_at(a) > depth_at(b);
    c.top = a_top ? c.rod_a : c.rod_b;
    c.top_arc_index = a_top ? c.arc_index_a : c.arc_index_b;
  }

  apply_camera(config.camera, rng, &picture);
  out.image = picture;
  return out;
}

}  // namespace mbest::synth

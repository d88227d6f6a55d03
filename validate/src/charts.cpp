#include "charts.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <cairo.h>

// Cairo's text loads fontconfig, which leaks a few hundred bytes once per process (inside
// libfontconfig, unreachable from us). Under LeakSanitizer (MBEST_SANITIZE) this hook keeps that
// third-party leak from failing every program that draws a chart; it has no effect otherwise.
extern "C" const char* __lsan_default_suppressions() { return "leak:libfontconfig.so\n"; }

namespace mbest::validate {

namespace {

constexpr int kWidth = 640, kHeight = 340;
constexpr double kLeft = 56, kRight = 16, kTop = 44, kBottom = 64;

struct Rgb {
  double r, g, b;
};
const Rgb kSeriesColours[] = {{0.20, 0.45, 0.75}, {0.90, 0.50, 0.15}, {0.30, 0.65, 0.35}};

cairo_status_t append_bytes(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

void text(cairo_t* cr, const std::string& s, double x, double y, double size, double align_x,
          bool bold = false) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  cairo_move_to(cr, x - align_x * e.x_advance, y);
  cairo_show_text(cr, s.c_str());
}

std::string format(const char* fmt, double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

}  // namespace

std::string bar_chart_png(const std::string& title, const std::string& x_title,
                          const std::vector<std::string>& categories,
                          const std::vector<ChartSeries>& series) {
  double lowest = 100;
  for (const ChartSeries& s : series)
    for (double v : s.percent)
      if (!std::isnan(v)) lowest = std::min(lowest, v);
  const double y0 = std::max(0.0, std::floor((lowest - 2) / 5) * 5);
  const double step = 100 - y0 > 50 ? 20 : (100 - y0 > 20 ? 5 : (100 - y0 > 10 ? 2 : 1));

  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, kWidth, kHeight);
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);

  const double plot_w = kWidth - kLeft - kRight, plot_h = kHeight - kTop - kBottom;
  const auto y_of = [&](double v) { return kTop + plot_h * (1 - (v - y0) / (100 - y0)); };
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  text(cr, title, kWidth / 2.0, 22, 15, 0.5, true);
  // Grid and y ticks.
  cairo_set_line_width(cr, 1);
  for (double v = y0; v <= 100 + 1e-9; v += step) {
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, kLeft, std::round(y_of(v)) + 0.5);
    cairo_line_to(cr, kLeft + plot_w, std::round(y_of(v)) + 0.5);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
    text(cr, format("%.0f %%", v), kLeft - 6, y_of(v) + 4, 11, 1);
  }
  cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
  text(cr, x_title, kLeft + plot_w / 2, kHeight - 10, 12, 0.5);

  const double group_w = plot_w / std::max<size_t>(1, categories.size());
  const double bar_w = std::min(60.0, 0.8 * group_w / std::max<size_t>(1, series.size()));
  for (size_t c = 0; c < categories.size(); ++c) {
    const double group_x = kLeft + group_w * c;
    const double bars_x = group_x + (group_w - bar_w * series.size()) / 2;
    cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
    text(cr, categories[c], group_x + group_w / 2, kTop + plot_h + 16, 12, 0.5);
    std::string counts;
    for (size_t s = 0; s < series.size(); ++s) {
      const ChartSeries& ser = series[s];
      const double v = c < ser.percent.size() ? ser.percent[c] : NAN;
      const int n = c < ser.counts.size() ? ser.counts[c] : 0;
      counts += (s == 0 ? "n=" : "/") + std::to_string(n);
      const double x = bars_x + bar_w * s;
      if (std::isnan(v)) {
        cairo_set_source_rgb(cr, 0.55, 0.55, 0.55);
        text(cr, "-", x + bar_w / 2, kTop + plot_h - 4, 11, 0.5);
        continue;
      }
      const Rgb& col = kSeriesColours[s % 3];
      cairo_set_source_rgb(cr, col.r, col.g, col.b);
      cairo_rectangle(cr, x + 1, y_of(v), bar_w - 2, kTop + plot_h - y_of(v));
      cairo_fill(cr);
      cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
      text(cr, format(100 - y0 <= 10 ? "%.2f" : "%.1f", v), x + bar_w / 2, y_of(v) - 3, 10, 0.5);
    }
    // One count when every series has the same, else one per series: "n=8/6".
    bool same = true;
    for (const ChartSeries& ser : series)
      same = same && c < ser.counts.size() && ser.counts[c] == series[0].counts[c];
    if (same && !series.empty()) counts = "n=" + std::to_string(series[0].counts[c]);
    cairo_set_source_rgb(cr, 0.45, 0.45, 0.45);
    text(cr, counts, group_x + group_w / 2, kTop + plot_h + 30, 10, 0.5);
  }
  // Axes and legend.
  cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
  cairo_move_to(cr, kLeft + 0.5, kTop);
  cairo_line_to(cr, kLeft + 0.5, kTop + plot_h + 0.5);
  cairo_line_to(cr, kLeft + plot_w, kTop + plot_h + 0.5);
  cairo_stroke(cr);
  double lx = kWidth - kRight;
  for (size_t s = series.size(); s-- > 0;) {
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 11);
    cairo_text_extents_t e;
    cairo_text_extents(cr, series[s].name.c_str(), &e);
    lx -= e.x_advance;
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    text(cr, series[s].name, lx, kTop - 8, 11, 0);
    const Rgb& col = kSeriesColours[s % 3];
    cairo_set_source_rgb(cr, col.r, col.g, col.b);
    cairo_rectangle(cr, lx - 14, kTop - 17, 10, 10);
    cairo_fill(cr);
    lx -= 26;
  }

  cairo_destroy(cr);
  std::string png;
  cairo_surface_write_to_png_stream(surface, append_bytes, &png);
  cairo_surface_destroy(surface);
  return png;
}

std::string base64(const std::string& bytes) {
  static const char* kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < bytes.size()) {
    unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

}  // namespace mbest::validate

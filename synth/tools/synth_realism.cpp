// Semantic DICE of the built-in colour filter (mbest::colour_filter) against ground truth,
// for scripts/synth-realism.sh. Usage: synth_realism IMAGES_DIR LABELS_DIR
// Pairs IMAGES_DIR/<stem>.{png,jpg} with LABELS_DIR/<stem>.png (non-zero = DLO) and prints
// one line: "<images> <mean per-image DICE %> <pooled DICE %> <mean per-image DICE % with
// the pixels within 1 px of the ground truth's boundary left out>". The last figure tells a
// disagreement about where the tubes' edges lie (exact half coverage in synthetic labels,
// the labelling tool's threshold in real ones) from a disagreement about the tubes.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "mbest/core/segmentation.h"

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  if (argc != 3) {
    std::fprintf(stderr, "usage: synth_realism IMAGES_DIR LABELS_DIR\n");
    return 1;
  }
  std::vector<fs::path> images;
  for (const auto& e : fs::directory_iterator(argv[1])) {
    const std::string ext = e.path().extension().string();
    if (ext == ".png" || ext == ".jpg") images.push_back(e.path());
  }
  std::sort(images.begin(), images.end());
  double sum_dice = 0, sum_inner = 0;
  long long inter = 0, total = 0;
  int n = 0;
  for (const fs::path& image : images) {
    const fs::path label = fs::path(argv[2]) / (image.stem().string() + ".png");
    auto bgr = mbest::read_image(image.string());
    if (!bgr) {
      std::fprintf(stderr, "%s\n", bgr.error().message.c_str());
      return 1;
    }
    auto truth = mbest::read_mask(label.string(), bgr.value().size());
    if (!truth) {
      std::fprintf(stderr, "%s\n", truth.error().message.c_str());
      return 1;
    }
    auto pred = mbest::colour_filter(bgr.value());
    if (!pred) {
      std::fprintf(stderr, "%s: %s\n", image.c_str(), pred.error().message.c_str());
      return 1;
    }
    const long long a = cv::countNonZero(pred.value()), b = cv::countNonZero(truth.value());
    const long long both = cv::countNonZero(pred.value() & truth.value());
    sum_dice += a + b > 0 ? 2.0 * both / (a + b) : 1.0;
    cv::Mat grown, shrunk;
    const cv::Mat k = cv::Mat::ones(3, 3, CV_8UC1);
    cv::dilate(truth.value(), grown, k);
    cv::erode(truth.value(), shrunk, k);
    const cv::Mat keep = ~(grown & ~shrunk);
    const long long ia = cv::countNonZero(pred.value() & keep), ib = cv::countNonZero(truth.value() & keep);
    const long long iboth = cv::countNonZero(pred.value() & truth.value() & keep);
    sum_inner += ia + ib > 0 ? 2.0 * iboth / (ia + ib) : 1.0;
    inter += both;
    total += a + b;
    ++n;
  }
  if (n == 0) {
    std::fprintf(stderr, "no images in %s\n", argv[1]);
    return 1;
  }
  std::printf("%d %.2f %.2f %.2f\n", n, 100 * sum_dice / n, total > 0 ? 200.0 * inter / total : 100.0,
              100 * sum_inner / n);
  return 0;
}

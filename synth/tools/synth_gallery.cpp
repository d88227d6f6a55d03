// synth_gallery OUT.png TILE_WIDTH DIR... : one row per generated split folder DIR (a
// preset), each scene as its picture beside its colour-coded label image, scaled to
// TILE_WIDTH px wide. Used by scripts/synth-gallery.sh.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace fs = std::filesystem;

cv::Mat colour_labels(const cv::Mat& labels) {
  static const cv::Vec3b kColours[] = {{0, 0, 0},       {60, 60, 230},  {80, 200, 80},  {230, 120, 40},
                                       {40, 200, 230},  {200, 70, 200}, {230, 230, 60}, {120, 120, 255},
                                       {255, 160, 160}, {90, 160, 255}, {160, 255, 160}, {200, 200, 200}, {100, 40, 160}};
  cv::Mat out(labels.size(), CV_8UC3);
  for (int y = 0; y < labels.rows; ++y)
    for (int x = 0; x < labels.cols; ++x) out.at<cv::Vec3b>(y, x) = kColours[labels.at<ushort>(y, x) % 13];
  return out;
}

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: synth_gallery OUT.png TILE_WIDTH SPLIT_DIR...\n");
    return 2;
  }
  const int tile = std::stoi(argv[2]);
  std::vector<cv::Mat> rows;
  for (int a = 3; a < argc; ++a) {
    std::vector<fs::path> images;
    for (const auto& e : fs::directory_iterator(fs::path(argv[a]) / "images")) {
      if (e.path().filename().string()[0] != '.') images.push_back(e.path());
    }
    std::sort(images.begin(), images.end());
    std::vector<cv::Mat> tiles;
    for (const fs::path& image : images) {
      const cv::Mat picture = cv::imread(image.string(), cv::IMREAD_COLOR);
      const fs::path label_file = fs::path(argv[a]) / "labels" / (image.stem().string() + ".png");
      const cv::Mat labels = cv::imread(label_file.string(), cv::IMREAD_UNCHANGED);
      if (picture.empty() || labels.type() != CV_16UC1) {
        std::fprintf(stderr, "synth_gallery: cannot read %s or its labels\n", image.c_str());
        return 1;
      }
      const cv::Size size(tile, tile * picture.rows / picture.cols);
      cv::Mat p, l;
      cv::resize(picture, p, size, 0, 0, cv::INTER_AREA);
      cv::resize(colour_labels(labels), l, size, 0, 0, cv::INTER_NEAREST);
      tiles.push_back(p);
      tiles.push_back(l);
    }
    cv::Mat row;
    cv::hconcat(tiles, row);
    rows.push_back(row);
  }
  cv::Mat gallery;
  cv::vconcat(rows, gallery);
  if (!cv::imwrite(argv[1], gallery, {cv::IMWRITE_PNG_COMPRESSION, 9})) {
    std::fprintf(stderr, "synth_gallery: cannot write %s\n", argv[1]);
    return 1;
  }
  return 0;
}

#include "mbest/core/skeleton.h"

#include <bitset>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "mbest/core/keypoints.h"
#include "scenes.h"

namespace mbest {
namespace {

int neighbours(const Skeleton& s, cv::Point p) {
  return static_cast<int>(std::bitset<8>(neighbour_code(s.image.ptr<uint8_t>(p.y) + p.x, s.image.step)).count());
}

TEST(Skeleton, StraightRodBecomesOneThinLineInsideTheMask) {
  cv::Mat mask = cv::Mat::zeros(100, 200, CV_8UC1);
  test::draw_rod(mask, {{30, 50}, {170, 50}}, 15);
  const Skeleton s = skeletonize(mask);
  ASSERT_GT(s.pixels.size(), 100u);
  int ends = 0;
  for (const cv::Point& p : s.pixels) {
    EXPECT_TRUE(mask.at<uint8_t>(p)) << p;
    const int n = neighbours(s, p);
    EXPECT_LE(n, 2) << "line pixel with " << n << " neighbours at " << p;
    ends += n == 1;
  }
  EXPECT_EQ(ends, 2);
}

TEST(Skeleton, DiagonalRodHasNoStaircaseJunctions) {
  cv::Mat mask = cv::Mat::zeros(200, 200, CV_8UC1);
  test::draw_rod(mask, {{20, 30}, {180, 170}}, 11);
  const Skeleton s = skeletonize(mask);
  const Keypoints kp = detect_keypoints(s);
  EXPECT_TRUE(kp.junction_pixels.empty()) << kp.junction_pixels.size() << " junction pixels";
  EXPECT_EQ(kp.ends.size(), 2u);
}

TEST(Skeleton, AnnulusKeepsItsHole) {
  cv::Mat mask = cv::Mat::zeros(200, 200, CV_8UC1);
  cv::circle(mask, {100, 100}, 67, 255, -1);  // a thick cv::circle has pinholes: cut the hole
  cv::circle(mask, {100, 100}, 53, 0, -1);
  const Skeleton s = skeletonize(mask);
  const Keypoints kp = detect_keypoints(s);
  EXPECT_TRUE(kp.ends.empty());
  EXPECT_TRUE(kp.junction_pixels.empty());
  EXPECT_GT(s.pixels.size(), 300u);  // about 2 pi 60
}

TEST(Skeleton, SkeletonPixelsAreSortedAndMarkedInTheImage) {
  cv::Mat mask = cv::Mat::zeros(60, 60, CV_8UC1);
  cv::rectangle(mask, {5, 5}, {50, 20}, 255, -1);
  const Skeleton s = skeletonize(mask);
  EXPECT_EQ(static_cast<int>(s.pixels.size()), cv::countNonZero(s.image));
  for (size_t i = 1; i < s.pixels.size(); ++i)
    EXPECT_TRUE(s.pixels[i - 1].y < s.pixels[i].y ||
                (s.pixels[i - 1].y == s.pixels[i].y && s.pixels[i - 1].x < s.pixels[i].x));
}

TEST(Skeleton, EmptyFullAndTinyMasks) {
  EXPECT_TRUE(skeletonize(cv::Mat::zeros(30, 40, CV_8UC1)).pixels.empty());
  const Skeleton full = skeletonize(cv::Mat(30, 40, CV_8UC1, cv::Scalar(255)));
  EXPECT_FALSE(full.pixels.empty());
  EXPECT_EQ(skeletonize(cv::Mat(1, 1, CV_8UC1, cv::Scalar(1))).pixels.size(), 1u);
  EXPECT_EQ(skeletonize(cv::Mat(1, 50, CV_8UC1, cv::Scalar(1))).pixels.size(), 50u);
}

// The thinning written plainly, pixel by pixel, as skeleton.h states it: Zhang-Suen
// sub-iterations judged on the image before each (with Lu and Wang's B >= 3), then staircase
// corners removed in raster order. The fast version packs 64 pixels into a word and tiles
// the image; this is what it must equal.
cv::Mat plain_thinning(const cv::Mat& mask) {
  cv::Mat img = cv::Mat::zeros(mask.rows + 2, mask.cols + 2, CV_8UC1);
  img(cv::Rect(1, 1, mask.cols, mask.rows)).setTo(1, mask != 0);
  const auto code = [&](int x, int y) { return neighbour_code(img.ptr<uint8_t>(y) + x, img.step); };
  const auto bit = [](int c, int k) { return (c >> (k % 8)) & 1; };
  for (bool changed = true; changed;) {
    changed = false;
    for (int pass = 0; pass < 2; ++pass) {
      std::vector<cv::Point> go;
      for (int y = 1; y <= mask.rows; ++y)
        for (int x = 1; x <= mask.cols; ++x) {
          if (!img.at<uint8_t>(y, x)) continue;
          const int c = code(x, y);
          int b = 0, a = 0;
          for (int k = 0; k < 8; ++k) b += bit(c, k), a += !bit(c, k) && bit(c, k + 1);
          const int n = bit(c, 0), e = bit(c, 2), s = bit(c, 4), w = bit(c, 6);
          const bool rule = pass == 0 ? !(n && e && s) && !(e && s && w) : !(n && e && w) && !(n && s && w);
          if (b >= 3 && b <= 6 && a == 1 && rule) go.emplace_back(x, y);
        }
      for (const cv::Point& p : go) img.at<uint8_t>(p) = 0;
      changed |= !go.empty();
    }
  }
  for (int y = 1; y <= mask.rows; ++y)
    for (int x = 1; x <= mask.cols; ++x) {
      if (!img.at<uint8_t>(y, x)) continue;
      const int c = code(x, y);
      int b = 0, yokoi = 0;
      for (int k = 0; k < 8; ++k) b += bit(c, k);
      for (int k = 0; k < 8; k += 2) {
        const int xk = !bit(c, k), xk1 = !bit(c, k + 1), xk2 = !bit(c, k + 2);
        yokoi += xk - (xk && xk1 && xk2);
      }
      const int n = bit(c, 0), e = bit(c, 2), s = bit(c, 4), w = bit(c, 6);
      const bool corner = (n && e) || (e && s) || (s && w) || (w && n);
      if (b >= 2 && yokoi == 1 && corner) img.at<uint8_t>(y, x) = 0;
    }
  return img(cv::Rect(1, 1, mask.cols, mask.rows)).clone();
}

TEST(Skeleton, EqualsThePlainThinningOnRandomMasks) {
  cv::RNG rng(20261201);
  for (int k = 0; k < 1000; ++k) {
    const int rows = rng.uniform(1, 60), cols = rng.uniform(1, 80);  // tiles cut anywhere
    cv::Mat mask = cv::Mat::zeros(rows, cols, CV_8UC1);
    if (k % 3 == 0) {
      rng.fill(mask, cv::RNG::UNIFORM, 0, 2);  // noise: every neighbourhood there is
    } else if (k % 3 == 1) {
      for (int i = 0; i < 5; ++i)
        cv::line(mask, {rng.uniform(0, cols), rng.uniform(0, rows)}, {rng.uniform(0, cols), rng.uniform(0, rows)},
                 255, rng.uniform(1, 14));
    } else {
      mask.setTo(255);  // blobs with holes, touching the border
      for (int i = 0; i < 4; ++i) cv::circle(mask, {rng.uniform(0, cols), rng.uniform(0, rows)}, rng.uniform(0, 9), 0, -1);
    }
    const Skeleton s = skeletonize(mask);
    const cv::Mat plain = plain_thinning(mask);
    ASSERT_EQ(cv::countNonZero(s.image != plain), 0) << "mask " << k << ", " << cols << " x " << rows;
    EXPECT_EQ(static_cast<int>(s.pixels.size()), cv::countNonZero(plain));
  }
}

}  // namespace
}  // namespace mbest

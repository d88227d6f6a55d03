#include "mbest/core/instance_mask.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "scenes.h"

namespace mbest {
namespace {

TEST(InstanceMask, EveryReachableMaskPixelGoesToTheNearestCenterline) {
  cv::Mat mask = cv::Mat::zeros(100, 100, CV_8UC1);
  cv::rectangle(mask, {10, 10}, {89, 89}, 255, -1);
  std::vector<Dlo> dlos(2);
  for (int y = 10; y < 90; ++y) {
    dlos[0].centerline.emplace_back(30, y);
    dlos[1].centerline.emplace_back(70, y);
  }
  const cv::Mat labels = instance_labels(mask, dlos, {});
  EXPECT_EQ(labels.type(), CV_16UC1);
  EXPECT_EQ(cv::countNonZero(labels), cv::countNonZero(mask));
  EXPECT_EQ(labels.at<uint16_t>(50, 12), 1);
  EXPECT_EQ(labels.at<uint16_t>(50, 45), 1);
  EXPECT_EQ(labels.at<uint16_t>(50, 55), 2);
  EXPECT_EQ(labels.at<uint16_t>(50, 88), 2);
  EXPECT_EQ(labels.at<uint16_t>(5, 5), 0);
}

TEST(InstanceMask, TopBandBelongsToTheTopStrandButNotItsSurroundings) {
  cv::Mat mask = cv::Mat::zeros(100, 100, CV_8UC1);
  cv::rectangle(mask, {0, 40}, {99, 59}, 255, -1);  // horizontal rod, radius 10
  cv::rectangle(mask, {40, 0}, {59, 99}, 255, -1);  // vertical rod
  std::vector<Dlo> dlos(2);
  for (int x = 0; x < 100; ++x) dlos[0].centerline.emplace_back(x, 50);
  for (int y = 0; y < 100; ++y) dlos[1].centerline.emplace_back(50, y);
  TopStrand top{1, {}, {}};
  for (int y = 30; y < 70; ++y) {
    top.path.emplace_back(50, y);
    top.radius.push_back(9.5f);
  }
  const cv::Mat labels = instance_labels(mask, dlos, {top});
  EXPECT_EQ(labels.at<uint16_t>(50, 50), 2);  // the crossing goes to the top strand
  EXPECT_EQ(labels.at<uint16_t>(45, 41), 2);
  EXPECT_EQ(labels.at<uint16_t>(50, 20), 1);  // the horizontal rod away from the crossing
  EXPECT_EQ(labels.at<uint16_t>(50, 80), 1);
  EXPECT_EQ(cv::countNonZero(labels), cv::countNonZero(mask));
}

TEST(InstanceMask, MaskPartsNoCenterlineReachesStayBackground) {
  cv::Mat mask = cv::Mat::zeros(50, 50, CV_8UC1);
  cv::rectangle(mask, {5, 5}, {20, 20}, 255, -1);
  cv::rectangle(mask, {30, 30}, {45, 45}, 255, -1);
  std::vector<Dlo> dlos(1);
  dlos[0].centerline = {{10, 10}, {11, 11}};
  const cv::Mat labels = instance_labels(mask, dlos, {});
  EXPECT_EQ(labels.at<uint16_t>(20, 20), 1);
  EXPECT_EQ(labels.at<uint16_t>(40, 40), 0);
}

// A 60 x 20 band: red on top (rows 10-19), blue below (rows 20-29), every pixel labelled
// DLO 0 (label 1) as if one drawn path had claimed it all; a white glare spot in the blue.
struct Band {
  cv::Mat mask = cv::Mat::zeros(40, 80, CV_8UC1);
  cv::Mat bgr = cv::Mat::zeros(40, 80, CV_8UC3);
  cv::Mat labels = cv::Mat::zeros(40, 80, CV_16UC1);
  Band() {
    mask(cv::Rect(10, 10, 60, 20)).setTo(255);
    bgr(cv::Rect(10, 10, 60, 10)).setTo(cv::Scalar(40, 40, 200));
    bgr(cv::Rect(10, 20, 60, 10)).setTo(cv::Scalar(200, 90, 30));
    bgr(cv::Rect(30, 22, 4, 4)).setTo(cv::Scalar(255, 255, 255));
    labels.setTo(1, mask);
  }
};

cv::Vec3f lab_of(const cv::Scalar& bgr) {
  cv::Mat pixel(1, 1, CV_8UC3, bgr), lab;
  cv::cvtColor(pixel, lab, cv::COLOR_BGR2Lab);
  const cv::Vec3b v = lab.at<cv::Vec3b>(0, 0);
  return {v[0] * 100.0f / 255, v[1] - 128.0f, v[2] - 128.0f};
}

TEST(InstanceMask, ColourDecidesWhichDloAPixelInACrossingZoneShows) {
  Band b;
  ColourZone z;
  for (int x = 10; x < 50; x += 2) z.discs.push_back({cv::Point(x, 20), 11.0f});  // x < 62
  z.colours = {{0, lab_of({40, 40, 200})}, {1, lab_of({200, 90, 30})}};
  refine_labels_by_colour(b.labels, b.mask, b.bgr, {z}, 10, 30);
  EXPECT_EQ(b.labels.at<uint16_t>(15, 20), 1) << "red stays with DLO 0";
  EXPECT_EQ(b.labels.at<uint16_t>(25, 20), 2) << "blue goes to DLO 1";
  EXPECT_EQ(b.labels.at<uint16_t>(24, 31), 1) << "glare matches neither: unchanged";
  EXPECT_EQ(b.labels.at<uint16_t>(25, 68), 1) << "outside the zone: unchanged";
  EXPECT_EQ(b.labels.at<uint16_t>(5, 20), 0) << "background stays background";
}

TEST(InstanceMask, ColourBeatsTheDrawnLabelEvenBesideANearColour) {
  // A third DLO in the zone is a lighter blue, within the margin of the blue one. Blue
  // pixels drawn as the red DLO still go to the blue one: it is the drawn label that the
  // pixel's colour has to beat. Between the two blues the colour is no evidence, so a blue
  // pixel drawn as the lighter blue keeps its label.
  Band b;
  ColourZone z;
  for (int x = 10; x < 50; x += 2) z.discs.push_back({cv::Point(x, 20), 11.0f});
  const cv::Vec3f blue = lab_of({200, 90, 30});
  z.colours = {{0, lab_of({40, 40, 200})}, {1, blue}, {2, blue + cv::Vec3f(12, 0, 0)}};
  b.labels.at<uint16_t>(27, 40) = 3;
  refine_labels_by_colour(b.labels, b.mask, b.bgr, {z}, 10, 30);
  EXPECT_EQ(b.labels.at<uint16_t>(25, 20), 2) << "blue drawn as red goes to the blue DLO";
  EXPECT_EQ(b.labels.at<uint16_t>(27, 40), 3) << "blue drawn as the lighter blue stays";
  EXPECT_EQ(b.labels.at<uint16_t>(15, 20), 1) << "red stays with DLO 0";
}

// A zone along two strands lying side by side (DLOs 0 and 1) relabels only their pixels:
// the blue pixels drawn as a third DLO (label 3, say a blue rod across the band that the
// zone does not list) keep their label; without the flag they go to the blue DLO.
TEST(InstanceMask, ZoneOfTwoStrandsLeavesAThirdDlosPixelsAlone) {
  ColourZone z;
  for (int x = 10; x < 50; x += 2) z.discs.push_back({cv::Point(x, 20), 11.0f});
  z.colours = {{0, lab_of({40, 40, 200})}, {1, lab_of({200, 90, 30})}};
  for (bool own_only : {true, false}) {
    Band b;
    b.labels(cv::Rect(36, 20, 4, 10)).setTo(3);
    z.own_pixels_only = own_only;
    refine_labels_by_colour(b.labels, b.mask, b.bgr, {z}, 10, 30);
    EXPECT_EQ(b.labels.at<uint16_t>(25, 20), 2) << "blue drawn as red goes to the blue DLO";
    EXPECT_EQ(b.labels.at<uint16_t>(25, 37), own_only ? 3 : 2) << "blue drawn as a third DLO";
  }
}

// The band drawn right (red DLO 0 above, blue DLO 1 below), with blue specks in the red.
struct DrawnBand : Band {
  ColourZone zone;
  DrawnBand() {
    labels(cv::Rect(10, 20, 60, 10)).setTo(2);
    for (int x = 10; x < 50; x += 2) zone.discs.push_back({cv::Point(x, 20), 11.0f});
    zone.colours = {{0, lab_of({40, 40, 200})}, {1, lab_of({200, 90, 30})}};
  }
  void speck(cv::Rect r) { bgr(r).setTo(cv::Scalar(200, 90, 30)); }
};

TEST(InstanceMask, ColourOfAPixelIsReadOverItsNeighbourhood) {
  // One noisy pixel on the red strand's edge, beside the blue strand: its neighbours are
  // red, so it stays red (alone it would go to the blue DLO, whose pixels it touches).
  DrawnBand b;
  b.speck({20, 19, 1, 1});
  refine_labels_by_colour(b.labels, b.mask, b.bgr, {b.zone}, 10, 30);
  EXPECT_EQ(b.labels.at<uint16_t>(19, 20), 1);
  EXPECT_EQ(b.labels.at<uint16_t>(20, 20), 2);
}

TEST(InstanceMask, AFewRelabelledPixelsCutOffFromTheirDloGoBack) {
  DrawnBand b;
  b.speck({20, 11, 3, 3});  // a 3 x 3 blue speck inside the red strand: 5 px after the median
  b.speck({40, 17, 3, 3});  // the same, touching the blue strand
  b.speck({44, 11, 4, 4});  // a 4 x 4 speck inside the red strand: 12 px after the median
  refine_labels_by_colour(b.labels, b.mask, b.bgr, {b.zone}, 10, 30);
  EXPECT_EQ(b.labels.at<uint16_t>(12, 21), 1) << "cut off from the blue DLO and small: back";
  EXPECT_EQ(b.labels.at<uint16_t>(18, 41), 2) << "joined to the blue DLO's pixels: kept";
  EXPECT_EQ(b.labels.at<uint16_t>(12, 45), 2) << "cut off but larger: kept";
  EXPECT_EQ(b.labels.at<uint16_t>(15, 30), 1);
}

TEST(InstanceMask, ColourLeavesLabelsAloneWhenItCannotTellTheDlosApart) {
  ColourZone z;
  for (int x = 10; x < 70; x += 2) z.discs.push_back({cv::Point(x, 20), 11.0f});
  const cv::Vec3f red = lab_of({40, 40, 200}), blue = lab_of({200, 90, 30});
  {  // a DLO paired wrongly through the crossing carries both colours
    Band b;
    const cv::Mat before = b.labels.clone();
    ColourZone both = z;
    both.colours = {{0, red}, {0, blue}, {1, blue}, {1, red}};
    refine_labels_by_colour(b.labels, b.mask, b.bgr, {both}, 10, 30);
    EXPECT_EQ(cv::countNonZero(b.labels != before), 0);
  }
  {  // one DLO only, or the refinement off
    Band b;
    const cv::Mat before = b.labels.clone();
    ColourZone one = z;
    one.colours = {{0, red}, {0, blue}};
    refine_labels_by_colour(b.labels, b.mask, b.bgr, {one}, 10, 30);
    z.colours = {{0, red}, {1, blue}};
    refine_labels_by_colour(b.labels, b.mask, b.bgr, {z}, 0, 30);
    refine_labels_by_colour(b.labels, b.mask, cv::Mat(), {z}, 10, 30);
    EXPECT_EQ(cv::countNonZero(b.labels != before), 0);
  }
}

}  // namespace
}  // namespace mbest

// Segmentation: the pluggable first step of mBEST. Colour image in, binary mask out.
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include "mbest/core/result.h"

namespace mbest {

// HSV colour filter tuned for coloured DLOs on a dark background (the mbest-real set).
// bgr: CV_8UC3. Returns CV_8UC1, 255 = DLO, 0 = background.
Result<cv::Mat> colour_filter(const cv::Mat& bgr);

// Reads a mask file (any 8- or 16-bit, 1- to 4-channel image; non-zero = DLO) and checks it
// is `expected` in size when `expected` is not empty. Returns CV_8UC1 0/255.
Result<cv::Mat> read_mask(const std::string& path, cv::Size expected = cv::Size());

// The mask kept beside an image in a sibling folder: for a/images/x.jpg and `folder`
// "semantic", a/semantic/x.png (the layout `mbest synth` writes).
std::string sibling_mask_path(const std::string& image_path, const std::string& folder);

// Reads a colour image (CV_8UC3). Errors name the file.
Result<cv::Mat> read_image(const std::string& path);

}  // namespace mbest

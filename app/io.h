// File helpers of the mbest executable: outputs are written to a temporary name in the
// same folder and renamed, so an interrupted run never leaves a half-written file.
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include "mbest/core/result.h"

namespace mbest::app {

// Writes `image` to `path` (format from the extension) through a temporary file.
Status write_image_atomic(const std::string& path, const cv::Mat& image);

// Writes `text` to `path` through a temporary file.
Status write_text_atomic(const std::string& path, const std::string& text);

// Creates `dir` and its parents; the error names the folder.
Status make_dirs(const std::string& dir);

}  // namespace mbest::app

// Output files are written to a temporary name beside the target and renamed into place,
// so an interrupted or failed write never leaves a half-written file under the real name.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mbest/core/result.h"

namespace mbest {

// The temporary name used for `path`: hidden, in the same folder (a rename within one
// file system is atomic) and keeping the extension so tools that go by the name still see
// the file's type, e.g. "out/a.png" -> "out/.a.tmp.png".
// It is the same on every run, so a resumed run overwrites what an interrupted one left.
std::string temporary_path_for(const std::string& path);

// Writes `bytes` to `path` through its temporary name, replacing any existing file. On
// failure the temporary file is removed and the error names `path` and the reason.
Status write_file_atomically(const std::string& path, const std::string& bytes);
Status write_file_atomically(const std::string& path, const std::vector<uchar>& bytes);

// Encodes `image` in the format of `path`'s extension (cv::imencode `params`) and writes
// it like write_file_atomically.
Status write_image_atomically(const std::string& path, const cv::Mat& image,
                              const std::vector<int>& params = {});

}  // namespace mbest

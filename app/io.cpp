#include "io.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <system_error>

#include <unistd.h>

#include <opencv2/imgcodecs.hpp>

namespace mbest::app {
namespace fs = std::filesystem;
namespace {

// A sibling of `path` that keeps its extension (the image codec is chosen by it).
std::string temp_name(const std::string& path) {
  const fs::path p(path);
  return (p.parent_path() / ("." + p.stem().string() + ".tmp" + std::to_string(::getpid()) +
                             p.extension().string())).string();
}

Status commit(const std::string& tmp, const std::string& path) {
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    return Error{path + ": cannot write (" + ec.message() + ")"};
  }
  return ok_status();
}

}  // namespace

Status write_image_atomic(const std::string& path, const cv::Mat& image) {
  const std::string tmp = temp_name(path);
  bool ok = false;
  try {
    ok = cv::imwrite(tmp, image);
  } catch (const cv::Exception& e) {
    ok = false;
  }
  if (!ok) {
    std::error_code ec;
    fs::remove(tmp, ec);
    return Error{path + ": cannot write the image (folder not writable or disk full?)"};
  }
  return commit(tmp, path);
}

Status write_text_atomic(const std::string& path, const std::string& text) {
  const std::string tmp = temp_name(path);
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) return Error{path + ": cannot write (folder not writable?)"};
    out << text;
    out.flush();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      return Error{path + ": write failed (disk full?)"};
    }
  }
  return commit(tmp, path);
}

Status make_dirs(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return Error{dir + ": cannot create the folder (" + ec.message() + ")"};
  return ok_status();
}

}  // namespace mbest::app

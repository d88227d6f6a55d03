#include "mbest/core/atomic_file.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include <opencv2/imgcodecs.hpp>

namespace mbest {
namespace {

namespace fs = std::filesystem;

Status write_through_temporary(const std::string& path, const char* data, size_t size) {
  const std::string tmp = temporary_path_for(path);
  std::error_code ignored;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return Error{path + ": cannot write (" + std::strerror(errno) + ")"};
    out.write(data, static_cast<std::streamsize>(size));
    out.close();
    if (!out) {
      const int err = errno;  // before remove() can change it
      fs::remove(tmp, ignored);
      return Error{path + ": cannot write (" + std::strerror(err) + ")"};
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ignored);
    return Error{path + ": cannot write (" + ec.message() + ")"};
  }
  return ok_status();
}

}  // namespace

std::string temporary_path_for(const std::string& path) {
  const fs::path p(path);
  return (p.parent_path() / ("." + p.stem().string() + ".tmp" + p.extension().string())).string();
}

Status write_file_atomically(const std::string& path, const std::string& bytes) {
  return write_through_temporary(path, bytes.data(), bytes.size());
}

Status write_file_atomically(const std::string& path, const std::vector<uchar>& bytes) {
  return write_through_temporary(path, reinterpret_cast<const char*>(bytes.data()), bytes.size());
}

Status write_image_atomically(const std::string& path, const cv::Mat& image, const std::vector<int>& params) {
  const std::string ext = fs::path(path).extension().string();
  std::vector<uchar> bytes;
  bool encoded = false;
  try {
    encoded = !image.empty() && cv::imencode(ext, image, bytes, params);
  } catch (const cv::Exception& e) {  // e.g. an extension no codec knows
    return Error{path + ": cannot encode the image as '" + ext + "' (" + e.err + ")"};
  }
  if (!encoded) return Error{path + ": cannot encode the image as '" + ext + "'"};
  return write_file_atomically(path, bytes);
}

}  // namespace mbest

#include "io.h"

#include <filesystem>
#include <system_error>

namespace mbest::app {

Status make_dirs(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Error{dir + ": cannot create the folder (" + ec.message() + ")"};
  return ok_status();
}

}  // namespace mbest::app

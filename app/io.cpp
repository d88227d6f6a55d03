#include "io.h"

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

namespace mbest::app {
namespace {

std::atomic<bool> g_interrupted{false};
extern "C" void on_interrupt(int) { g_interrupted = true; }

}  // namespace

const std::atomic<bool>& catch_interrupts() {
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  return g_interrupted;
}

Result<JsonOption> json_option(const std::string& option, const std::string& value) {
  const size_t first = value.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && value[first] == '{') return JsonOption{value, option};
  std::error_code ec;
  if (std::filesystem::is_directory(value, ec))
    return Error{option + " " + value + ": is a folder, not a JSON file"};
  std::ifstream in(value);
  if (!in)
    return Error{option + " " + value + ": cannot read the file (give a JSON file, or an "
                 "inline JSON object: text starting with '{')"};
  std::stringstream text;
  text << in.rdbuf();
  return JsonOption{text.str(), value};
}

Status make_dirs(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Error{dir + ": cannot create the folder (" + ec.message() + ")"};
  return ok_status();
}

}  // namespace mbest::app

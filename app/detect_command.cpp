// mbest detect: runs the detector on an image or a data set folder and writes, per image,
// an instance label PNG, a JSON of centerlines and crossings, and optionally an overlay.
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "io.h"
#include "mbest/core/atomic_file.h"
#include "mbest/core/detector.h"
#include "mbest/core/median.h"
#include "mbest/core/overlay.h"
#include "mbest/core/segmentation.h"

namespace mbest::app {
namespace fs = std::filesystem;
namespace {

bool is_image(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  return ext == ".jpg" || ext == ".jpeg" || ext == ".png";
}

struct Input {
  fs::path path;      // the image
  fs::path relative;  // its path relative to INPUT (the file name for a single image)
};

// Every image under a folder whose parent folder is named `images`, or, where there is none,
// every image directly in the folder; sorted for a stable order.
Result<std::vector<Input>> list_inputs(const fs::path& input) {
  std::error_code ec;
  if (!fs::exists(input, ec)) return Error{input.string() + ": no such file or folder"};
  if (!fs::is_directory(input, ec)) {
    if (!is_image(input)) return Error{input.string() + ": not a .jpg, .jpeg or .png image"};
    return std::vector<Input>{{input, input.filename()}};
  }
  std::vector<Input> out;
  for (auto it = fs::recursive_directory_iterator(input, fs::directory_options::skip_permission_denied, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
    if (it->is_regular_file() && is_image(it->path()) && it->path().parent_path().filename() == "images")
      out.push_back({it->path(), fs::relative(it->path(), input)});
  if (ec) return Error{input.string() + ": cannot list the folder (" + ec.message() + ")"};
  if (out.empty())
    for (const auto& e : fs::directory_iterator(input, ec))
      if (e.is_regular_file() && is_image(e.path())) out.push_back({e.path(), e.path().filename()});
  if (out.empty()) return Error{input.string() + ": no .jpg, .jpeg or .png images found"};
  std::sort(out.begin(), out.end(), [](const Input& a, const Input& b) { return a.relative < b.relative; });
  return out;
}

nlohmann::json detection_json(const Detection& det, const std::string& image, cv::Size size) {
  nlohmann::json j;
  j["image"] = image;
  j["width"] = size.width;
  j["height"] = size.height;
  j["dlos"] = nlohmann::json::array();
  for (size_t i = 0; i < det.dlos.size(); ++i) {
    const Dlo& d = det.dlos[i];
    nlohmann::json cl = nlohmann::json::array(), rad = nlohmann::json::array();
    for (const cv::Point& p : d.centerline) cl.push_back({p.x, p.y});
    for (float r : d.radius) rad.push_back(std::round(r * 100) / 100);
    j["dlos"].push_back({{"id", i + 1}, {"closed", d.closed}, {"centerline", cl},
                         {"radius", rad}, {"crossings", d.crossings}});
  }
  j["crossings"] = nlohmann::json::array();
  for (const Crossing& c : det.crossings) {
    std::vector<int> ids;
    for (int d : c.dlos) ids.push_back(d + 1);
    j["crossings"].push_back({{"location", {c.location.x, c.location.y}},
                              {"angle_deg", std::round(c.angle_deg * 10) / 10},
                              {"dlos_top_first", ids}});
  }
  nlohmann::json t;
  for (const StageTime& s : det.timings) t[s.stage] = s.ms;
  j["stages_ms"] = t;
  j["total_ms"] = det.total_ms();
  return j;
}


struct Options {
  std::string input, mask, mask_sibling, config, out = "mbest-out", timings;
  DetectorConfig detector;
  bool overlay = false, quiet = false;
};

// Detects one image and writes its outputs; returns its timing record.
Result<nlohmann::json> process(const Input& in, const Options& o, bool mask_is_folder) {
  Result<cv::Mat> image = read_image(in.path.string());
  if (!image) return image.error();
  cv::Mat mask;
  if (!o.mask_sibling.empty()) {
    Result<cv::Mat> m = read_mask(sibling_mask_path(in.path.string(), o.mask_sibling), image.value().size());
    if (!m) return m.error();
    mask = std::move(m).value();
  } else if (o.mask.empty()) {
    Result<cv::Mat> m = colour_filter(image.value());
    if (!m) return m.error();
    mask = std::move(m).value();
  } else {
    fs::path mp = mask_is_folder ? fs::path(o.mask) / in.relative : fs::path(o.mask);
    if (mask_is_folder) mp.replace_extension(".png");
    Result<cv::Mat> m = read_mask(mp.string(), image.value().size());
    if (!m) return m.error();
    mask = std::move(m).value();
  }
  // A mask that covers every pixel is a segmentation gone wrong: no DLO can be told from
  // it, and an empty result would read as a frame without DLOs. An empty mask is such a
  // frame: its outputs are written, with a note.
  const int foreground = cv::countNonZero(mask);
  if (foreground == static_cast<int>(mask.total()))
    return Error{in.path.string() + ": the mask covers every pixel (" + std::to_string(mask.cols) + "x" +
                 std::to_string(mask.rows) + "): no DLO can be told from it; check the segmentation"};
  Result<Detection> det = detect(mask, image.value(), o.detector);
  if (!det) return Error{in.path.string() + ": " + det.error().message};

  fs::path base = fs::path(o.out) / in.relative;
  if (Status s = make_dirs(base.parent_path().string()); !s) return s.error();
  const std::string stem = (base.parent_path() / base.stem()).string();
  cv::Mat labels = det.value().labels;
  if (Status s = write_image_atomically(stem + ".labels.png", labels); !s) return s.error();
  const nlohmann::json j = detection_json(det.value(), in.relative.string(), mask.size());
  if (Status s = write_file_atomically(stem + ".json", j.dump()); !s) return s.error();
  if (o.overlay)
    if (Status s = write_image_atomically(stem + ".overlay.png", draw_overlay(image.value(), det.value())); !s)
      return s.error();
  nlohmann::json record{{"path", in.relative.string()}, {"total_ms", j["total_ms"]}, {"stages_ms", j["stages_ms"]},
                        {"dlos", det.value().dlos.size()}};
  if (foreground == 0) record["note"] = in.path.string() + ": the mask is empty: no DLO (outputs written)";
  return record;
}

int run(Options o) {
  if (!o.config.empty()) {
    Result<JsonOption> given = json_option("--config", o.config);
    if (!given) {
      std::cerr << "mbest detect: " << given.error().message << "\n";
      return 2;
    }
    Result<DetectorConfig> c = parse_detector_config(given.value().text);
    if (!c) {
      std::cerr << "mbest detect: --config " << o.config << ": " << c.error().message << "\n";
      return 2;
    }
    o.detector = c.value();
  }
  Result<std::vector<Input>> inputs = list_inputs(o.input);
  if (!inputs) {
    std::cerr << "mbest detect: " << inputs.error().message << "\n";
    return 2;
  }
  std::error_code ec;
  const bool mask_is_folder = !o.mask.empty() && fs::is_directory(o.mask, ec);
  if (!o.mask.empty() && !fs::exists(o.mask, ec)) {
    std::cerr << "mbest detect: --mask " << o.mask << ": no such file or folder\n";
    return 2;
  }
  if (!o.mask.empty() && !mask_is_folder && inputs.value().size() > 1) {
    std::cerr << "mbest detect: --mask must be a folder when INPUT is a folder\n";
    return 2;
  }
  // The timings file is written after the batch: a path that cannot take it is an argument
  // error found now, not after hours of detection.
  if (!o.timings.empty()) {
    const fs::path parent = fs::path(o.timings).parent_path();
    const std::string folder = parent.empty() ? "." : parent.string();
    if (fs::is_directory(o.timings, ec)) {
      std::cerr << "mbest detect: --timings " << o.timings << ": is a folder, not a file name\n";
      return 2;
    }
    if (Status s = make_dirs(folder); !s) {
      std::cerr << "mbest detect: --timings: " << s.error().message << "\n";
      return 2;
    }
    if (::access(folder.c_str(), W_OK) != 0) {
      std::cerr << "mbest detect: --timings " << o.timings << ": cannot write in " << folder << " ("
                << std::strerror(errno) << ")\n";
      return 2;
    }
  }
  if (Status s = make_dirs(o.out); !s) {
    std::cerr << "mbest detect: " << s.error().message << "\n";
    return 2;
  }
  const std::atomic<bool>& interrupted = catch_interrupts();

  const auto& list = inputs.value();
  const bool progress = list.size() > 1 && !o.quiet;
  const bool tty = ::isatty(STDERR_FILENO);  // redraw one line, or log every tenth
  nlohmann::json records = nlohmann::json::array();
  int failed = 0;
  for (size_t i = 0; i < list.size() && !interrupted; ++i) {
    Result<nlohmann::json> r = process(list[i], o, mask_is_folder);
    if (!r) {
      ++failed;
      std::cerr << (progress && tty ? "\n" : "") << "mbest detect: " << r.error().message << "\n";
    } else {
      nlohmann::json record = std::move(r).value();
      if (record.contains("note")) {
        std::cerr << (progress && tty ? "\n" : "") << "mbest detect: note: " << record["note"].get<std::string>() << "\n";
        record.erase("note");
      }
      records.push_back(std::move(record));
    }
    const bool log_line = (i + 1) % std::max<size_t>(1, list.size() / 10) == 0 || i + 1 == list.size();
    if (progress && (tty || log_line))
      std::cerr << (tty ? "\r" : "") << "[" << i + 1 << "/" << list.size() << "] "
                << list[i].relative.string()
                << (failed ? "  (" + std::to_string(failed) + " failed)" : "")
                << (tty ? "\033[K" : "\n") << std::flush;
  }
  if (progress && tty) std::cerr << "\n";
  if (interrupted) std::cerr << "mbest detect: interrupted; the images finished so far are complete\n";

  if (!o.timings.empty()) {
    std::vector<double> totals;
    std::map<std::string, std::vector<double>> stages;
    for (const auto& r : records) {
      totals.push_back(r["total_ms"].get<double>());
      for (const auto& [k, v] : r["stages_ms"].items()) stages[k].push_back(v.get<double>());
    }
    nlohmann::json t{{"images", records}, {"median_total_ms", median(totals)}};
    nlohmann::json ms = nlohmann::json::object();
    for (auto& [k, v] : stages) ms[k] = median(v);
    t["median_stages_ms"] = ms;
    if (Status s = write_file_atomically(o.timings, t.dump(2)); !s) {
      std::cerr << "mbest detect: " << s.error().message << "\n";
      return 1;
    }
  }
  if (!o.quiet)
    std::cerr << "mbest detect: " << records.size() << " image(s) written to " << o.out
              << (failed ? ", " + std::to_string(failed) + " failed" : "") << "\n";
  if (interrupted) return 130;
  return failed ? 1 : 0;
}

}  // namespace

void add_detect_command(CLI::App& app, int* exit_code) {
  auto opts = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "detect",
      "Detect DLOs in an image or a data set folder. For each image writes <stem>.labels.png "
      "(16-bit, 0 = background, 1..N = DLOs; crossing pixels belong to the DLO on top), "
      "<stem>.json (ordered centerlines, radii, crossings with the DLO on top, stage timings) "
      "and, with --overlay, <stem>.overlay.png, mirroring INPUT's folders under --out. Exit "
      "code 1 if an image failed (the others are written), 2 on bad arguments, 130 when "
      "interrupted (Ctrl-C finishes the image at hand).");
  cmd->add_option("INPUT", opts->input,
                  "An image (.jpg/.jpeg/.png), or a folder: every image under it whose parent "
                  "folder is named 'images' (the mbest-real and `mbest synth` layout), else "
                  "every image directly in it")
      ->required();
  cmd->add_option("--mask", opts->mask,
                  "Mask file (non-zero = DLO) for a single image, or a folder mirroring INPUT "
                  "(the mask of INPUT/a/images/x.jpg is MASK/a/images/x.png). Default: the "
                  "built-in HSV colour filter (coloured DLOs on a dark background)");
  cmd->add_option("--mask-sibling", opts->mask_sibling,
                  "Take each mask from a sibling folder of the image's: the mask of "
                  "a/images/x.jpg is a/NAME/x.png (e.g. `semantic` in `mbest synth` output)")
      ->excludes("--mask");
  cmd->add_option("--config", opts->config,
                  "Detector constants: a JSON file, or an inline object such as '{\"fit_radii\": 4}' (lengths in units of the "
                  "widest DLO's radius); every field is described in DetectorConfig, "
                  "core/include/mbest/core/detector.h");
  cmd->add_option("--out", opts->out, "Output folder (created if missing)")->capture_default_str();
  cmd->add_flag("--overlay", opts->overlay, "Also write <stem>.overlay.png for a person to check");
  cmd->add_option("--timings", opts->timings,
                  "Write per-image and median detector milliseconds per stage to this JSON file "
                  "(mask in, labels and centerlines out; decoding and colour filter excluded); its "
                  "folder is made if missing, and checked before any image is detected");
  cmd->add_flag("--quiet,-q", opts->quiet, "No progress line");
  cmd->callback([opts, exit_code] { *exit_code = run(*opts); });
}

}  // namespace mbest::app

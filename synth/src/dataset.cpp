#include "mbest/synth/dataset.h"

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>
#include <png.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "mbest/core/atomic_file.h"
#include "mbest/synth/rod.h"
#include "mbest/synth/scene.h"

namespace mbest::synth {

const char* const kGeneratorVersion = "0.3.0";

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

void png_append(png_structp png, png_bytep data, png_size_t n) {
  auto* out = static_cast<std::vector<uchar>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + n);
}
void png_no_flush(png_structp) {}

// The picture as an 8-bit RGB PNG, encoded with libpng directly: zlib level 1 and the "up"
// row filter only. OpenCV's encoder lets libpng try every filter on every row, which took
// 40 % longer on these pictures and gave larger files. Returns false on a libpng error.
bool encode_picture_png(const cv::Mat& bgr, std::vector<uchar>* out) {
  out->clear();
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, info ? &info : nullptr);
    return false;
  }
  png_set_write_fn(png, out, png_append, png_no_flush);
  png_set_compression_level(png, 1);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
  png_set_IHDR(png, info, static_cast<png_uint_32>(bgr.cols), static_cast<png_uint_32>(bgr.rows), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_set_bgr(png);
  for (int y = 0; y < bgr.rows; ++y) png_write_row(png, const_cast<png_bytep>(bgr.ptr<uchar>(y)));
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return true;
}

// PNG settings fixed so the bytes do not depend on OpenCV's defaults changing.
const std::vector<int> kPng = {cv::IMWRITE_PNG_COMPRESSION, 1};
// Masks and label images are long runs of one value: zlib's run-length strategy encodes
// them several times faster than the default and about as small.
const std::vector<int> kPngMask = {cv::IMWRITE_PNG_COMPRESSION, 1, cv::IMWRITE_PNG_STRATEGY,
                                   cv::IMWRITE_PNG_STRATEGY_RLE};
// 0/255 masks as 1-bit PNGs: they read back as the same 0/255 8-bit image, and encode
// ~7x faster than 8-bit ones.
const std::vector<int> kPngBilevel = {cv::IMWRITE_PNG_COMPRESSION, 1, cv::IMWRITE_PNG_STRATEGY,
                                      cv::IMWRITE_PNG_STRATEGY_RLE, cv::IMWRITE_PNG_BILEVEL, 1};

// Records this split in OUT/dataset.json, or checks it matches what is recorded.
Status record_dataset(const DatasetOptions& o) {
  const fs::path file = fs::path(o.out) / "dataset.json";
  json doc = {{"generator", "mbest synth"}, {"version", kGeneratorVersion}, {"splits", json::object()}};
  std::error_code ec;
  if (fs::exists(file, ec)) {
    std::ifstream in(file);
    try {
      doc = json::parse(in);
    } catch (const json::exception& e) {
      return Error{file.string() + ": not valid JSON (" + e.what() + ")"};
    }
  }
  const json entry = {{"preset", o.config.preset}, {"seed", o.seed}, {"count", o.count}, {"config", to_json(o.config)}};
  if (doc.value("version", "") != kGeneratorVersion) {
    return Error{file.string() + " was written by generator version " + doc.value("version", "?") +
                 ", this is " + kGeneratorVersion + "; use another --out"};
  }
  if (!doc.contains("splits") || !doc["splits"].is_object()) {
    return Error{file.string() + ": field 'splits' is missing"};
  }
  if (doc["splits"].contains(o.split)) {
    if (doc["splits"][o.split] != entry) {
      return Error{file.string() + " already holds split '" + o.split +
                   "' made with another preset, config, seed or count; use another --out or --split"};
    }
    return ok_status();
  }
  doc["splits"][o.split] = entry;
  return write_file_atomically(file.string(), doc.dump(2) + "\n");
}

}  // namespace

std::string scene_stem(int index) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%06d", index);
  return buf;
}

Result<GeneratedScene> generate_scene(const SynthConfig& config, std::uint64_t seed, int index) {
  Rng rng(scene_seed(seed, static_cast<std::uint64_t>(index)));
  const Scene scene = compose_scene(config, rng);
  Result<RenderedScene> render = render_scene(scene, config, rng);
  if (!render) return render.error();
  GeneratedScene out;
  out.render = std::move(render).value();
  SceneAnnotation& a = out.annotation;
  const std::string stem = scene_stem(index);
  a.image = "images/" + stem + "." + config.camera.format;
  a.labels = "labels/" + stem + ".png";
  a.semantic = "semantic/" + stem + ".png";
  a.width = scene.width;
  a.height = scene.height;
  a.preset = config.preset;
  a.seed = seed;
  a.index = index;
  for (size_t i = 0; i < scene.rods.size(); ++i) {
    const SceneRod& r = scene.rods[i];
    RodAnnotation ra;
    ra.id = static_cast<int>(i) + 1;
    ra.width_px = r.width;
    ra.color_rgb = r.color_rgb;
    ra.closed = r.closed;
    ra.centerline = r.centerline;
    ra.amodal_mask = "amodal/" + stem + "_" + std::to_string(ra.id) + ".png";
    ra.complexity = complexity(r.centerline, r.width, r.closed);
    for (const cv::Point2d& p : r.centerline) {
      if (p.x < -0.5 || p.y < -0.5 || p.x > scene.width - 0.5 || p.y > scene.height - 0.5) ra.leaves_image = true;
    }
    a.rods.push_back(std::move(ra));
  }
  a.crossings = out.render.crossings;
  return out;
}

Status write_scene(const GeneratedScene& scene, const SynthConfig& config, const std::string& split_dir) {
  const SceneAnnotation& a = scene.annotation;
  const fs::path dir(split_dir);
  std::vector<int> params = kPng;
  if (config.camera.format == "jpg") params = {cv::IMWRITE_JPEG_QUALITY, config.camera.jpeg_quality};
  Status s = ok_status();
  if (config.camera.format == "png" && scene.render.image.type() == CV_8UC3) {
    std::vector<uchar> bytes;
    if (!encode_picture_png(scene.render.image, &bytes)) return Error{"cannot encode " + (dir / a.image).string()};
    s = write_file_atomically((dir / a.image).string(), bytes);
  } else {
    s = write_image_atomically((dir / a.image).string(), scene.render.image, params);
  }
  if (s) s = write_image_atomically((dir / a.labels).string(), scene.render.labels, kPngMask);
  if (s) s = write_image_atomically((dir / a.semantic).string(), scene.render.labels > 0, kPngBilevel);
  for (size_t i = 0; s && i < a.rods.size(); ++i) {
    s = write_image_atomically((dir / a.rods[i].amodal_mask).string(), scene.render.amodal[i], kPngBilevel);
  }
  if (!s) return s;
  // The annotation last: its presence marks the scene done.
  return write_annotation(a, (dir / "annotations" / (scene_stem(a.index) + ".json")).string());
}

Status generate_dataset(const DatasetOptions& o, const std::function<void(const Progress&)>& progress) {
  if (o.count < 0) return Error{"--count must be >= 0"};
  if (o.shard_count < 1 || o.shard_index < 0 || o.shard_index >= o.shard_count) {
    return Error{"--shard: index must be in 0..n-1"};
  }
  if (o.split.empty() || o.split.find('/') != std::string::npos || o.split[0] == '.') {
    return Error{"--split: '" + o.split + "' is not a plain folder name"};
  }
  const fs::path split_dir = fs::path(o.out) / o.split;
  std::error_code ec;
  for (const char* sub : {"images", "labels", "semantic", "amodal", "annotations"}) {
    fs::create_directories(split_dir / sub, ec);
    if (ec) return Error{"cannot create folder " + (split_dir / sub).string() + ": " + ec.message()};
  }
  Status recorded = record_dataset(o);
  if (!recorded) return recorded;

  std::vector<int> todo;
  Progress p;
  for (int i = o.shard_index; i < o.count; i += o.shard_count) {
    ++p.total;
    if (fs::exists(split_dir / "annotations" / (scene_stem(i) + ".json"), ec)) {
      ++p.skipped;
    } else {
      todo.push_back(i);
    }
  }
  std::mutex mutex;
  if (progress) progress(p);
  std::atomic<size_t> next{0};
  std::atomic<bool> failed{false};
  Status first_error = ok_status();
  const auto stopped = [&] { return o.stop && o.stop->load(); };
  auto worker = [&]() {
    for (size_t k = next++; k < todo.size() && !failed && !stopped(); k = next++) {
      Result<GeneratedScene> scene = generate_scene(o.config, o.seed, todo[k]);
      Status s = scene ? write_scene(scene.value(), o.config, split_dir.string()) : Status(scene.error());
      std::lock_guard<std::mutex> lock(mutex);
      if (!s) {
        if (!failed) first_error = s;
        failed = true;
        return;
      }
      ++p.done;
      if (progress) progress(p);
    }
  };
  const int jobs = std::max(1, std::min<int>(o.jobs, static_cast<int>(todo.size())));
  std::vector<std::thread> threads;
  for (int j = 1; j < jobs; ++j) threads.emplace_back(worker);
  worker();
  for (std::thread& t : threads) t.join();
  if (failed) return first_error;
  if (stopped() && p.done < static_cast<int>(todo.size())) {
    return Error{"interrupted: " + std::to_string(p.skipped + p.done) + " of " + std::to_string(p.total) +
                 " scenes are written, each complete; the same command generates the rest"};
  }

  for (int i = 0; i < o.count; ++i) {
    if (!fs::exists(split_dir / "annotations" / (scene_stem(i) + ".json"), ec)) return ok_status();
  }
  return write_coco(split_dir.string(), o.count);
}

Status write_coco(const std::string& split_dir, int count) {
  const fs::path dir(split_dir);
  json images = json::array(), annotations = json::array();
  int next_id = 1;
  for (int i = 0; i < count; ++i) {
    const std::string file = (dir / "annotations" / (scene_stem(i) + ".json")).string();
    Result<SceneAnnotation> a = read_annotation(file);
    if (!a) return a.error();
    const SceneAnnotation& s = a.value();
    const std::string labels_file = (dir / s.labels).string();
    const cv::Mat labels = cv::imread(labels_file, cv::IMREAD_UNCHANGED);
    if (labels.empty() || labels.type() != CV_16UC1) return Error{"cannot read 16-bit labels " + labels_file};
    images.push_back({{"id", i}, {"file_name", s.image}, {"width", s.width}, {"height", s.height}});
    for (const RodAnnotation& r : s.rods) {
      const cv::Mat mask = labels == r.id;
      const int area = cv::countNonZero(mask);
      if (area == 0) continue;
      const cv::Rect box = cv::boundingRect(mask);
      // Uncompressed RLE, column-major, starting with a run of zeros (COCO's convention).
      json counts = json::array();
      uchar current = 0;
      long run = 0;
      for (int x = 0; x < mask.cols; ++x) {
        for (int y = 0; y < mask.rows; ++y) {
          const uchar v = mask.at<uchar>(y, x) ? 1 : 0;
          if (v != current) {
            counts.push_back(run);
            run = 0;
            current = v;
          }
          ++run;
        }
      }
      counts.push_back(run);
      annotations.push_back({{"id", next_id++},
                             {"image_id", i},
                             {"category_id", 1},
                             {"iscrowd", 0},
                             {"area", area},
                             {"bbox", json::array({box.x, box.y, box.width, box.height})},
                             {"segmentation", {{"size", json::array({mask.rows, mask.cols})}, {"counts", counts}}},
                             {"attributes", {{"rod_id", r.id}}}});
    }
  }
  const json coco = {{"info", {{"description", "mbest synth"}, {"version", kGeneratorVersion}}},
                     {"images", images},
                     {"annotations", annotations},
                     {"categories", json::array({{{"id", 1}, {"name", "rod"}, {"supercategory", "dlo"}}})}};
  return write_file_atomically((dir / "coco.json").string(), coco.dump() + "\n");
}

}  // namespace mbest::synth

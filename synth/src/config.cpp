#include "mbest/synth/config.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

namespace mbest::synth {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

const std::vector<std::string> kBackgroundTypes = {"solid", "paper", "gradient", "noise",
                                                   "wood",  "checker", "clutter", "folder"};
const std::vector<std::string> kPalettes = {"real", "cables", "random"};

json range_json(const Range& r) { return json::array({r.lo, r.hi}); }

// Overlays `over` on `base`; a key absent from `base` is an unknown field.
Status merge(json& base, const json& over, const std::string& path, const std::string& source) {
  if (!over.is_object()) {
    return Error{source + ": " + (path.empty() ? "the config" : "field '" + path + "'") +
                 " must be a JSON object"};
  }
  for (auto it = over.begin(); it != over.end(); ++it) {
    const std::string field = path.empty() ? it.key() : path + "." + it.key();
    if (field == "preset") return Error{source + ": field 'preset' is set with --preset"};
    auto b = base.find(it.key());
    if (b == base.end()) return Error{source + ": unknown field '" + field + "'"};
    if (b->is_object()) {
      Status s = merge(*b, it.value(), field, source);
      if (!s) return s;
    } else {
      *b = it.value();
    }
  }
  return ok_status();
}

// Typed, range-checked reads of the merged JSON; the first error is kept.
class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}
  bool failed() const { return !error_.empty(); }
  const std::string& error() const { return error_; }

  void number(const json& obj, const std::string& path, const std::string& key, double lo,
              double hi, double* out) {
    const json& v = obj.at(key);
    if (!v.is_number()) return fail(path + key, "must be a number");
    const double x = v.get<double>();
    if (!(x >= lo && x <= hi)) return fail(path + key, out_of_range(x, lo, hi));
    *out = x;
  }
  void integer(const json& obj, const std::string& path, const std::string& key, int lo,
               int hi, int* out) {
    const json& v = obj.at(key);
    if (!v.is_number_integer()) return fail(path + key, "must be an integer");
    const long long x = v.get<long long>();
    if (x < lo || x > hi) return fail(path + key, out_of_range(double(x), lo, hi));
    *out = static_cast<int>(x);
  }
  void range(const json& obj, const std::string& path, const std::string& key, double lo,
             double hi, Range* out, bool integral = false) {
    const json& v = obj.at(key);
    if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number()) {
      return fail(path + key, "must be a range [lo, hi]");
    }
    Range r{v[0].get<double>(), v[1].get<double>()};
    if (integral && (!v[0].is_number_integer() || !v[1].is_number_integer())) {
      return fail(path + key, "must be a range of integers [lo, hi]");
    }
    if (!(r.lo >= lo && r.hi <= hi)) {
      return fail(path + key, "[" + fmt(r.lo) + ", " + fmt(r.hi) + "] is outside [" +
                                  fmt(lo) + ", " + fmt(hi) + "]");
    }
    if (r.lo > r.hi) return fail(path + key, "has lo > hi");
    *out = r;
  }
  void text(const json& obj, const std::string& path, const std::string& key,
            const std::vector<std::string>& allowed, std::string* out) {
    const json& v = obj.at(key);
    if (!v.is_string()) return fail(path + key, "must be a string");
    const std::string s = v.get<std::string>();
    if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), s) == allowed.end()) {
      return fail(path + key, "'" + s + "' is not one of " + join(allowed));
    }
    *out = s;
  }
  void color(const json& obj, const std::string& path, const std::string& key, cv::Vec3b* out) {
    const json& v = obj.at(key);
    bool good = v.is_array() && v.size() == 3;
    for (size_t i = 0; good && i < 3; ++i) {
      good = v[i].is_number_integer() && v[i].get<int>() >= 0 && v[i].get<int>() <= 255;
    }
    if (!good) return fail(path + key, "must be [r, g, b] with integers in 0..255");
    *out = cv::Vec3b(v[0].get<int>(), v[1].get<int>(), v[2].get<int>());
  }
  void fail(const std::string& field, const std::string& what) {
    if (error_.empty()) error_ = source_ + ": field '" + field + "' " + what;
  }
  static std::string join(const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
    return s;
  }

 private:
  static std::string fmt(double x) {
    std::string s = std::to_string(x);
    s.erase(s.find_last_not_of('0') + 1);
    if (!s.empty() && s.back() == '.') s.pop_back();
    return s;
  }
  static std::string out_of_range(double x, double lo, double hi) {
    return "value " + fmt(x) + " is outside [" + fmt(lo) + ", " + fmt(hi) + "]";
  }
  std::string source_;
  std::string error_;
};

Result<SynthConfig> from_json(const json& j, const std::string& preset, const std::string& source) {
  SynthConfig c;
  c.preset = preset;
  Reader r(source);
  const json& s = j.at("scene");
  SceneConfig& sc = c.scene;
  const std::string ps = "scene.";
  r.integer(s, ps, "width", 16, 8192, &sc.width);
  r.integer(s, ps, "height", 16, 8192, &sc.height);
  r.range(s, ps, "rods", 1, 12, &sc.rods, true);
  r.range(s, ps, "width_px", 1, 200, &sc.width_px);
  r.range(s, ps, "length_px", 10, 20000, &sc.length_px);
  r.range(s, ps, "complexity", 0, 1, &sc.complexity);
  r.range(s, ps, "natural_curvature", 0, 0.2, &sc.natural_curvature);
  r.number(s, ps, "leave_image", 0, 1, &sc.leave_image);
  r.range(s, ps, "crossings", 0, 1000, &sc.crossings, true);
  r.integer(s, ps, "planned_crossings", 0, 12, &sc.planned_crossings);
  r.range(s, ps, "crossing_angle_deg", 1, 90, &sc.crossing_angle_deg);
  r.integer(s, ps, "parallel_strands", 0, 6, &sc.parallel_strands);
  r.range(s, ps, "parallel_gap_px", 0, 50, &sc.parallel_gap_px);
  r.range(s, ps, "parallel_length_px", 10, 5000, &sc.parallel_length_px);
  r.number(s, ps, "self_loop", 0, 1, &sc.self_loop);
  r.range(s, ps, "loop_size", 0.5, 20, &sc.loop_size);
  r.integer(s, ps, "rings", 0, 12, &sc.rings);
  r.range(s, ps, "ring_diameter_px", 10, 5000, &sc.ring_diameter_px);
  r.integer(s, ps, "triple_points", 0, 4, &sc.triple_points);

  const json& rj = j.at("render");
  const std::string pr = "render.";
  r.text(rj, pr, "palette", kPalettes, &c.render.palette);
  r.number(rj, pr, "shading", 0, 1, &c.render.shading);
  r.number(rj, pr, "glare", 0, 1, &c.render.glare);
  r.number(rj, pr, "shadow", 0, 1, &c.render.shadow);
  const json& bj = rj.at("background");
  const std::string pb = "render.background.";
  BackgroundConfig& bg = c.render.background;
  if (!bj.at("types").is_array() || bj.at("types").empty()) {
    r.fail(pb + "types", "must be a non-empty array of names");
  } else {
    bg.types.clear();
    for (const json& t : bj.at("types")) {
      if (!t.is_string() ||
          std::find(kBackgroundTypes.begin(), kBackgroundTypes.end(), t.get<std::string>()) ==
              kBackgroundTypes.end()) {
        r.fail(pb + "types", std::string("has '") + (t.is_string() ? t.get<std::string>() : t.dump()) +
                                 "', not one of " + Reader::join(kBackgroundTypes));
        break;
      }
      bg.types.push_back(t.get<std::string>());
    }
  }
  r.color(bj, pb, "color_rgb", &bg.color_rgb);
  r.text(bj, pb, "folder", {}, &bg.folder);

  const json& cj = j.at("camera");
  const std::string pc = "camera.";
  r.range(cj, pc, "blur_sigma", 0, 10, &c.camera.blur_sigma);
  r.range(cj, pc, "noise_sigma", 0, 60, &c.camera.noise_sigma);
  r.range(cj, pc, "exposure", 0.1, 4, &c.camera.exposure);
  r.text(cj, pc, "format", {"png", "jpg"}, &c.camera.format);
  r.integer(cj, pc, "jpeg_quality", 1, 100, &c.camera.jpeg_quality);
  if (r.failed()) return Error{r.error()};

  if (sc.planned_crossings + sc.parallel_strands + 3 * sc.triple_points + sc.rings > 24) {
    return Error{source + ": fields 'scene.planned_crossings', 'scene.parallel_strands', "
                          "'scene.triple_points', 'scene.rings' ask for too many rods"};
  }
  if (std::find(bg.types.begin(), bg.types.end(), "folder") != bg.types.end()) {
    std::error_code ec;
    if (bg.folder.empty()) {
      return Error{source + ": field 'render.background.folder' must be set for type 'folder'"};
    }
    if (!fs::is_directory(bg.folder, ec)) {
      return Error{source + ": field 'render.background.folder': cannot read folder '" +
                   bg.folder + "'"};
    }
    for (fs::directory_iterator it(bg.folder, ec), end; !ec && it != end; it.increment(ec)) {
      std::string ext = it->path().extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
      if (ext == ".png" || ext == ".jpg" || ext == ".jpeg") bg.folder_files.push_back(it->path().string());
    }
    if (ec) {
      return Error{source + ": field 'render.background.folder': cannot read folder '" +
                   bg.folder + "' (" + ec.message() + ")"};
    }
    if (bg.folder_files.empty()) {
      return Error{source + ": field 'render.background.folder': no .png or .jpg images in '" +
                   bg.folder + "'"};
    }
    // Sorted, so the file a scene draws does not depend on directory order.
    std::sort(bg.folder_files.begin(), bg.folder_files.end());
  }
  return c;
}

SynthConfig real_tubes(int rods) {
  // Matched to mbest-real (scripts/synth-realism.sh): portrait 672x896 frames, tubes
  // ~12 px wide as measured on the labels, loops 60-120 px across, a faint highlight, and
  // the sensor noise left after the real set's JPEG compression. The rods are long enough
  // to cross each other ~3 times a scene unplanned, as the real ones do.
  SynthConfig c;
  c.scene.width = 672;
  c.scene.height = 896;
  c.scene.rods = {double(rods), double(rods)};
  c.scene.width_px = {9.5, 13};
  c.scene.length_px = {900, 1700};
  c.scene.complexity = {0.15, 0.45};  // the real tubes bend in broad arcs
  c.scene.leave_image = 0.7;
  c.scene.self_loop = 0.3;
  c.scene.loop_size = {4, 7};  // the real tubes' loops are 60-120 px across
  c.render.palette = "real";
  c.render.glare = 0.3;
  c.render.shading = 1;
  c.camera.blur_sigma = {0.5, 0.9};
  c.camera.noise_sigma = {3, 5};
  c.camera.exposure = {0.9, 1.1};
  c.camera.format = "jpg";
  c.camera.jpeg_quality = 90;
  return c;
}

}  // namespace

std::vector<std::string> preset_names() { return {"s1", "s2", "s3", "cables", "stress"}; }

Result<SynthConfig> preset_config(const std::string& name) {
  SynthConfig c;
  if (name == "s1" || name == "s2" || name == "s3") {
    c = real_tubes(name[1] - '0');
  } else if (name == "cables") {
    c.scene.rods = {2, 8};
    c.scene.width_px = {4, 9};
    c.scene.length_px = {400, 1400};
    c.scene.complexity = {0.2, 0.8};
    c.scene.natural_curvature = {0, 0.01};
    c.scene.leave_image = 0.6;
    c.scene.self_loop = 0.15;
    c.render.palette = "cables";
    c.render.glare = 0.7;
    c.render.shadow = 0.5;
    c.render.background.types = {"wood", "paper", "checker", "clutter", "noise", "gradient"};
    c.render.background.color_rgb = {140, 120, 100};
    c.camera.blur_sigma = {0.3, 1.0};
    c.camera.noise_sigma = {1, 5};
    c.camera.exposure = {0.8, 1.2};
    c.camera.format = "jpg";
    c.camera.jpeg_quality = 88;
  } else if (name == "stress") {
    c.scene.rods = {4, 8};
    c.scene.width_px = {7, 14};
    c.scene.length_px = {500, 1300};
    c.scene.complexity = {0.3, 0.9};
    c.scene.leave_image = 0.4;
    c.scene.planned_crossings = 2;
    c.scene.crossing_angle_deg = {3, 20};
    c.scene.parallel_strands = 1;
    c.scene.self_loop = 0.5;
    c.scene.rings = 1;
    c.scene.ring_diameter_px = {90, 180};
    c.scene.triple_points = 1;
    c.render.palette = "random";
    c.render.glare = 0.6;
    c.render.shadow = 0.4;
    c.render.background.types = {"noise", "gradient", "paper"};
    c.render.background.color_rgb = {60, 60, 70};
    c.camera.blur_sigma = {0.3, 0.8};
    c.camera.noise_sigma = {1, 4};
    c.camera.format = "png";
  } else {
    return Error{"unknown preset '" + name + "' (presets: s1, s2, s3, cables, stress)"};
  }
  c.preset = name;
  return c;
}

json to_json(const SynthConfig& c) {
  const SceneConfig& s = c.scene;
  const BackgroundConfig& b = c.render.background;
  return {{"preset", c.preset},
          {"scene",
           {{"width", s.width},
            {"height", s.height},
            {"rods", json::array({int(s.rods.lo), int(s.rods.hi)})},
            {"width_px", range_json(s.width_px)},
            {"length_px", range_json(s.length_px)},
            {"complexity", range_json(s.complexity)},
            {"natural_curvature", range_json(s.natural_curvature)},
            {"leave_image", s.leave_image},
            {"crossings", json::array({int(s.crossings.lo), int(s.crossings.hi)})},
            {"planned_crossings", s.planned_crossings},
            {"crossing_angle_deg", range_json(s.crossing_angle_deg)},
            {"parallel_strands", s.parallel_strands},
            {"parallel_gap_px", range_json(s.parallel_gap_px)},
            {"parallel_length_px", range_json(s.parallel_length_px)},
            {"self_loop", s.self_loop},
            {"loop_size", range_json(s.loop_size)},
            {"rings", s.rings},
            {"ring_diameter_px", range_json(s.ring_diameter_px)},
            {"triple_points", s.triple_points}}},
          {"render",
           {{"palette", c.render.palette},
            {"shading", c.render.shading},
            {"glare", c.render.glare},
            {"shadow", c.render.shadow},
            {"background",
             {{"types", b.types},
              {"color_rgb", json::array({b.color_rgb[0], b.color_rgb[1], b.color_rgb[2]})},
              {"folder", b.folder}}}}},
          {"camera",
           {{"blur_sigma", range_json(c.camera.blur_sigma)},
            {"noise_sigma", range_json(c.camera.noise_sigma)},
            {"exposure", range_json(c.camera.exposure)},
            {"format", c.camera.format},
            {"jpeg_quality", c.camera.jpeg_quality}}}};
}

Result<SynthConfig> make_config(const std::string& preset, const json& overrides,
                                const std::string& source) {
  Result<SynthConfig> base = preset_config(preset);
  if (!base) return base;
  json full = to_json(base.value());
  if (!overrides.is_null()) {
    Status s = merge(full, overrides, "", source);
    if (!s) return s.error();
  }
  return from_json(full, preset, source);
}

Result<SynthConfig> load_config(const std::string& preset, const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{"cannot read config file " + path};
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    return Error{path + ": not valid JSON (" + e.what() + ")"};
  }
  return make_config(preset, j, path);
}

}  // namespace mbest::synth

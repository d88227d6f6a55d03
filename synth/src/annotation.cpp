#include "mbest/synth/annotation.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "mbest/core/atomic_file.h"

namespace mbest::synth {
namespace {

using nlohmann::json;

json point_json(const cv::Point2d& p) { return json::array({p.x, p.y}); }

// Reads JSON fields with errors naming the file and the field path.
class FieldReader {
 public:
  explicit FieldReader(std::string file) : file_(std::move(file)) {}
  const std::string& error() const { return error_; }
  bool failed() const { return !error_.empty(); }

  const json* field(const json& obj, const std::string& key, const std::string& path,
                    bool optional = false) {
    if (failed()) return nullptr;
    if (!obj.is_object()) return fail(path, "is not an object");
    auto it = obj.find(key);
    if (it == obj.end()) return optional ? nullptr : fail(path + key, "is missing");
    return &*it;
  }
  template <class T>
  void get(const json& obj, const std::string& key, const std::string& path, T* out,
           bool optional = false) {
    const json* f = field(obj, key, path, optional);
    if (!f) return;
    try {
      *out = f->get<T>();
    } catch (const json::exception&) {
      fail(path + key, "has the wrong type");
    }
  }
  void point(const json& obj, const std::string& key, const std::string& path,
             cv::Point2d* out) {
    const json* f = field(obj, key, path);
    if (!f) return;
    if (!f->is_array() || f->size() != 2 || !(*f)[0].is_number() || !(*f)[1].is_number()) {
      fail(path + key, "is not an [x, y] pair");
      return;
    }
    *out = {(*f)[0].get<double>(), (*f)[1].get<double>()};
  }
  std::nullptr_t fail(const std::string& field, const std::string& what) {
    if (error_.empty()) error_ = file_ + ": field '" + field + "' " + what;
    return nullptr;
  }

 private:
  std::string file_;
  std::string error_;
};

}  // namespace

Status write_annotation(const SceneAnnotation& scene, const std::string& path) {
  json rods = json::array();
  for (const RodAnnotation& r : scene.rods) {
    json centerline = json::array();
    for (const cv::Point2d& p : r.centerline) {
      // 3 decimals: sub-pixel, and the file stays byte-stable and compact.
      centerline.push_back(json::array({std::round(p.x * 1000) / 1000, std::round(p.y * 1000) / 1000}));
    }
    const Complexity& c = r.complexity;
    rods.push_back({{"id", r.id},
                    {"width_px", r.width_px},
                    {"color_rgb", json::array({r.color_rgb[0], r.color_rgb[1], r.color_rgb[2]})},
                    {"closed", r.closed},
                    {"leaves_image", r.leaves_image},
                    {"amodal_mask", r.amodal_mask},
                    {"complexity",
                     {{"mean_abs_curvature", c.mean_abs_curvature},
                      {"curvature_std_x_width", c.curvature_std_x_width},
                      {"total_turning_rad", c.total_turning_rad},
                      {"inflections", c.inflections},
                      {"normalised_bending_energy", c.normalised_bending_energy}}},
                    {"centerline", std::move(centerline)}});
  }
  json crossings = json::array();
  for (const CrossingAnnotation& x : scene.crossings) {
    crossings.push_back({{"location", point_json(x.location)},
                         {"angle_deg", x.angle_deg},
                         {"rods", json::array({x.rod_a, x.rod_b})},
                         {"top", x.top},
                         {"arc_index", json::array({x.arc_index_a, x.arc_index_b})},
                         {"top_arc_index", x.top_arc_index}});
  }
  const json j = {{"image", scene.image},   {"labels", scene.labels},
                  {"semantic", scene.semantic}, {"width", scene.width},
                  {"height", scene.height}, {"preset", scene.preset},
                  {"seed", scene.seed},     {"index", scene.index},
                  {"rods", std::move(rods)}, {"crossings", std::move(crossings)}};
  return write_file_atomically(path, j.dump(1) + "\n");
}

Result<SceneAnnotation> read_annotation(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{"cannot read annotation file " + path};
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    return Error{path + ": not valid JSON (" + e.what() + ")"};
  }
  FieldReader f(path);
  SceneAnnotation s;
  f.get(j, "image", "", &s.image);
  f.get(j, "labels", "", &s.labels);
  f.get(j, "semantic", "", &s.semantic, true);
  f.get(j, "width", "", &s.width);
  f.get(j, "height", "", &s.height);
  f.get(j, "preset", "", &s.preset);
  f.get(j, "seed", "", &s.seed);
  f.get(j, "index", "", &s.index);
  const json* rods = f.field(j, "rods", "");
  if (rods && !rods->is_array()) f.fail("rods", "is not an array");
  for (size_t i = 0; rods && !f.failed() && i < rods->size(); ++i) {
    const json& r = (*rods)[i];
    const std::string p = "rods[" + std::to_string(i) + "].";
    RodAnnotation rod;
    f.get(r, "id", p, &rod.id);
    f.get(r, "width_px", p, &rod.width_px);
    std::vector<int> rgb;
    f.get(r, "color_rgb", p, &rgb);
    if (!f.failed() && rgb.size() != 3) f.fail(p + "color_rgb", "is not [r, g, b]");
    if (!f.failed()) rod.color_rgb = cv::Vec3b(rgb[0], rgb[1], rgb[2]);
    f.get(r, "closed", p, &rod.closed);
    f.get(r, "leaves_image", p, &rod.leaves_image, true);
    f.get(r, "amodal_mask", p, &rod.amodal_mask);
    const json* c = f.field(r, "complexity", p);
    if (c) {
      const std::string pc = p + "complexity.";
      f.get(*c, "mean_abs_curvature", pc, &rod.complexity.mean_abs_curvature);
      f.get(*c, "curvature_std_x_width", pc, &rod.complexity.curvature_std_x_width);
      f.get(*c, "total_turning_rad", pc, &rod.complexity.total_turning_rad);
      f.get(*c, "inflections", pc, &rod.complexity.inflections);
      f.get(*c, "normalised_bending_energy", pc, &rod.complexity.normalised_bending_energy);
    }
    const json* cl = f.field(r, "centerline", p);
    if (cl && !cl->is_array()) f.fail(p + "centerline", "is not an array");
    for (size_t k = 0; cl && !f.failed() && k < cl->size(); ++k) {
      const json& q = (*cl)[k];
      if (!q.is_array() || q.size() != 2 || !q[0].is_number() || !q[1].is_number()) {
        f.fail(p + "centerline[" + std::to_string(k) + "]", "is not an [x, y] pair");
        break;
      }
      rod.centerline.emplace_back(q[0].get<double>(), q[1].get<double>());
    }
    s.rods.push_back(std::move(rod));
  }
  const json* xs = f.field(j, "crossings", "");
  if (xs && !xs->is_array()) f.fail("crossings", "is not an array");
  for (size_t i = 0; xs && !f.failed() && i < xs->size(); ++i) {
    const json& x = (*xs)[i];
    const std::string p = "crossings[" + std::to_string(i) + "].";
    CrossingAnnotation c;
    f.point(x, "location", p, &c.location);
    f.get(x, "angle_deg", p, &c.angle_deg);
    std::vector<int> pair, arc;
    f.get(x, "rods", p, &pair);
    if (!f.failed() && pair.size() != 2) f.fail(p + "rods", "is not [a, b]");
    f.get(x, "top", p, &c.top);
    f.get(x, "arc_index", p, &arc);
    if (!f.failed() && arc.size() != 2) f.fail(p + "arc_index", "is not [ia, ib]");
    if (f.failed()) break;
    c.rod_a = pair[0];
    c.rod_b = pair[1];
    c.arc_index_a = arc[0];
    c.arc_index_b = arc[1];
    c.top_arc_index = c.arc_index_a;
    f.get(x, "top_arc_index", p, &c.top_arc_index, true);
    s.crossings.push_back(c);
  }
  if (f.failed()) return Error{f.error()};
  return s;
}

}  // namespace mbest::synth

// Generator configuration: every control of a scene, its rendering and its camera, with
// defaults. The JSON form mirrors the structs: {"scene": {...}, "render": {...},
// "camera": {...}}; a range is [lo, hi], drawn uniformly per scene (or per rod).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>
#include <opencv2/core.hpp>

#include "mbest/core/result.h"

namespace mbest::synth {

struct Range {
  double lo = 0, hi = 0;
};

struct SceneConfig {
  int width = 896, height = 672;         // "width", "height": px, 16..8192
  Range rods{1, 3};                      // "rods": rod count, integers in 1..12
  Range width_px{10, 14};                // "width_px": rod diameter, 1..200
  Range length_px{700, 1400};            // "length_px": 10..20000
  Range complexity{0.3, 0.6};            // "complexity": waviness in 0..1
  Range natural_curvature{0, 0};         // "natural_curvature": |rest curvature| 1/px, 0..0.2
  double leave_image = 0.5;              // "leave_image": P(a rod leaves the image), 0..1
  Range crossings{0, 1000};              // "crossings": accepted total count (best of retries)
  int planned_crossings = 0;             // "planned_crossings": rods made to cross one, 0..12
  Range crossing_angle_deg{20, 90};      // "crossing_angle_deg": of planned crossings, 1..90
  int parallel_strands = 0;              // "parallel_strands": side-by-side pairs, 0..6
  Range parallel_gap_px{1, 4};           // "parallel_gap_px": gap between the tubes, 0..50
  Range parallel_length_px{80, 250};     // "parallel_length_px": the shared stretch, 10..5000
  double self_loop = 0;                  // "self_loop": P(a rod has a loop), 0..1
  Range loop_size{2, 3.5};               // "loop_size": a loop's elastica scale (its size)
                                         //   in rod widths, 0.5..20 (at least 10-14 px)
  int rings = 0;                         // "rings": closed rods, 0..12
  Range ring_diameter_px{80, 200};       // "ring_diameter_px": 10..5000
  int triple_points = 0;                 // "triple_points": three rods through one point, 0..4
};

struct BackgroundConfig {
  // "types": any of solid, gradient, noise, wood, paper, checker, clutter, folder; one is
  // drawn per scene.
  std::vector<std::string> types{"solid"};
  cv::Vec3b color_rgb{0, 0, 0};  // "color_rgb": the solid colour and the base of the others
  std::string folder;            // "folder": images for the "folder" type (png, jpg)
  std::vector<std::string> folder_files;  // not in JSON: filled when the config is validated
};

struct RenderConfig {
  std::string palette = "real";  // "palette": real (pink/green/teal/yellow), cables, random
  double shading = 1;            // "shading": 0 = flat colour, 1 = full tube shading
  double glare = 0.6;            // "glare": specular strength, 0..1
  double shadow = 0;             // "shadow": soft shadow strength on the background, 0..1
  BackgroundConfig background;   // "background"
};

struct CameraConfig {
  Range blur_sigma{0, 0};      // "blur_sigma": Gaussian blur, px, 0..10
  Range noise_sigma{0, 0};     // "noise_sigma": sensor noise, grey levels, 0..60
  Range exposure{1, 1};        // "exposure": gain, 0.1..4
  std::string format = "png";  // "format": png or jpg
  int jpeg_quality = 92;       // "jpeg_quality": 1..100
};

struct SynthConfig {
  std::string preset;  // "preset": name of the preset this config started from
  SceneConfig scene;
  RenderConfig render;
  CameraConfig camera;
};

// Names of the presets: s1, s2, s3, cables, stress.
std::vector<std::string> preset_names();

// The preset's configuration. Errors name the unknown preset.
Result<SynthConfig> preset_config(const std::string& name);

// The preset, overridden field by field by `overrides` (a JSON object, possibly nested
// partially), then validated: unknown fields, wrong types, values out of range and an
// unreadable background folder are errors naming the field (e.g. "scene.rods"). `source`
// names the origin of the overrides in messages (a file name).
Result<SynthConfig> make_config(const std::string& preset, const nlohmann::json& overrides,
                                const std::string& source);

// Reads a JSON file of overrides, then as make_config.
Result<SynthConfig> load_config(const std::string& preset, const std::string& path);

// The full JSON form (every field), as recorded in OUT/dataset.json.
nlohmann::json to_json(const SynthConfig& config);

}  // namespace mbest::synth

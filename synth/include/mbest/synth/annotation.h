// Ground truth of one synthetic scene, as written to OUT/<split>/annotations/<stem>.json.
// The JSON form (keys in quotes) is the contract between synth/ (writer) and validate/
// (reader). Coordinates are pixels, x right, y down, pixel centres at integer coordinates.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mbest/core/result.h"

namespace mbest::synth {

// Curvature-complexity figures of one rod, computed on its centerline resampled at 1 px.
struct Complexity {
  double mean_abs_curvature = 0;         // "mean_abs_curvature", 1/px
  double curvature_std_x_width = 0;      // "curvature_std_x_width", dimensionless
  double total_turning_rad = 0;          // "total_turning_rad", sum |turning angle|
  int inflections = 0;                   // "inflections", sign changes of curvature
  double normalised_bending_energy = 0;  // "normalised_bending_energy", L * sum k^2 ds
};

struct RodAnnotation {
  int id = 0;                         // "id": the rod's value in the label image (1..N)
  double width_px = 0;                // "width_px": full width (diameter)
  cv::Vec3b color_rgb;                // "color_rgb": [r, g, b]
  bool closed = false;                // "closed": a ring
  std::vector<cv::Point2d> centerline;  // "centerline": [[x, y], ...] ordered, ~1 px apart
  std::string amodal_mask;            // "amodal_mask": path relative to the split folder
  Complexity complexity;              // "complexity": {...}
  // Added fields (optional when read; default false):
  bool leaves_image = false;          // "leaves_image": part of the centerline is outside
};

struct CrossingAnnotation {
  cv::Point2d location;            // "location": [x, y]
  double angle_deg = 0;            // "angle_deg": in [0, 90]
  int rod_a = 0, rod_b = 0;        // "rods": [a, b] (a == b for a self-crossing)
  int top = 0;                     // "top": id of the rod on top
  int arc_index_a = 0;             // "arc_index": [ia, ib], the centerline sample index of
  int arc_index_b = 0;             //   each strand at the crossing (rod a's, then rod b's)
  // Added field (optional when read; default arc_index_a): the arc index of the strand on
  // top, which tells the strands of a self-crossing apart.
  int top_arc_index = 0;           // "top_arc_index"
};

struct SceneAnnotation {
  std::string image;   // "image": path relative to the split folder, e.g. "images/0000.png"
  std::string labels;  // "labels": e.g. "labels/0000.png" (16-bit, 0 = background, id = rod)
  int width = 0, height = 0;  // "width", "height"
  std::string preset;         // "preset"
  unsigned long long seed = 0;  // "seed": the dataset seed
  int index = 0;                // "index": the scene's index in the dataset
  std::vector<RodAnnotation> rods;            // "rods"
  std::vector<CrossingAnnotation> crossings;  // "crossings"
  // Added field (optional when read; default empty):
  std::string semantic;  // "semantic": e.g. "semantic/0000.png" (8-bit, 255 = any rod)
};

// Reads / writes the JSON form above; the write goes through a temporary file
// (mbest/core/atomic_file.h). Errors name the file and the field.
Result<SceneAnnotation> read_annotation(const std::string& path);
Status write_annotation(const SceneAnnotation& scene, const std::string& path);

}  // namespace mbest::synth

// Rendering of a composed scene with Cairo: per-rod coverage (antialiased), tube shading,
// glare, soft shadows, per-crossing z-order, camera effects; and the exact ground truth.
//
// Ground-truth rule: each rod's coverage of each pixel is rendered with Cairo (fraction
// c in [0, 1]); at a pixel the rods present are stacked in their local z-order and rod i's
// visible coverage is v_i = c_i * prod_{j above i} (1 - c_j). The picture (before camera
// effects) is sum_i v_i * colour_i + (1 - sum_i v_i) * background, and the label is the
// rod with v_i >= 0.5 (0 if none). So labels and picture agree pixel for pixel.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "mbest/core/result.h"
#include "mbest/synth/config.h"
#include "mbest/synth/rng.h"
#include "mbest/synth/scene.h"

namespace mbest::synth {

struct RenderedScene {
  cv::Mat image;                 // CV_8UC3 BGR, camera effects applied
  cv::Mat labels;                // CV_16UC1: 0 background, k + 1 for scene.rods[k]
  std::vector<cv::Mat> amodal;   // per rod, CV_8UC1: 255 where its own coverage >= 0.5
  std::vector<CrossingAnnotation> crossings;  // scene.crossings with the rendered top
};

// Renders `scene` with config.render and config.camera. Errors come from the background
// (an unreadable folder image).
Result<RenderedScene> render_scene(const Scene& scene, const SynthConfig& config, Rng& rng);

}  // namespace mbest::synth

// Scene composition: the rods of one scene (elastic rod shapes placed in the image, with
// planned crossings, parallel strands, loops, rings and triple points) and the crossings
// found in their geometry. Rendering is separate (render.h).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "mbest/synth/annotation.h"
#include "mbest/synth/config.h"
#include "mbest/synth/rng.h"

namespace mbest::synth {

struct SceneRod {
  double width = 0;                     // px, full diameter
  cv::Vec3b color_rgb;
  bool closed = false;
  double natural_curvature = 0;         // 1/px, signed
  double bending_energy = 0;            // discrete energy of the solved shape (rod.h)
  std::vector<cv::Point2d> centerline;  // 1 px apart, image coordinates
};

struct Scene {
  int width = 0, height = 0;
  std::vector<SceneRod> rods;   // rod k has label id k + 1
  std::vector<int> base_order;  // rod indices, bottom first
  // Crossings inside the image. `top` holds the wanted top rod id (and top_arc_index the
  // wanted top strand); rendering may only be able to honour it approximately and
  // replaces both with what the picture shows.
  std::vector<CrossingAnnotation> crossings;
};

// Draws a scene from the config. Deterministic in the Rng state.
Scene compose_scene(const SynthConfig& config, Rng& rng);

// Every crossing of the centerlines (two rods, or a rod with itself away from its
// neighbourhood) whose location lies inside a width x height image; `top` is left 0.
// Rod ids are index + 1. Ordered by (rod_a, arc_index_a, rod_b, arc_index_b).
std::vector<CrossingAnnotation> find_crossings(const std::vector<SceneRod>& rods, int width,
                                               int height);

}  // namespace mbest::synth

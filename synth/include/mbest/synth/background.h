// Backgrounds behind the rods: solid, gradient, noise, procedural textures (wood, paper,
// checker, clutter of distractor lines and blobs) or an image from a user folder.
#pragma once

#include <opencv2/core.hpp>

#include "mbest/core/result.h"
#include "mbest/synth/config.h"
#include "mbest/synth/rng.h"

namespace mbest::synth {

// A size.width x size.height CV_8UC3 (BGR) background of one of config.types, drawn with
// rng. Errors name an unreadable folder image.
Result<cv::Mat> make_background(const BackgroundConfig& config, cv::Size size, Rng& rng);

}  // namespace mbest::synth

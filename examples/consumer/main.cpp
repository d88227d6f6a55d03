// Uses the three mbest libraries the way a program of your own would: generates one scene
// (mbest::synth; scene 0 of what `mbest synth --preset PRESET --seed SEED` writes), detects its DLOs from the mask and the picture (mbest::core), and scores
// the instance labels against the scene's exact ground truth (mbest::validate).
// Usage: mbest_consumer [PRESET [SEED]]   (default s2 1)
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "mbest/core/detector.h"
#include "mbest/synth/config.h"
#include "mbest/synth/dataset.h"
#include "mbest/validate/dice.h"

int main(int argc, char** argv) {
  const std::string preset = argc > 1 ? argv[1] : "s2";
  std::uint64_t seed = 1;
  if (argc > 2) {
    char* end = nullptr;
    errno = 0;
    seed = std::strtoull(argv[2], &end, 10);
    if (argv[2][0] < '0' || argv[2][0] > '9' || *end != '\0' || errno == ERANGE) {
      std::fprintf(stderr, "mbest_consumer: SEED must be a non-negative integer, got '%s'\n", argv[2]);
      return 2;
    }
  }

  const mbest::Result<mbest::synth::SynthConfig> config = mbest::synth::preset_config(preset);
  if (!config) {
    std::fprintf(stderr, "mbest_consumer: %s\n", config.error().message.c_str());
    return 2;
  }
  const mbest::Result<mbest::synth::GeneratedScene> generated =
      mbest::synth::generate_scene(config.value(), seed, 0);
  if (!generated) {
    std::fprintf(stderr, "mbest_consumer: %s\n", generated.error().message.c_str());
    return 1;
  }
  const mbest::synth::RenderedScene& rendered = generated.value().render;

  const cv::Mat mask = rendered.labels > 0;  // CV_8UC1, 255 on the rods
  const mbest::Result<mbest::Detection> detection = mbest::detect(mask, rendered.image);
  if (!detection) {
    std::fprintf(stderr, "mbest_consumer: %s\n", detection.error().message.c_str());
    return 1;
  }
  const mbest::Result<mbest::validate::DiceScore> dice =
      mbest::validate::matched_dice(rendered.labels, detection.value().labels);
  if (!dice) {
    std::fprintf(stderr, "mbest_consumer: %s\n", dice.error().message.c_str());
    return 1;
  }
  std::printf("%s seed %llu: %zu rods, %zu DLOs detected, strict DICE %.4f\n", preset.c_str(),
              static_cast<unsigned long long>(seed), generated.value().annotation.rods.size(),
              detection.value().dlos.size(), dice.value().strict);
  return 0;
}

// Data sets of generated scenes on disk:
//   OUT/dataset.json                       generator, version, and per split: preset, seed,
//                                          count and the full config
//   OUT/<split>/images/<stem>.png|jpg      the picture
//   OUT/<split>/labels/<stem>.png          16-bit instance labels (0 = background)
//   OUT/<split>/semantic/<stem>.png        8-bit, 255 = any rod
//   OUT/<split>/amodal/<stem>_<id>.png     8-bit full mask of rod <id>, occluded parts too
//   OUT/<split>/annotations/<stem>.json    annotation.h; written last, it marks the scene done
//   OUT/<split>/coco.json                  COCO instance segmentation of the visible masks,
//                                          written once every scene of the split is done
// Scene <index> depends only on (config, seed, index): any job count or sharding gives
// the same bytes. Every file is written to a hidden temporary name in its folder, then
// renamed, so an interrupted run leaves no half-written file under a real name.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

#include "mbest/core/result.h"
#include "mbest/synth/annotation.h"
#include "mbest/synth/config.h"
#include "mbest/synth/render.h"

namespace mbest::synth {

// The generator version recorded in dataset.json; bump it when scenes change.
extern const char* const kGeneratorVersion;

struct GeneratedScene {
  SceneAnnotation annotation;
  RenderedScene render;
};

// Composes and renders scene `index` of the data set `seed`, in memory (paths in the
// annotation are those of the layout above, for `format`).
Result<GeneratedScene> generate_scene(const SynthConfig& config, std::uint64_t seed, int index);

// Writes one scene's files under split_dir (annotation last). The image is encoded as
// config.camera.format.
Status write_scene(const GeneratedScene& scene, const SynthConfig& config,
                   const std::string& split_dir);

// "000042": the file stem of a scene index.
std::string scene_stem(int index);

struct DatasetOptions {
  SynthConfig config;
  std::uint64_t seed = 0;
  int count = 0;
  std::string out;              // OUT
  std::string split = "train";  // folder name under OUT
  int jobs = 1;
  int shard_index = 0, shard_count = 1;  // this run makes indices i with i % count == index
  // When set and it turns true, workers start no further scene: those being written are
  // finished, and generate_dataset returns an error saying how many are done. Running the
  // same options again generates the rest.
  const std::atomic<bool>* stop = nullptr;
};

struct Progress {
  int done = 0;     // scenes finished by this run
  int skipped = 0;  // scenes of this shard found already done
  int total = 0;    // scenes of this shard
};

// Generates the shard's scenes that are not done yet, calling `progress` (from worker
// threads, serialised) after each. Errors: a dataset.json made with another config, seed
// or count; unwritable folders; an unreadable background image; a stop request.
Status generate_dataset(const DatasetOptions& options,
                        const std::function<void(const Progress&)>& progress);

// Writes split_dir/coco.json from the split's annotations and labels. Errors name the
// missing or unreadable file.
Status write_coco(const std::string& split_dir, int count);

}  // namespace mbest::synth

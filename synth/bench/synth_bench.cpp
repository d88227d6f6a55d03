// Throughput of the scene generator at 896x672 with 3 rods, glare and a textured
// background: scenes per second on one core, in memory (compose + render) and written to
// disk (encoded, every file of the layout, annotation included).
#include <filesystem>
#include <string>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>

#include "mbest/synth/dataset.h"

namespace {

mbest::synth::SynthConfig bench_config() {
  mbest::synth::SynthConfig c = mbest::synth::preset_config("cables").value();
  c.scene.rods = {3, 3};
  c.scene.width_px = {8, 14};
  c.scene.width = 896;
  c.scene.height = 672;
  c.render.glare = 0.7;
  c.render.background.types = {"wood", "paper", "noise", "clutter"};
  c.camera.format = "png";
  return c;
}

void BM_SceneInMemory(benchmark::State& state) {
  const mbest::synth::SynthConfig config = bench_config();
  int index = 0;
  for (auto _ : state) {
    auto scene = mbest::synth::generate_scene(config, 7, index++);
    benchmark::DoNotOptimize(scene.value().render.image.data);
  }
  state.counters["scenes/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_SceneToDisk(benchmark::State& state) {
  mbest::synth::SynthConfig config = bench_config();
  config.camera.format = state.range(0) ? "jpg" : "png";
  const std::string dir = (std::filesystem::temp_directory_path() / "mbest_synth_bench").string();
  for (const char* sub : {"images", "labels", "semantic", "amodal", "annotations"}) {
    std::filesystem::create_directories(std::filesystem::path(dir) / sub);
  }
  int index = 0;
  for (auto _ : state) {
    auto scene = mbest::synth::generate_scene(config, 7, index++);
    auto status = mbest::synth::write_scene(scene.value(), config, dir);
    if (!status) state.SkipWithError(status.error().message.c_str());
  }
  state.counters["scenes/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  std::filesystem::remove_all(dir);
}

}  // namespace

BENCHMARK(BM_SceneInMemory)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SceneToDisk)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

int main(int argc, char** argv) {
  cv::setNumThreads(1);  // per core: no OpenCV worker threads
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}

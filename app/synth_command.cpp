// `mbest synth`: generate a labeled data set of elastic-rod scenes.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "io.h"
#include "mbest/synth/config.h"
#include "mbest/synth/dataset.h"

namespace mbest::app {
namespace {

struct SynthArgs {
  std::string preset = "s3";
  std::string config;
  int count = 0;
  unsigned long long seed = 0;
  std::string out;
  int jobs = 1;
  std::string shard = "0/1";
  std::string split = "train";
  bool quiet = false;
};

// "i/n" with 0 <= i < n.
bool parse_shard(const std::string& text, int* index, int* count) {
  const auto slash = text.find('/');
  if (slash == std::string::npos) return false;
  try {
    size_t used = 0;
    *index = std::stoi(text.substr(0, slash), &used);
    if (used != slash) return false;
    *count = std::stoi(text.substr(slash + 1), &used);
    if (used != text.size() - slash - 1) return false;
  } catch (const std::exception&) {
    return false;
  }
  return *count >= 1 && *index >= 0 && *index < *count;
}

int run_synth(const SynthArgs& args) {
  synth::DatasetOptions options;
  Result<synth::SynthConfig> config = synth::make_config(args.preset, nlohmann::json(), "--preset");
  if (!args.config.empty()) {
    Result<JsonOption> given = json_option("--config", args.config);
    if (!given) {
      std::cerr << "mbest synth: " << given.error().message << "\n";
      return 2;
    }
    nlohmann::json overrides;
    try {
      overrides = nlohmann::json::parse(given.value().text);
    } catch (const nlohmann::json::exception& e) {
      std::cerr << "mbest synth: " << given.value().source << ": not valid JSON (" << e.what() << ")\n";
      return 2;
    }
    config = synth::make_config(args.preset, overrides, given.value().source);
  }
  if (!config) {
    std::cerr << "mbest synth: " << config.error().message << "\n";
    return 2;
  }
  if (!parse_shard(args.shard, &options.shard_index, &options.shard_count)) {
    std::cerr << "mbest synth: --shard '" << args.shard << "' is not i/n with 0 <= i < n\n";
    return 2;
  }
  options.config = std::move(config).value();
  options.seed = args.seed;
  options.count = args.count;
  options.out = args.out;
  options.split = args.split;
  options.jobs = args.jobs;
  options.stop = &catch_interrupts();
  const auto start = std::chrono::steady_clock::now();
  auto progress = [&](const synth::Progress& p) {
    if (args.quiet) return;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "\rmbest synth: %d/%d scenes (%d already done), %.1f scenes/s   ",
                 p.done + p.skipped, p.total, p.skipped, seconds > 0 ? p.done / seconds : 0.0);
    std::fflush(stderr);
  };
  const Status status = synth::generate_dataset(options, progress);
  if (!args.quiet) std::fprintf(stderr, "\n");
  if (!status) {
    std::cerr << "mbest synth: " << status.error().message << "\n";
    return *options.stop ? 130 : 1;
  }
  return 0;
}

}  // namespace

void add_synth_command(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<SynthArgs>();
  CLI::App* cmd = app.add_subcommand(
      "synth",
      "Generate labeled scenes of elastic rods (images, 16-bit instance labels, semantic and amodal "
      "masks, JSON annotations, COCO file). Scene i depends only on (config, seed, i): any --jobs or "
      "--shard gives identical files. Re-running resumes, skipping finished scenes. Exit code 1 "
      "on a failure, 2 on bad arguments, 130 when interrupted (Ctrl-C finishes the scenes being "
      "written).");
  cmd->add_option("--preset", args->preset, "s1, s2, s3 (like the real dev set), cables, stress")
      ->capture_default_str();
  cmd->add_option("--config", args->config,
                  "Preset fields to override: a JSON file, or an inline object such as "
                  "'{\"scene\": {\"rods\": [2, 5]}}'; unknown fields and out-of-range values are errors");
  cmd->add_option("--count", args->count, "number of scenes in the split")->required()->check(CLI::Range(0, 100000000));
  cmd->add_option("--seed", args->seed, "data set seed")->capture_default_str();
  cmd->add_option("--out", args->out, "output folder (OUT/dataset.json, OUT/<split>/...)")->required();
  cmd->add_option("--jobs", args->jobs, "worker threads")->capture_default_str()->check(CLI::Range(1, 256));
  cmd->add_option("--shard", args->shard, "make only scenes i with i % n == index, as index/n")->capture_default_str();
  cmd->add_option("--split", args->split, "split folder name under OUT")->capture_default_str();
  cmd->add_flag("--quiet,-q", args->quiet, "no progress line on stderr");
  cmd->callback([args, exit_code]() { *exit_code = run_synth(*args); });
}

}  // namespace mbest::app

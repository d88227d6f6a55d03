// mbest_bench: the detector's speed on a data set, the way the issue asks for it: median
// milliseconds per frame, per tier and per stage, single thread, mask in, labels and
// centerlines out. Masks are made once up front (built-in colour filter), so only the
// detector is timed. Every frame is run --rounds times, the tiers taking turns round by
// round; medians are over all runs. The best_ms column is the median over frames of each
// frame's fastest run: on a shared machine, where a neighbour's load slows whole seconds,
// it moves far less from run to run than the median, and it is the figure to compare two
// builds by.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "mbest/core/detector.h"
#include "mbest/core/median.h"
#include "mbest/core/segmentation.h"

namespace fs = std::filesystem;

namespace {

struct Frame {
  cv::Mat mask, image;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"mbest_bench: median detector milliseconds per frame, per tier and per stage"};
  std::string dataset, json_out, config_path;
  int rounds = 10;
  app.add_option("DATASET", dataset, "Folder of tiers (e.g. ../shared/datasets/mbest-real): each "
                 "subfolder with an images/ folder is a tier")->required();
  app.add_option("--rounds", rounds, "Runs of every frame")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--json", json_out, "Also write the figures to this JSON file");
  app.add_option("--config", config_path, "Detector constants (JSON), as `mbest detect --config`")
      ->check(CLI::ExistingFile);
  CLI11_PARSE(app, argc, argv);

  mbest::DetectorConfig config;
  if (!config_path.empty()) {
    std::ifstream in(config_path);
    std::stringstream text;
    text << in.rdbuf();
    auto c = mbest::parse_detector_config(text.str());
    if (!c) {
      std::cerr << "mbest_bench: " << config_path << ": " << c.error().message << "\n";
      return 2;
    }
    config = c.value();
  }

  std::map<std::string, std::vector<Frame>> tiers;
  std::error_code ec;
  for (const auto& tier : fs::directory_iterator(dataset, ec)) {
    const fs::path images = tier.path() / "images";
    if (!fs::is_directory(images)) continue;
    std::vector<fs::path> files;
    for (const auto& f : fs::directory_iterator(images)) files.push_back(f.path());
    std::sort(files.begin(), files.end());
    for (const fs::path& f : files) {
      auto img = mbest::read_image(f.string());
      if (!img) continue;
      auto mask = mbest::colour_filter(img.value());
      if (!mask) continue;
      tiers[tier.path().filename().string()].push_back({mask.value(), img.value()});
    }
  }
  if (ec || tiers.empty()) {
    std::cerr << "mbest_bench: " << dataset << ": no tier folders with images/ found\n";
    return 2;
  }

  nlohmann::json out;
  std::map<std::string, double> tier_median, tier_best, tier_mask_px;
  std::printf("%-6s %6s %9s %10s %10s %10s %10s   per stage (median ms)\n", "tier", "frames", "mask_px",
              "median_ms", "p10_ms", "p90_ms", "best_ms");
  // Round by round over every tier, so that a slow spell of a shared machine falls on all
  // tiers alike instead of on whichever ran then: the tiers' ratio is what drifts most.
  struct Runs {
    std::vector<double> totals;
    std::map<std::string, std::vector<double>> stages;
    std::vector<std::string> stage_order;
  };
  std::map<std::string, Runs> runs;
  for (int r = 0; r < rounds; ++r)
    for (const auto& [name, frames] : tiers)
      for (const Frame& f : frames) {
        auto det = mbest::detect(f.mask, f.image, config);
        if (!det) {
          std::cerr << "mbest_bench: " << det.error().message << "\n";
          return 1;
        }
        Runs& run = runs[name];
        run.totals.push_back(det.value().total_ms());
        for (const auto& s : det.value().timings) {
          if (!run.stages.count(s.stage)) run.stage_order.push_back(s.stage);
          run.stages[s.stage].push_back(s.ms);
        }
      }
  for (const auto& [name, frames] : tiers) {
    auto& [totals, stages, stage_order] = runs[name];
    std::vector<double> fastest(frames.size(), std::numeric_limits<double>::infinity());
    for (size_t k = 0; k < totals.size(); ++k)  // run k is frame k % frames of its round
      fastest[k % frames.size()] = std::min(fastest[k % frames.size()], totals[k]);
    tier_best[name] = mbest::median(fastest);
    std::sort(totals.begin(), totals.end());
    const double med = mbest::median(totals);
    tier_median[name] = med;
    // How much mask there is to work on: the detector's work grows with it.
    std::vector<double> mask_px;
    for (const Frame& f : frames) mask_px.push_back(cv::countNonZero(f.mask));
    tier_mask_px[name] = mbest::median(mask_px);
    std::printf("%-6s %6zu %9.0f %10.3f %10.3f %10.3f %10.3f  ", name.c_str(), frames.size(),
                tier_mask_px[name], med, totals[totals.size() / 10], totals[totals.size() * 9 / 10],
                tier_best[name]);
    nlohmann::json st;
    for (const std::string& s : stage_order) {
      st[s] = mbest::median(stages[s]);
      std::printf(" %s %.3f", s.c_str(), mbest::median(stages[s]));
    }
    std::printf("\n");
    out["tiers"][name] = {{"frames", frames.size()}, {"runs", totals.size()}, {"median_ms", med},
                          {"median_best_ms", tier_best[name]}, {"median_mask_px", tier_mask_px[name]},
                          {"median_stages_ms", st}};
  }
  if (tier_median.count("S1") && tier_median.count("S3") && tier_median["S1"] > 0) {
    const double ratio = tier_median["S3"] / tier_median["S1"];
    const double mask_ratio = tier_mask_px["S1"] > 0 ? tier_mask_px["S3"] / tier_mask_px["S1"] : 0;
    const double best_ratio = tier_best["S1"] > 0 ? tier_best["S3"] / tier_best["S1"] : 0;
    std::printf("S3/S1 median ratio: %.2f, of best runs: %.2f (median mask pixels: %.2f)\n", ratio,
                best_ratio, mask_ratio);
    out["s3_over_s1"] = ratio;
    out["s3_over_s1_best"] = best_ratio;
    out["s3_over_s1_mask_px"] = mask_ratio;
  }
  if (!json_out.empty()) std::ofstream(json_out) << out.dump(2) << "\n";
  return 0;
}

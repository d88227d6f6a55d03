// `mbest eval DATASET (--pred DIR | --run [--mask-sibling NAME | --colour-filter] [--config C])
//  [--report DIR] [--json] [gates]`:
// scores predictions against a data set's ground truth and prints a table per tier.
// Exit codes: 0 success, 1 bad input, 2 a tier misses a gate (--min-dice, --max-below-95,
// --max-count-errors).
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "io.h"
#include "mbest/core/detector.h"
#include "mbest/validate/dataset.h"
#include "mbest/validate/evaluation.h"
#include "mbest/validate/report.h"
#include "mbest/validate/summary.h"

namespace mbest::app {

namespace {

struct EvalArgs {
  std::string dataset;
  std::string pred;
  bool run = false;
  std::string mask_sibling;  // with --run; empty: auto
  bool colour_filter = false;
  std::string config;
  std::string report;
  bool json = false;
  double min_dice = -1;
  int max_below_95 = -1, max_count_errors = -1;  // -1: not checked
  int threads = 2;
  int worst = 8;
  int failed_crossings = 2;
  bool quiet = false;
};

std::string command_line(const EvalArgs& a) {
  std::ostringstream out;
  out << "mbest eval " << a.dataset << (a.run ? " --run" : " --pred " + a.pred);
  if (!a.mask_sibling.empty()) out << " --mask-sibling " << a.mask_sibling;
  if (a.colour_filter) out << " --colour-filter";
  if (!a.config.empty()) out << " --config '" << a.config << "'";
  if (!a.report.empty()) out << " --report " << a.report;
  if (a.json) out << " --json";
  if (a.min_dice >= 0) out << " --min-dice " << a.min_dice;
  if (a.max_below_95 >= 0) out << " --max-below-95 " << a.max_below_95;
  if (a.max_count_errors >= 0) out << " --max-count-errors " << a.max_count_errors;
  return out.str();
}

// Progress on stderr: a line redrawn in place on a terminal; otherwise, for the slow --run,
// a line every tenth of the images. None with --quiet.
std::function<void(int, int)> progress_printer(bool run, bool quiet) {
  const bool tty = ::isatty(STDERR_FILENO);
  if (quiet || (!tty && !run)) return {};
  return [tty](int done, int total) {
    if (tty) {
      std::fprintf(stderr, "\reval: %d/%d images", done, total);
      if (done == total) std::fprintf(stderr, "\r\033[K");
    } else if (done == total || done % std::max(1, total / 10) == 0) {
      std::fprintf(stderr, "eval: %d/%d images\n", done, total);
    }
    std::fflush(stderr);
  };
}

int run_eval(const EvalArgs& a) {
  namespace v = mbest::validate;
  if (!a.run && a.pred.empty()) {
    std::cerr << "mbest eval: give the predictions with --pred DIR (a `mbest detect --out` "
                 "folder) or compute them with --run\n";
    return kEvalBadInput;
  }
  if (!a.run && !std::filesystem::is_directory(a.pred)) {
    std::cerr << "mbest eval: " << a.pred << ": prediction folder not found\n";
    return kEvalBadInput;
  }
  Result<v::Dataset> dataset = v::open_dataset(a.dataset);
  if (!dataset) {
    std::cerr << "mbest eval: " << dataset.error().message << "\n";
    return kEvalBadInput;
  }
  v::EvalOptions options;
  options.pred_dir = a.pred;
  options.run = a.run;
  if (a.run && !a.colour_filter) {
    // Synthetic scenes carry their exact mask in semantic/; the colour filter is made for
    // coloured DLOs on a dark background and fails on the generator's textured ones.
    const std::string name = a.mask_sibling.empty() ? "semantic" : a.mask_sibling;
    const std::string missing = v::missing_sibling_mask(dataset.value(), name);
    if (missing.empty()) {
      options.mask_sibling = name;
    } else if (!a.mask_sibling.empty()) {
      std::cerr << "mbest eval: --mask-sibling " << name << ": " << missing << ": no such mask\n";
      return kEvalBadInput;
    }
  }
  if (!a.config.empty()) {
    Result<JsonOption> given = json_option("--config", a.config);
    if (!given) {
      std::cerr << "mbest eval: " << given.error().message << "\n";
      return kEvalBadInput;
    }
    Result<DetectorConfig> c = parse_detector_config(given.value().text);
    if (!c) {
      std::cerr << "mbest eval: --config " << a.config << ": " << c.error().message << "\n";
      return kEvalBadInput;
    }
    options.detector = c.value();
  }
  options.threads = a.threads;
  options.keep_worst = a.report.empty() ? 0 : a.worst;
  options.keep_failed_crossings = a.report.empty() ? 0 : a.failed_crossings;
  Result<v::Evaluation> evaluation = v::evaluate(dataset.value(), options, progress_printer(a.run, a.quiet));
  if (!evaluation) {
    std::cerr << "mbest eval: " << evaluation.error().message << "\n";
    return kEvalBadInput;
  }
  const v::Evaluation& e = evaluation.value();
  const v::Summary summary = v::summarise(e);
  if (!a.run && summary.all.missing_predictions == summary.all.images) {
    std::cerr << "mbest eval: " << a.pred << ": no prediction for any image of " << a.dataset
              << " (expected e.g. " << v::prediction_paths(e.images[0].item, a.pred).labels
              << ", as `mbest detect " << a.dataset << " --out " << a.pred << "` writes)\n";
    return kEvalBadInput;
  }
  const v::ReportInfo info{command_line(a)};
  if (a.json) {
    std::cout << v::report_json(e, summary, info);
  } else {
    const std::string masks =
        options.mask_sibling.empty() ? "the colour filter" : options.mask_sibling + "/";
    const std::string source = a.run ? "computed with --run, masks from " + masks : "from " + a.pred;
    std::printf("mbest eval %s: %zu images (%s layout), predictions %s, %.2f s\n\n%s",
                e.dataset.root.c_str(), e.images.size(),
                e.dataset.synthetic ? "synth" : "mbest-real", source.c_str(), e.seconds,
                v::tier_table(e, summary).c_str());
  }
  if (!a.report.empty()) {
    if (Status s = v::write_report(e, summary, info, a.report); !s) {
      std::cerr << "mbest eval: " << s.error().message << "\n";
      return kEvalBadInput;
    }
    std::cerr << "mbest eval: wrote " << a.report << "/report.{json,md,html}\n";
  }
  int code = 0;
  for (const v::TierSummary& t : summary.tiers) {
    if (a.min_dice >= 0 && t.strict_mean < a.min_dice) {
      std::fprintf(stderr, "mbest eval: tier %s: strict DICE %.2f %% is below --min-dice %.2f %%\n",
                   t.tier.c_str(), t.strict_mean, a.min_dice);
      code = 2;
    }
    if (a.max_below_95 >= 0 && t.below_95 > a.max_below_95) {
      std::fprintf(stderr, "mbest eval: tier %s: %d images below 95 %% strict DICE (allowed: %d)\n",
                   t.tier.c_str(), t.below_95, a.max_below_95);
      code = 2;
    }
    if (a.max_count_errors >= 0 && t.count_errors > a.max_count_errors) {
      std::fprintf(stderr, "mbest eval: tier %s: %d images with a wrong DLO count (allowed: %d)\n",
                   t.tier.c_str(), t.count_errors, a.max_count_errors);
      code = 2;
    }
  }
  return code;
}

}  // namespace

void add_eval_command(CLI::App& app, int* exit_code) {
  CLI::App* cmd = app.add_subcommand(
      "eval",
      "Score predictions against a data set's ground truth: matched DICE per tier (strict, "
      "lenient, count errors); on synthetic data also crossing resolution and centerline error, "
      "and in the reports the detector's crossing list (beyond metrics.md). "
      "Exit code 1 on bad input, 2 when a tier misses a gate (--min-dice, --max-below-95, "
      "--max-count-errors).");
  auto a = std::make_shared<EvalArgs>();
  cmd->add_option("DATASET", a->dataset,
                  "data set: DATASET/<tier>/images + labels (mbest-real), or the synth layout "
                  "with annotations/")
      ->required();
  CLI::Option* pred =
      cmd->add_option("--pred", a->pred, "predictions: the folder of `mbest detect DATASET --out DIR`");
  CLI::Option* run = cmd->add_flag(
      "--run", a->run,
      "compute predictions now: mask -> detect; the mask is the image's in the sibling folder "
      "semantic/ when every image has one (the synth layout), else the colour filter's");
  pred->excludes(run);
  CLI::Option* sibling = cmd->add_option(
      "--mask-sibling", a->mask_sibling,
      "with --run, take each mask from this sibling folder of the image's (a/images/x.jpg -> "
      "a/NAME/x.png); every image must have one");
  sibling->needs(run);
  cmd->add_flag("--colour-filter", a->colour_filter,
                "with --run, make every mask with the colour filter (coloured DLOs on a dark "
                "background), even where a semantic/ folder exists")
      ->needs(run)
      ->excludes(sibling);
  cmd->add_option("--config", a->config,
                  "with --run, detector constants: a JSON file, or an inline object such as "
                  "'{\"epsilon_radii\": 12}' (fields of DetectorConfig)")
      ->needs(run);
  cmd->add_option("--report", a->report, "write report.json, report.md and report.html into DIR");
  cmd->add_flag("--json", a->json, "print report.json to stdout instead of the table");
  cmd->add_flag("--quiet,-q", a->quiet, "no progress line on stderr");
  cmd->add_option("--min-dice", a->min_dice,
                  "exit with code 2 if any tier's strict DICE (percent) is below this")
      ->check(CLI::Range(0.0, 100.0));
  cmd->add_option("--max-below-95", a->max_below_95,
                  "exit with code 2 if any tier has more images below 95 % strict DICE")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--max-count-errors", a->max_count_errors,
                  "exit with code 2 if any tier has more images with a wrong DLO count")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--threads", a->threads, "images scored in parallel")->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd->add_option("--worst", a->worst, "images in the report's gallery of the worst images")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000));
  cmd->add_option("--failed-crossings", a->failed_crossings,
                  "synthetic data: per tier and crossing-angle bin, how many images the report "
                  "lists (report.md) and shows close up (report.html) at their first crossing "
                  "paired wrong")
      ->capture_default_str()
      ->check(CLI::Range(0, 100));
  cmd->callback([a, exit_code] { *exit_code = run_eval(*a); });
}

}  // namespace mbest::app

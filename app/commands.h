// Subcommands of the `mbest` executable. Each registers itself on the top-level CLI11 app;
// when it runs it stores its process exit code in *exit_code (0 = success).
#pragma once

#include <CLI/CLI.hpp>

namespace mbest::app {

void add_detect_command(CLI::App& app, int* exit_code);
void add_synth_command(CLI::App& app, int* exit_code);
void add_eval_command(CLI::App& app, int* exit_code);

// eval's exit code for bad input, its arguments included, whether eval or the option parser
// finds the fault (the other commands use 2 there; eval's 2 means that a tier missed a gate).
constexpr int kEvalBadInput = 1;

}  // namespace mbest::app

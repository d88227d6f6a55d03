// mbest: detect deformable linear objects, generate labeled rod scenes, measure accuracy.
#include <iostream>

#include <CLI/CLI.hpp>

#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"mbest: detection of deformable linear objects (cables, ropes, tubes, wires)"};
  app.require_subcommand(1);
  int exit_code = 0;
  mbest::app::add_detect_command(app, &exit_code);
  mbest::app::add_synth_command(app, &exit_code);
  mbest::app::add_eval_command(app, &exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  return exit_code;
}

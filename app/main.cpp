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
  // CLI11 would only say that a command is required.
  const auto named = [&](CLI::App* c) { return c->check_name(argv[1]); };
  if (argc > 1 && argv[1][0] != '-' && app.get_subcommands(named).empty()) {
    std::cerr << "mbest: unknown command '" << argv[1] << "' (commands: detect, synth, eval; see mbest --help)\n";
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 prints the message (or the help, exit 0); any error in the arguments exits 2,
    // as the commands' own checks of their arguments do.
    return app.exit(e) == 0 ? 0 : 2;
  }
  return exit_code;
}

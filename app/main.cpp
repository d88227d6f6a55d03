// mbest: detect deformable linear objects, generate labeled rod scenes, measure accuracy.
#include <iostream>
#include <string>

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
    // CLI11 prints the message (or the help, exit 0). An error in the arguments exits as the
    // command's own checks of its arguments do (commands.h).
    const bool eval = argc > 1 && std::string(argv[1]) == "eval";
    return app.exit(e) == 0 ? 0 : eval ? mbest::app::kEvalBadInput : 2;
  }
  return exit_code;
}

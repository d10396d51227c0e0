// SPDX-License-Identifier: MIT
/// @file cmmcomp-replay: replays a recorded controller session (docs/recordings.md) through the
/// plugins' own request handlers with a given model — or against a live cmmcomp-agent — and checks
/// every answer byte for byte against the recording. The options are in options.cpp, the replay
/// they run in run.cpp.
#include <CLI/CLI.hpp>

#include "../common/command.hpp"
#include "../common/usage.hpp"
#include "commands.hpp"

static int run_tool(int argc, char** argv) {
  CLI::App app{
      "cmmcomp-replay: replays a recorded controller session (a Modbus transcript or a candump "
      "-l log, docs/recordings.md) through cmmcomp-agent's own request handlers with the given "
      "model, or against a live agent (--live), and checks every answer byte for byte.\n"
      "Exit status: 0 every answer matches, 1 a mismatch, 2 unreadable input or bad options."};
  const cmmcomp::tools::Command command = cmmcomp::tools::replay::add_options(app);
  return cmmcomp::tools::run_commands(
      app, {command}, "cmmcomp-replay", argc, argv, cmmcomp::tools::config_error_is_usage);
}

int main(int argc, char** argv) {
  return cmmcomp::tools::guarded_main("cmmcomp-replay", run_tool, argc, argv);
}

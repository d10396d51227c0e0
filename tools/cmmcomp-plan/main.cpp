// SPDX-License-Identifier: MIT
/// @file cmmcomp-plan: the feed planner (docs/planner.md). From a model with its U95, a point error
/// budget, the machine's limits and the feature's geometry, the fastest probing setting with
/// compensation and the fastest without, their times per point and the ratio. The options are in
/// options.cpp, the planning they run in run.cpp.
#include <CLI/CLI.hpp>

#include "../common/command.hpp"
#include "../common/usage.hpp"
#include "commands.hpp"

static int run_tool(int argc, char** argv) {
  CLI::App app{
      "cmmcomp-plan: the fastest probing setting whose point error meets a budget at a coverage "
      "(95 %), with "
      "the model's correction and without it (docs/planner.md)."};
  const cmmcomp::tools::Command command = cmmcomp::tools::plan::add_options(app);
  return cmmcomp::tools::run_commands(
      app, {command}, "cmmcomp-plan", argc, argv, cmmcomp::tools::config_error_is_usage);
}

int main(int argc, char** argv) {
  return cmmcomp::tools::guarded_main("cmmcomp-plan", run_tool, argc, argv);
}

// SPDX-License-Identifier: MIT
/// @file cmmcomp-study: the project's experiments as C++ over the libraries (docs/study.md). Each
/// subcommand runs one cmmcomp::study experiment on the recipes it is given, prints its table (or
/// --json), judges its targets with one known-unmet list and checks (or writes) its block of the
/// results page; exit 1 when a target fails or the block is stale, 2 on a usage error. The
/// subcommands are declared in commands.hpp, one file per subcommand or group.
#include <CLI/CLI.hpp>
#include <cmmcomp/study/report.hpp>
#include <cmmcomp/version.hpp>
#include <string>
#include <vector>

#include "../common/command.hpp"
#include "../common/usage.hpp"
#include "commands.hpp"

static int run_tool(int argc, char** argv) {
  namespace study = cmmcomp::tools::study;
  CLI::App app{"cmmcomp-study: the project's experiments over the libraries (docs/study.md)"};
  app.set_version_flag("--version", std::string("cmmcomp ") + CMMCOMP_VERSION_STRING);
  app.require_subcommand(1);
  const std::string command = cmmcomp::study::command_line(argc, argv);
  const std::vector<cmmcomp::tools::Command> commands{
      study::add_accuracy(app, command),
      study::add_cell_interpolant(app, command),
      study::add_dataset(app),
      study::add_train(app),
      study::add_interval_coverage(app, command),
      study::add_interval_calibration(app, command),
      study::add_calibration(app, command),
      study::add_identify_multistart(app, command),
      study::add_cross_machine(app, command),
      study::add_qualified_sweep(app, command),
      study::add_cycle_speedup(app, command),
      study::add_render(app, command),
  };
  return cmmcomp::tools::run_commands(
      app, commands, "cmmcomp-study", argc, argv, cmmcomp::tools::config_error_is_usage);
}

int main(int argc, char** argv) {
  return cmmcomp::tools::guarded_main("cmmcomp-study", run_tool, argc, argv);
}

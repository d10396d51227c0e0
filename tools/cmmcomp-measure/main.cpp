// SPDX-License-Identifier: MIT
/// @file cmmcomp-measure: the experiment on a real machine (docs/measurement.md). `plan` writes the
/// designed moves in randomised run order as plan.csv and an I++ DME program; `extract` turns the
/// machine's recordings into the dataset CSV cmmcomp-train reads, with a per-move report. The
/// subcommands are declared in commands.hpp, one file each.
#include <CLI/CLI.hpp>
#include <cmmcomp/version.hpp>
#include <string>
#include <vector>

#include "../common/command.hpp"
#include "../common/usage.hpp"
#include "commands.hpp"

static int run_tool(int argc, char** argv) {
  namespace measure = cmmcomp::tools::measure;
  CLI::App app{
      "cmmcomp-measure: plan the experiment for a real machine, and extract its "
      "recordings into the four parameters"};
  app.set_version_flag("--version", std::string("cmmcomp ") + CMMCOMP_VERSION_STRING);
  app.require_subcommand(1);
  const std::vector<cmmcomp::tools::Command> commands{
      measure::add_plan(app),
      measure::add_extract(app),
  };
  return cmmcomp::tools::run_commands(app, commands, "cmmcomp-measure", argc, argv);
}

int main(int argc, char** argv) {
  return cmmcomp::tools::guarded_main("cmmcomp-measure", run_tool, argc, argv);
}

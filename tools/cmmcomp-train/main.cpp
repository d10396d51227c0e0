// SPDX-License-Identifier: MIT
/// @file cmmcomp-train: train the T-S network on a dataset, evaluate it (Table 5), export it. The
/// subcommands are declared in commands.hpp, one file per subcommand or group.
#include <CLI/CLI.hpp>
#include <cmmcomp/version.hpp>
#include <string>
#include <vector>

#include "../common/command.hpp"
#include "../common/usage.hpp"
#include "commands.hpp"

static int run_tool(int argc, char** argv) {
  namespace train = cmmcomp::tools::train;
  CLI::App app{"cmmcomp-train: train, evaluate and export the T-S fuzzy network"};
  app.set_version_flag("--version", std::string("cmmcomp ") + CMMCOMP_VERSION_STRING);
  app.require_subcommand(1);
  const std::vector<cmmcomp::tools::Command> commands{
      train::add_fit(app),
      train::add_conditions(app),
      train::add_eval(app),
      train::add_export(app),
  };
  return cmmcomp::tools::run_commands(app, commands, "cmmcomp-train", argc, argv);
}

int main(int argc, char** argv) {
  return cmmcomp::tools::guarded_main("cmmcomp-train", run_tool, argc, argv);
}

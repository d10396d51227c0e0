// SPDX-License-Identifier: MIT
/// @file cmmcomp-sim: plan probing moves (and, with the digital twin, simulate them). The
/// subcommands are declared in commands.hpp, one file per subcommand or group.
#include <CLI/CLI.hpp>
#include <cmmcomp/version.hpp>
#include <string>
#include <vector>

#include "../common/command.hpp"
#include "../common/usage.hpp"
#include "commands.hpp"

static int run_tool(int argc, char** argv) {
  namespace sim = cmmcomp::tools::sim;
  CLI::App app{"cmmcomp-sim: probing-move profiles and the CMM digital twin"};
  app.set_version_flag("--version", std::string("cmmcomp ") + CMMCOMP_VERSION_STRING);
  app.require_subcommand(1);
  const std::vector<cmmcomp::tools::Command> commands{
      sim::add_profile(app),
      sim::add_move(app),
      sim::add_dataset(app),
      sim::add_record(app),
      sim::add_anova(app),
      sim::add_identify(app),
      sim::add_machine(app),
      sim::add_paper(app),
      sim::add_serve_ipp(app),
  };
  return cmmcomp::tools::run_commands(app, commands, "cmmcomp-sim", argc, argv);
}

int main(int argc, char** argv) {
  return cmmcomp::tools::guarded_main("cmmcomp-sim", run_tool, argc, argv);
}

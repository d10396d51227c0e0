// SPDX-License-Identifier: MIT
/// @file cmmcomp-vc: a virtual CMM controller that runs an ISO 10360-2 style length test at speed
/// on the digital twin and asks cmmcomp-agent for each correction over Modbus TCP or CAN. The
/// options are in options.cpp, the test they run in run.cpp.
#include <CLI/CLI.hpp>

#include "../common/command.hpp"
#include "../common/usage.hpp"
#include "commands.hpp"

static int run_tool(int argc, char** argv) {
  CLI::App app{
      "cmmcomp-vc: a virtual CMM controller. Runs an ISO 10360-2 style bidirectional length "
      "test on the digital twin at a fast (compensated) and a slow (reference) setting, asks "
      "cmmcomp-agent for every fast point's correction over Modbus TCP or CAN, and reports the "
      "length errors against MPE_E = 1.9 + L/300 um and the time per point."};
  const cmmcomp::tools::Command command = cmmcomp::tools::vc::add_options(app);
  return cmmcomp::tools::run_commands(
      app, {command}, "cmmcomp-vc", argc, argv, cmmcomp::tools::vc::failure_status);
}

int main(int argc, char** argv) {
  return cmmcomp::tools::guarded_main("cmmcomp-vc", run_tool, argc, argv);
}

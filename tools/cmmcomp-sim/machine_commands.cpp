// SPDX-License-Identifier: MIT
/// @file cmmcomp-sim machine (print a machine file, or the table of its keys) and paper (a machine
/// next to the paper's tables at one noise seed).
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/dynamics/paper_check.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include "commands.hpp"
#include "shared.hpp"

namespace cmmcomp::tools::sim {
namespace {

struct MachineCommand {
  std::string machine_in, machine_out;
  bool keys = false;
};

int run_machine(const MachineCommand& cmd) {
  if (cmd.keys) {
    std::fputs(cmmcomp::dynamics::format_machine_keys().c_str(), stdout);
    return 0;
  }
  const std::string text = cmmcomp::dynamics::format_machine(machine_from(cmd.machine_in));
  if (cmd.machine_out.empty()) {
    std::fputs(text.c_str(), stdout);
  } else {
    cmmcomp::io::write_file_atomically(cmd.machine_out, text);
  }
  return 0;
}

struct PaperCommand {
  std::string machine;
  std::uint64_t seed = 1;
  bool check = false;
};

/// The machine next to the paper for one noise seed; exit 1 with --check when a requirement fails
/// at it. The verdict over many seeds, with a known-unmet list, is `cmmcomp-study calibration`.
int run_paper(const PaperCommand& cmd) {
  const cmmcomp::dynamics::Machine machine = machine_from(cmd.machine);
  std::printf("machine: %s (%s)\n\n", machine.name.c_str(), machine.description.c_str());
  const cmmcomp::dynamics::PaperComparison c =
      cmmcomp::dynamics::compare_with_paper(machine, cmd.seed);
  std::fputs(cmmcomp::dynamics::format_paper_comparison(c).c_str(), stdout);
  return cmd.check && !c.all_passed() ? 1 : 0;
}

}  // namespace

Command add_machine(CLI::App& app) {
  auto cmd = std::make_shared<MachineCommand>();
  CLI::App* machine = app.add_subcommand(
      "machine", "print a machine file (default: the embedded one), to start your own from");
  machine->add_option("--machine", cmd->machine_in, "machine file to check and re-print");
  machine->add_option("-o,--output", cmd->machine_out, "write to this file instead of stdout");
  machine->add_flag(
      "--keys", cmd->keys, "print the table of keys (markdown, as in docs/machine-file.md)");
  return {machine, [cmd] { return run_machine(*cmd); }};
}

Command add_paper(CLI::App& app) {
  auto cmd = std::make_shared<PaperCommand>();
  CLI::App* paper = app.add_subcommand(
      "paper",
      "compare a machine with the paper's Tables 1, 2, 4 and 5 and the smoothness requirement at "
      "one noise seed (over many seeds: cmmcomp-study calibration)");
  paper->add_option("--machine", cmd->machine, "machine file (default: embedded)");
  paper->add_option("--seed", cmd->seed, "noise seed")->capture_default_str();
  paper->add_flag("--check", cmd->check, "exit 1 when a requirement fails at this seed");
  return {paper, [cmd] { return run_paper(*cmd); }};
}

}  // namespace cmmcomp::tools::sim

// SPDX-License-Identifier: MIT
/// @file cmmcomp-study cross-machine (the real-machine workflow on twins, each machine's own
/// model next to the shipped one) and qualified-sweep (the length test's speed-up over a
/// qualified machine).
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/study/cross_machine.hpp>
#include <cmmcomp/study/qualified_sweep.hpp>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "reporting.hpp"

namespace cmmcomp::tools::study {
namespace {

struct CrossMachineCommand {
  std::vector<std::string> machines, differ;
  std::string shipped, plan = "l18x3", work;
  Output out;
};

int run_cross_machine(const CrossMachineCommand& cmd) {
  cmmcomp::study::CampaignSetup setup;
  cmmcomp::study::parse_campaign_plan(cmd.plan, setup);
  const std::vector<cmmcomp::study::StudyMachine> list =
      cmmcomp::study::study_machines(cmd.machines, cmd.differ);
  const cmmcomp::study::CrossMachineResult r = cmmcomp::study::cross_machine(
      list, cmmcomp::io::load_compensation_model(cmd.shipped), setup, cmd.work, run_options());
  return finish(cmmcomp::study::cross_machine_document(r), r.targets, cmd.out);
}

struct SweepCommand {
  std::string model, machine;
  std::vector<std::uint64_t> seeds{1, 2, 3, 4, 5};
  cmmcomp::study::SweepGrid grid;
  Output out;
};

int run_qualified_sweep(const SweepCommand& cmd) {
  const cmmcomp::dynamics::Machine m = cmd.machine.empty()
                                           ? cmmcomp::dynamics::default_machine()
                                           : cmmcomp::dynamics::load_machine(cmd.machine);
  const cmmcomp::study::SweepResult r = cmmcomp::study::qualified_sweep(
      cmmcomp::io::load_compensation_model(cmd.model), m, cmd.seeds, cmd.grid, run_options());
  return finish(cmmcomp::study::qualified_sweep_document(r), r.targets, cmd.out);
}

}  // namespace

Command add_cross_machine(CLI::App& app, const std::string& command) {
  auto cmd = std::make_shared<CrossMachineCommand>();
  cmd->out.command = command;
  CLI::App* cross = app.add_subcommand(
      "cross-machine",
      "the real-machine workflow on twins (plan, record, extract, fit, test), each machine's own "
      "model next to the shipped one (docs/training.md, \"Other machines\")");
  cross->add_option("--machine", cmd->machines, "\"default\" or a machine file, repeatable")
      ->required();
  cross->add_option("--dynamics-differ",
                    cmd->differ,
                    "a machine (its name: the file's stem) where the shipped model must lose, "
                    "repeatable");
  cross->add_option("--shipped", cmd->shipped, "the shipped model to compare with")
      ->required()
      ->check(CLI::ExistingFile);
  cross->add_option("--plan", cmd->plan, "l18x3 or lhsN (N Latin-hypercube moves)")
      ->capture_default_str();
  cross->add_option("--work", cmd->work, "keep every file here (default: a temporary folder)");
  add_reporting(cross, cmd->out);
  return {cross, [cmd] { return run_cross_machine(*cmd); }};
}

Command add_qualified_sweep(CLI::App& app, const std::string& command) {
  auto cmd = std::make_shared<SweepCommand>();
  cmd->out.command = command;
  CLI::App* sweep = app.add_subcommand(
      "qualified-sweep",
      "the length test's speed-up over a qualified machine: every setting of a grid, every seed, "
      "the model served in process (docs/planner.md, \"The qualified reference\")");
  sweep->add_option("--model", cmd->model, "the model (data/models/default-y.json)")
      ->required()
      ->check(CLI::ExistingFile);
  sweep->add_option("--machine", cmd->machine, "machine file (default: the embedded machine)")
      ->check(CLI::ExistingFile);
  sweep->add_option("--seeds", cmd->seeds, "noise seeds")->delimiter(',')->capture_default_str();
  sweep->add_option("--pv", cmd->grid.pv_mm_s, "PV values [mm/s]")
      ->delimiter(',')
      ->capture_default_str();
  sweep->add_option("--pd", cmd->grid.pd_mm, "PD values [mm]")
      ->delimiter(',')
      ->capture_default_str();
  sweep->add_option("--av", cmd->grid.av_mm_s, "AV values [mm/s]")
      ->delimiter(',')
      ->capture_default_str();
  sweep->add_option("--ad", cmd->grid.ad_mm, "AD values [mm]")
      ->delimiter(',')
      ->capture_default_str();
  add_reporting(sweep, cmd->out);
  return {sweep, [cmd] { return run_qualified_sweep(*cmd); }};
}

}  // namespace cmmcomp::tools::study

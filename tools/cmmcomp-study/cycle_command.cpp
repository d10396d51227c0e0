// SPDX-License-Identifier: MIT
/// @file cmmcomp-study cycle-speedup: the whole probing cycle's speed-up over a qualified machine
/// with the same controller freedom (study/cycle_speedup.hpp, docs/study.md).
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/study/cycle_speedup.hpp>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "reporting.hpp"

namespace cmmcomp::tools::study {
namespace {

struct CycleCommand {
  std::vector<std::string> machines, models;
  std::vector<double> pd_mm{20.0, 40.0, 80.0};
  std::vector<double> y_mm{0.0, 250.0, 500.0};
  std::string identify_start;
  int campaign_moves = 150;
  std::uint64_t campaign_seed = 1;
  Output out;
};

cmmcomp::dynamics::Machine machine_named(const std::string& spec) {
  return spec == "default" ? cmmcomp::dynamics::default_machine()
                           : cmmcomp::dynamics::load_machine(spec);
}

int run_cycle_speedup(const CycleCommand& cmd) {
  if (!cmd.models.empty() && cmd.models.size() != cmd.machines.size()) {
    throw ConfigError("give one --model per --machine (\"none\" for a machine without one)");
  }
  std::vector<cmmcomp::study::CycleSubject> subjects;
  for (std::size_t i = 0; i < cmd.machines.size(); ++i) {
    cmmcomp::study::CycleSubject s;
    s.truth = machine_named(cmd.machines[i]);
    if (!cmd.models.empty() && cmd.models[i] != "none") {
      s.has_model = true;
      s.model = machine_named(cmd.models[i]);
    }
    subjects.push_back(s);
  }
  cmmcomp::study::CycleRules rules;
  rules.y_mm = cmd.y_mm;
  const cmmcomp::study::RunOptions options = run_options();
  cmmcomp::study::CampaignIdentification campaign;
  if (!cmd.identify_start.empty()) {
    campaign.moves = cmd.campaign_moves;
    campaign.seed = cmd.campaign_seed;
    campaign.start = machine_named(cmd.identify_start);
  }
  const cmmcomp::study::CycleSpeedupResult r =
      cmmcomp::study::cycle_speedup(subjects,
                                    cmd.pd_mm,
                                    rules,
                                    cmd.identify_start.empty() ? nullptr : &campaign,
                                    options.progress);
  return finish(cmmcomp::study::cycle_speedup_document(r), r.targets, cmd.out);
}

}  // namespace

Command add_cycle_speedup(CLI::App& app, const std::string& command) {
  auto cmd = std::make_shared<CycleCommand>();
  cmd->out.command = command;
  CLI::App* sub = app.add_subcommand(
      "cycle-speedup",
      "the whole probing cycle: the fastest cycle (every controller setting the machine allows) "
      "of the qualified uncompensated machine against the compensated one, on the twin");
  sub->add_option(
         "--machine", cmd->machines, "\"default\" or a machine file (the truth), repeatable")
      ->required();
  sub->add_option("--model",
                  cmd->models,
                  "the machine identified for each --machine, in order (\"none\": the oracle "
                  "only)");
  sub->add_option("--pd", cmd->pd_mm, "positioning distances [mm]")
      ->delimiter(',')
      ->capture_default_str();
  sub->add_option("--y", cmd->y_mm, "the program's carriage positions [mm]")
      ->delimiter(',')
      ->capture_default_str();
  sub->add_option(
      "--identify-from",
      cmd->identify_start,
      "identify each --machine without a --model from its own campaign, starting "
      "from this machine file (\"default\" or a file: data/machines/default-start.toml)");
  sub->add_option("--campaign-moves", cmd->campaign_moves, "moves of each campaign")
      ->check(CLI::Range(10, 200))
      ->capture_default_str();
  sub->add_option("--campaign-seed", cmd->campaign_seed, "each campaign's design and noise seed")
      ->capture_default_str();
  add_reporting(sub, cmd->out);
  return {sub, [cmd] { return run_cycle_speedup(*cmd); }};
}

}  // namespace cmmcomp::tools::study

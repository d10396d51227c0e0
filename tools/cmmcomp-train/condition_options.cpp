// SPDX-License-Identifier: MIT
/// @file The training-condition options of cmmcomp-train fit and conditions.
#include "condition_options.hpp"

#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/measure/conditions.hpp>
#include <cmmcomp/measure/extract.hpp>

namespace cmmcomp::tools::train {

void add_condition_options(CLI::App* cmd, ConditionOptions& c) {
  cmd->add_option("--campaign",
                  c.campaigns,
                  "the campaign summary (OUTPUT.summary.json of cmmcomp-measure extract) of the "
                  "data, repeatable: the model records its controller timing, axis and noise");
  cmd->add_option("--machine",
                  c.machine,
                  "machine file the data was simulated with, or 'default' (the embedded "
                  "machine): the model records its name and controller timing");
  cmd->add_option("--axis", c.axis, "the axis the moves ran on (x, y, z, ...)");
  cmd->add_option("--noise-floor",
                  c.noise_floor,
                  "the data's repeat noise per parameter: MPE,RPE,MAE,RAE [um], or 'table1' "
                  "(the twin's noise, the paper's Table 1)");
  cmd->add_option(
      "--pa", c.pa, "PA the data was taken at, LO or LO:HI [mm/s2] (default: the data's)");
  cmd->add_option(
      "--aa", c.aa, "AA the data was taken at, LO or LO:HI [mm/s2] (default: the data's)");
}

cmmcomp::io::TrainingConditions fit_conditions(const ConditionOptions& cmd,
                                               const std::vector<cmmcomp::DatasetRow>& rows) {
  namespace measure = cmmcomp::measure;
  measure::ConditionSources sources;
  for (const std::string& path : cmd.campaigns) {
    sources.campaigns.push_back(measure::read_extraction_summary(path));
  }
  if (!cmd.machine.empty()) {
    sources.machine = cmd.machine == "default" ? cmmcomp::dynamics::default_machine()
                                               : cmmcomp::dynamics::load_machine(cmd.machine);
    sources.machine_label = cmd.machine;
  }
  sources.axis = cmd.axis;
  if (!cmd.noise_floor.empty()) sources.noise_floor = measure::parse_noise_floor(cmd.noise_floor);
  if (!cmd.pa.empty()) sources.pa_mm_s2 = measure::parse_condition_range(cmd.pa, "--pa");
  if (!cmd.aa.empty()) sources.aa_mm_s2 = measure::parse_condition_range(cmd.aa, "--aa");
  return measure::training_conditions(rows, sources);
}

}  // namespace cmmcomp::tools::train

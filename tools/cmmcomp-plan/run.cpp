// SPDX-License-Identifier: MIT
/// @file cmmcomp-plan's run: the model(s), the machine and the request from the options, the
/// plan (cmmcomp::planning::plan_feeds) and its table, JSON or cmmcomp-vc settings.
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/io/default_model.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/planning/plan_report.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "commands.hpp"

namespace cmmcomp::tools::plan {

namespace planning = cmmcomp::planning;

int run(const Options& opt, bool y_given) {
  std::vector<planning::ModelAtY> per_y;
  for (const std::string& m : opt.model_at) per_y.push_back(planning::parse_model_at(m));
  const cmmcomp::io::CompensationModelFile model =
      opt.model.empty() ? cmmcomp::io::CompensationModelFile(cmmcomp::io::default_model_file())
                        : cmmcomp::io::load_compensation_model(opt.model);
  const cmmcomp::dynamics::Machine machine = opt.machine.empty()
                                                 ? cmmcomp::dynamics::default_machine()
                                                 : cmmcomp::dynamics::load_machine(opt.machine);
  for (const std::string& w : cmmcomp::dynamics::implausible_parameters(machine.parameters)) {
    std::fprintf(stderr, "warning: %s: %s\n", opt.machine.c_str(), w.c_str());
  }
  planning::PlanRequest request;
  request.budget.budget_um = opt.budget_um;
  request.budget.share = opt.share;
  request.budget.length_mm = opt.length_mm;
  if (opt.budget_um <= 0) planning::parse_mpe_e(opt.mpe_e, request.budget);
  planning::PlanProblem& p = request.problem;
  p.mae_limit_um = opt.mae_limit_um;
  p.pv_mm_s = planning::parse_interval(opt.pv, "--pv");
  p.av_mm_s = planning::parse_interval(opt.av, "--av");
  p.pa_mm_s2 = planning::parse_interval(opt.pa, "--pa");
  p.aa_mm_s2 = planning::parse_interval(opt.aa, "--aa");
  p.pd_mm = planning::parse_interval(opt.pd, "--pd");
  p.ad_mm = planning::parse_interval(opt.ad, "--ad");
  p.y_mm = planning::parse_number_list(opt.y, "--y");
  p.z_mm = opt.z_mm;
  p.grid_points = opt.grid;
  p.coverage = opt.coverage;
  p.edge_margin = opt.edge_margin;
  if (!opt.reversal_map.empty()) {
    p.qualified = planning::parse_reversal_map(opt.reversal_map, opt.sphere_y_mm);
  }
  request.y_given = y_given;
  if (opt.trained_pa_given) request.given.pa_mm_s2 = opt.trained_pa;
  if (opt.trained_aa_given) request.given.aa_mm_s2 = opt.trained_aa;
  if (!opt.machine.empty()) {
    planning::restrict_to_capabilities(p, machine.capabilities, opt.machine);
    request.given.dwell_s = machine.parameters.controller_dwell_s;
    request.given.smoothing_s = machine.parameters.controller_smoothing_s;
    request.given.machine_label = "the controller of " + opt.machine;
  }
  request.brute_force_points = opt.brute_force;

  const planning::PlanReport report = planning::plan_feeds(model, per_y, request);
  if (!report.corner_aware && p.edge_margin == 0) {
    std::fprintf(stderr,
                 "cmmcomp-plan: note: this model's interval has no corner gain (a format-2 file, "
                 "or a fit whose residuals did not grow towards the corners), so its U95 may be "
                 "too narrow in the corners where the fastest settings lie; --edge-margin 0.2 "
                 "keeps clear of them (docs/planner.md)\n");
  }
  if (!opt.vc_settings.empty()) {
    cmmcomp::io::write_file_atomically(opt.vc_settings, planning::format_vc_settings(report));
  }
  if (opt.json) {
    std::printf("%s\n", planning::format_plan_json(report).c_str());
  } else {
    std::printf("%s", planning::format_plan_table(report).c_str());
  }
  return report.compensated.found ? 0 : 1;
}

}  // namespace cmmcomp::tools::plan

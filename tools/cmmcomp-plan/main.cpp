// SPDX-License-Identifier: MIT
/// @file cmmcomp-plan: the feed planner (docs/planner.md). From a model with its U95, a point
/// error budget, the machine's limits and the feature's geometry, the fastest probing setting
/// with compensation and the fastest without, their times per point and the ratio.
#include <CLI/CLI.hpp>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/default_model.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/planning/plan_report.hpp>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "../common/usage.hpp"

namespace {

namespace planning = cmmcomp::planning;

struct Options {
  std::string model;
  std::vector<std::string> model_at;  // Y=PATH, a model per Y
  double budget_um = 0.0;
  std::string mpe_e = "1.9,300";
  double length_mm = 20.0;
  double share = 0.5;
  double mae_limit_um = 25.0;
  std::string pv = "0:1e9";
  std::string av = "0:1e9";
  std::string pa = "0:1e9";
  std::string aa = "0:1e9";
  std::string pd = "0:1e9";
  std::string ad = "0:1e9";
  std::string y = "250";
  double z_mm = 0.0;
  std::string machine;
  int grid = 11;
  double edge_margin = 0.0;
  int brute_force = 0;
  double trained_pa = 200.0;
  double trained_aa = 60.0;
  bool trained_pa_given = false, trained_aa_given = false;
  double coverage = 0.95;
  std::string vc_settings;
  bool json = false;
  std::string reversal_map;  // Y=UM,…: the qualified reference's map (cmmcomp-vc --qualify)
  double sphere_y_mm = 250.0;
};

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

}  // namespace

static int run_tool(int argc, char** argv) {
  CLI::App app{
      "cmmcomp-plan: the fastest probing setting whose point error meets a budget at a coverage "
      "(95 %), with "
      "the model's correction and without it (docs/planner.md)."};
  Options opt;
  auto* one_model = app.add_option("--model",
                                   opt.model,
                                   "model file with an interval calibration (default: the "
                                   "shipped 4-input model)");
  app.add_option("--model-at",
                 opt.model_at,
                 "Y=PATH: a model per carriage position (repeat it: one trained at each Y); the "
                 "setting is judged at each Y by its model, and --y defaults to these Y")
      ->excludes(one_model);
  auto* budget =
      app.add_option("--budget-um", opt.budget_um, "point error budget [µm] (instead of --mpe-e)")
          ->check(CLI::PositiveNumber);
  app.add_option("--coverage",
                 opt.coverage,
                 "the coverage the budget is stated at; every model's interval must have been "
                 "calibrated at it (cmmcomp-train fit --interval-coverage)")
      ->check(CLI::Range(0.5, 0.999))
      ->capture_default_str();
  auto* mpe_e =
      app.add_option("--mpe-e", opt.mpe_e, "A,K of MPE_E = A + L/K µm")->capture_default_str();
  auto* length = app.add_option("--length", opt.length_mm, "length L of the MPE_E budget [mm]")
                     ->capture_default_str();
  auto* share =
      app.add_option("--share",
                     opt.share,
                     "share of MPE_E(L) one point may use (0.5: a bidirectional length's two "
                     "touches)")
          ->capture_default_str();
  budget->excludes(mpe_e)->excludes(length)->excludes(share);
  app.add_option("--mae-limit-um", opt.mae_limit_um, "bound on |MAE| + U95(MAE) [µm]")
      ->capture_default_str();
  app.add_option("--pv", opt.pv, "the machine's PV range LO:HI [mm/s]")->capture_default_str();
  app.add_option("--av", opt.av, "the machine's AV range LO:HI [mm/s]")->capture_default_str();
  app.add_option("--pa", opt.pa, "the machine's PA range LO:HI [mm/s²]")->capture_default_str();
  app.add_option("--aa", opt.aa, "the machine's AA range LO:HI [mm/s²]")->capture_default_str();
  app.add_option("--pd", opt.pd, "PD the feature allows LO:HI [mm] (LO: its minimum)")
      ->capture_default_str();
  app.add_option("--ad", opt.ad, "AD the feature allows LO:HI [mm] (LO: its minimum)")
      ->capture_default_str();
  auto* y_option = app.add_option("--y", opt.y, "carriage positions the setting must hold at [mm]")
                       ->capture_default_str();
  app.add_option("--z", opt.z_mm, "ram position [mm]")->capture_default_str();
  app.add_option("--machine",
                 opt.machine,
                 "machine file whose controller dwell and smoothing count in the time per point "
                 "(default: those the model was trained at; it must agree with them)");
  app.add_option("--edge-margin",
                 opt.edge_margin,
                 "share of each model input's range kept clear at both ends, in [0, 0.45) "
                 "(docs/planner.md)")
      ->capture_default_str();
  app.add_option("--grid", opt.grid, "points per input of the global grid")
      ->capture_default_str()
      ->check(CLI::Range(2, 41));
  app.add_option("--brute-force",
                 opt.brute_force,
                 "also search an N^4 grid exhaustively and print its best (a check; 0: none)")
      ->check(CLI::Range(0, 41) & !CLI::IsMember({1}));
  CLI::Option* trained_pa =
      app.add_option("--trained-pa",
                     opt.trained_pa,
                     "PA to plan at [mm/s²], within the model's training range (default: the "
                     "highest the model file records; needed for a model that records none)")
          ->check(CLI::PositiveNumber);
  CLI::Option* trained_aa =
      app.add_option("--trained-aa",
                     opt.trained_aa,
                     "AA to plan at [mm/s²], within the model's training range (default: the "
                     "highest the model file records; needed for a model that records none)")
          ->check(CLI::PositiveNumber);
  app.add_option("--vc-settings",
                 opt.vc_settings,
                 "also write the two settings as cmmcomp-vc --fast/--slow values to FILE: lines "
                 "'compensated=…' and 'uncompensated=…' (a line only for a setting found)");
  auto* map = app.add_option(
      "--reversal-map",
      opt.reversal_map,
      "Y=UM,…: judge the uncompensated setting as a CMM with this static reversal map and its "
      "probe qualified at the measuring setting (cmmcomp-vc --qualify --map-only prints it; "
      "needs a model that sees Y; docs/planner.md, \"The qualified reference\")");
  app.add_option(
         "--sphere-y", opt.sphere_y_mm, "with --reversal-map: the reference sphere's Y [mm]")
      ->capture_default_str()
      ->needs(map);
  app.add_flag("--json", opt.json, "print the result as JSON");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cmmcomp::tools::usage_exit(app, e);
  }
  opt.trained_pa_given = trained_pa->count() > 0;
  opt.trained_aa_given = trained_aa->count() > 0;
  try {
    return run(opt, y_option->count() > 0);
  } catch (const cmmcomp::ConfigError& e) {
    std::fprintf(stderr, "cmmcomp-plan: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cmmcomp-plan: %s\n", e.what());
    return 1;
  }
}

int main(int argc, char** argv) {
  return cmmcomp::tools::guarded_main("cmmcomp-plan", run_tool, argc, argv);
}

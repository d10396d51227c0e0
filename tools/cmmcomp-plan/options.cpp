// SPDX-License-Identifier: MIT
/// @file cmmcomp-plan's options: the model(s), the budget, the machine's limits, the feature and
/// the outputs.
#include <memory>

#include "commands.hpp"

namespace cmmcomp::tools::plan {

Command add_options(CLI::App& app) {
  auto opt = std::make_shared<Options>();
  auto* one_model = app.add_option("--model",
                                   opt->model,
                                   "model file with an interval calibration (default: the "
                                   "shipped 4-input model)");
  app.add_option("--model-at",
                 opt->model_at,
                 "Y=PATH: a model per carriage position (repeat it: one trained at each Y); the "
                 "setting is judged at each Y by its model, and --y defaults to these Y")
      ->excludes(one_model);
  auto* budget =
      app.add_option("--budget-um", opt->budget_um, "point error budget [µm] (instead of --mpe-e)")
          ->check(CLI::PositiveNumber);
  app.add_option("--coverage",
                 opt->coverage,
                 "the coverage the budget is stated at; every model's interval must have been "
                 "calibrated at it (cmmcomp-train fit --interval-coverage)")
      ->check(CLI::Range(0.5, 0.999))
      ->capture_default_str();
  auto* mpe_e =
      app.add_option("--mpe-e", opt->mpe_e, "A,K of MPE_E = A + L/K µm")->capture_default_str();
  auto* length = app.add_option("--length", opt->length_mm, "length L of the MPE_E budget [mm]")
                     ->capture_default_str();
  auto* share =
      app.add_option("--share",
                     opt->share,
                     "share of MPE_E(L) one point may use (0.5: a bidirectional length's two "
                     "touches)")
          ->capture_default_str();
  budget->excludes(mpe_e)->excludes(length)->excludes(share);
  app.add_option("--mae-limit-um", opt->mae_limit_um, "bound on |MAE| + U95(MAE) [µm]")
      ->capture_default_str();
  app.add_option("--pv", opt->pv, "the machine's PV range LO:HI [mm/s]")->capture_default_str();
  app.add_option("--av", opt->av, "the machine's AV range LO:HI [mm/s]")->capture_default_str();
  app.add_option("--pa", opt->pa, "the machine's PA range LO:HI [mm/s²]")->capture_default_str();
  app.add_option("--aa", opt->aa, "the machine's AA range LO:HI [mm/s²]")->capture_default_str();
  app.add_option("--pd", opt->pd, "PD the feature allows LO:HI [mm] (LO: its minimum)")
      ->capture_default_str();
  app.add_option("--ad", opt->ad, "AD the feature allows LO:HI [mm] (LO: its minimum)")
      ->capture_default_str();
  auto* y_option = app.add_option("--y", opt->y, "carriage positions the setting must hold at [mm]")
                       ->capture_default_str();
  app.add_option("--z", opt->z_mm, "ram position [mm]")->capture_default_str();
  app.add_option("--machine",
                 opt->machine,
                 "machine file whose controller dwell and smoothing count in the time per point "
                 "(default: those the model was trained at; it must agree with them), and whose "
                 "[capabilities] narrow --pv, --pa, --av, --aa and --ad");
  app.add_option("--edge-margin",
                 opt->edge_margin,
                 "share of each model input's range kept clear at both ends, in [0, 0.45) "
                 "(docs/planner.md)")
      ->capture_default_str();
  app.add_option("--grid", opt->grid, "points per input of the global grid")
      ->capture_default_str()
      ->check(CLI::Range(2, 41));
  app.add_option("--brute-force",
                 opt->brute_force,
                 "also search an N^4 grid exhaustively and print its best (a check; 0: none)")
      ->check(CLI::Range(0, 41) & !CLI::IsMember({1}));
  CLI::Option* trained_pa =
      app.add_option("--trained-pa",
                     opt->trained_pa,
                     "PA to plan at [mm/s²], within the model's training range (default: the "
                     "highest the model file records; needed for a model that records none)")
          ->check(CLI::PositiveNumber);
  CLI::Option* trained_aa =
      app.add_option("--trained-aa",
                     opt->trained_aa,
                     "AA to plan at [mm/s²], within the model's training range (default: the "
                     "highest the model file records; needed for a model that records none)")
          ->check(CLI::PositiveNumber);
  app.add_option("--vc-settings",
                 opt->vc_settings,
                 "also write the two settings as cmmcomp-vc --fast/--slow values to FILE: lines "
                 "'compensated=…' and 'uncompensated=…' (a line only for a setting found)");
  auto* map = app.add_option(
      "--reversal-map",
      opt->reversal_map,
      "Y=UM,…: judge the uncompensated setting as a CMM with this static reversal map and its "
      "probe qualified at the measuring setting (cmmcomp-vc --qualify --map-only prints it; "
      "needs a model that sees Y; docs/planner.md, \"The qualified reference\")");
  app.add_option(
         "--sphere-y", opt->sphere_y_mm, "with --reversal-map: the reference sphere's Y [mm]")
      ->capture_default_str()
      ->needs(map);
  app.add_flag("--json", opt->json, "print the result as JSON");
  return {&app, [opt, trained_pa, trained_aa, y_option] {
            opt->trained_pa_given = trained_pa->count() > 0;
            opt->trained_aa_given = trained_aa->count() > 0;
            return run(*opt, y_option->count() > 0);
          }};
}

}  // namespace cmmcomp::tools::plan

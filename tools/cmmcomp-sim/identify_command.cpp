// SPDX-License-Identifier: MIT
/// @file cmmcomp-sim identify: fit a machine file to measured moves (and the paper's tables) with
/// Ceres.
#include <unistd.h>

#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/training/machine_identification.hpp>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>

#include "commands.hpp"
#include "shared.hpp"

namespace cmmcomp::tools::sim {
namespace {

struct IdentifyCommand {
  std::string measured, machine_path, output, anova_targets, grid_mean_targets, free, fixed;
  bool magnitudes = false, cvode = false, fixed_given = false;
  int max_iterations = 50, threads = 0;
  double anova_y_mm = 250;
  double move_sigma_rel = 0.0, anova_sigma = 3.0, grid_sigma_rel = 0.05;
};

int run_identify(const IdentifyCommand& cmd) {
  using namespace cmmcomp::training;
  const cmmcomp::dynamics::Machine start = machine_from(cmd.machine_path);
  IdentificationTargets targets;
  targets.moves = cmmcomp::io::read_dataset_csv(cmd.measured);
  targets.compare_magnitudes = cmd.magnitudes;
  if (!cmd.anova_targets.empty()) {
    targets.anova = read_anova_targets(cmd.anova_targets);
    targets.anova.fixed.y_mm = cmd.anova_y_mm;
  }
  if (!cmd.grid_mean_targets.empty()) {
    targets.grid_mean = read_grid_mean_targets(cmd.grid_mean_targets);
    targets.grid_mean.fixed.y_mm = cmd.anova_y_mm;
  }
  targets.anova.sigma_pct = cmd.anova_sigma;
  targets.grid_mean.relative_sigma = cmd.grid_sigma_rel;
  IdentificationOptions options;
  options.relative_move_sigma = cmd.move_sigma_rel;
  options.max_iterations = cmd.max_iterations;
  options.cvode = cmd.cvode;
  options.threads = cmd.threads;
  if (!cmd.free.empty()) {
    std::istringstream names(cmd.free);
    std::string name;
    while (std::getline(names, name, ',')) options.free_parameters.push_back(name);
  }
  if (cmd.fixed_given) {
    options.fixed_parameters.clear();
    std::istringstream names(cmd.fixed == "none" ? std::string() : cmd.fixed);
    std::string name;
    while (std::getline(names, name, ',')) options.fixed_parameters.push_back(name);
  }
  // Progress on a terminal only (an identification takes minutes); quiet in logs and pipes.
  if (isatty(fileno(stderr)) != 0) {
    options.progress = [](int iteration, double cost) {
      std::fprintf(stderr, "cmmcomp-sim identify: iteration %3d  cost %.6g\n", iteration, cost);
    };
  }
  const IdentificationReport r = identify_machine(start, targets, options);
  std::printf("%s", format_identification_report(r, start.name, cmd.measured).c_str());
  for (const std::string& w : bound_warnings(r)) std::fprintf(stderr, "warning: %s\n", w.c_str());
  if (!r.usable) {
    std::fprintf(stderr, "cmmcomp-sim: the fit is not usable: %s\n", r.termination.c_str());
    return 1;
  }
  cmmcomp::io::write_file_atomically(cmd.output, cmmcomp::dynamics::format_machine(r.fitted));
  std::printf("\nwrote %s\n", cmd.output.c_str());
  return 0;
}

}  // namespace

Command add_identify(CLI::App& app) {
  auto id = std::make_shared<IdentifyCommand>();
  CLI::App* identify =
      app.add_subcommand("identify", "fit a machine file to measured moves (Ceres)");
  identify->add_option("measured", id->measured, "measured moves (dataset CSV schema)")->required();
  identify->add_option("--machine", id->machine_path, "start machine (default: embedded)");
  identify->add_option("-o,--output", id->output, "fitted machine file")->required();
  identify->add_option("--anova-targets",
                       id->anova_targets,
                       "also fit L18 ANOVA weights (CSV in the layout of the paper's Table 4)");
  identify->add_option("--grid-mean-targets",
                       id->grid_mean_targets,
                       "mean |value| targets over the full 3^4 grid (the paper's Table 5 CSV)");
  identify
      ->add_option("--anova-y", id->anova_y_mm, "carriage Y of the ANOVA and grid experiments [mm]")
      ->capture_default_str();
  identify->add_flag("--magnitudes", id->magnitudes, "measured RPE/RAE are magnitudes");
  identify
      ->add_option("--move-sigma-rel",
                   id->move_sigma_rel,
                   "weigh measured moves by this fraction of each value (0 = Table 1 sigmas)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  identify->add_option("--anova-sigma", id->anova_sigma, "ANOVA weight residual scale [points]")
      ->check(CLI::Range(0.1, 100.0))
      ->capture_default_str();
  identify
      ->add_option("--grid-sigma-rel", id->grid_sigma_rel, "grid-mean residual scale (fraction)")
      ->check(CLI::Range(0.001, 1.0))
      ->capture_default_str();
  identify->add_option("--free", id->free, "comma-separated section.key list to fit (default all)");
  CLI::Option* fixed = identify->add_option(
      "--fixed",
      id->fixed,
      "comma-separated section.key list never fitted, or 'none' (default: the controller "
      "timing, controller.dwell_s,controller.smoothing_s, which the recordings measure)");
  identify->add_option("--max-iterations", id->max_iterations, "Levenberg-Marquardt iterations")
      ->capture_default_str();
  identify->add_option("--threads", id->threads, "threads (0 = all cores)");
  identify->add_flag("--cvode",
                     id->cvode,
                     "simulate with CVODE (rtol 1e-6) instead of the exponential integrator: "
                     "about 10x slower, the path the shipped default machine was identified on");
  return {identify, [id, fixed] {
            id->fixed_given = fixed->count() > 0;
            return run_identify(*id);
          }};
}

}  // namespace cmmcomp::tools::sim

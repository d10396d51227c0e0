// SPDX-License-Identifier: MIT
/// @file cmmcomp-study interval-coverage (a shipped model's 95 % interval, held out, on unseen
/// machines, outside the domain and in the corners) and interval-calibration (the interval's
/// calibration plot).
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/study/interval_calibration.hpp>
#include <cmmcomp/study/interval_coverage.hpp>
#include <cmmcomp/study/recipe.hpp>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "reporting.hpp"

namespace cmmcomp::tools::study {
namespace {

using cmmcomp::study::Target;

struct CoverageCommand {
  std::string model, model_y, recipe;
  std::vector<std::string> variants;
  Output out;
};

int run_interval_coverage(const CoverageCommand& cmd) {
  const cmmcomp::study::CoverageResult r =
      cmmcomp::study::interval_coverage(cmmcomp::io::load_compensation_model(cmd.model),
                                        cmmcomp::io::load_compensation_model(cmd.model_y),
                                        cmmcomp::study::load_recipe(cmd.recipe),
                                        cmd.variants,
                                        run_options());
  return finish(cmmcomp::study::interval_coverage_document(r), r.targets, cmd.out);
}

struct CalibrationPlotCommand {
  std::string recipe, plot;
  std::vector<double> levels{0.50, 0.60, 0.70, 0.80, 0.90, 0.95, 0.99};
  Output out;
};

int run_interval_calibration(const CalibrationPlotCommand& cmd) {
  const cmmcomp::study::IntervalCalibrationResult r = cmmcomp::study::interval_calibration(
      cmmcomp::study::load_recipe(cmd.recipe), cmd.levels, run_options());
  if (!cmd.plot.empty()) {
    // The script goes to gnuplot's standard input: no file left behind, no shell.
    const std::string script = cmmcomp::study::interval_calibration_plot(r, cmd.plot);
    FILE* gnuplot = popen("gnuplot", "w");
    const bool written = gnuplot != nullptr &&
                         std::fwrite(script.data(), 1, script.size(), gnuplot) == script.size();
    if (gnuplot == nullptr || pclose(gnuplot) != 0 || !written) {
      std::fprintf(
          stderr, "warning: gnuplot could not draw %s (is gnuplot installed?)\n", cmd.plot.c_str());
    }
  }
  std::vector<Target> targets;  // a measurement, not a check
  return finish(cmmcomp::study::interval_calibration_document(r), targets, cmd.out);
}

}  // namespace

Command add_interval_coverage(CLI::App& app, const std::string& command) {
  auto cmd = std::make_shared<CoverageCommand>();
  cmd->out.command = command;
  CLI::App* coverage = app.add_subcommand(
      "interval-coverage",
      "the coverage of a shipped model's 95 % interval: held out, on unseen machines, outside the "
      "domain and at the corners of the box (docs/uncertainty.md)");
  coverage->add_option("--model", cmd->model, "the 4-input model")
      ->required()
      ->check(CLI::ExistingFile);
  coverage->add_option("--model-y", cmd->model_y, "the 5-input model (corners)")
      ->required()
      ->check(CLI::ExistingFile);
  coverage->add_option("--recipe", cmd->recipe, "the 4-input model's recipe (machine, test seeds)")
      ->required()
      ->check(CLI::ExistingFile);
  coverage->add_option("--variant", cmd->variants, "a machine file the model never saw, repeatable")
      ->check(CLI::ExistingFile);
  add_reporting(coverage, cmd->out);
  return {coverage, [cmd] { return run_interval_coverage(*cmd); }};
}

Command add_interval_calibration(CLI::App& app, const std::string& command) {
  auto cmd = std::make_shared<CalibrationPlotCommand>();
  cmd->out.command = command;
  CLI::App* calibration_plot = app.add_subcommand(
      "interval-calibration",
      "the interval's calibration plot: the recipe's network retrained at each nominal coverage, "
      "the empirical coverage on its held-out moves (docs/uncertainty.md)");
  calibration_plot->add_option("--recipe", cmd->recipe, "recipe file")
      ->required()
      ->check(CLI::ExistingFile);
  calibration_plot->add_option("--levels", cmd->levels, "nominal coverages in (0, 1)")
      ->delimiter(',')
      ->capture_default_str();
  calibration_plot->add_option("--plot", cmd->plot, "draw it to this PNG (gnuplot)");
  add_reporting(calibration_plot, cmd->out);
  return {calibration_plot, [cmd] { return run_interval_calibration(*cmd); }};
}

}  // namespace cmmcomp::tools::study

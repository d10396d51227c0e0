// SPDX-License-Identifier: MIT
/// @file cmmcomp-study: the project's experiments as C++ over the libraries (docs/study.md). Each
/// subcommand runs one cmmcomp::study experiment on the recipes it is given, prints its table
/// (or --json), judges its targets with one known-unmet list and checks (or writes) its block of
/// the results page; exit 1 when a target fails or the block is stale, 2 on a usage error.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cmmcomp/schema.hpp>
#include <cmmcomp/study/acceptance.hpp>
#include <cmmcomp/study/accuracy.hpp>
#include <cmmcomp/study/calibration.hpp>
#include <cmmcomp/study/cross_machine.hpp>
#include <cmmcomp/study/identify_multistart.hpp>
#include <cmmcomp/study/interval_calibration.hpp>
#include <cmmcomp/study/interval_coverage.hpp>
#include <cmmcomp/study/qualified_sweep.hpp>
#include <cmmcomp/study/recipe.hpp>
#include <cmmcomp/study/report.hpp>
#include <cmmcomp/study/train.hpp>
#include <cmmcomp/version.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "../common/usage.hpp"

namespace {

using cmmcomp::study::Document;
using cmmcomp::study::Target;

using Output = cmmcomp::study::ReportOptions;

/// Prints the experiment's publication and returns its exit status.
int finish(const Document& result, const std::vector<Target>& targets, const Output& out) {
  const cmmcomp::study::Publication p = cmmcomp::study::publish(result, targets, out);
  std::printf("%s\n", p.text.c_str());
  if (!p.note.empty()) std::fprintf(stderr, "%s\n", p.note.c_str());
  return p.status;
}

cmmcomp::study::RunOptions run_options() {
  cmmcomp::study::RunOptions o;
  if (isatty(fileno(stderr)) != 0) {
    o.progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  }
  return o;
}

int run_accuracy(const std::vector<std::string>& recipes, const Output& out) {
  std::vector<Target> targets;
  std::vector<cmmcomp::study::AccuracyResult> results;
  for (const std::string& path : recipes) {
    results.push_back(
        cmmcomp::study::fit_and_test(cmmcomp::study::load_recipe(path), run_options()));
    targets.insert(targets.end(), results.back().targets.begin(), results.back().targets.end());
  }
  return finish(cmmcomp::study::accuracy_document(results), targets, out);
}

int run_cell_interpolant(const std::vector<std::string>& recipes, const Output& out) {
  std::vector<Target> targets;
  std::vector<cmmcomp::study::CellInterpolantResult> results;
  for (const std::string& path : recipes) {
    results.push_back(
        cmmcomp::study::cell_interpolant(cmmcomp::study::load_recipe(path), run_options()));
    targets.insert(targets.end(), results.back().targets.begin(), results.back().targets.end());
  }
  return finish(cmmcomp::study::cell_interpolant_document(results), targets, out);
}

int run_dataset(const std::string& path,
                const std::string& part,
                std::uint64_t seed,
                bool seed_given,
                const std::string& output) {
  cmmcomp::study::Recipe recipe = cmmcomp::study::load_recipe(path);
  const cmmcomp::dynamics::Machine machine = cmmcomp::study::recipe_machine(recipe);
  std::vector<cmmcomp::DatasetRow> rows;
  if (part == "training") {
    if (seed_given) {
      for (auto& p : recipe.training) p.seed = seed;
    }
    rows = cmmcomp::study::training_rows(recipe, machine);
  } else {
    cmmcomp::study::DatasetPart test = recipe.test;
    if (seed_given) test.seed = seed;
    rows = cmmcomp::study::simulate_part(recipe, machine, test);
  }
  cmmcomp::io::write_dataset_csv(output, rows);
  std::printf(
      "wrote %zu rows (%s of %s) to %s\n", rows.size(), part.c_str(), path.c_str(), output.c_str());
  return 0;
}

int run_train(const std::string& path,
              const std::string& output,
              const std::string& data_out,
              const std::string& interval_folds) {
  const cmmcomp::study::Recipe recipe = cmmcomp::study::load_recipe(path);
  const auto rows = cmmcomp::study::training_rows(recipe, cmmcomp::study::recipe_machine(recipe));
  if (!data_out.empty()) cmmcomp::io::write_dataset_csv(data_out, rows);
  cmmcomp::study::FitOverrides overrides;
  if (!interval_folds.empty()) overrides.interval_folds = interval_folds;
  const cmmcomp::study::TrainedModel m = cmmcomp::study::train_model(recipe, rows, overrides);
  const std::string id =
      std::visit([&](const auto& f) { return cmmcomp::io::save_model_file(output, f); }, m.file);
  std::printf("trained %s on %zu moves of %s: %s\nwrote %s (model id %s)\n",
              cmmcomp::training::to_string(m.summary.method),
              m.samples,
              path.c_str(),
              m.summary.message.c_str(),
              output.c_str(),
              id.c_str());
  return 0;
}

int run_interval_coverage(const std::string& model,
                          const std::string& model_y,
                          const std::string& recipe,
                          const std::vector<std::string>& variants,
                          const Output& out) {
  const cmmcomp::study::CoverageResult r =
      cmmcomp::study::interval_coverage(cmmcomp::io::load_compensation_model(model),
                                        cmmcomp::io::load_compensation_model(model_y),
                                        cmmcomp::study::load_recipe(recipe),
                                        variants,
                                        run_options());
  return finish(cmmcomp::study::interval_coverage_document(r), r.targets, out);
}

int run_qualified_sweep(const std::string& model,
                        const std::string& machine,
                        const std::vector<std::uint64_t>& seeds,
                        const cmmcomp::study::SweepGrid& grid,
                        const Output& out) {
  const cmmcomp::dynamics::Machine m = machine.empty() ? cmmcomp::dynamics::default_machine()
                                                       : cmmcomp::dynamics::load_machine(machine);
  const cmmcomp::study::SweepResult r = cmmcomp::study::qualified_sweep(
      cmmcomp::io::load_compensation_model(model), m, seeds, grid, run_options());
  return finish(cmmcomp::study::qualified_sweep_document(r), r.targets, out);
}

int run_cross_machine(const std::vector<std::string>& machines,
                      const std::vector<std::string>& differ,
                      const std::string& shipped,
                      const std::string& plan,
                      const std::string& work,
                      const Output& out) {
  cmmcomp::study::CampaignSetup setup;
  cmmcomp::study::parse_campaign_plan(plan, setup);
  const std::vector<cmmcomp::study::StudyMachine> list =
      cmmcomp::study::study_machines(machines, differ);
  const cmmcomp::study::CrossMachineResult r = cmmcomp::study::cross_machine(
      list, cmmcomp::io::load_compensation_model(shipped), setup, work, run_options());
  return finish(cmmcomp::study::cross_machine_document(r), r.targets, out);
}

int run_calibration(const std::string& machine, std::uint64_t seed, int seeds, const Output& out) {
  const cmmcomp::dynamics::Machine m = machine.empty() ? cmmcomp::dynamics::default_machine()
                                                       : cmmcomp::dynamics::load_machine(machine);
  const cmmcomp::study::CalibrationResult r =
      cmmcomp::study::paper_calibration(m, seed, seeds, run_options());
  return finish(cmmcomp::study::calibration_document(r), r.targets, out);
}

int run_identify_multistart(const std::string& start,
                            const std::string& free,
                            const std::string& paper_dir,
                            int max_iterations,
                            const cmmcomp::study::MultistartPlan& plan,
                            const Output& out) {
  cmmcomp::study::PaperIdentification p = cmmcomp::study::paper_identification(paper_dir);
  std::istringstream names(free);
  for (std::string name; std::getline(names, name, ',');) p.options.free_parameters.push_back(name);
  p.options.max_iterations = max_iterations;
  const cmmcomp::study::MultistartResult r = cmmcomp::study::identify_multistart(
      cmmcomp::dynamics::load_machine(start), p.targets, p.options, plan, run_options());
  std::vector<Target> targets;  // a measurement, not a check
  return finish(cmmcomp::study::identify_multistart_document(r), targets, out);
}

int run_interval_calibration(const std::string& recipe,
                             const std::vector<double>& levels,
                             const std::string& plot,
                             const Output& out) {
  const cmmcomp::study::IntervalCalibrationResult r = cmmcomp::study::interval_calibration(
      cmmcomp::study::load_recipe(recipe), levels, run_options());
  if (!plot.empty()) {
    // The script goes to gnuplot's standard input: no file left behind, no shell.
    const std::string script = cmmcomp::study::interval_calibration_plot(r, plot);
    FILE* gnuplot = popen("gnuplot", "w");
    const bool written = gnuplot != nullptr &&
                         std::fwrite(script.data(), 1, script.size(), gnuplot) == script.size();
    if (gnuplot == nullptr || pclose(gnuplot) != 0 || !written) {
      std::fprintf(
          stderr, "warning: gnuplot could not draw %s (is gnuplot installed?)\n", plot.c_str());
    }
  }
  std::vector<Target> targets;  // a measurement, not a check
  return finish(cmmcomp::study::interval_calibration_document(r), targets, out);
}

/// Renders result documents (the JSON of `--json`) into the page's blocks.
int run_render(const std::vector<std::string>& documents, const Output& out) {
  int status = 0;
  for (const std::string& path : documents) {
    const Document doc = Document::parse(
        cmmcomp::io::read_file_bounded(path, "study document", std::uintmax_t{1} << 24),
        nullptr,
        false);
    if (doc.is_discarded()) {
      throw cmmcomp::ConfigError(path + ": not JSON (expected an experiment's --json output)");
    }
    cmmcomp::study::PageSync sync;
    try {
      sync = cmmcomp::study::sync_page(out.page, doc, out.update_page);
    } catch (const nlohmann::json::exception& e) {
      throw cmmcomp::ConfigError(path + ": not a study document: " + e.what());
    }
    if (!sync.current) {
      std::fprintf(
          stderr,
          "cmmcomp-study: %s the block \"%s\" of %s from %s\n",
          out.update_page ? "updated" : "stale:",
          (doc.contains("block") && doc["block"].is_string() ? doc["block"].get<std::string>()
                                                             : std::string())
              .c_str(),
          out.page.c_str(),
          path.c_str());
      if (!out.update_page) status = 1;
    }
  }
  return status;
}

}  // namespace

static int run_tool(int argc, char** argv) {
  CLI::App app{"cmmcomp-study: the project's experiments over the libraries (docs/study.md)"};
  app.set_version_flag("--version", std::string("cmmcomp ") + CMMCOMP_VERSION_STRING);
  app.require_subcommand(1);
  std::vector<std::string> recipes;
  Output out;
  out.command = cmmcomp::study::command_line(argc, argv);
  // The reporting options of every experiment: the known-unmet list, JSON, the results page.
  const auto reporting = [&out](CLI::App* sub) {
    sub->add_option("--known-unmet", out.known_unmet, "targets known to be unmet, one per line")
        ->check(CLI::ExistingFile);
    sub->add_flag("--json", out.json, "print the results and the verdict as JSON");
    sub->add_option("--page", out.page, "check this results page's block (docs/results.md)")
        ->check(CLI::ExistingFile);
    sub->add_flag("--update-page", out.update_page, "write the block instead of checking it")
        ->needs(sub->get_option("--page"));
    sub->add_option("--block", out.block, "the block's name (default: the experiment's)");
  };
  CLI::App* accuracy = app.add_subcommand(
      "accuracy",
      "train each recipe's network and test it: Table 5 and the interval's coverage per test, "
      "judged against the paper's reductions and 1.5 x the noise floor");
  CLI::App* cells = app.add_subcommand(
      "cell-interpolant",
      "what the (PV, PD) cell means of each recipe's three-level training design predict of RPE");
  for (CLI::App* sub : {accuracy, cells}) {
    sub->add_option("--recipe", recipes, "recipe file (data/recipes/*.toml), repeatable")
        ->required()
        ->check(CLI::ExistingFile);
    reporting(sub);
  }
  std::string recipe_path, part = "training", output;
  std::uint64_t seed = 0;
  CLI::App* dataset = app.add_subcommand("dataset", "simulate a recipe's training or test dataset");
  dataset->add_option("--recipe", recipe_path, "recipe file")->required()->check(CLI::ExistingFile);
  dataset->add_option("--part", part, "training or test")
      ->check(CLI::IsMember({"training", "test"}))
      ->capture_default_str();
  CLI::Option* seed_opt =
      dataset->add_option("--seed", seed, "another seed (every training part's, or the test's)");
  dataset->add_option("-o,--output", output, "dataset CSV")->required();
  std::string train_recipe, model_out, data_out, folds;
  CLI::App* train = app.add_subcommand(
      "train", "train a recipe's network as cmmcomp-train fit does, recording its conditions");
  train->add_option("--recipe", train_recipe, "recipe file")->required()->check(CLI::ExistingFile);
  train->add_option("-o,--output", model_out, "model file to write")->required();
  train->add_option("--data-out", data_out, "also write the training dataset CSV here");
  train->add_option("--interval-folds", folds, "override the recipe's (ridge, as-served, narrower)")
      ->check(CLI::IsMember({"ridge", "as-served", "narrower"}));
  std::string cov_model, cov_model_y, cov_recipe;
  std::vector<std::string> variants;
  CLI::App* coverage = app.add_subcommand(
      "interval-coverage",
      "the coverage of a shipped model's 95 % interval: held out, on unseen machines, outside the "
      "domain and at the corners of the box (docs/uncertainty.md)");
  coverage->add_option("--model", cov_model, "the 4-input model")
      ->required()
      ->check(CLI::ExistingFile);
  coverage->add_option("--model-y", cov_model_y, "the 5-input model (corners)")
      ->required()
      ->check(CLI::ExistingFile);
  coverage->add_option("--recipe", cov_recipe, "the 4-input model's recipe (machine, test seeds)")
      ->required()
      ->check(CLI::ExistingFile);
  coverage->add_option("--variant", variants, "a machine file the model never saw, repeatable")
      ->check(CLI::ExistingFile);
  reporting(coverage);
  std::string ic_recipe, ic_plot;
  std::vector<double> ic_levels{0.50, 0.60, 0.70, 0.80, 0.90, 0.95, 0.99};
  CLI::App* calibration_plot = app.add_subcommand(
      "interval-calibration",
      "the interval's calibration plot: the recipe's network retrained at each nominal coverage, "
      "the empirical coverage on its held-out moves (docs/uncertainty.md)");
  calibration_plot->add_option("--recipe", ic_recipe, "recipe file")
      ->required()
      ->check(CLI::ExistingFile);
  calibration_plot->add_option("--levels", ic_levels, "nominal coverages in (0, 1)")
      ->delimiter(',')
      ->capture_default_str();
  calibration_plot->add_option("--plot", ic_plot, "draw it to this PNG (gnuplot)");
  reporting(calibration_plot);
  std::string cal_machine;
  std::uint64_t cal_seed = 1;
  int cal_seeds = 1;
  CLI::App* calibration = app.add_subcommand(
      "calibration",
      "the twin against the paper's Tables 1, 2, 4, 5 and the smoothness requirement over noise "
      "seeds: every requirement must hold for all but one in 50 (docs/machine-model.md)");
  calibration->add_option("--machine", cal_machine, "machine file (default: the embedded machine)")
      ->check(CLI::ExistingFile);
  calibration->add_option("--seed", cal_seed, "the first noise seed")->capture_default_str();
  calibration->add_option("--seeds", cal_seeds, "noise seeds")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  reporting(calibration);
  std::string ms_start = "data/machines/default-start.toml", ms_paper = "data/paper";
  std::string ms_free =
      "structure.mode_frequency_hz,structure.participation,structure.shape_growth,"
      "hose.time_constant_s,hose.viscous_drag_Ns_per_m,hose.coulomb_drag_N,"
      "hose.coulomb_speed_m_per_s,hose.accel_lag_s2,controller.dwell_s,controller.smoothing_s";
  int ms_iterations = 40;
  cmmcomp::study::MultistartPlan ms_plan;
  CLI::App* multistart = app.add_subcommand(
      "identify-multistart",
      "how many minima the identification has: identify the machine against the paper's tables "
      "from N scaled starts and judge each fit's calibration (docs/machine-model.md, \"Cost\")");
  multistart->add_option("--start", ms_start, "start machine file")
      ->check(CLI::ExistingFile)
      ->capture_default_str();
  multistart->add_option("--free", ms_free, "the parameters fitted and scaled, comma-separated")
      ->capture_default_str();
  multistart->add_option("--paper-data", ms_paper, "folder of the paper's target tables")
      ->check(CLI::ExistingDirectory)
      ->capture_default_str();
  multistart->add_option("--starts", ms_plan.starts, "starts (0: the start file itself)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  multistart
      ->add_option("--spread", ms_plan.spread, "each start scales a parameter by 2^u, |u| <= this")
      ->capture_default_str();
  multistart->add_option("--seed", ms_plan.seed, "seed of the starts")->capture_default_str();
  multistart
      ->add_option("--max-iterations", ms_iterations, "Levenberg–Marquardt iterations per fit")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  multistart
      ->add_option(
          "--calibration-seeds", ms_plan.calibration_seeds, "noise seeds of each fit's calibration")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  reporting(multistart);
  std::vector<std::string> cm_machines, cm_differ;
  std::string cm_shipped, cm_plan = "l18x3", cm_work;
  CLI::App* cross = app.add_subcommand(
      "cross-machine",
      "the real-machine workflow on twins (plan, record, extract, fit, test), each machine's own "
      "model next to the shipped one (docs/training.md, \"Other machines\")");
  cross->add_option("--machine", cm_machines, "\"default\" or a machine file, repeatable")
      ->required();
  cross->add_option("--dynamics-differ",
                    cm_differ,
                    "a machine (its name: the file's stem) where the shipped model must lose, "
                    "repeatable");
  cross->add_option("--shipped", cm_shipped, "the shipped model to compare with")
      ->required()
      ->check(CLI::ExistingFile);
  cross->add_option("--plan", cm_plan, "l18x3 or lhsN (N Latin-hypercube moves)")
      ->capture_default_str();
  cross->add_option("--work", cm_work, "keep every file here (default: a temporary folder)");
  reporting(cross);
  std::string sweep_model, sweep_machine;
  std::vector<std::uint64_t> sweep_seeds{1, 2, 3, 4, 5};
  cmmcomp::study::SweepGrid grid;
  CLI::App* sweep = app.add_subcommand(
      "qualified-sweep",
      "the length test's speed-up over a qualified machine: every setting of a grid, every seed, "
      "the model served in process (docs/planner.md, \"The qualified reference\")");
  sweep->add_option("--model", sweep_model, "the model (data/models/default-y.json)")
      ->required()
      ->check(CLI::ExistingFile);
  sweep->add_option("--machine", sweep_machine, "machine file (default: the embedded machine)")
      ->check(CLI::ExistingFile);
  sweep->add_option("--seeds", sweep_seeds, "noise seeds")->delimiter(',')->capture_default_str();
  sweep->add_option("--pv", grid.pv_mm_s, "PV values [mm/s]")
      ->delimiter(',')
      ->capture_default_str();
  sweep->add_option("--pd", grid.pd_mm, "PD values [mm]")->delimiter(',')->capture_default_str();
  sweep->add_option("--av", grid.av_mm_s, "AV values [mm/s]")
      ->delimiter(',')
      ->capture_default_str();
  sweep->add_option("--ad", grid.ad_mm, "AD values [mm]")->delimiter(',')->capture_default_str();
  reporting(sweep);
  std::vector<std::string> documents;
  CLI::App* render = app.add_subcommand(
      "render", "render result documents (--json output) into their blocks of a results page");
  render->add_option("documents", documents, "result documents (JSON)")
      ->required()
      ->check(CLI::ExistingFile);
  render->add_option("--page", out.page, "the results page")->required()->check(CLI::ExistingFile);
  render->add_flag("--check", "fail when a block is stale instead of writing the page");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cmmcomp::tools::usage_exit(app, e);
  }
  try {
    if (accuracy->parsed()) return run_accuracy(recipes, out);
    if (cells->parsed()) return run_cell_interpolant(recipes, out);
    if (calibration_plot->parsed()) {
      return run_interval_calibration(ic_recipe, ic_levels, ic_plot, out);
    }
    if (multistart->parsed()) {
      return run_identify_multistart(ms_start, ms_free, ms_paper, ms_iterations, ms_plan, out);
    }
    if (calibration->parsed()) return run_calibration(cal_machine, cal_seed, cal_seeds, out);
    if (cross->parsed()) {
      return run_cross_machine(cm_machines, cm_differ, cm_shipped, cm_plan, cm_work, out);
    }
    if (sweep->parsed()) {
      return run_qualified_sweep(sweep_model, sweep_machine, sweep_seeds, grid, out);
    }
    if (render->parsed()) {
      out.update_page = render->count("--check") == 0;
      return run_render(documents, out);
    }
    if (train->parsed()) return run_train(train_recipe, model_out, data_out, folds);
    if (coverage->parsed()) {
      return run_interval_coverage(cov_model, cov_model_y, cov_recipe, variants, out);
    }
    return run_dataset(recipe_path, part, seed, seed_opt->count() > 0, output);
  } catch (const cmmcomp::ConfigError& e) {
    std::fprintf(stderr, "cmmcomp-study: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cmmcomp-study: %s\n", e.what());
    return 1;
  }
}

int main(int argc, char** argv) {
  return cmmcomp::tools::guarded_main("cmmcomp-study", run_tool, argc, argv);
}

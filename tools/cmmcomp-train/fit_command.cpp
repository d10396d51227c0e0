// SPDX-License-Identifier: MIT
/// @file cmmcomp-train fit: train the T-S network on a dataset CSV, write a model file.
#include <fmt/format.h>
#include <unistd.h>

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cmmcomp/io/sha256.hpp>
#include <cmmcomp/measure/conditions.hpp>
#include <cmmcomp/schema.hpp>
#include <cmmcomp/training/fnn_trainer.hpp>
#include <cmmcomp/training/trained_model_file.hpp>
#include <cmmcomp/version.hpp>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "condition_options.hpp"

namespace cmmcomp::tools::train {
namespace {

struct FitCommand {
  std::string data, output, method = "lm";
  int folds = 5;
  std::uint64_t seed = 1;
  double lambda = -1;
  int max_iterations = cmmcomp::training::FnnTrainingOptions{}.max_iterations;
  double interval_coverage = cmmcomp::training::FnnTrainingOptions{}.interval_coverage;
  std::string interval_folds =
      cmmcomp::training::to_string(cmmcomp::training::FnnTrainingOptions{}.interval_folds);
  std::string inputs = cmmcomp::training::input_set_name<cmmcomp::PaperInputs>();
  ConditionOptions conditions;
};

template <typename Inputs>
int run_fit(const FitCommand& cmd, const ConditionOptions& condition_options) {
  using namespace cmmcomp::training;
  const auto rows = cmmcomp::io::read_dataset_csv(cmd.data);
  if (rows.size() < static_cast<std::size_t>(cmd.folds)) {
    throw cmmcomp::ConfigError(
        fmt::format("{}: {} samples, fewer than the {} folds", cmd.data, rows.size(), cmd.folds));
  }
  const cmmcomp::io::TrainingConditions conditions = fit_conditions(condition_options, rows);
  if (!conditions.dwell_s || !conditions.smoothing_s) {
    std::fprintf(stderr,
                 "warning: cmmcomp-train: the model will not record the controller's dwell and "
                 "smoothing (no --campaign or --machine): cmmcomp-plan refuses to plan with it "
                 "unless given them; pass --campaign OUTPUT.summary.json (the extract's summary) "
                 "or --machine FILE|default (a twin's dataset)\n");
  }
  FnnTrainingOptions options;
  options.method =
      cmd.method == "gd" ? FnnMethod::kGradientDescent : FnnMethod::kLevenbergMarquardt;
  options.folds = cmd.folds;
  options.seed = cmd.seed;
  options.lambda = cmd.lambda;
  options.max_iterations = cmd.max_iterations;
  options.interval_coverage = cmd.interval_coverage;
  options.interval_folds = parse_interval_folds(cmd.interval_folds);
  if (isatty(fileno(stderr)) != 0) {
    options.progress = [](int iteration, double cost) {
      std::fprintf(stderr, "\riteration %4d  cost %.6g", iteration, cost);
    };
  }
  const auto result = train_network<Inputs>(rows, options);
  if (options.progress) std::fputc('\n', stderr);
  const TrainingSummary& s = result.summary;
  std::printf("%s",
              format_training_report(
                  s, result.interval, rows.size(), cmd.data, cmd.lambda < 0, cmd.interval_coverage)
                  .c_str());
  if (!s.usable()) {
    std::fprintf(stderr, "cmmcomp-train: the trained model is not usable: %s\n", s.message.c_str());
    return 1;
  }
  const cmmcomp::io::ModelFileOf<Inputs> file =
      model_file(result,
                 Provenance{cmmcomp::io::sha256_file_hex(cmd.data),
                            cmd.seed,
                            std::string("cmmcomp-train ") + CMMCOMP_VERSION_STRING},
                 conditions);
  std::printf("conditions: %s\n", cmmcomp::measure::describe_conditions(conditions).c_str());
  const std::string id = cmmcomp::io::save_model_file(cmd.output, file);
  std::printf("wrote %s (model id %s)\n", cmd.output.c_str(), id.c_str());
  return 0;
}

int run(const FitCommand& cmd) {
  // --inputs is one of the served sets' values (CLI11 checked it).
  int rc = 2;
  cmmcomp::for_each_input_set(cmmcomp::ServedInputSets{}, [&](auto set) {
    if (cmd.inputs == cmmcomp::training::input_set_name<decltype(set)>()) {
      rc = run_fit<decltype(set)>(cmd, cmd.conditions);
    }
  });
  return rc;
}

}  // namespace

Command add_fit(CLI::App& app) {
  auto cmd = std::make_shared<FitCommand>();
  CLI::App* fit = app.add_subcommand("fit", "train on a dataset CSV, write a model file");
  fit->add_option("data", cmd->data, "training dataset (docs/dataset-csv.md)")->required();
  fit->add_option("-o,--output", cmd->output, "model file (JSON)")->required();
  fit->add_option("--method", cmd->method, "lm (Ceres) or gd (the paper's)")
      ->check(CLI::IsMember({"lm", "gd"}))
      ->capture_default_str();
  fit->add_option("--folds", cmd->folds, "cross-validation folds")
      ->check(CLI::Range(2, 1000))
      ->capture_default_str();
  fit->add_option("--seed", cmd->seed, "seed (folds, GD start)")->capture_default_str();
  fit->add_option("--lambda", cmd->lambda, "ridge weight (default: chosen by CV)");
  fit->add_option("--max-iterations", cmd->max_iterations, "LM iterations")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  fit->add_option("--interval-coverage",
                  cmd->interval_coverage,
                  "nominal coverage of the calibrated prediction interval, in (0, 1); 0: none "
                  "(docs/uncertainty.md)")
      ->check(CLI::Range(0.0, 0.999))
      ->capture_default_str();
  fit->add_option("--interval-folds",
                  cmd->interval_folds,
                  "fold models of the interval's calibration: ridge (the ridge fits), as-served "
                  "(networks trained as the served one, one LM solve or GD run per fold) or "
                  "narrower (per output the narrower interval of the two; with --method gd the "
                  "same as as-served; docs/uncertainty.md)")
      ->check(CLI::IsMember({"ridge", "as-served", "narrower"}))
      ->capture_default_str();
  std::vector<std::string> served_inputs;
  cmmcomp::for_each_input_set(cmmcomp::ServedInputSets{}, [&](auto set) {
    served_inputs.push_back(cmmcomp::training::input_set_name<decltype(set)>());
  });
  fit->add_option("--inputs",
                  cmd->inputs,
                  "network inputs: pv,pd,av,ad (the paper's, 81 rules) or pv,pd,av,ad,y (with the "
                  "carriage position, 243 rules)")
      ->check(CLI::IsMember(served_inputs))
      ->capture_default_str();
  add_condition_options(fit, cmd->conditions);
  return {fit, [cmd] { return run(*cmd); }};
}

}  // namespace cmmcomp::tools::train

// SPDX-License-Identifier: MIT
/// @file cmmcomp-train: train the T-S network on a dataset, evaluate it (Table 5), export it.
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cmmcomp/measure/conditions.hpp>
#include <cmmcomp/measure/extract.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <cmmcomp/schema.hpp>
#include <cmmcomp/training/evaluation.hpp>
#include <cmmcomp/training/fnn_trainer.hpp>
#include <cmmcomp/training/trained_model_file.hpp>
#include <cmmcomp/version.hpp>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "../common/usage.hpp"

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
};

/// Where a model's training conditions come from (docs/model-file.md, "Conditions").
struct ConditionOptions {
  std::vector<std::string> campaigns;
  std::string machine, axis, noise_floor;
  std::string pa, aa;  ///< LO[:HI] [mm/s²]; empty: from the data
};

/// Adds the options of ConditionOptions to `cmd`.
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

/// The conditions the model records (measure/conditions.hpp) from the options.
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

template <typename Inputs>
int run_eval(const cmmcomp::io::ModelFileOf<Inputs>& file,
             const std::string& data,
             bool json,
             const std::string& plot,
             bool check) {
  const auto rows = cmmcomp::io::read_dataset_csv(data);
  const cmmcomp::training::TestSetEvaluation e =
      cmmcomp::training::evaluate_test_set<Inputs>(file.model, file.interval, rows, data);
  const cmmcomp::training::HeldOutCheck verdict = cmmcomp::training::held_out_check(
      e.table, e.coverage_pct, 100.0 * file.interval.coverage, e.samples);
  const cmmcomp::training::TestSetReportHeader header{
      file.model_id, Inputs::kCount, data, file.interval.coverage, file.format_version};
  const cmmcomp::training::HeldOutCheck* checked = check ? &verdict : nullptr;
  if (json) {
    std::printf("%s\n", cmmcomp::training::format_test_set_json(e, header, checked).c_str());
  } else {
    std::printf("%s", cmmcomp::training::format_test_set_report(e, header, checked).c_str());
  }
  const bool has_interval = file.interval.available();
  if (!plot.empty()) {
    // The paper's Fig. 5: measured, predicted and residual for 50 test samples per parameter.
    const std::string dat = plot + ".dat";
    const std::string gp = plot + ".gp";
    const cmmcomp::training::Fig5Plot fig =
        cmmcomp::training::fig5_plot(e.predictions,
                                     dat,
                                     plot,
                                     file.model_id,
                                     has_interval ? 100.0 * file.interval.coverage : 0.0);
    cmmcomp::io::write_file_atomically(dat, fig.data);
    cmmcomp::io::write_file_atomically(gp, fig.script);
    const std::string command = "gnuplot '" + gp + "'";
    if (std::system(command.c_str()) != 0) {
      throw cmmcomp::Error("gnuplot failed to draw " + plot + " (is gnuplot installed?)");
    }
    std::printf("wrote %s\n", plot.c_str());
  }
  return check && !verdict.passed ? 1 : 0;
}

}  // namespace

static int run_tool(int argc, char** argv) {
  CLI::App app{"cmmcomp-train: train, evaluate and export the T-S fuzzy network"};
  app.set_version_flag("--version", std::string("cmmcomp ") + CMMCOMP_VERSION_STRING);
  app.require_subcommand(1);

  FitCommand fit_cmd;
  CLI::App* fit = app.add_subcommand("fit", "train on a dataset CSV, write a model file");
  fit->add_option("data", fit_cmd.data, "training dataset (docs/dataset-csv.md)")->required();
  fit->add_option("-o,--output", fit_cmd.output, "model file (JSON)")->required();
  fit->add_option("--method", fit_cmd.method, "lm (Ceres) or gd (the paper's)")
      ->check(CLI::IsMember({"lm", "gd"}))
      ->capture_default_str();
  fit->add_option("--folds", fit_cmd.folds, "cross-validation folds")
      ->check(CLI::Range(2, 1000))
      ->capture_default_str();
  fit->add_option("--seed", fit_cmd.seed, "seed (folds, GD start)")->capture_default_str();
  fit->add_option("--lambda", fit_cmd.lambda, "ridge weight (default: chosen by CV)");
  fit->add_option("--max-iterations", fit_cmd.max_iterations, "LM iterations")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  fit->add_option("--interval-coverage",
                  fit_cmd.interval_coverage,
                  "nominal coverage of the calibrated prediction interval, in (0, 1); 0: none "
                  "(docs/uncertainty.md)")
      ->check(CLI::Range(0.0, 0.999))
      ->capture_default_str();
  fit->add_option("--interval-folds",
                  fit_cmd.interval_folds,
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
                  fit_cmd.inputs,
                  "network inputs: pv,pd,av,ad (the paper's, 81 rules) or pv,pd,av,ad,y (with the "
                  "carriage position, 243 rules)")
      ->check(CLI::IsMember(served_inputs))
      ->capture_default_str();
  ConditionOptions fit_conditions_opt;
  add_condition_options(fit, fit_conditions_opt);

  ConditionOptions set_conditions_opt;
  std::string conditions_model, conditions_output, conditions_data;
  CLI::App* set_conditions = app.add_subcommand(
      "conditions",
      "record the training conditions in a model file (e.g. one of format 3, which has none), "
      "the network unchanged; prints them for a model given alone");
  set_conditions->add_option("model", conditions_model, "model file")->required();
  set_conditions->add_option("-o,--output", conditions_output, "model file to write");
  set_conditions->add_option(
      "--data", conditions_data, "the model's training dataset: PA and AA from it");
  add_condition_options(set_conditions, set_conditions_opt);

  std::string model_path, data_path, plot_path, header_path, symbol = "cmmcomp_model";
  bool json = false;
  CLI::App* eval = app.add_subcommand("eval", "Table 5 of a model on a test dataset");
  eval->add_option("model", model_path, "model file")->required();
  eval->add_option("data", data_path, "test dataset")->required();
  eval->add_flag("--json", json, "print one JSON object keyed mpe rpe mae rae");
  eval->add_option("--plot", plot_path, "draw the paper's Fig. 5 to this PNG (gnuplot)");
  bool check = false;
  eval->add_flag("--check",
                 check,
                 "the held-out check: exit 1 unless every reduction reaches the paper's Table 5 "
                 "and every interval covers within 3 points of its nominal coverage (or the "
                 "binomial 2-sigma band of the sample count, if wider)");

  CLI::App* exp = app.add_subcommand(
      "export", "write a model as a constexpr C++ header or a C source for the firmware ABI");
  exp->add_option("model", model_path, "model file")->required();
  std::string c_source_path;
  std::string scalar = "double";
  auto* header_opt = exp->add_option("--header", header_path, "output: constexpr C++ header");
  auto* c_opt =
      exp->add_option("--c-source",
                      c_source_path,
                      "output: C99 source of a cmmcomp_fw_model (cmmcomp/compensator_fw.h)");
  header_opt->excludes(c_opt);
  exp->add_option("--symbol", symbol, "C or C++ name of the model")->capture_default_str();
  exp->add_option("--scalar", scalar, "precision of the exported parameters: double or float")
      ->check(CLI::IsMember({"double", "float"}))
      ->capture_default_str();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cmmcomp::tools::usage_exit(app, e);
  }
  try {
    if (fit->parsed()) {
      // --inputs is one of the served sets' values (CLI11 checked it).
      int rc = 2;
      cmmcomp::for_each_input_set(cmmcomp::ServedInputSets{}, [&](auto set) {
        if (fit_cmd.inputs == cmmcomp::training::input_set_name<decltype(set)>()) {
          rc = run_fit<decltype(set)>(fit_cmd, fit_conditions_opt);
        }
      });
      return rc;
    }
    if (set_conditions->parsed()) {
      auto any = cmmcomp::io::load_compensation_model(conditions_model);
      if (conditions_output.empty()) {
        std::printf(
            "%s: model %s, format %d: conditions: %s\n",
            conditions_model.c_str(),
            cmmcomp::io::model_id(any).c_str(),
            std::visit([](const auto& f) { return f.format_version; }, any),
            cmmcomp::measure::describe_conditions(cmmcomp::io::training_conditions(any)).c_str());
        return 0;
      }
      std::vector<cmmcomp::DatasetRow> rows;
      if (!conditions_data.empty()) {
        rows = cmmcomp::io::read_dataset_csv(conditions_data);
        const std::string recorded =
            std::visit([](const auto& f) { return f.training.data_file_sha256; }, any);
        const std::string hash = cmmcomp::io::sha256_file_hex(conditions_data);
        if (!recorded.empty() && recorded != hash) {
          throw cmmcomp::ConfigError(conditions_data +
                                     " is not the model's training data (SHA-256 " + hash +
                                     ", the model records " + recorded + ")");
        }
      } else if (set_conditions_opt.pa.empty() || set_conditions_opt.aa.empty()) {
        throw cmmcomp::ConfigError(
            "give --data (the training dataset) or both --pa and --aa: the model's PA and AA");
      }
      const cmmcomp::io::TrainingConditions c = fit_conditions(set_conditions_opt, rows);
      const std::string id = std::visit(
          [&](auto& file) {
            file.conditions = c;
            return cmmcomp::io::save_model_file(conditions_output, file);
          },
          any);
      std::printf("conditions: %s\nwrote %s (model id %s)\n",
                  cmmcomp::measure::describe_conditions(c).c_str(),
                  conditions_output.c_str(),
                  id.c_str());
      return 0;
    }
    if (eval->parsed() || exp->parsed()) {
      // Any input set the compensator serves; the file's names say which.
      const auto any = cmmcomp::io::load_compensation_model(model_path);
      if (eval->parsed()) {
        return std::visit(
            [&](const auto& file) { return run_eval(file, data_path, json, plot_path, check); },
            any);
      }
      if (header_path.empty() && c_source_path.empty()) {
        std::fprintf(stderr, "cmmcomp-train export: give --header or --c-source\n");
        return 2;
      }
      const bool c_source = !c_source_path.empty();
      const std::string text = std::visit(
          [&](const auto& file) {
            return c_source ? cmmcomp::io::export_model_c_source(file, symbol, scalar == "float")
                            : cmmcomp::io::export_model_header(file, symbol, scalar == "float");
          },
          any);
      const std::string& path = c_source ? c_source_path : header_path;
      cmmcomp::io::write_file_atomically(path, text);
      std::printf("wrote %s (model id %s)\n", path.c_str(), cmmcomp::io::model_id(any).c_str());
      return 0;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cmmcomp-train: %s\n", e.what());
    return 1;
  }
  return 0;
}

int main(int argc, char** argv) {
  return cmmcomp::tools::guarded_main("cmmcomp-train", run_tool, argc, argv);
}

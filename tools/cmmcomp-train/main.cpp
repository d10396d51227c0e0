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
#include <cmmcomp/measure/extract.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <cmmcomp/schema.hpp>
#include <cmmcomp/training/evaluation.hpp>
#include <cmmcomp/training/fnn_trainer.hpp>
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

/// The --inputs value of `Inputs`: its labels in lower case, comma separated ("pv,pd,av,ad").
template <typename Inputs>
std::string inputs_option(Inputs /*set*/ = {}) {
  std::string s;
  for (const char* label : Inputs::labels()) {
    if (!s.empty()) s += ',';
    for (const char* c = label; *c != '\0'; ++c) {
      s += static_cast<char>(std::tolower(static_cast<unsigned char>(*c)));
    }
  }
  return s;
}

struct FitCommand {
  std::string data, output, method = "lm";
  int folds = 5;
  std::uint64_t seed = 1;
  double lambda = -1;
  int max_iterations = cmmcomp::training::FnnTrainingOptions{}.max_iterations;
  double interval_coverage = cmmcomp::training::FnnTrainingOptions{}.interval_coverage;
  std::string interval_folds =
      cmmcomp::training::to_string(cmmcomp::training::FnnTrainingOptions{}.interval_folds);
  std::string inputs = inputs_option<cmmcomp::PaperInputs>();
};

/// Where a model's training conditions come from (docs/model-file.md, "Conditions").
struct ConditionOptions {
  std::vector<std::string> campaigns;
  std::string machine, axis, noise_floor;
  std::string pa, aa;  ///< LO[:HI] [mm/s²]; empty: from the data
};

/// "LO" or "LO:HI" → a range (0 < LO <= HI).
cmmcomp::io::ConditionRange parse_condition_range(const std::string& text, const char* option) {
  const auto number = [&](const std::string& t) {
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (t.empty() || *end != '\0' || !std::isfinite(v) || v <= 0) {
      throw cmmcomp::ConfigError(std::string(option) + ": '" + text +
                                 "' is not LO or LO:HI with 0 < LO <= HI [mm/s2]");
    }
    return v;
  };
  const auto colon = text.find(':');
  const cmmcomp::io::ConditionRange r =
      colon == std::string::npos ? cmmcomp::io::ConditionRange{number(text), number(text)}
                                 : cmmcomp::io::ConditionRange{number(text.substr(0, colon)),
                                                               number(text.substr(colon + 1))};
  if (r.lo > r.hi) {
    throw cmmcomp::ConfigError(std::string(option) + ": '" + text + "' has LO > HI");
  }
  return r;
}

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

/// The conditions the model records: PA and AA from the data, the controller timing and the
/// noise from the campaigns, or the timing and name from a machine file; --axis and
/// --noise-floor set theirs. ConfigError when two sources disagree.
cmmcomp::io::TrainingConditions fit_conditions(const ConditionOptions& cmd,
                                               const std::vector<cmmcomp::DatasetRow>& rows) {
  using cmmcomp::ConfigError;
  cmmcomp::io::TrainingConditions c = cmmcomp::io::dataset_conditions(rows);
  if (!cmd.pa.empty()) c.pa_mm_s2 = parse_condition_range(cmd.pa, "--pa");
  if (!cmd.aa.empty()) c.aa_mm_s2 = parse_condition_range(cmd.aa, "--aa");
  std::vector<cmmcomp::measure::CampaignSummary> summaries;
  for (const std::string& path : cmd.campaigns) {
    summaries.push_back(cmmcomp::measure::read_extraction_summary(path));
  }
  const cmmcomp::io::TrainingConditions from_campaigns =
      cmmcomp::measure::campaign_conditions(summaries);
  c.dwell_s = from_campaigns.dwell_s;
  c.smoothing_s = from_campaigns.smoothing_s;
  c.axis = from_campaigns.axis;
  c.noise_floor = from_campaigns.noise_floor;
  if (!cmd.machine.empty()) {
    const cmmcomp::dynamics::Machine m = cmd.machine == "default"
                                             ? cmmcomp::dynamics::default_machine()
                                             : cmmcomp::dynamics::load_machine(cmd.machine);
    c.machine = m.name;
    const auto take = [&](std::optional<double>& slot, double value, const char* what) {
      if (slot && std::abs(*slot - value) > 0.010) {
        throw ConfigError(fmt::format(
            "--machine {}: controller {} {} s, but the campaign ran with {} s: give the machine "
            "file the campaign's controller setting",
            cmd.machine,
            what,
            value,
            *slot));
      }
      if (!slot) slot = value;
    };
    take(c.dwell_s, m.parameters.controller_dwell_s, "dwell");
    take(c.smoothing_s, m.parameters.controller_smoothing_s, "smoothing");
  }
  if (!cmd.axis.empty()) {
    if (!c.axis.empty() && c.axis != cmd.axis) {
      throw ConfigError("--axis " + cmd.axis + ", but the campaign ran on axis " + c.axis);
    }
    c.axis = cmd.axis;
  }
  if (cmd.noise_floor == "table1") {
    c.noise_floor.assign(cmmcomp::paper::kTable1Std.begin(), cmmcomp::paper::kTable1Std.end());
  } else if (!cmd.noise_floor.empty()) {
    c.noise_floor.clear();
    std::stringstream list(cmd.noise_floor);
    for (std::string item; std::getline(list, item, ',');) {
      char* end = nullptr;
      const double v = std::strtod(item.c_str(), &end);
      if (item.empty() || *end != '\0' || !std::isfinite(v) || v < 0) {
        throw ConfigError("--noise-floor: '" + item + "' is not a number >= 0");
      }
      c.noise_floor.push_back(v);
    }
    if (c.noise_floor.size() != 4) {
      throw ConfigError("--noise-floor: expected 4 values (MPE, RPE, MAE, RAE [um]) or 'table1'");
    }
  }
  return c;
}

/// The conditions as one line for the user, "unknown" where the model will not know.
std::string describe(const cmmcomp::io::TrainingConditions& c) {
  const auto range = [](const std::optional<cmmcomp::io::ConditionRange>& r) {
    if (!r) return std::string("unknown");
    return r->lo == r->hi ? fmt::format("{:g}", r->lo) : fmt::format("{:g}..{:g}", r->lo, r->hi);
  };
  const auto value = [](const std::optional<double>& v) {
    return v ? fmt::format("{:g} s", *v) : std::string("unknown");
  };
  std::string noise = "unknown";
  if (!c.noise_floor.empty()) {
    noise = fmt::format("{:.3g}, {:.3g}, {:.3g}, {:.3g} um",
                        c.noise_floor[0],
                        c.noise_floor[1],
                        c.noise_floor[2],
                        c.noise_floor[3]);
  }
  return fmt::format(
      "PA {} mm/s2, AA {} mm/s2, dwell {}, smoothing {}, axis {}, machine {}, noise floor {}",
      range(c.pa_mm_s2),
      range(c.aa_mm_s2),
      value(c.dwell_s),
      value(c.smoothing_s),
      c.axis.empty() ? "unknown" : c.axis,
      c.machine.empty() ? "unknown" : c.machine,
      noise);
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
  for (const IntervalFolds f :
       {IntervalFolds::kRidge, IntervalFolds::kAsServed, IntervalFolds::kNarrower}) {
    if (cmd.interval_folds == to_string(f)) options.interval_folds = f;
  }
  if (isatty(fileno(stderr)) != 0) {
    options.progress = [](int iteration, double cost) {
      std::fprintf(stderr, "\riteration %4d  cost %.6g", iteration, cost);
    };
  }
  const auto result = train_network<Inputs>(rows, options);
  if (options.progress) std::fputc('\n', stderr);
  const TrainingSummary& s = result.summary;
  std::printf("trained %s on %zu samples of %s in %.2f s: %s\n",
              to_string(s.method),
              rows.size(),
              cmd.data.c_str(),
              s.wall_seconds,
              s.message.c_str());
  std::printf("lambda %.3g (%s), %d iterations, cost %.6g -> %.6g\n",
              s.lambda,
              cmd.lambda < 0 ? "chosen by cross-validation" : "fixed",
              s.iterations,
              s.initial_cost,
              s.final_cost);
  std::printf("prior (%zu design points):", s.design_points);
  for (std::size_t o = 0; o < s.prior.size() && o < 4; ++o) {
    std::printf("%s %s %s", o ? "," : "", cmmcomp::kErrors[o].label, s.prior[o].c_str());
  }
  std::printf("\n");
  // The interval's columns are named by its coverage: U95 at the default 0.95.
  const std::string u_name = fmt::format("U{:g}", 100.0 * cmd.interval_coverage);
  std::printf("%-6s %14s %14s %14s %14s %12s %12s %10s\n",
              "",
              "init RMSE um",
              "train RMSE um",
              "CV RMSE um",
              (u_name + " um").c_str(),
              (u_name + " gain").c_str(),
              "corner gain",
              (u_name + " folds").c_str());
  for (std::size_t o = 0; o < 4; ++o) {
    std::printf("%-6s %14.4f %14.4f %14.4f %14.4f %12.3f %12.3f %10s\n",
                cmmcomp::kErrors[o].label,
                s.init_train_rmse[o],
                s.train_rmse[o],
                s.cv_rmse[o],
                result.interval.half_width[o],
                result.interval.extrapolation_gain[o],
                result.interval.corner_gain[o],
                o < s.interval_folds.size() ? to_string(s.interval_folds[o]) : "-");
  }
  if (!s.usable()) {
    std::fprintf(stderr, "cmmcomp-train: the trained model is not usable: %s\n", s.message.c_str());
    return 1;
  }
  cmmcomp::io::ModelFileOf<Inputs> file;
  file.model = result.model;
  file.training.data_file_sha256 = cmmcomp::io::sha256_file_hex(cmd.data);
  file.training.method = to_string(s.method);
  file.training.lambda = s.lambda;
  file.training.cv_rmse = s.cv_rmse;
  file.training.trained_at = cmmcomp::io::utc_timestamp_now();
  file.training.seed = cmd.seed;
  file.training.tool_version = std::string("cmmcomp-train ") + CMMCOMP_VERSION_STRING;
  file.conditions = conditions;
  std::printf("conditions: %s\n", describe(conditions).c_str());
  file.interval = result.interval;
  if (result.interval.available()) {
    file.interval_method = interval_method(s.interval_folds);
    file.interval_samples = s.interval_samples;
  }
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
  constexpr int kInputs = Inputs::kCount;
  const auto rows = cmmcomp::io::read_dataset_csv(data);
  const cmmcomp::training::TestSetEvaluation e =
      cmmcomp::training::evaluate_test_set<Inputs>(file.model, file.interval, rows, data);
  const cmmcomp::training::TestSetPredictions& p = e.predictions;
  const std::size_t n = e.samples;
  const std::size_t outside = e.outside;
  const bool has_interval = file.interval.available();
  const auto coverage_pct = [&](std::size_t o) { return e.coverage_pct[o]; };
  std::array<double, 4> u_sum{};
  for (std::size_t o = 0; o < 4; ++o) {
    for (double u : p.half_width[o]) u_sum[o] += u;
  }
  const auto& t = e.table;
  const std::array<double, 4>& coverages = e.coverage_pct;
  const cmmcomp::training::HeldOutCheck verdict =
      cmmcomp::training::held_out_check(t, coverages, 100.0 * file.interval.coverage, n);
  if (json) {
    nlohmann::json j;
    for (std::size_t o = 0; o < 4; ++o) {
      j[cmmcomp::kErrors[o].key] = {{"mean_before_um", t[o].mean_before},
                                    {"mean_after_um", t[o].mean_after},
                                    {"reduction_pct", t[o].reduction_pct},
                                    {"var_after_um2", t[o].var_after},
                                    {"max_abs_residual_um", t[o].max_abs}};
      if (has_interval) {
        j[cmmcomp::kErrors[o].key]["coverage_pct"] = coverage_pct(o);
        j[cmmcomp::kErrors[o].key]["mean_u95_um"] = u_sum[o] / static_cast<double>(n);
      }
    }
    j["interval_coverage_nominal_pct"] = 100.0 * file.interval.coverage;
    if (check) {
      j["check"] = {{"passed", verdict.passed},
                    {"missed", verdict.missed},
                    {"coverage_band_pct", verdict.coverage_band_pct}};
    }
    j["samples"] = n;
    j["outside_domain"] = outside;
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf(
        "model %s (%d inputs) on %s: %zu samples (%zu outside the training ranges, "
        "clamped)\n",
        file.model_id.c_str(),
        kInputs,
        data.c_str(),
        n,
        outside);
    std::printf("Table 5 layout; in brackets the paper's Table 5\n");
    std::printf("%-5s %20s %20s %20s %20s %12s\n",
                "",
                "mean before um",
                "mean after um",
                "reduction %",
                "variance after um2",
                "max |res| um");
    for (std::size_t o = 0; o < 4; ++o) {
      std::printf("%-5s %11.3f (%6.3f) %11.3f (%6.3f) %11.1f (%6.1f) %11.3f (%6.3f) %12.3f\n",
                  cmmcomp::kErrors[o].label,
                  t[o].mean_before,
                  cmmcomp::paper::kTable5MeanBefore[o],
                  t[o].mean_after,
                  cmmcomp::paper::kTable5MeanAfter[o],
                  t[o].reduction_pct,
                  cmmcomp::paper::kTable5Reduction[o],
                  t[o].var_after,
                  cmmcomp::paper::kTable5VarianceAfter[o],
                  t[o].max_abs);
    }
    if (has_interval) {
      std::printf(
          "prediction interval (nominal coverage %.0f %%): measured within predicted +- U\n",
          100.0 * file.interval.coverage);
      for (std::size_t o = 0; o < 4; ++o) {
        std::printf("%-5s coverage %5.1f %%  mean U %.3f um\n",
                    cmmcomp::kErrors[o].label,
                    coverage_pct(o),
                    u_sum[o] / static_cast<double>(n));
      }
    } else {
      std::printf("prediction interval: the model has none (format version %d)\n",
                  file.format_version);
    }
  }
  if (check && !json) {
    std::printf(
        "held-out check (each reduction >= the paper's Table 5, each coverage within "
        "%.0f +- %.1f %% for %zu samples): %s%s\n",
        100.0 * file.interval.coverage,
        verdict.coverage_band_pct,
        n,
        verdict.passed ? "PASS" : "FAIL: ",
        verdict.missed.c_str());
  }
  if (!plot.empty()) {
    // The paper's Fig. 5: measured, predicted and residual for 50 test samples per parameter.
    const std::string dat = plot + ".dat";
    const std::string gp = plot + ".gp";
    const cmmcomp::training::Fig5Plot fig = cmmcomp::training::fig5_plot(
        p, dat, plot, file.model_id, has_interval ? 100.0 * file.interval.coverage : 0.0);
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
  cmmcomp::for_each_input_set(cmmcomp::ServedInputSets{},
                              [&](auto set) { served_inputs.push_back(inputs_option(set)); });
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
        if (fit_cmd.inputs == inputs_option(set)) {
          rc = run_fit<decltype(set)>(fit_cmd, fit_conditions_opt);
        }
      });
      return rc;
    }
    if (set_conditions->parsed()) {
      auto any = cmmcomp::io::load_compensation_model(conditions_model);
      if (conditions_output.empty()) {
        std::printf("%s: model %s, format %d: conditions: %s\n",
                    conditions_model.c_str(),
                    cmmcomp::io::model_id(any).c_str(),
                    std::visit([](const auto& f) { return f.format_version; }, any),
                    describe(cmmcomp::io::training_conditions(any)).c_str());
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
                  describe(c).c_str(),
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

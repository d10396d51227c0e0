// SPDX-License-Identifier: MIT
/// @file cmmcomp-study: the project's experiments as C++ over the libraries (docs/study.md). Each
/// subcommand runs one cmmcomp::study experiment on the recipes it is given, prints its table
/// (or --json) and judges its targets with one known-unmet list; exit 1 when the check fails.
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cmmcomp/schema.hpp>
#include <cmmcomp/study/acceptance.hpp>
#include <cmmcomp/study/accuracy.hpp>
#include <cmmcomp/study/interval_coverage.hpp>
#include <cmmcomp/study/recipe.hpp>
#include <cmmcomp/study/train.hpp>
#include <cmmcomp/version.hpp>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../common/usage.hpp"

namespace {

using cmmcomp::study::Target;

nlohmann::ordered_json targets_json(const std::vector<Target>& targets) {
  nlohmann::ordered_json a = nlohmann::ordered_json::array();
  for (const Target& t : targets) {
    a.push_back({{"name", t.name},
                 {"measured", t.measured},
                 {"limit", t.limit},
                 {"kind", t.kind == Target::Kind::kAtLeast ? "at least" : "at most"},
                 {"unit", t.unit},
                 {"met", t.met()},
                 {"known_unmet", t.known_unmet}});
  }
  return a;
}

/// Judges `targets`, prints the verdict (text) and returns the exit status.
int judge(std::vector<Target>& targets,
          const std::string& known_unmet_path,
          nlohmann::ordered_json* json) {
  const cmmcomp::study::KnownUnmet known = known_unmet_path.empty()
                                               ? cmmcomp::study::KnownUnmet{}
                                               : cmmcomp::study::read_known_unmet(known_unmet_path);
  const cmmcomp::study::Verdict v = cmmcomp::study::check(targets, known);
  if (json != nullptr) {
    (*json)["targets"] = targets_json(targets);
    (*json)["passed"] = v.passed;
    (*json)["failures"] = v.failures;
    std::printf("%s\n", json->dump(2).c_str());
  } else {
    for (const Target& t : targets) {
      if (t.known_unmet && !t.met()) std::printf("%s: known unmet, still unmet\n", t.name.c_str());
    }
    for (const std::string& f : v.failures) std::printf("FAIL: %s\n", f.c_str());
    std::printf(
        "%s: %s (%zu targets)\n", "cmmcomp-study", v.passed ? "PASS" : "FAIL", targets.size());
  }
  return v.passed ? 0 : 1;
}

cmmcomp::study::RunOptions run_options() {
  cmmcomp::study::RunOptions o;
  if (isatty(fileno(stderr)) != 0) {
    o.progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  }
  return o;
}

int run_accuracy(const std::vector<std::string>& recipes, const std::string& known, bool json) {
  std::vector<Target> targets;
  nlohmann::ordered_json j;
  j["experiment"] = "accuracy";
  j["tests"] = nlohmann::ordered_json::array();
  if (!json) {
    std::printf("%-36s %-4s %10s %10s %9s %9s  (limit: residual um, reduction %%)\n",
                "test",
                "",
                "before um",
                "after um",
                "reduct %",
                "cover %");
  }
  for (const std::string& path : recipes) {
    const cmmcomp::study::AccuracyResult r =
        cmmcomp::study::fit_and_test(cmmcomp::study::load_recipe(path), run_options());
    for (const auto& t : r.tests) {
      nlohmann::ordered_json test{{"label", t.label},
                                  {"recipe", r.recipe},
                                  {"train_seed", t.train_seed},
                                  {"test_seed", t.test_seed},
                                  {"train_samples", t.train_samples},
                                  {"test_samples", t.evaluation.samples},
                                  {"outside", t.evaluation.outside}};
      for (std::size_t p = 0; p < cmmcomp::kErrorCount; ++p) {
        const auto& row = t.evaluation.table[p];
        const double cov = t.evaluation.coverage_pct[p];
        test[cmmcomp::kErrors[p].key] = {
            {"mean_before_um", row.mean_before},
            {"mean_after_um", row.mean_after},
            {"reduction_pct", row.reduction_pct},
            {"coverage_pct", std::isfinite(cov) ? nlohmann::ordered_json(cov) : nullptr}};
        if (!json) {
          std::printf("%-36s %-4s %10.3f %10.3f %9.1f %9.1f\n",
                      p == 0 ? t.label.c_str() : "",
                      cmmcomp::kErrors[p].label,
                      row.mean_before,
                      row.mean_after,
                      row.reduction_pct,
                      cov);
        }
      }
      j["tests"].push_back(test);
    }
    targets.insert(targets.end(), r.targets.begin(), r.targets.end());
  }
  return judge(targets, known, json ? &j : nullptr);
}

int run_cell_interpolant(const std::vector<std::string>& recipes,
                         const std::string& known,
                         bool json) {
  std::vector<Target> targets;
  nlohmann::ordered_json j;
  j["experiment"] = "cell-interpolant";
  j["tests"] = nlohmann::ordered_json::array();
  for (const std::string& path : recipes) {
    const auto r =
        cmmcomp::study::cell_interpolant(cmmcomp::study::load_recipe(path), run_options());
    for (const auto& t : r.tests) {
      j["tests"].push_back({{"label", t.label},
                            {"rpe_mean_before_um", t.mean_before_um},
                            {"rpe_mean_after_um", t.mean_after_um},
                            {"rpe_reduction_pct", t.reduction_pct}});
      if (!json) {
        std::printf(
            "%s: RPE mean before %.3f um, cell interpolant mean |residual| %.3f um, "
            "reduction %.1f %%\n",
            t.label.c_str(),
            t.mean_before_um,
            t.mean_after_um,
            t.reduction_pct);
      }
    }
    targets.insert(targets.end(), r.targets.begin(), r.targets.end());
  }
  return judge(targets, known, json ? &j : nullptr);
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
                          const std::string& known,
                          bool json) {
  const cmmcomp::study::CoverageResult r =
      cmmcomp::study::interval_coverage(cmmcomp::io::load_compensation_model(model),
                                        cmmcomp::io::load_compensation_model(model_y),
                                        cmmcomp::study::load_recipe(recipe),
                                        variants,
                                        run_options());
  std::vector<Target> targets = r.targets;
  nlohmann::ordered_json j;
  j["experiment"] = "interval-coverage";
  j["model"] = r.model_id;
  j["model_y"] = r.model_y_id;
  j["rows"] = nlohmann::ordered_json::array();
  if (!json) {
    std::printf("model %s (5-input %s), nominal coverage 95 %%\n",
                r.model_id.c_str(),
                r.model_y_id.c_str());
    std::printf(
        "| test set | moves | outside domain | coverage %% (mean U95 µm) MPE | RPE | MAE | RAE "
        "|\n");
    std::printf("|---|---|---|---|---|---|---|\n");
  }
  for (const auto& row : r.rows) {
    nlohmann::ordered_json o{{"name", row.name}, {"moves", row.moves}, {"outside", row.outside}};
    std::string cells;
    for (std::size_t p = 0; p < cmmcomp::kErrorCount; ++p) {
      o[cmmcomp::kErrors[p].key] = {{"coverage_pct", row.coverage_pct[p]},
                                    {"mean_u95_um", row.mean_u95_um[p]}};
      cells += fmt::format(" | {:.1f} ({:.2f})", row.coverage_pct[p], row.mean_u95_um[p]);
    }
    j["rows"].push_back(o);
    if (!json)
      std::printf(
          "| %s | %zu | %zu%s |\n", row.name.c_str(), row.moves, row.outside, cells.c_str());
  }
  for (std::size_t p = 0; p < cmmcomp::kErrorCount; ++p) {
    j["pooled_coverage_pct"][cmmcomp::kErrors[p].key] = r.pooled_pct[p];
    if (!json) {
      std::printf("pooled over the held-out seeds: %s coverage %.1f %%\n",
                  cmmcomp::kErrors[p].key,
                  r.pooled_pct[p]);
    }
  }
  return judge(targets, known, json ? &j : nullptr);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"cmmcomp-study: the project's experiments over the libraries (docs/study.md)"};
  app.set_version_flag("--version", std::string("cmmcomp ") + CMMCOMP_VERSION_STRING);
  app.require_subcommand(1);
  std::vector<std::string> recipes;
  std::string known;
  bool json = false;
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
    sub->add_option("--known-unmet", known, "targets known to be unmet, one per line")
        ->check(CLI::ExistingFile);
    sub->add_flag("--json", json, "print the results and the verdict as JSON");
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
  coverage->add_option("--known-unmet", known, "targets known to be unmet, one per line")
      ->check(CLI::ExistingFile);
  coverage->add_flag("--json", json, "print the results and the verdict as JSON");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cmmcomp::tools::usage_exit(app, e);
  }
  try {
    if (accuracy->parsed()) return run_accuracy(recipes, known, json);
    if (cells->parsed()) return run_cell_interpolant(recipes, known, json);
    if (train->parsed()) return run_train(train_recipe, model_out, data_out, folds);
    if (coverage->parsed()) {
      return run_interval_coverage(cov_model, cov_model_y, cov_recipe, variants, known, json);
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

// SPDX-License-Identifier: MIT
/// @file cmmcomp-study dataset (a recipe's training or test dataset, simulated) and train (a
/// recipe's network, trained as cmmcomp-train fit does).
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cmmcomp/schema.hpp>
#include <cmmcomp/study/recipe.hpp>
#include <cmmcomp/study/train.hpp>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "commands.hpp"

namespace cmmcomp::tools::study {
namespace {

struct DatasetCommand {
  std::string recipe_path, part = "training", output;
  std::uint64_t seed = 0;
};

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

struct TrainCommand {
  std::string recipe, model_out, data_out, folds;
};

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

}  // namespace

Command add_dataset(CLI::App& app) {
  auto cmd = std::make_shared<DatasetCommand>();
  CLI::App* dataset = app.add_subcommand("dataset", "simulate a recipe's training or test dataset");
  dataset->add_option("--recipe", cmd->recipe_path, "recipe file")
      ->required()
      ->check(CLI::ExistingFile);
  dataset->add_option("--part", cmd->part, "training or test")
      ->check(CLI::IsMember({"training", "test"}))
      ->capture_default_str();
  CLI::Option* seed_opt = dataset->add_option(
      "--seed", cmd->seed, "another seed (every training part's, or the test's)");
  dataset->add_option("-o,--output", cmd->output, "dataset CSV")->required();
  return {dataset, [cmd, seed_opt] {
            return run_dataset(
                cmd->recipe_path, cmd->part, cmd->seed, seed_opt->count() > 0, cmd->output);
          }};
}

Command add_train(CLI::App& app) {
  auto cmd = std::make_shared<TrainCommand>();
  CLI::App* train = app.add_subcommand(
      "train", "train a recipe's network as cmmcomp-train fit does, recording its conditions");
  train->add_option("--recipe", cmd->recipe, "recipe file")->required()->check(CLI::ExistingFile);
  train->add_option("-o,--output", cmd->model_out, "model file to write")->required();
  train->add_option("--data-out", cmd->data_out, "also write the training dataset CSV here");
  train
      ->add_option(
          "--interval-folds", cmd->folds, "override the recipe's (ridge, as-served, narrower)")
      ->check(CLI::IsMember({"ridge", "as-served", "narrower"}));
  return {train,
          [cmd] { return run_train(cmd->recipe, cmd->model_out, cmd->data_out, cmd->folds); }};
}

}  // namespace cmmcomp::tools::study

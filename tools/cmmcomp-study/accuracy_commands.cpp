// SPDX-License-Identifier: MIT
/// @file cmmcomp-study accuracy (each recipe's network trained and tested against the paper's
/// Table 5) and cell-interpolant (what the (PV, PD) cell means of a recipe's design predict).
#include <cmmcomp/study/accuracy.hpp>
#include <cmmcomp/study/recipe.hpp>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "reporting.hpp"

namespace cmmcomp::tools::study {
namespace {

using cmmcomp::study::Target;

struct RecipesCommand {
  std::vector<std::string> recipes;
  Output out;
};

int run_accuracy(const RecipesCommand& cmd) {
  std::vector<Target> targets;
  std::vector<cmmcomp::study::AccuracyResult> results;
  for (const std::string& path : cmd.recipes) {
    results.push_back(
        cmmcomp::study::fit_and_test(cmmcomp::study::load_recipe(path), run_options()));
    targets.insert(targets.end(), results.back().targets.begin(), results.back().targets.end());
  }
  return finish(cmmcomp::study::accuracy_document(results), targets, cmd.out);
}

int run_cell_interpolant(const RecipesCommand& cmd) {
  std::vector<Target> targets;
  std::vector<cmmcomp::study::CellInterpolantResult> results;
  for (const std::string& path : cmd.recipes) {
    results.push_back(
        cmmcomp::study::cell_interpolant(cmmcomp::study::load_recipe(path), run_options()));
    targets.insert(targets.end(), results.back().targets.begin(), results.back().targets.end());
  }
  return finish(cmmcomp::study::cell_interpolant_document(results), targets, cmd.out);
}

/// The options of both: the recipes, then the reporting options.
std::shared_ptr<RecipesCommand> add_recipes(CLI::App* sub, const std::string& command) {
  auto cmd = std::make_shared<RecipesCommand>();
  cmd->out.command = command;
  sub->add_option("--recipe", cmd->recipes, "recipe file (data/recipes/*.toml), repeatable")
      ->required()
      ->check(CLI::ExistingFile);
  add_reporting(sub, cmd->out);
  return cmd;
}

}  // namespace

Command add_accuracy(CLI::App& app, const std::string& command) {
  CLI::App* accuracy = app.add_subcommand(
      "accuracy",
      "train each recipe's network and test it: Table 5 and the interval's coverage per test, "
      "judged against the paper's reductions and 1.5 x the noise floor");
  auto cmd = add_recipes(accuracy, command);
  return {accuracy, [cmd] { return run_accuracy(*cmd); }};
}

Command add_cell_interpolant(CLI::App& app, const std::string& command) {
  CLI::App* cells = app.add_subcommand(
      "cell-interpolant",
      "what the (PV, PD) cell means of each recipe's three-level training design predict of RPE");
  auto cmd = add_recipes(cells, command);
  return {cells, [cmd] { return run_cell_interpolant(*cmd); }};
}

}  // namespace cmmcomp::tools::study

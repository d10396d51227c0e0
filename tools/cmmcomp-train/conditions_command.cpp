// SPDX-License-Identifier: MIT
/// @file cmmcomp-train conditions: record the training conditions in a model file (the network
/// unchanged), or print them for a model given alone.
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cmmcomp/io/sha256.hpp>
#include <cmmcomp/measure/conditions.hpp>
#include <cmmcomp/schema.hpp>
#include <cstdio>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "commands.hpp"
#include "condition_options.hpp"

namespace cmmcomp::tools::train {
namespace {

struct ConditionsCommand {
  ConditionOptions conditions;
  std::string model, output, data;
};

int run_conditions(const ConditionsCommand& cmd) {
  auto any = cmmcomp::io::load_compensation_model(cmd.model);
  if (cmd.output.empty()) {
    std::printf(
        "%s: model %s, format %d: conditions: %s\n",
        cmd.model.c_str(),
        cmmcomp::io::model_id(any).c_str(),
        std::visit([](const auto& f) { return f.format_version; }, any),
        cmmcomp::measure::describe_conditions(cmmcomp::io::training_conditions(any)).c_str());
    return 0;
  }
  std::vector<cmmcomp::DatasetRow> rows;
  if (!cmd.data.empty()) {
    rows = cmmcomp::io::read_dataset_csv(cmd.data);
    const std::string recorded =
        std::visit([](const auto& f) { return f.training.data_file_sha256; }, any);
    const std::string hash = cmmcomp::io::sha256_file_hex(cmd.data);
    if (!recorded.empty() && recorded != hash) {
      throw cmmcomp::ConfigError(cmd.data + " is not the model's training data (SHA-256 " + hash +
                                 ", the model records " + recorded + ")");
    }
  } else if (cmd.conditions.pa.empty() || cmd.conditions.aa.empty()) {
    throw cmmcomp::ConfigError(
        "give --data (the training dataset) or both --pa and --aa: the model's PA and AA");
  }
  const cmmcomp::io::TrainingConditions c = fit_conditions(cmd.conditions, rows);
  const std::string id = std::visit(
      [&](auto& file) {
        file.conditions = c;
        return cmmcomp::io::save_model_file(cmd.output, file);
      },
      any);
  std::printf("conditions: %s\nwrote %s (model id %s)\n",
              cmmcomp::measure::describe_conditions(c).c_str(),
              cmd.output.c_str(),
              id.c_str());
  return 0;
}

}  // namespace

Command add_conditions(CLI::App& app) {
  auto cmd = std::make_shared<ConditionsCommand>();
  CLI::App* set_conditions = app.add_subcommand(
      "conditions",
      "record the training conditions in a model file (e.g. one of format 3, which has none), "
      "the network unchanged; prints them for a model given alone");
  set_conditions->add_option("model", cmd->model, "model file")->required();
  set_conditions->add_option("-o,--output", cmd->output, "model file to write");
  set_conditions->add_option(
      "--data", cmd->data, "the model's training dataset: PA and AA from it");
  add_condition_options(set_conditions, cmd->conditions);
  return {set_conditions, [cmd] { return run_conditions(*cmd); }};
}

}  // namespace cmmcomp::tools::train

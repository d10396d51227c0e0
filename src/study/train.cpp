// SPDX-License-Identifier: MIT
/// @file A recipe's network as a model file (include/cmmcomp/study/train.hpp).
#include <fmt/format.h>

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/io/sha256.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <cmmcomp/study/train.hpp>
#include <cmmcomp/training/trained_model_file.hpp>
#include <cmmcomp/version.hpp>

namespace cmmcomp::study {
namespace {

template <typename Inputs>
TrainedModel train_with(const Recipe& recipe,
                        const std::vector<DatasetRow>& rows,
                        const FitOverrides& overrides) {
  using namespace training;
  FnnTrainingOptions o;
  o.seed = recipe.fit.seed;
  if (recipe.fit.max_iterations) o.max_iterations = *recipe.fit.max_iterations;
  const std::optional<std::string> folds =
      overrides.interval_folds ? overrides.interval_folds : recipe.fit.interval_folds;
  if (folds) o.interval_folds = parse_interval_folds(*folds);
  if (overrides.interval_coverage) o.interval_coverage = *overrides.interval_coverage;
  auto result = train_network<Inputs>(rows, o);
  if (!result.summary.usable()) {
    throw Error(recipe.source + ": the trained network is not usable: " + result.summary.message);
  }
  io::TrainingConditions c = io::dataset_conditions(rows);
  const dynamics::Machine machine = recipe_machine(recipe);
  c.machine = machine.name;
  c.dwell_s = machine.parameters.controller_dwell_s;
  c.smoothing_s = machine.parameters.controller_smoothing_s;
  c.axis = recipe.axis;
  if (recipe.noise) c.noise_floor.assign(paper::kTable1Std.begin(), paper::kTable1Std.end());
  const io::ModelFileOf<Inputs> file =
      model_file(result,
                 Provenance{io::sha256_hex(io::format_dataset_csv(rows)),
                            recipe.fit.seed,
                            std::string("cmmcomp-study ") + CMMCOMP_VERSION_STRING},
                 c);
  // Through the file's text: the checksum and id are what a saved file has.
  TrainedModel out{io::parse_compensation_model(io::format_model_json(file), recipe.source),
                   result.summary,
                   rows.size()};
  return out;
}

}  // namespace

TrainedModel train_model(const Recipe& recipe,
                         const std::vector<DatasetRow>& rows,
                         const FitOverrides& overrides) {
  std::optional<TrainedModel> out;
  for_each_input_set(ServedInputSets{}, [&](auto set) {
    using Inputs = decltype(set);
    if (recipe.inputs == training::input_set_name<Inputs>())
      out = train_with<Inputs>(recipe, rows, overrides);
  });
  if (!out) {
    throw ConfigError(recipe.source + ": inputs '" + recipe.inputs +
                      "' are not an input set the compensator serves (pv,pd,av,ad or "
                      "pv,pd,av,ad,y)");
  }
  return std::move(*out);
}

}  // namespace cmmcomp::study

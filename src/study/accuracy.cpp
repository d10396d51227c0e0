// SPDX-License-Identifier: MIT
/// @file The accuracy experiments (include/cmmcomp/study/accuracy.hpp).
#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <cmmcomp/study/accuracy.hpp>
#include <cmmcomp/study/train.hpp>
#include <map>
#include <set>
#include <type_traits>
#include <variant>

#include "../training/fnn_prior.hpp"

namespace cmmcomp::study {
namespace {

/// The (training seed, test seed) pairs the recipe runs: its cases, or its training seed (the
/// first part's) with every test seed.
std::vector<std::pair<std::uint64_t, std::uint64_t>> pairs_of(const Recipe& recipe) {
  if (!recipe.cases.empty()) return recipe.cases;
  std::vector<std::pair<std::uint64_t, std::uint64_t>> pairs;
  for (const std::uint64_t t : recipe.test_seeds) {
    pairs.emplace_back(recipe.training.front().seed, t);
  }
  return pairs;
}

/// The recipe with every training part at `seed` (a case), or as it is.
Recipe reseeded(Recipe recipe, std::uint64_t seed) {
  if (!recipe.cases.empty()) {
    for (DatasetPart& p : recipe.training) p.seed = seed;
  }
  return recipe;
}

std::string label_of(const Recipe& recipe, std::uint64_t train_seed, std::uint64_t test_seed) {
  return fmt::format("{} train {} test {}", recipe.name, train_seed, test_seed);
}

}  // namespace

training::TestSetEvaluation evaluate_model_file(const io::CompensationModelFile& file,
                                                const std::vector<DatasetRow>& rows,
                                                const std::string& label) {
  return std::visit(
      [&](const auto& f) {
        using Inputs = typename std::decay_t<decltype(f)>::InputSet;
        return training::evaluate_test_set<Inputs>(f.model, f.interval, rows, label);
      },
      file);
}

AccuracyResult fit_and_test(const Recipe& recipe, const RunOptions& options) {
  AccuracyResult out;
  out.recipe = recipe.name;
  const dynamics::Machine machine = recipe_machine(recipe);
  const auto say = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  const auto pairs = pairs_of(recipe);
  // One network per distinct training seed.
  std::map<std::uint64_t, TrainedModel> networks;
  for (const auto& [train_seed, test_seed] : pairs) {
    (void)test_seed;
    if (networks.count(train_seed) != 0) continue;
    const Recipe r = reseeded(recipe, train_seed);
    const auto rows = training_rows(r, machine, options.threads);
    say(fmt::format("{}: training on {} moves (seed {})", recipe.name, rows.size(), train_seed));
    networks.emplace(train_seed, train_model(r, rows));
  }
  for (const auto& [train_seed, test_seed] : pairs) {
    DatasetPart test = recipe.test;
    test.seed = test_seed;
    const auto rows = simulate_part(recipe, machine, test, options.threads);
    AccuracyTest t;
    t.label = label_of(recipe, train_seed, test_seed);
    t.train_seed = train_seed;
    t.test_seed = test_seed;
    t.train_samples = networks.at(train_seed).samples;
    t.evaluation = evaluate_model_file(networks.at(train_seed).file, rows, t.label);
    say(t.label + ": tested on " + std::to_string(rows.size()) + " moves");
    for (Target& target : table5_targets(t.label + ": ",
                                         t.evaluation.table,
                                         recipe.acceptance.reduction,
                                         recipe.acceptance.residual_factor)) {
      out.targets.push_back(std::move(target));
    }
    out.tests.push_back(std::move(t));
  }
  return out;
}

CellInterpolantResult cell_interpolant(const Recipe& recipe, const RunOptions& options) {
  CellInterpolantResult out;
  out.recipe = recipe.name;
  const dynamics::Machine machine = recipe_machine(recipe);
  constexpr std::size_t kRpe = static_cast<std::size_t>(ErrorParameter::kRpe);
  for (const auto& [train_seed, test_seed] : pairs_of(recipe)) {
    const auto train = training_rows(reseeded(recipe, train_seed), machine, options.threads);
    std::set<double> pvs, pds;
    for (const DatasetRow& r : train) {
      pvs.insert(r.pv_mm_s);
      pds.insert(r.pd_mm);
    }
    if (pvs.size() != 3 || pds.size() != 3) {
      throw ConfigError(recipe.source + ": the cell interpolant needs three PV and three PD " +
                        "levels in the training data");
    }
    // The tensor quadratic through the nine (PV, PD) cell means is the least-squares tensor
    // quadratic over the samples (fnn_prior's shape over the two inputs), when every cell is
    // filled: training::fit_prior with its tiny ridge.
    const double pv_lo = *pvs.begin(), pv_span = *pvs.rbegin() - pv_lo;
    const double pd_lo = *pds.begin(), pd_span = *pds.rbegin() - pd_lo;
    std::set<std::pair<double, double>> cells;
    Eigen::MatrixXd x(static_cast<Eigen::Index>(train.size()), 2);
    Eigen::VectorXd z(static_cast<Eigen::Index>(train.size()));
    std::vector<Eigen::Index> rows;
    for (std::size_t k = 0; k < train.size(); ++k) {
      const auto i = static_cast<Eigen::Index>(k);
      x(i, 0) = (train[k].pv_mm_s - pv_lo) / pv_span;
      x(i, 1) = (train[k].pd_mm - pd_lo) / pd_span;
      z(i) = train[k].rpe_um;
      rows.push_back(i);
      cells.emplace(train[k].pv_mm_s, train[k].pd_mm);
    }
    if (cells.size() != 9) {
      throw ConfigError(recipe.source + ": a (PV, PD) cell of the training data is empty");
    }
    const training::detail::PriorShape shape{{0, 1}, {}};
    const Eigen::VectorXd c = training::detail::fit_prior(shape, x, z, rows);
    DatasetPart test = recipe.test;
    test.seed = test_seed;
    const auto tests = simulate_part(recipe, machine, test, options.threads);
    double before = 0, after = 0;
    for (const DatasetRow& r : tests) {
      const double xt[2] = {(r.pv_mm_s - pv_lo) / pv_span, (r.pd_mm - pd_lo) / pd_span};
      const double predicted = training::detail::prior_features(shape, xt).dot(c);
      before += std::abs(r.rpe_um);
      after += std::abs(r.rpe_um - predicted);
    }
    CellInterpolantTest t;
    t.label = label_of(recipe, train_seed, test_seed);
    t.mean_before_um = before / static_cast<double>(tests.size());
    t.mean_after_um = after / static_cast<double>(tests.size());
    t.reduction_pct = 100.0 * (1.0 - after / before);
    if (options.progress) options.progress(t.label + ": cell interpolant tested");
    out.targets.push_back({t.label + ": rpe_reduction",
                           t.reduction_pct,
                           paper::kTable5Reduction[kRpe],
                           Target::Kind::kAtLeast,
                           "%"});
    out.targets.push_back({t.label + ": rpe_residual",
                           t.mean_after_um,
                           recipe.acceptance.residual_factor * noise_floor_um(kRpe),
                           Target::Kind::kAtMost,
                           "um"});
    out.tests.push_back(t);
  }
  return out;
}

}  // namespace cmmcomp::study

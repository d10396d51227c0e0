// SPDX-License-Identifier: MIT
/// @file Training time of the T-S network on 54 samples of the twin: the paper's L18 × 3, where
/// the trainer keeps its ridge fit (18 design points cannot place the premise's 24 centres and
/// widths, fnn_trainer.hpp step 5), and 54 Latin-hypercube moves, where LM refines it.
#include <benchmark/benchmark.h>

#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/dynamics/dataset.hpp>
#include <cmmcomp/training/fnn_trainer.hpp>
#include <string>
#include <vector>

namespace {

using namespace cmmcomp;

training::Samples<4> twin_training_set(const doe::Design& design) {
  dynamics::DatasetOptions options;
  options.noise.enabled = true;
  options.noise.seed = 1;
  const auto rows = dynamics::simulate_dataset(
      dynamics::default_machine(), dynamics::rows_from_design(design, {}), options);
  return training::samples<cmmcomp::PaperInputs>(rows);
}

training::Samples<4> paper_training_set() {
  return twin_training_set(doe::replicate(doe::paper_l18_design(), 3));
}

// 54 distinct moves over the ranges of Table 3's levels, one each.
training::Samples<4> lhs_training_set() {
  std::vector<std::string> names;
  std::vector<double> lower, upper;
  for (const doe::Factor& f : doe::paper_table3_factors()) {
    names.push_back(f.name);
    lower.push_back(f.levels.front());
    upper.push_back(f.levels.back());
  }
  return twin_training_set(doe::latin_hypercube(names, lower, upper, 54, 1));
}

// The multi-output network (shared premise, MPE/RPE/MAE/RAE) with default options on `s`.
void train_four_outputs(benchmark::State& state, const training::Samples<4>& s) {
  training::FnnTrainingOptions options;
  for (auto _ : state) {
    auto r = training::train_fnn<4, 3, 4>(s.inputs, s.targets, options);
    benchmark::DoNotOptimize(r.model.params.values.data());
    state.counters["lm_iterations"] = r.summary.iterations;
  }
}

// On the L18 × 3: prior choice, CV and the interval's folds; no LM (lm_iterations reports 0).
void BM_TrainPaperInputs4Outputs(benchmark::State& state) {
  train_four_outputs(state, paper_training_set());
}
BENCHMARK(BM_TrainPaperInputs4Outputs)->Unit(benchmark::kMillisecond)->Iterations(3);

// On 54 Latin-hypercube moves: first-order prior, CV, 8 LM iterations, and five more LM solves
// for the interval's folds trained as served.
void BM_TrainPaperInputs4OutputsLhs54(benchmark::State& state) {
  train_four_outputs(state, lhs_training_set());
}
BENCHMARK(BM_TrainPaperInputs4OutputsLhs54)->Unit(benchmark::kMillisecond)->Iterations(3);

// The paper's form on the L18 × 3: four single-output networks, one after the other.
void BM_TrainFourPaperNetworks(benchmark::State& state) {
  const training::Samples<4> s = paper_training_set();
  training::FnnTrainingOptions options;
  for (auto _ : state) {
    for (std::size_t o = 0; o < 4; ++o) {
      std::vector<std::array<double, 1>> y;
      for (const auto& t : s.targets) y.push_back({t[o]});
      auto r = training::train_fnn<4, 3, 1>(s.inputs, y, options);
      benchmark::DoNotOptimize(r.model.params.values.data());
    }
  }
}
BENCHMARK(BM_TrainFourPaperNetworks)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

// SPDX-License-Identifier: MIT
/// @file Training time of the T-S network on the paper's 54 samples (L18 × 3 from the twin).
#include <benchmark/benchmark.h>

#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/dynamics/dataset.hpp>
#include <cmmcomp/training/fnn_trainer.hpp>

namespace {

using namespace cmmcomp;

training::Samples<4> paper_training_set() {
  dynamics::DatasetOptions options;
  options.noise.enabled = true;
  options.noise.seed = 1;
  const auto rows = dynamics::simulate_dataset(
      dynamics::default_machine(),
      dynamics::rows_from_design(doe::replicate(doe::paper_l18_design(), 3), {}),
      options);
  return training::samples<cmmcomp::PaperInputs>(rows);
}

// The multi-output network (shared premise, MPE/RPE/MAE/RAE), default options (CV + LM).
void BM_TrainPaperInputs4Outputs(benchmark::State& state) {
  const training::Samples<4> s = paper_training_set();
  training::FnnTrainingOptions options;
  for (auto _ : state) {
    auto r = training::train_fnn<4, 3, 4>(s.inputs, s.targets, options);
    benchmark::DoNotOptimize(r.model.params.values.data());
    state.counters["lm_iterations"] = r.summary.iterations;
  }
}
BENCHMARK(BM_TrainPaperInputs4Outputs)->Unit(benchmark::kMillisecond)->Iterations(3);

// The paper's form: four single-output networks, one after the other.
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

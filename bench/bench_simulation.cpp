// SPDX-License-Identifier: MIT
/// @file Cost of the digital twin: one baseline move, and the training + test datasets.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/dynamics/bridge_model.hpp>
#include <cmmcomp/dynamics/dataset.hpp>

namespace {

using namespace cmmcomp;

// One baseline move (PV 40, PD 40, AV 12, AD 10, Y 250) on one core; counters report CVODE work.
void BM_BaselineMove(benchmark::State& state) {
  dynamics::BridgeSimulator sim(dynamics::default_machine());
  dynamics::SimulationResult r;
  for (auto _ : state) {
    r = sim.simulate(motion::baseline_move(), 0.25);
    benchmark::DoNotOptimize(r.errors_um);
  }
  state.counters["cvode_steps"] = static_cast<double>(r.stats.steps);
  state.counters["rhs_evals"] = static_cast<double>(r.stats.rhs_evals);
  state.counters["root_evals"] = static_cast<double>(r.stats.root_evals);
}
BENCHMARK(BM_BaselineMove)->Unit(benchmark::kMillisecond);

// Cost against accuracy: the baseline move at rtol 10^-k (atol 10^-(k+3) m), k = state.range(0).
// max_dev_um is the largest change of the four parameters against rtol 1e-10 / atol 1e-13 m, so
// one run shows what each tolerance costs and buys.
void BM_BaselineMoveTolerance(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  dynamics::SimulationOptions tight;
  tight.integrator.relative_tolerance = 1e-10;
  tight.integrator.absolute_tolerance = 1e-13;
  const auto reference = dynamics::BridgeSimulator(dynamics::default_machine(), tight)
                             .simulate(motion::baseline_move(), 0.25);
  dynamics::SimulationOptions options;
  options.integrator.relative_tolerance = std::pow(10.0, -k);
  options.integrator.absolute_tolerance = std::pow(10.0, -(k + 3));
  dynamics::BridgeSimulator sim(dynamics::default_machine(), options);
  dynamics::SimulationResult r;
  for (auto _ : state) {
    r = sim.simulate(motion::baseline_move(), 0.25);
    benchmark::DoNotOptimize(r.errors_um);
  }
  double dev = 0.0;
  for (const auto member : {&errors::DynamicErrors::mpe,
                            &errors::DynamicErrors::rpe,
                            &errors::DynamicErrors::mae,
                            &errors::DynamicErrors::rae}) {
    dev = std::max(dev, std::abs(r.errors_um.*member - reference.errors_um.*member));
  }
  state.counters["cvode_steps"] = static_cast<double>(r.stats.steps);
  state.counters["rhs_evals"] = static_cast<double>(r.stats.rhs_evals);
  state.counters["max_dev_um"] = dev;
}
BENCHMARK(BM_BaselineMoveTolerance)->DenseRange(5, 8)->Unit(benchmark::kMillisecond);

// The slowest L18 corner: PV 100 over PD 80, AV 16 over AD 15.
void BM_FastMove(benchmark::State& state) {
  dynamics::BridgeSimulator sim(dynamics::default_machine());
  const motion::ProbingMove m{0.100, 0.200, 0.080, 0.016, 0.060, 0.015, 0.0};
  dynamics::SimulationResult r;
  for (auto _ : state) {
    r = sim.simulate(m, 0.25);
    benchmark::DoNotOptimize(r.errors_um);
  }
  state.counters["cvode_steps"] = static_cast<double>(r.stats.steps);
  state.counters["rhs_evals"] = static_cast<double>(r.stats.rhs_evals);
}
BENCHMARK(BM_FastMove)->Unit(benchmark::kMillisecond);

// The dataset pair: L18 × 3 (54 moves) plus a 270-sample Latin hypercube, with noise,
// on state.range(0) threads. Wall time is what counts (UseRealTime).
void BM_TrainingAndTestDatasets(benchmark::State& state) {
  const dynamics::Machine machine = dynamics::default_machine();
  const auto train = dynamics::rows_from_design(doe::replicate(doe::paper_l18_design(), 3), {});
  const auto factors = doe::paper_table3_factors();
  std::vector<std::string> names;
  std::vector<double> lo, hi;
  for (const auto& f : factors) {
    names.push_back(f.name);
    lo.push_back(f.levels.front());
    hi.push_back(f.levels.back());
  }
  const auto test = dynamics::rows_from_design(doe::latin_hypercube(names, lo, hi, 270, 7), {});
  dynamics::DatasetOptions options;
  options.threads = static_cast<int>(state.range(0));
  options.noise.enabled = true;
  for (auto _ : state) {
    auto a = dynamics::simulate_dataset(machine, train, options);
    auto b = dynamics::simulate_dataset(machine, test, options);
    benchmark::DoNotOptimize(a.data());
    benchmark::DoNotOptimize(b.data());
  }
}
BENCHMARK(BM_TrainingAndTestDatasets)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

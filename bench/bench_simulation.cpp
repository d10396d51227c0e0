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

// The largest change of the four parameters between two results [µm].
double max_deviation(const errors::DynamicErrors& a, const errors::DynamicErrors& b) {
  double dev = 0.0;
  for (const auto member : {&errors::DynamicErrors::mpe,
                            &errors::DynamicErrors::rpe,
                            &errors::DynamicErrors::mae,
                            &errors::DynamicErrors::rae}) {
    dev = std::max(dev, std::abs(a.*member - b.*member));
  }
  return dev;
}

// CVODE at rtol 1e-10 / atol 1e-13 m: the reference every accuracy counter is measured against.
dynamics::SimulationResult reference_baseline() {
  dynamics::SimulationOptions tight;
  tight.integration = dynamics::Integration::kCvode;
  tight.integrator.relative_tolerance = 1e-10;
  tight.integrator.absolute_tolerance = 1e-13;
  return dynamics::BridgeSimulator(dynamics::default_machine(), tight)
      .simulate(motion::baseline_move(), 0.25);
}

void report_work(benchmark::State& state, const dynamics::SimulationResult& r) {
  state.counters["steps"] = static_cast<double>(r.stats.steps);
  state.counters["rhs_evals"] = static_cast<double>(r.stats.rhs_evals);
  state.counters["root_evals"] = static_cast<double>(r.stats.root_evals);
  state.counters["expm"] = static_cast<double>(r.stats.matrix_exponentials);
}

/// Times the baseline move with `options` and reports its work and its distance to the
/// reference (max_dev_um, against CVODE at rtol 1e-10).
void time_baseline(benchmark::State& state, const dynamics::SimulationOptions& options) {
  const auto reference = reference_baseline();
  dynamics::BridgeSimulator sim(dynamics::default_machine(), options);
  dynamics::SimulationResult r;
  for (auto _ : state) {
    r = sim.simulate(motion::baseline_move(), 0.25);
    benchmark::DoNotOptimize(r.errors_um);
  }
  report_work(state, r);
  state.counters["max_dev_um"] = max_deviation(r.errors_um, reference.errors_um);
}

// One baseline move (PV 40, PD 40, AV 12, AD 10, Y 250) on one core with the default options
// (the exponential integrator).
void BM_BaselineMove(benchmark::State& state) { time_baseline(state, {}); }
BENCHMARK(BM_BaselineMove)->Unit(benchmark::kMillisecond);

// The same move with CVODE at its default tolerances (Integration::kCvode): the ratio to
// BM_BaselineMove in one run is the exponential integrator's speed-up.
void BM_BaselineMoveCvode(benchmark::State& state) {
  dynamics::SimulationOptions options;
  options.integration = dynamics::Integration::kCvode;
  time_baseline(state, options);
}
BENCHMARK(BM_BaselineMoveCvode)->Unit(benchmark::kMillisecond);

// Cost against accuracy of the exponential integrator: the baseline move with a longest step of
// state.range(0) µs.
void BM_BaselineMoveExponentialStep(benchmark::State& state) {
  dynamics::SimulationOptions options;
  options.exponential_max_step_s = static_cast<double>(state.range(0)) * 1e-6;
  time_baseline(state, options);
}
BENCHMARK(BM_BaselineMoveExponentialStep)
    ->Arg(250)
    ->Arg(500)
    ->Arg(1000)
    ->Arg(2000)
    ->Arg(4000)
    ->Unit(benchmark::kMillisecond);

// Cost against accuracy: the baseline move at rtol 10^-k (atol 10^-(k+3) m), k = state.range(0).
// max_dev_um is the largest change of the four parameters against rtol 1e-10 / atol 1e-13 m, so
// one run shows what each tolerance costs and buys.
void BM_BaselineMoveTolerance(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  dynamics::SimulationOptions options;
  options.integration = dynamics::Integration::kCvode;
  options.integrator.relative_tolerance = std::pow(10.0, -k);
  options.integrator.absolute_tolerance = std::pow(10.0, -(k + 3));
  time_baseline(state, options);
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
  report_work(state, r);
}
BENCHMARK(BM_FastMove)->Unit(benchmark::kMillisecond);

// One whole probing cycle at the oracle's setting of the whole-cycle study (PV 200, PA 1200,
// PD 40, AV 10, AA 300, AD 0.5, no dwell, smoothing one mode period, Y 500): what the grey-box
// model's prediction costs per request (vc::TwinSource), on the default machine's 6 states and,
// state.range(0) = 1, with a second mode (8 states).
void BM_WholeCycle(benchmark::State& state) {
  dynamics::Machine machine = dynamics::default_machine();
  if (state.range(0) == 1) {
    machine.parameters.mode2_participation = 0.25;
    machine.parameters.mode2_frequency_hz = 65.0;
    machine.parameters.mode_carriage_mass_share = 0.3;
  }
  dynamics::BridgeSimulator sim(machine);
  motion::ProbingMove cycle = motion::probing_move_mm(200, 1200, 40, 10, 300, 0.5);
  cycle.dwell = 0.0;
  cycle.smoothing = 1.0 / machine.parameters.mode_frequency_hz;
  dynamics::SimulationResult r;
  for (auto _ : state) {
    r = sim.simulate_cycle(cycle, 0.5);
    benchmark::DoNotOptimize(r.errors_um);
  }
  report_work(state, r);
}
BENCHMARK(BM_WholeCycle)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

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

// SPDX-License-Identifier: MIT
/// @file Cost of one RT evaluation of the paper's T-S network (81 rules), double and float.
#include <benchmark/benchmark.h>

#include <array>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cstddef>
#include <random>
#include <vector>

namespace {

namespace fz = cmmcomp::fuzzy;

constexpr std::size_t kInputSamples = 1024;  // a power of two, cycled through

// A random valid model in the paper's shape: ranges of the paper's move parameters [SI], set
// centres spread over [0, 1], widths around the set spacing, consequents of a few micrometres.
template <typename Scalar, int kOutputs>
fz::TskModel<Scalar, 4, 3, kOutputs> random_model(std::mt19937_64& rng) {
  fz::TskModel<Scalar, 4, 3, kOutputs> m;
  m.ranges = {fz::InputRange{0.01, 0.10},
              fz::InputRange{0.005, 0.20},
              fz::InputRange{0.002, 0.03},
              fz::InputRange{0.001, 0.02}};
  std::uniform_real_distribution<double> jitter(-0.1, 0.1);
  std::uniform_real_distribution<double> width(0.2, 0.5);
  std::uniform_real_distribution<double> coef(-5e-6, 5e-6);
  for (int i = 0; i < 4; ++i) {
    for (int s = 0; s < 3; ++s) {
      m.params.centre(i, s) = static_cast<Scalar>(0.5 * s + jitter(rng));
      m.params.width(i, s) = static_cast<Scalar>(width(rng));
    }
  }
  for (int o = 0; o < kOutputs; ++o) {
    for (int j = 0; j < m.kRules; ++j) {
      for (int k = 0; k < 5; ++k) m.params.consequent(o, j, k) = static_cast<Scalar>(coef(rng));
    }
  }
  return m;
}

// Inputs drawn over the training ranges, widened by `outside` of the range on each side.
template <typename Model>
std::vector<std::array<double, 4>> random_inputs(const Model& m,
                                                 std::mt19937_64& rng,
                                                 double outside) {
  std::vector<std::array<double, 4>> xs(kInputSamples);
  std::uniform_real_distribution<double> u(-outside, 1.0 + outside);
  for (auto& x : xs) {
    for (std::size_t i = 0; i < 4; ++i) {
      const fz::InputRange& r = m.ranges[i];
      x[i] = r.lo + u(rng) * (r.hi - r.lo);
    }
  }
  return xs;
}

template <typename Scalar, int kOutputs>
void run(benchmark::State& state, double outside, fz::DomainPolicy policy) {
  std::mt19937_64 rng(20190601u);
  const auto model = random_model<Scalar, kOutputs>(rng);
  const auto xs = random_inputs(model, rng, outside);
  std::array<double, kOutputs> y{};
  std::size_t k = 0;
  std::size_t failures = 0;
  for (auto _ : state) {
    const cmmcomp::Status s = fz::evaluate(model, xs[k], y, policy);
    failures += cmmcomp::ok(s) ? 0u : 1u;
    benchmark::DoNotOptimize(y);
    k = (k + 1) & (kInputSamples - 1);
  }
  if (failures != 0) state.SkipWithError("evaluate failed");
}

// The RT case: all four error parameters from one premise, inputs inside the domain.
void BM_Evaluate4OutputsDouble(benchmark::State& state) {
  run<double, 4>(state, 0.0, fz::DomainPolicy::kClamp);
}
void BM_Evaluate4OutputsFloat(benchmark::State& state) {
  run<float, 4>(state, 0.0, fz::DomainPolicy::kClamp);
}
// The paper's form: one output per network.
void BM_Evaluate1OutputDouble(benchmark::State& state) {
  run<double, 1>(state, 0.0, fz::DomainPolicy::kClamp);
}
void BM_Evaluate1OutputFloat(benchmark::State& state) {
  run<float, 1>(state, 0.0, fz::DomainPolicy::kClamp);
}
// Worst-case path: half the inputs outside their range, clamped or extrapolated.
void BM_Evaluate4OutputsDoubleOutsideClamp(benchmark::State& state) {
  run<double, 4>(state, 0.5, fz::DomainPolicy::kClamp);
}
void BM_Evaluate4OutputsDoubleOutsideExtrapolate(benchmark::State& state) {
  run<double, 4>(state, 0.5, fz::DomainPolicy::kExtrapolate);
}

BENCHMARK(BM_Evaluate4OutputsDouble)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(BM_Evaluate4OutputsFloat)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(BM_Evaluate1OutputDouble)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(BM_Evaluate1OutputFloat)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(BM_Evaluate4OutputsDoubleOutsideClamp)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(BM_Evaluate4OutputsDoubleOutsideExtrapolate)->Repetitions(5)->ReportAggregatesOnly(true);

}  // namespace

// SPDX-License-Identifier: MIT
/// @file Cost of planning and sampling a probing move (both RT-safe).
#include <benchmark/benchmark.h>

#include <cmmcomp/motion/move_profile.hpp>

namespace {

using cmmcomp::motion::MoveProfile;
using cmmcomp::motion::ProbingMove;

void BM_PlanTrapezoidal(benchmark::State& state) {
  ProbingMove m = cmmcomp::motion::baseline_move();
  MoveProfile p;
  for (auto _ : state) {
    benchmark::DoNotOptimize(MoveProfile::plan(m, p));
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_PlanTrapezoidal);

void BM_PlanJerkLimitedShortApproach(benchmark::State& state) {
  ProbingMove m = cmmcomp::motion::baseline_move();
  m.jerk = 2.0;
  m.approach_distance = 0.0012;  // touch inside the ramp-down: the iterative cut
  MoveProfile p;
  for (auto _ : state) {
    benchmark::DoNotOptimize(MoveProfile::plan(m, p));
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_PlanJerkLimitedShortApproach);

void BM_Sample(benchmark::State& state) {
  MoveProfile p;
  if (!cmmcomp::ok(MoveProfile::plan(cmmcomp::motion::baseline_move(), p))) return;
  double t = 0.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(p.sample(t));
    t += 1e-3;
    if (t > p.duration()) t = 0.0;
  }
}
BENCHMARK(BM_Sample);

}  // namespace

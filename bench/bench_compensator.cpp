// SPDX-License-Identifier: MIT
/// @file Cost of one MoveCompensator::before_approach (the paper's inputs, 3 sets, 4 outputs),
/// through the C++ API and the C ABI, with and without the prediction interval, and with the
/// shipped 5-input model. Target: median <= 300 ns
/// per call.
#include <benchmark/benchmark.h>
#include <cmmcomp/compensator.h>

#include <array>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace {

namespace cm = cmmcomp::compensation;
constexpr std::size_t kMoves = 1024;  // a power of two, cycled through

// A random valid model over the paper's move ranges (mm, mm/s), consequents of a few µm.
cm::Model<cmmcomp::PaperInputs> random_model(std::mt19937_64& rng) {
  cm::Model<cmmcomp::PaperInputs> m;
  m.ranges = {cmmcomp::fuzzy::InputRange{10.0, 100.0},
              cmmcomp::fuzzy::InputRange{5.0, 200.0},
              cmmcomp::fuzzy::InputRange{2.0, 30.0},
              cmmcomp::fuzzy::InputRange{1.0, 20.0}};
  std::uniform_real_distribution<double> jitter(-0.1, 0.1);
  std::uniform_real_distribution<double> width(0.2, 0.5);
  std::uniform_real_distribution<double> coef(-5.0, 5.0);
  for (int i = 0; i < 4; ++i) {
    for (int s = 0; s < 3; ++s) {
      m.params.centre(i, s) = 0.5 * s + jitter(rng);
      m.params.width(i, s) = width(rng);
    }
  }
  for (int k = cm::Model<cmmcomp::PaperInputs>::Params::kConsequentsOffset;
       k < cm::Model<cmmcomp::PaperInputs>::kParamCount;
       ++k) {
    m.params.values[static_cast<unsigned>(k)] = coef(rng);
  }
  return m;
}

std::vector<cm::MoveRequest> random_moves(const cm::Model<cmmcomp::PaperInputs>::Network& m,
                                          std::mt19937_64& rng) {
  std::vector<cm::MoveRequest> moves(kMoves);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto in = [&](int i) {
    const auto& r = m.ranges[static_cast<unsigned>(i)];
    return r.lo + u(rng) * (r.hi - r.lo);
  };
  std::uint32_t seq = 0;
  for (auto& r : moves) {
    r.sequence = seq++;
    r.axis = static_cast<std::uint8_t>(seq % 3);
    r.direction = {0.0, 0.0, -1.0};
    r.pv_mm_s = in(0);
    r.pd_mm = in(1);
    r.av_mm_s = in(2);
    r.ad_mm = in(3);
    r.pa_mm_s2 = 500.0;
    r.aa_mm_s2 = 200.0;
    r.y_mm = 100.0;
    r.z_mm = -50.0;
  }
  return moves;
}

// The timed loop: one before_approach per iteration, cycling through `moves`.
void time_calls(benchmark::State& state,
                const cm::MoveCompensator& comp,
                const std::vector<cm::MoveRequest>& moves) {
  cm::Correction out;
  std::size_t k = 0;
  std::size_t failures = 0;
  for (auto _ : state) {
    failures += cmmcomp::ok(comp.before_approach(moves[k], out)) ? 0u : 1u;
    benchmark::DoNotOptimize(out);
    k = (k + 1) & (kMoves - 1);
  }
  if (failures != 0) state.SkipWithError("before_approach failed");
}

void BM_BeforeApproach(benchmark::State& state) {
  std::mt19937_64 rng(20190601u);
  const auto model = random_model(rng);
  const auto moves = random_moves(model, rng);
  cm::MoveCompensator comp;
  for (int axis = 0; axis < cm::kMaxAxes; ++axis) {
    if (comp.publish(axis, model, 1u) != cmmcomp::Status::kOk) state.SkipWithError("publish");
  }
  time_calls(state, comp, moves);
}
BENCHMARK(BM_BeforeApproach);

// The same calls with the model's interval calibration published: each Correction carries
// U95 (docs/uncertainty.md). The difference to BM_BeforeApproach, in one run, is its cost
// (issue 15 aims at <= 30 ns).
void BM_BeforeApproachWithU95(benchmark::State& state) {
  std::mt19937_64 rng(20190601u);
  const auto model = random_model(rng);
  const auto moves = random_moves(model, rng);
  cm::IntervalCalibration interval;
  interval.coverage = 0.95;
  interval.half_width = {2.7, 2.2, 1.3, 0.7};
  interval.extrapolation_gain = {0.4, 1.9, 0.0, 0.2};
  interval.corner_gain = {1.1, 2.5, 1.6, 2.4};
  cm::MoveCompensator comp;
  for (int axis = 0; axis < cm::kMaxAxes; ++axis) {
    if (comp.publish(axis, model, interval, 1u) != cmmcomp::Status::kOk) {
      state.SkipWithError("publish");
    }
  }
  time_calls(state, comp, moves);
}
BENCHMARK(BM_BeforeApproachWithU95);

// The 5-input model (PV, PD, AV, AD, Y; 243 rules): the shipped data/models/default-y.json, moves
// spread over its ranges, Y included.
void BM_BeforeApproach5Inputs(benchmark::State& state) {
  const auto file =
      cmmcomp::io::load_model_file_of<cmmcomp::CarriageInputs>(CMMCOMP_DEFAULT_Y_MODEL);
  std::mt19937_64 rng(20190601u);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto in = [&](int i) {
    const auto& r = file.model.ranges[static_cast<unsigned>(i)];
    return r.lo + u(rng) * (r.hi - r.lo);
  };
  std::vector<cm::MoveRequest> moves(kMoves);
  for (auto& r : moves) {
    r.direction = {1.0, 0.0, 0.0};
    r.pv_mm_s = in(0);
    r.pd_mm = in(1);
    r.av_mm_s = in(2);
    r.ad_mm = in(3);
    r.y_mm = in(4);
    r.pa_mm_s2 = 200.0;
    r.aa_mm_s2 = 60.0;
  }
  cm::MoveCompensator comp;
  if (comp.publish(0, file.compensation_model(), 1u) != cmmcomp::Status::kOk) {
    state.SkipWithError("publish");
  }
  time_calls(state, comp, moves);
}
BENCHMARK(BM_BeforeApproach5Inputs);

void BM_CapiBeforeApproach(benchmark::State& state) {
  std::mt19937_64 rng(20190601u);
  cmmcomp::io::ModelFileOf<cmmcomp::PaperInputs> file;
  file.model = random_model(rng);
  const auto moves = random_moves(file.model, rng);
  file.training.method = "benchmark";
  file.training.cv_rmse = {0.0, 0.0, 0.0, 0.0};
  file.training.trained_at = "2026-01-01T00:00:00Z";
  file.training.tool_version = "bench_compensator";
  const std::string text = cmmcomp::io::format_model_json(file);
  cmmcomp_compensator* c = nullptr;
  if (cmmcomp_create_from_memory(text.data(), text.size(), &c) != CMMCOMP_OK) {
    state.SkipWithError("create");
    return;
  }
  std::vector<cmmcomp_move_request> reqs(kMoves);
  for (std::size_t i = 0; i < kMoves; ++i) {
    const cm::MoveRequest& m = moves[i];
    reqs[i] = cmmcomp_move_request{m.sequence,
                                   m.axis,
                                   {m.direction[0], m.direction[1], m.direction[2]},
                                   m.pv_mm_s,
                                   m.pa_mm_s2,
                                   m.pd_mm,
                                   m.av_mm_s,
                                   m.aa_mm_s2,
                                   m.ad_mm,
                                   m.y_mm,
                                   m.z_mm};
  }
  cmmcomp_correction out{};
  std::size_t k = 0;
  std::size_t failures = 0;
  for (auto _ : state) {
    failures += cmmcomp_before_approach(c, &reqs[k], &out) == CMMCOMP_OK ? 0u : 1u;
    benchmark::DoNotOptimize(out);
    k = (k + 1) & (kMoves - 1);
  }
  cmmcomp_destroy(c);
  if (failures != 0) state.SkipWithError("cmmcomp_before_approach failed");
}
BENCHMARK(BM_CapiBeforeApproach);

}  // namespace

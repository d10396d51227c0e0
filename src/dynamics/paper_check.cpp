// SPDX-License-Identifier: MIT
/// @file The paper comparison behind the main job and the calibration test.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/dynamics/bridge_model.hpp>
#include <cmmcomp/dynamics/dataset.hpp>
#include <cmmcomp/dynamics/paper_check.hpp>
#include <cmmcomp/paper_reference.hpp>

namespace cmmcomp::dynamics {
namespace {

std::array<double, 4> magnitudes(const errors::DynamicErrors& e) {
  return {e.mpe, std::fabs(e.rpe), e.mae, std::fabs(e.rae)};
}

const doe::AnovaTable& table(const io::DatasetAnova& a, std::size_t p) {
  const doe::AnovaTable* t[] = {&a.mpe, &a.rpe, &a.mae, &a.rae};
  return *t[p];
}

/// Rank (0 = largest) of factor `name` by weight in `t`.
int rank_of(const doe::AnovaTable& t, const std::string& name) {
  const double w = t.factor(name).weight_percent;
  int rank = 0;
  for (const doe::AnovaRow& r : t.factors) {
    if (r.weight_percent > w) ++rank;
  }
  return rank;
}

}  // namespace

bool PaperComparison::all_passed() const {
  return std::all_of(checks.begin(), checks.end(), [](const PaperCheck& c) { return c.passed; });
}

PaperComparison compare_with_paper(const Machine& machine, std::uint64_t seed, int threads) {
  PaperComparison c;
  BridgeSimulator sim(machine);
  for (std::size_t i = 0; i < 3; ++i) {
    c.by_y[i] = sim.simulate(motion::baseline_move(), paper::kTable2Y_mm[i] * 1e-3).errors_um;
  }
  DatasetOptions options;
  options.threads = threads;
  options.noise.enabled = true;
  options.noise.seed = seed;
  const auto rows = simulate_dataset(
      machine, rows_from_design(doe::replicate(doe::paper_l18_design(), 3), {}), options);
  c.anova = io::anova_of_dataset(rows);

  const auto base = magnitudes(c.by_y[1]);
  const auto y0 = magnitudes(c.by_y[0]);
  const auto y500 = magnitudes(c.by_y[2]);
  for (std::size_t p = 0; p < 4; ++p) {
    const char* name = paper::kParameters[p];
    const double ref = paper::kTable1Mean[p];
    c.checks.push_back({fmt::format("Table 1: baseline {} within ±20 % of {:.3f} um", name, ref),
                        std::fabs(base[p] - ref) <= 0.2 * ref,
                        fmt::format("{:.3f} um ({:+.1f} %)", base[p], 100 * (base[p] / ref - 1))});
  }
  for (std::size_t p = 0; p < 4; ++p) {
    const char* name = paper::kParameters[p];
    c.checks.push_back({fmt::format("Table 2: {} at Y 500 >= 1.4x its Y 250 value", name),
                        y500[p] >= 1.4 * base[p],
                        fmt::format("{:.2f}x", y500[p] / base[p])});
  }
  for (std::size_t p = 0; p < 4; ++p) {
    const char* name = paper::kParameters[p];
    const double ref = paper::kTable2[0][p];
    c.checks.push_back({fmt::format("Table 2: {} at Y 0 within ±30 % of {:.3f} um", name, ref),
                        std::fabs(y0[p] - ref) <= 0.3 * ref,
                        fmt::format("{:.3f} um ({:+.1f} %)", y0[p], 100 * (y0[p] / ref - 1))});
  }
  const struct {
    std::size_t parameter;
    const char* factor;
    int max_rank;
  } ranks[] = {{0, "PV", 0}, {1, "PV", 0}, {2, "AV", 0}, {3, "AV", 0}, {1, "PD", 1}, {3, "AD", 1}};
  for (const auto& r : ranks) {
    const doe::AnovaTable& t = table(c.anova, r.parameter);
    const int rank = rank_of(t, r.factor);
    c.checks.push_back(
        {fmt::format("Table 4: {} {} for {}",
                     r.factor,
                     r.max_rank == 0 ? "is the largest factor" : "ranks in the top two",
                     paper::kParameters[r.parameter]),
         rank <= r.max_rank,
         fmt::format("rank {} ({:.1f} %)", rank + 1, t.factor(r.factor).weight_percent)});
  }
  for (std::size_t p = 0; p < 4; ++p) {
    const double w = table(c.anova, p).error.weight_percent;
    c.checks.push_back({fmt::format("Table 4: error row below 25 % for {}", paper::kParameters[p]),
                        w < 25.0,
                        fmt::format("{:.1f} %", w)});
  }
  return c;
}

std::string format_paper_comparison(const PaperComparison& c) {
  std::string s;
  auto out = std::back_inserter(s);
  fmt::format_to(out,
                 "Baseline move (PV 40, PA 200, PD 40, AV 12, AA 60, AD 10 mm, mm/s, mm/s^2)"
                 ", noiseless, vs the paper's Tables 1 and 2 [um]:\n");
  fmt::format_to(
      out, "  {:<6} {:>14} {:>14} {:>14} {:>14}\n", "Y mm", "MPE", "|RPE|", "MAE", "|RAE|");
  for (std::size_t i = 0; i < 3; ++i) {
    const auto m = magnitudes(c.by_y[i]);
    fmt::format_to(out, "  {:<6g}", paper::kTable2Y_mm[i]);
    for (std::size_t p = 0; p < 4; ++p) {
      const double ref = i == 1 ? paper::kTable1Mean[p] : paper::kTable2[i][p];
      fmt::format_to(out, " {:>6.2f} ({:>5.2f})", m[p], ref);
    }
    fmt::format_to(out, "\n");
  }
  fmt::format_to(out,
                 "  (model (paper)); signed at Y 250: RPE {:+.2f}, RAE {:+.2f} um "
                 "(+ = tip ahead of the scale)\n\n",
                 c.by_y[1].rpe,
                 c.by_y[1].rae);
  fmt::format_to(out,
                 "ANOVA of the L18 x 3 experiment ({} samples, Table 1 noise), weight % "
                 "model (paper):\n",
                 c.anova.samples);
  fmt::format_to(
      out, "  {:<6} {:>15} {:>15} {:>15} {:>15}\n", "factor", "MPE", "|RPE|", "MAE", "|RAE|");
  for (std::size_t f = 0; f < 5; ++f) {
    fmt::format_to(out, "  {:<6}", paper::kAnovaSources[f]);
    for (std::size_t p = 0; p < 4; ++p) {
      const doe::AnovaTable& t = table(c.anova, p);
      const double w =
          f == 4 ? t.error.weight_percent : t.factor(paper::kAnovaSources[f]).weight_percent;
      fmt::format_to(out, " {:>6.1f} ({:>5.1f})", w, paper::kTable4Weight[p][f]);
    }
    fmt::format_to(out, "\n");
  }
  fmt::format_to(out, "\nCalibration requirements:\n");
  for (const PaperCheck& k : c.checks) {
    fmt::format_to(
        out, "  [{}] {:<52} {}\n", k.passed ? "pass" : "FAIL", k.requirement, k.measured);
  }
  return s;
}

}  // namespace cmmcomp::dynamics

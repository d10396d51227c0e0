// SPDX-License-Identifier: MIT
/// @file The paper comparison behind the main job and the calibration test.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/doe/dataset_anova.hpp>
#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/dynamics/bridge_model.hpp>
#include <cmmcomp/dynamics/dataset.hpp>
#include <cmmcomp/dynamics/paper_check.hpp>
#include <cmmcomp/paper_reference.hpp>

namespace cmmcomp::dynamics {
namespace {

constexpr int kRepeats = 3;
constexpr int kMedianSeeds = 20;
constexpr int kSweepPoints = 21;
// A turn smaller than this fraction of Table 1's σ is not an extremum (hysteresis).
constexpr double kFlatSigma = 0.01;
constexpr std::array<const char*, 4> kInputNames = PaperInputs::labels();

std::array<double, 4> magnitudes(const errors::DynamicErrors& e) {
  return {e.mpe, std::fabs(e.rpe), e.mae, std::fabs(e.rae)};
}
std::array<double, 4> magnitudes(const DatasetRow& r) {
  return {r.mpe_um, std::fabs(r.rpe_um), r.mae_um, std::fabs(r.rae_um)};
}

const doe::AnovaTable& table(const doe::DatasetAnova& a, std::size_t p) {
  const doe::AnovaTable* t[] = {&a.mpe, &a.rpe, &a.mae, &a.rae};
  return *t[p];
}

/// Simulates each run once (noiseless) and repeats it `repeats` times consecutively, as
/// doe::replicate orders them.
std::vector<DatasetRow> simulate_replicated(const Machine& machine,
                                            const doe::Design& design,
                                            int threads) {
  DatasetOptions options;
  options.threads = threads;
  const auto unique = simulate_dataset(machine, rows_from_design(design, {}), options);
  std::vector<DatasetRow> rows;
  for (const DatasetRow& r : unique) rows.insert(rows.end(), kRepeats, r);
  return rows;
}

/// `clean` with the noise `simulate_dataset` would give row i for `seed`.
std::vector<DatasetRow> with_noise(std::vector<DatasetRow> rows, std::uint64_t seed) {
  MeasurementNoise noise;
  noise.enabled = true;
  noise.seed = seed;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    DatasetRow& r = rows[i];
    const errors::DynamicErrors e =
        add_noise(errors::DynamicErrors{r.mpe_um, r.rpe_um, r.mae_um, r.rae_um}, noise, i);
    r.mpe_um = e.mpe;
    r.rpe_um = e.rpe;
    r.mae_um = e.mae;
    r.rae_um = e.rae;
  }
  return rows;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Interior extrema of a sampled curve, counted with hysteresis: a turn counts once the curve
/// has come back by more than `flat` from its running extreme, so round-off or a residual ripple
/// far below the noise on a flat curve is not an extremum.
int interior_extrema(const std::vector<double>& v, double flat) {
  int count = 0;
  int direction = 0;  // +1 rising, -1 falling, 0 not yet known
  double extreme = v.front();
  for (std::size_t i = 1; i < v.size(); ++i) {
    const double x = v[i];
    if (direction == 0) {
      if (std::fabs(x - extreme) > flat) direction = x > extreme ? 1 : -1;
      extreme = direction == 0 ? extreme : x;
      continue;
    }
    if ((direction > 0 && x > extreme) || (direction < 0 && x < extreme)) {
      extreme = x;
    } else if (std::fabs(x - extreme) > flat) {
      ++count;
      direction = -direction;
      extreme = x;
    }
  }
  return count;
}

/// The sweeps of the smoothness requirement, simulated in one parallel batch.
std::vector<SweepResult> run_sweeps(const Machine& machine, int threads) {
  const std::vector<doe::Factor> factors = doe::paper_table3_factors();  // SI units
  std::array<std::array<double, 3>, 4> level_mm{};
  for (std::size_t f = 0; f < 4; ++f) {
    for (std::size_t l = 0; l < 3; ++l) level_mm[f][l] = factors[f].levels[l] * 1e3;
  }
  std::vector<DatasetRow> rows;
  for (int input = 0; input < 4; ++input) {
    for (int combo = 0; combo < 8; ++combo) {
      for (int k = 0; k < kSweepPoints; ++k) {
        std::array<double, 4> x{};
        int bit = 0;
        for (int f = 0; f < 4; ++f) {
          const auto& lv = level_mm[static_cast<std::size_t>(f)];
          if (f == input) {
            x[static_cast<std::size_t>(f)] = lv[0] + (lv[2] - lv[0]) * k / (kSweepPoints - 1);
          } else {
            x[static_cast<std::size_t>(f)] = ((combo >> bit++) & 1) != 0 ? lv[2] : lv[0];
          }
        }
        DatasetRow r;
        r.pv_mm_s = x[0];
        r.pd_mm = x[1];
        r.av_mm_s = x[2];
        r.ad_mm = x[3];
        r.pa_mm_s2 = 200;
        r.aa_mm_s2 = 60;
        r.y_mm = 250;
        rows.push_back(r);
      }
    }
  }
  DatasetOptions options;
  options.threads = threads;
  rows = simulate_dataset(machine, rows, options);

  std::vector<SweepResult> results;
  for (int input = 0; input < 4; ++input) {
    for (int p = 0; p < 4; ++p) {
      SweepResult s;
      s.input = input;
      s.parameter = p;
      const double sigma = paper::kTable1Std[static_cast<std::size_t>(p)];
      for (int combo = 0; combo < 8; ++combo) {
        const int first_index = (input * 8 + combo) * kSweepPoints;
        const auto first = static_cast<std::size_t>(first_index);
        std::vector<double> v;
        bool triangular = false;
        for (int k = 0; k < kSweepPoints; ++k) {
          const DatasetRow& r = rows[first + static_cast<std::size_t>(k)];
          v.push_back(magnitudes(r)[static_cast<std::size_t>(p)]);
          triangular |= r.pd_mm < r.pv_mm_s * r.pv_mm_s / r.pa_mm_s2;
        }
        if (triangular && p < 2) continue;  // positioning parameters change character there
        ++s.counted;
        s.max_interior_extrema =
            std::max(s.max_interior_extrema, interior_extrema(v, kFlatSigma * sigma));
        // The quadratic through the values at the three levels (points 0, 10, 20).
        const double y0 = v[0];
        const double y1 = v[kSweepPoints / 2];
        const double y2 = v[kSweepPoints - 1];
        for (int k = 0; k < kSweepPoints; ++k) {
          const double u = 2.0 * k / (kSweepPoints - 1) - 1.0;  // -1 .. 1
          const double q = y1 + 0.5 * (y2 - y0) * u + 0.5 * (y2 - 2.0 * y1 + y0) * u * u;
          s.max_deviation_sigma = std::max(s.max_deviation_sigma,
                                           std::fabs(v[static_cast<std::size_t>(k)] - q) / sigma);
        }
      }
      results.push_back(s);
    }
  }
  return results;
}

std::string percent_off(double model, double ref) {
  return fmt::format("{:.3f} um ({:+.1f} %)", model, 100.0 * (model / ref - 1.0));
}

}  // namespace

bool PaperComparison::all_passed() const {
  return std::all_of(checks.begin(), checks.end(), [](const PaperCheck& c) { return c.passed; });
}

PaperSimulations simulate_paper_experiments(const Machine& machine, int threads) {
  PaperSimulations s;
  BridgeSimulator sim(machine);
  for (std::size_t i = 0; i < 3; ++i) {
    s.by_y[i] = sim.simulate(motion::baseline_move(), paper::kTable2Y_mm[i] * 1e-3).errors_um;
  }
  s.l18 = simulate_replicated(machine, doe::paper_l18_design(), threads);
  s.grid = simulate_replicated(machine, doe::full_factorial(doe::paper_table3_factors()), threads);
  s.sweeps = run_sweeps(machine, threads);
  return s;
}

PaperComparison compare_with_paper(const Machine& machine, std::uint64_t seed, int threads) {
  return compare_with_paper(simulate_paper_experiments(machine, threads), seed);
}

PaperComparison compare_with_paper(const PaperSimulations& sims, std::uint64_t seed) {
  PaperComparison c;
  c.by_y = sims.by_y;
  c.sweeps = sims.sweeps;

  // Table 4: the median weight over 20 noise seeds.
  std::array<std::array<std::vector<double>, 5>, 4> weights;
  for (int k = 0; k < kMedianSeeds; ++k) {
    const doe::DatasetAnova a =
        doe::anova_of_dataset(with_noise(sims.l18, seed + static_cast<std::uint64_t>(k)));
    for (std::size_t p = 0; p < 4; ++p) {
      const doe::AnovaTable& t = table(a, p);
      for (std::size_t f = 0; f < 5; ++f) {
        weights[p][f].push_back(f == 4 ? t.error.weight_percent
                                       : t.factor(paper::kAnovaSources[f]).weight_percent);
      }
    }
  }
  for (std::size_t p = 0; p < 4; ++p) {
    for (std::size_t f = 0; f < 5; ++f) c.median_weight[p][f] = median(weights[p][f]);
  }
  // Table 5: mean |value| over the noisy grid.
  const std::vector<DatasetRow> grid = with_noise(sims.grid, seed);
  for (const DatasetRow& r : grid) {
    const auto m = magnitudes(r);
    for (std::size_t p = 0; p < 4; ++p)
      c.grid_mean_um[p] += m[p] / static_cast<double>(grid.size());
  }

  const auto base = magnitudes(c.by_y[1]);
  for (std::size_t p = 0; p < 4; ++p) {
    const double ref = paper::kTable1Mean[p];
    c.checks.push_back(
        {fmt::format("Table 1: baseline {} within ±10 % of {:.3f} um", paper::kParameters[p], ref),
         std::fabs(base[p] - ref) <= 0.10 * ref,
         percent_off(base[p], ref)});
  }
  for (std::size_t i = 0; i < 3; ++i) {
    const auto m = magnitudes(c.by_y[i]);
    for (std::size_t p = 0; p < 4; ++p) {
      const double ref = paper::kTable2[i][p];
      c.checks.push_back({fmt::format("Table 2: {} at Y {:g} within ±15 % of {:.3f} um",
                                      paper::kParameters[p],
                                      paper::kTable2Y_mm[i],
                                      ref),
                          std::fabs(m[p] - ref) <= 0.15 * ref,
                          percent_off(m[p], ref)});
    }
  }
  for (std::size_t p = 0; p < 4; ++p) {
    for (std::size_t f = 0; f < 5; ++f) {
      const double ref = paper::kTable4Weight[p][f];
      const double w = c.median_weight[p][f];
      c.checks.push_back({fmt::format("Table 4: {} weight of {} within ±10 points of {:g} %",
                                      paper::kParameters[p],
                                      paper::kAnovaSources[f],
                                      ref),
                          std::fabs(w - ref) <= 10.0,
                          fmt::format("{:.1f} % (median of 20 seeds)", w),
                          true});
    }
  }
  for (std::size_t p = 0; p < 4; ++p) {
    const double ref = paper::kTable5MeanBefore[p];
    c.checks.push_back(
        {fmt::format(
             "Table 5: mean |{}| before within ±15 % of {:.3f} um", paper::kParameters[p], ref),
         std::fabs(c.grid_mean_um[p] - ref) <= 0.15 * ref,
         percent_off(c.grid_mean_um[p], ref),
         true});
  }
  for (const SweepResult& s : c.sweeps) {
    c.checks.push_back(
        {fmt::format("Smooth: {} over {}: <= 1 extremum, within 1 sigma of the quadratic",
                     paper::kParameters[static_cast<std::size_t>(s.parameter)],
                     kInputNames[static_cast<std::size_t>(s.input)]),
         s.max_interior_extrema <= 1 && s.max_deviation_sigma <= 1.0,
         fmt::format("{} extrema, {:.2f} sigma ({} of 8 sweeps{})",
                     s.max_interior_extrema,
                     s.max_deviation_sigma,
                     s.counted,
                     s.counted < 8 ? "; the rest cross into triangular positioning" : "")});
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
      fmt::format_to(out, " {:>6.2f} ({:>5.2f})", m[p], paper::kTable2[i][p]);
    }
    fmt::format_to(out, "\n");
  }
  fmt::format_to(out,
                 "  (model (paper)); signed at Y 250: RPE {:+.2f}, RAE {:+.2f} um "
                 "(+ = tip ahead of the scale); Table 1 means: {:.3f} {:.3f} {:.3f} {:.3f}\n\n",
                 c.by_y[1].rpe,
                 c.by_y[1].rae,
                 paper::kTable1Mean[0],
                 paper::kTable1Mean[1],
                 paper::kTable1Mean[2],
                 paper::kTable1Mean[3]);
  fmt::format_to(out,
                 "ANOVA of the L18 x 3 experiment (54 samples, Table 1 noise), median weight % "
                 "over 20 noise seeds, model (paper):\n");
  fmt::format_to(
      out, "  {:<6} {:>15} {:>15} {:>15} {:>15}\n", "factor", "MPE", "|RPE|", "MAE", "|RAE|");
  for (std::size_t f = 0; f < 5; ++f) {
    fmt::format_to(out, "  {:<6}", paper::kAnovaSources[f]);
    for (std::size_t p = 0; p < 4; ++p) {
      fmt::format_to(
          out, " {:>6.1f} ({:>5.1f})", c.median_weight[p][f], paper::kTable4Weight[p][f]);
    }
    fmt::format_to(out, "\n");
  }
  fmt::format_to(out,
                 "\nTable 5 'mean before' (full 3^4 grid x 3 at Y 250, Table 1 noise) [um], "
                 "model (paper):\n ");
  for (std::size_t p = 0; p < 4; ++p) {
    fmt::format_to(out,
                   " {} {:.2f} ({:.2f})",
                   paper::kParameters[p],
                   c.grid_mean_um[p],
                   paper::kTable5MeanBefore[p]);
  }
  fmt::format_to(out, "\n\nCalibration requirements:\n");
  for (const PaperCheck& k : c.checks) {
    fmt::format_to(
        out, "  [{}] {:<66} {}\n", k.passed ? "pass" : "FAIL", k.requirement, k.measured);
  }
  return s;
}

}  // namespace cmmcomp::dynamics

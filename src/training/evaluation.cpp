// SPDX-License-Identifier: MIT
/// @file Table 5 and Fig. 5 of a model on a test set.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <cmmcomp/training/evaluation.hpp>
#include <sstream>

namespace cmmcomp::training {

namespace {

std::size_t checked_size(const TestSetPredictions& p) {
  const std::size_t n = p.measured[0].size();
  for (std::size_t o = 0; o < kErrors.size(); ++o) {
    if (p.measured[o].size() != n || p.predicted[o].size() != n) {
      throw ConfigError("test set: measured and predicted values of different lengths");
    }
  }
  if (n == 0) throw ConfigError("test set: no samples");
  return n;
}

}  // namespace

HeldOutCheck held_out_check(const std::array<Table5Row, kErrors.size()>& table,
                            const std::array<double, kErrors.size()>& coverage_pct,
                            double nominal_coverage_pct,
                            std::size_t samples) {
  HeldOutCheck c;
  c.nominal_coverage_pct = nominal_coverage_pct;
  c.passed = true;
  const double q = nominal_coverage_pct / 100.0;
  const double binomial_2sigma =
      samples > 0 ? 200.0 * std::sqrt(q * (1.0 - q) / static_cast<double>(samples)) : 100.0;
  c.coverage_band_pct = std::max(kCoverageTolerancePct, binomial_2sigma);
  const double lo = nominal_coverage_pct - c.coverage_band_pct;
  const double hi = nominal_coverage_pct + c.coverage_band_pct;
  for (std::size_t o = 0; o < kErrors.size(); ++o) {
    HeldOutCheck::Parameter& p = c.parameters[o];
    p.reduction_pct = table[o].reduction_pct;
    p.paper_reduction_pct = paper::kTable5Reduction[o];
    p.coverage_pct = coverage_pct[o];
    p.reduction_met = p.reduction_pct >= p.paper_reduction_pct;
    p.coverage_met = p.coverage_pct >= lo && p.coverage_pct <= hi;
    const auto add = [&](const std::string& what) {
      c.missed += (c.missed.empty() ? "" : "; ") + what;
    };
    if (!p.reduction_met) {
      add(fmt::format("{} reduction {:.1f} % < {:.1f} %",
                      kErrors[o].label,
                      p.reduction_pct,
                      p.paper_reduction_pct));
    }
    if (!p.coverage_met) {
      add(std::isnan(p.coverage_pct) ? fmt::format("{} has no interval", kErrors[o].label)
                                     : fmt::format("{} coverage {:.1f} % outside {:.1f}–{:.1f} %",
                                                   kErrors[o].label,
                                                   p.coverage_pct,
                                                   lo,
                                                   hi));
    }
    c.passed = c.passed && p.reduction_met && p.coverage_met;
  }
  return c;
}

std::array<Table5Row, kErrors.size()> table5(const TestSetPredictions& p) {
  const std::size_t n = checked_size(p);
  std::array<Table5Row, kErrors.size()> t{};
  for (std::size_t o = 0; o < kErrors.size(); ++o) {
    double sum_before = 0, sum_after = 0, sum_r = 0, sum_r2 = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double r = p.measured[o][i] - p.predicted[o][i];
      sum_before += std::fabs(p.measured[o][i]);
      sum_after += std::fabs(r);
      sum_r += r;
      sum_r2 += r * r;
      t[o].max_abs = std::max(t[o].max_abs, std::fabs(r));
    }
    t[o].mean_before = sum_before / static_cast<double>(n);
    t[o].mean_after = sum_after / static_cast<double>(n);
    t[o].reduction_pct = 100.0 * (t[o].mean_before - t[o].mean_after) / t[o].mean_before;
    const double mean_r = sum_r / static_cast<double>(n);
    t[o].var_after = sum_r2 / static_cast<double>(n) - mean_r * mean_r;
  }
  return t;
}

Fig5Plot fig5_plot(const TestSetPredictions& p,
                   const std::string& data_path,
                   const std::string& png_path,
                   const std::string& model_id,
                   double coverage_pct) {
  const std::size_t n = checked_size(p);
  Fig5Plot plot;
  std::ostringstream data;
  const std::size_t shown = std::min<std::size_t>(50, n);
  bool band = coverage_pct > 0;
  for (std::size_t o = 0; o < kErrors.size(); ++o) band = band && p.half_width[o].size() == n;
  for (std::size_t i = 0; i < shown; ++i) {
    const std::size_t k = (i * n) / shown;  // spread over the test set, deterministic
    data << i + 1;
    for (std::size_t o = 0; o < kErrors.size(); ++o) {
      data << ' ' << p.measured[o][k] << ' ' << p.predicted[o][k] << ' '
           << p.measured[o][k] - p.predicted[o][k] << ' ' << (band ? p.half_width[o][k] : 0.0);
    }
    data << '\n';
  }
  plot.data = data.str();
  std::string& g = plot.script;
  g = "set terminal pngcairo size 1200,950 noenhanced\nset output '" + png_path + "'\n" +
      "set key outside bottom center horizontal\n" +
      fmt::format(
          "set multiplot layout 2,2 title 'Measured, predicted and residual ({} test "
          "samples){}{}'\n",
          shown,
          model_id.empty() ? "" : ", model " + model_id,
          band ? fmt::format("; band: the {:g} % interval", coverage_pct) : "");
  for (std::size_t o = 0; o < kErrors.size(); ++o) {
    const std::size_t c = 2 + 4 * o;
    g += fmt::format("set title '{} [µm]'\nset xlabel 'sample'\nset grid\nplot ", kErrors[o].label);
    if (band) {
      g += fmt::format(
          "'{}' using 1:(${}-${}):(${}+${}) with filledcurves fs transparent solid 0.2 noborder "
          "title 'predicted ± U', ",
          data_path,
          c + 1,
          c + 3,
          c + 1,
          c + 3);
    }
    g += fmt::format(
        "'{}' using 1:{} with linespoints title 'measured', '' using 1:{} with linespoints "
        "title 'predicted', '' using 1:{} with impulses lw 2 title 'residual'\n",
        data_path,
        c,
        c + 1,
        c + 2);
  }
  g += "unset multiplot\n";
  return plot;
}

}  // namespace cmmcomp::training

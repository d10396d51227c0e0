// SPDX-License-Identifier: MIT
/// @file Table 5 and Fig. 5 of a model on a test set.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <cmmcomp/training/evaluation.hpp>
#include <nlohmann/json.hpp>
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

namespace {

/// Mean half-width per parameter over the test set [µm].
std::array<double, kErrors.size()> mean_half_width(const TestSetEvaluation& e) {
  std::array<double, kErrors.size()> u{};
  for (std::size_t o = 0; o < kErrors.size(); ++o) {
    for (const double h : e.predictions.half_width[o]) u[o] += h;
    u[o] /= static_cast<double>(e.samples);
  }
  return u;
}

}  // namespace

std::string format_test_set_json(const TestSetEvaluation& e,
                                 const TestSetReportHeader& header,
                                 const HeldOutCheck* check) {
  const auto u = mean_half_width(e);
  nlohmann::json j;
  for (std::size_t o = 0; o < kErrors.size(); ++o) {
    const Table5Row& t = e.table[o];
    j[kErrors[o].key] = {{"mean_before_um", t.mean_before},
                         {"mean_after_um", t.mean_after},
                         {"reduction_pct", t.reduction_pct},
                         {"var_after_um2", t.var_after},
                         {"max_abs_residual_um", t.max_abs}};
    if (header.nominal_coverage > 0) {
      j[kErrors[o].key]["coverage_pct"] = e.coverage_pct[o];
      j[kErrors[o].key]["mean_u95_um"] = u[o];
    }
  }
  j["interval_coverage_nominal_pct"] = 100.0 * header.nominal_coverage;
  if (check != nullptr) {
    j["check"] = {{"passed", check->passed},
                  {"missed", check->missed},
                  {"coverage_band_pct", check->coverage_band_pct}};
  }
  j["samples"] = e.samples;
  j["outside_domain"] = e.outside;
  return j.dump(2);
}

std::string format_test_set_report(const TestSetEvaluation& e,
                                   const TestSetReportHeader& header,
                                   const HeldOutCheck* check) {
  std::string out = fmt::format(
      "model {} ({} inputs) on {}: {} samples ({} outside the training ranges, clamped)\n",
      header.model_id,
      header.inputs,
      header.data_label,
      e.samples,
      e.outside);
  out += "Table 5 layout; in brackets the paper's Table 5\n";
  out += fmt::format("{:<5} {:>20} {:>20} {:>20} {:>20} {:>12}\n",
                     "",
                     "mean before um",
                     "mean after um",
                     "reduction %",
                     "variance after um2",
                     "max |res| um");
  for (std::size_t o = 0; o < kErrors.size(); ++o) {
    const Table5Row& t = e.table[o];
    out += fmt::format(
        "{:<5} {:11.3f} ({:6.3f}) {:11.3f} ({:6.3f}) {:11.1f} ({:6.1f}) {:11.3f} ({:6.3f}) "
        "{:12.3f}\n",
        kErrors[o].label,
        t.mean_before,
        paper::kTable5MeanBefore[o],
        t.mean_after,
        paper::kTable5MeanAfter[o],
        t.reduction_pct,
        paper::kTable5Reduction[o],
        t.var_after,
        paper::kTable5VarianceAfter[o],
        t.max_abs);
  }
  if (header.nominal_coverage > 0) {
    const auto u = mean_half_width(e);
    out += fmt::format(
        "prediction interval (nominal coverage {:.0f} %): measured within predicted +- U\n",
        100.0 * header.nominal_coverage);
    for (std::size_t o = 0; o < kErrors.size(); ++o) {
      out += fmt::format("{:<5} coverage {:5.1f} %  mean U {:.3f} um\n",
                         kErrors[o].label,
                         e.coverage_pct[o],
                         u[o]);
    }
  } else {
    out += fmt::format("prediction interval: the model has none (format version {})\n",
                       header.format_version);
  }
  if (check != nullptr) {
    out += fmt::format(
        "held-out check (each reduction >= the paper's Table 5, each coverage within "
        "{:.0f} +- {:.1f} % for {} samples): {}{}\n",
        100.0 * header.nominal_coverage,
        check->coverage_band_pct,
        e.samples,
        check->passed ? "PASS" : "FAIL: ",
        check->missed);
  }
  return out;
}

}  // namespace cmmcomp::training

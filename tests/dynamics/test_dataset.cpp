// SPDX-License-Identifier: MIT
/// @file Dataset simulation: thread-count independence, noise, errors, designs and their ANOVA.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/doe/dataset_anova.hpp>
#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/doe/orthogonal_array.hpp>
#include <cmmcomp/dynamics/dataset.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "support/test_seed.hpp"

namespace cmmcomp::dynamics {
namespace {

using cmmcomp::DatasetRow;

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

/// The paper's factors on the four columns of an L9: 9 runs, every level of every factor.
doe::Design l9_design() {
  return doe::assign(doe::taguchi_l9(), doe::paper_table3_factors(), {0, 1, 2, 3});
}

std::vector<DatasetRow> first_rows(const std::vector<DatasetRow>& rows, std::size_t n) {
  return std::vector<DatasetRow>(rows.begin(), rows.begin() + static_cast<std::ptrdiff_t>(n));
}

void expect_identical_rows(const std::vector<DatasetRow>& a, const std::vector<DatasetRow>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    SCOPED_TRACE("row " + std::to_string(i + 1));
    EXPECT_EQ(a[i].pv_mm_s, b[i].pv_mm_s);
    EXPECT_EQ(a[i].pd_mm, b[i].pd_mm);
    EXPECT_EQ(a[i].av_mm_s, b[i].av_mm_s);
    EXPECT_EQ(a[i].ad_mm, b[i].ad_mm);
    EXPECT_EQ(a[i].pa_mm_s2, b[i].pa_mm_s2);
    EXPECT_EQ(a[i].aa_mm_s2, b[i].aa_mm_s2);
    EXPECT_EQ(a[i].y_mm, b[i].y_mm);
    EXPECT_EQ(a[i].mpe_um, b[i].mpe_um);
    EXPECT_EQ(a[i].rpe_um, b[i].rpe_um);
    EXPECT_EQ(a[i].mae_um, b[i].mae_um);
    EXPECT_EQ(a[i].rae_um, b[i].rae_um);
  }
}

/// Records every progress call.
struct ProgressLog {
  std::vector<std::pair<std::size_t, std::size_t>> calls;
  std::function<void(std::size_t, std::size_t)> callback() {
    return [this](std::size_t done, std::size_t total) { calls.emplace_back(done, total); };
  }
};

void expect_progress_reaches_total(const ProgressLog& log, std::size_t total) {
  ASSERT_FALSE(log.calls.empty());
  EXPECT_EQ(log.calls.back(), std::make_pair(total, total));
  for (std::size_t i = 0; i < log.calls.size(); ++i) {
    EXPECT_EQ(log.calls[i].second, total);
    EXPECT_LE(log.calls[i].first, total);
    if (i > 0) {
      EXPECT_GE(log.calls[i].first, log.calls[i - 1].first);
    }
  }
}

/// The L9 dataset simulated on one thread without noise, computed once.
const std::vector<DatasetRow>& l9_clean() {
  static const std::vector<DatasetRow> rows = [] {
    DatasetOptions o;
    o.threads = 1;
    return simulate_dataset(default_machine(), rows_from_design(l9_design(), FixedSettings{}), o);
  }();
  return rows;
}

TEST(RowsFromDesign, ConvertsSiFactorsToFileUnitsAndCopiesFixedSettings) {
  const doe::Design d = l9_design();
  FixedSettings fixed;
  fixed.pa_mm_s2 = 150;
  fixed.aa_mm_s2 = 50;
  fixed.y_mm = 400;
  const std::vector<DatasetRow> rows = rows_from_design(d, fixed);
  ASSERT_EQ(rows.size(), 9u);
  for (int r = 0; r < d.runs(); ++r) {
    const DatasetRow& row = rows[static_cast<std::size_t>(r)];
    EXPECT_DOUBLE_EQ(row.pv_mm_s, d.value(r, d.factor_index("PV")) * 1e3);
    EXPECT_DOUBLE_EQ(row.pd_mm, d.value(r, d.factor_index("PD")) * 1e3);
    EXPECT_DOUBLE_EQ(row.av_mm_s, d.value(r, d.factor_index("AV")) * 1e3);
    EXPECT_DOUBLE_EQ(row.ad_mm, d.value(r, d.factor_index("AD")) * 1e3);
    EXPECT_EQ(row.pa_mm_s2, 150);
    EXPECT_EQ(row.aa_mm_s2, 50);
    EXPECT_EQ(row.y_mm, 400);
    EXPECT_EQ(row.mpe_um, 0.0);
    EXPECT_EQ(row.rpe_um, 0.0);
    EXPECT_EQ(row.mae_um, 0.0);
    EXPECT_EQ(row.rae_um, 0.0);
  }
}

TEST(RowsFromDesign, AcceptsALatinHypercubeInAnyFactorOrder) {
  const doe::Design d = doe::latin_hypercube(
      {"AD", "PV", "AV", "PD"}, {0.005, 0.04, 0.008, 0.04}, {0.015, 0.1, 0.016, 0.08}, 5, 11);
  const std::vector<DatasetRow> rows = rows_from_design(d, FixedSettings{});
  ASSERT_EQ(rows.size(), 5u);
  for (int r = 0; r < 5; ++r) {
    const DatasetRow& row = rows[static_cast<std::size_t>(r)];
    EXPECT_DOUBLE_EQ(row.pv_mm_s, d.value(r, 1) * 1e3);
    EXPECT_DOUBLE_EQ(row.ad_mm, d.value(r, 0) * 1e3);
    EXPECT_GE(row.pv_mm_s, 40.0);
    EXPECT_LE(row.pv_mm_s, 100.0);
  }
}

TEST(RowsFromDesign, RejectsADesignWithoutTheMoveFactors) {
  const doe::Design missing = doe::full_factorial({doe::Factor{"PV", {0.04, 0.07}},
                                                   doe::Factor{"PD", {0.04, 0.06}},
                                                   doe::Factor{"AV", {0.008, 0.012}},
                                                   doe::Factor{"XX", {1, 2}}});
  EXPECT_THROW(rows_from_design(missing, FixedSettings{}), cmmcomp::ConfigError);
  const doe::Design extra = doe::full_factorial({doe::Factor{"PV", {0.04, 0.07}},
                                                 doe::Factor{"PD", {0.04, 0.06}},
                                                 doe::Factor{"AV", {0.008, 0.012}},
                                                 doe::Factor{"AD", {0.005, 0.01}},
                                                 doe::Factor{"PA", {0.2, 0.3}}});
  EXPECT_THROW(rows_from_design(extra, FixedSettings{}), cmmcomp::ConfigError);
}

TEST(SimulateDataset, ResultDoesNotDependOnTheThreadCount) {
  DatasetOptions o;
  o.threads = 2;
  ProgressLog log;
  o.progress = log.callback();
  const std::vector<DatasetRow> two =
      simulate_dataset(default_machine(), rows_from_design(l9_design(), FixedSettings{}), o);
  expect_identical_rows(two, l9_clean());
  expect_progress_reaches_total(log, 9);
  for (const DatasetRow& r : two) {
    EXPECT_TRUE(std::isfinite(r.mpe_um) && std::isfinite(r.rpe_um) && std::isfinite(r.mae_um) &&
                std::isfinite(r.rae_um));
    EXPECT_GT(r.mpe_um, 0.0);
  }
}

TEST(SimulateDataset, NoiselessRowsEqualTheSimulator) {
  const std::vector<DatasetRow>& rows = l9_clean();
  BridgeSimulator sim(default_machine());
  for (const std::size_t i : {std::size_t{0}, std::size_t{8}}) {
    const DatasetRow& r = rows[i];
    const motion::ProbingMove move = move_of(r);
    const errors::DynamicErrors e = sim.simulate(move, r.y_mm * 1e-3).errors_um;
    EXPECT_EQ(r.mpe_um, e.mpe) << "row " << i + 1;
    EXPECT_EQ(r.rpe_um, e.rpe) << "row " << i + 1;
    EXPECT_EQ(r.mae_um, e.mae) << "row " << i + 1;
    EXPECT_EQ(r.rae_um, e.rae) << "row " << i + 1;
  }
}

TEST(SimulateDataset, NoiseIsReproducibleForASeedAndDiffersForAnother) {
  const std::vector<DatasetRow> clean = first_rows(l9_clean(), 3);
  DatasetOptions o;
  o.noise.enabled = true;
  o.noise.seed = 7;
  o.threads = 2;
  const std::vector<DatasetRow> a = simulate_dataset(default_machine(), clean, o);
  o.threads = 1;
  const std::vector<DatasetRow> b = simulate_dataset(default_machine(), clean, o);
  expect_identical_rows(a, b);
  // Row i carries noise stream i on top of the noiseless simulation.
  for (std::size_t i = 0; i < clean.size(); ++i) {
    const errors::DynamicErrors e =
        add_noise({clean[i].mpe_um, clean[i].rpe_um, clean[i].mae_um, clean[i].rae_um}, o.noise, i);
    EXPECT_EQ(a[i].mpe_um, e.mpe) << "row " << i + 1;
    EXPECT_EQ(a[i].rpe_um, e.rpe) << "row " << i + 1;
    EXPECT_EQ(a[i].mae_um, e.mae) << "row " << i + 1;
    EXPECT_EQ(a[i].rae_um, e.rae) << "row " << i + 1;
    EXPECT_NE(a[i].rpe_um, clean[i].rpe_um) << "row " << i + 1;
  }
  o.noise.seed = 8;
  const std::vector<DatasetRow> c = simulate_dataset(default_machine(), clean, o);
  for (std::size_t i = 0; i < clean.size(); ++i) {
    EXPECT_NE(c[i].mpe_um, a[i].mpe_um) << "row " << i + 1;
    EXPECT_NE(c[i].rpe_um, a[i].rpe_um) << "row " << i + 1;
    EXPECT_NE(c[i].mae_um, a[i].mae_um) << "row " << i + 1;
    EXPECT_NE(c[i].rae_um, a[i].rae_um) << "row " << i + 1;
  }
}

TEST(SimulateDataset, InvalidRowIsNamedWithItsOneBasedNumber) {
  std::vector<DatasetRow> rows = first_rows(l9_clean(), 3);
  rows[1].pv_mm_s = 0.0;
  for (const int threads : {1, 2}) {
    DatasetOptions o;
    o.threads = threads;
    try {
      simulate_dataset(default_machine(), rows, o);
      ADD_FAILURE() << "threads " << threads << ": no error";
    } catch (const Error& e) {
      EXPECT_TRUE(contains(e.what(), "dataset row 2:")) << e.what();
      EXPECT_TRUE(contains(e.what(), "move")) << e.what();
    }
  }
}

TEST(SimulateDataset, CarriageOutOfRangeIsNamedWithItsRow) {
  std::vector<DatasetRow> rows = first_rows(l9_clean(), 1);
  rows[0].y_mm = -5.0;
  DatasetOptions o;
  o.threads = 1;
  try {
    simulate_dataset(default_machine(), rows, o);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_TRUE(contains(e.what(), "dataset row 1:")) << e.what();
    EXPECT_TRUE(contains(e.what(), "carriage position Y")) << e.what();
  }
}

TEST(SimulateDataset, EmptyDatasetReportsProgressAndReturnsNothing) {
  DatasetOptions o;
  ProgressLog log;
  o.progress = log.callback();
  EXPECT_TRUE(simulate_dataset(default_machine(), {}, o).empty());
  expect_progress_reaches_total(log, 0);
}

TEST(AddNoise, DisabledNoiseReturnsTheInput) {
  MeasurementNoise noise;
  noise.enabled = false;
  noise.mpe_sigma_um = 100;
  const errors::DynamicErrors clean{13.5, -5.25, 7.5, 3.75};
  for (std::uint64_t i : {0u, 1u, 12345u}) {
    const errors::DynamicErrors e = add_noise(clean, noise, i);
    EXPECT_EQ(e.mpe, clean.mpe);
    EXPECT_EQ(e.rpe, clean.rpe);
    EXPECT_EQ(e.mae, clean.mae);
    EXPECT_EQ(e.rae, clean.rae);
  }
}

TEST(AddNoise, HasZeroMeanAndTheConfiguredSpread) {
  SCOPED_TRACE(test::seed_message());
  MeasurementNoise noise;
  noise.enabled = true;
  noise.seed = test::seed();
  // MPE and MAE are folded to magnitudes: a large clean value keeps the fold out of reach.
  const errors::DynamicErrors clean{100.0, -5.0, 100.0, 3.0};
  const double sigma[4] = {
      noise.mpe_sigma_um, noise.rpe_sigma_um, noise.mae_sigma_um, noise.rae_sigma_um};
  const int n = 20000;
  double sum[4] = {0, 0, 0, 0};
  double sum2[4] = {0, 0, 0, 0};
  for (int i = 0; i < n; ++i) {
    const errors::DynamicErrors e = add_noise(clean, noise, static_cast<std::uint64_t>(i));
    const double d[4] = {
        e.mpe - clean.mpe, e.rpe - clean.rpe, e.mae - clean.mae, e.rae - clean.rae};
    for (int k = 0; k < 4; ++k) {
      sum[k] += d[k];
      sum2[k] += d[k] * d[k];
    }
  }
  const char* names[4] = {"MPE", "RPE", "MAE", "RAE"};
  for (int k = 0; k < 4; ++k) {
    const double mean = sum[k] / n;
    const double sd = std::sqrt(sum2[k] / n - mean * mean);
    // Standard errors: sigma/141 for the mean, sigma/200 for the sd; 3 % is 4 and 6 of them.
    EXPECT_LT(std::fabs(mean), 0.03 * sigma[k]) << names[k];
    EXPECT_NEAR(sd, sigma[k], 0.03 * sigma[k]) << names[k];
  }
}

TEST(AddNoise, MagnitudesStayNonNegativeAndStreamsDifferBySeedAndIndex) {
  MeasurementNoise noise;
  noise.enabled = true;
  const errors::DynamicErrors zero{0.0, 0.0, 0.0, 0.0};
  for (std::uint64_t i = 0; i < 1000; ++i) {
    const errors::DynamicErrors e = add_noise(zero, noise, i);
    ASSERT_GE(e.mpe, 0.0) << i;
    ASSERT_GE(e.mae, 0.0) << i;
  }
  const errors::DynamicErrors a = add_noise(zero, noise, 5);
  const errors::DynamicErrors again = add_noise(zero, noise, 5);
  EXPECT_EQ(a.rpe, again.rpe);
  EXPECT_NE(add_noise(zero, noise, 6).rpe, a.rpe);
  noise.seed = 2;
  EXPECT_NE(add_noise(zero, noise, 5).rpe, a.rpe);
}

/// The paper's L18 in file units with synthetic responses: MPE depends only on PV, RPE only on
/// PD, MAE only on AD and |RAE| only on AV (RAE negative, so the ANOVA must take magnitudes).
std::vector<DatasetRow> synthetic_l18() {
  std::vector<DatasetRow> rows = rows_from_design(doe::paper_l18_design(), FixedSettings{});
  for (DatasetRow& r : rows) {
    r.mpe_um = r.pv_mm_s / 10.0;
    r.rpe_um = r.pd_mm / 20.0;
    r.mae_um = r.ad_mm;
    r.rae_um = -r.av_mm_s / 4.0;
  }
  return rows;
}

void expect_single_factor(const doe::AnovaTable& t, const std::string& factor) {
  for (const std::string f : doe::kAnovaFactors) {
    EXPECT_NEAR(t.factor(f).weight_percent, f == factor ? 100.0 : 0.0, 1e-6)
        << "factor " << f << " (expected " << factor << " alone)";
  }
}

TEST(AnovaOfDataset, SyntheticResponsesAreAttributedToTheirFactor) {
  const doe::DatasetAnova a = doe::anova_of_dataset(synthetic_l18());
  EXPECT_EQ(a.runs, 18);
  EXPECT_EQ(a.samples, 18);
  expect_single_factor(a.mpe, "PV");
  expect_single_factor(a.rpe, "PD");
  expect_single_factor(a.mae, "AD");
  expect_single_factor(a.rae, "AV");
}

TEST(AnovaOfDataset, RepeatsAreAveraged) {
  // Each run twice, ±1 µm around the value: the averages, hence the weights, are unchanged.
  std::vector<DatasetRow> rows;
  for (const DatasetRow& r : synthetic_l18()) {
    DatasetRow up = r;
    DatasetRow down = r;
    up.mpe_um += 1.0;
    down.mpe_um -= 1.0;
    up.mae_um += 0.5;
    down.mae_um -= 0.5;
    rows.push_back(up);
    rows.push_back(down);
  }
  const doe::DatasetAnova a = doe::anova_of_dataset(rows);
  EXPECT_EQ(a.runs, 18);
  EXPECT_EQ(a.samples, 36);
  expect_single_factor(a.mpe, "PV");
  expect_single_factor(a.mae, "AD");
  const doe::DatasetAnova once = doe::anova_of_dataset(synthetic_l18());
  for (const std::string f : doe::kAnovaFactors) {
    EXPECT_NEAR(a.mpe.factor(f).weight_percent, once.mpe.factor(f).weight_percent, 1e-9) << f;
    EXPECT_NEAR(a.rpe.factor(f).weight_percent, once.rpe.factor(f).weight_percent, 1e-9) << f;
  }
}

TEST(AnovaOfDataset, RejectsVaryingFixedSettings) {
  std::vector<DatasetRow> rows = synthetic_l18();
  rows[3].y_mm += 1.0;
  EXPECT_THROW(doe::anova_of_dataset(rows), cmmcomp::ConfigError);
  rows = synthetic_l18();
  rows[5].pa_mm_s2 += 1.0;
  EXPECT_THROW(doe::anova_of_dataset(rows), cmmcomp::ConfigError);
  EXPECT_THROW(doe::anova_of_dataset({}), cmmcomp::ConfigError);
}

}  // namespace
}  // namespace cmmcomp::dynamics

// SPDX-License-Identifier: MIT
/// @file Stage 1 of train_fnn (docs/training.md, "How the trainer works"): check the data and
/// the options, and map them to normalised units; and the way back, from normalised-unit
/// parameters to a model in raw units. Private to the trainer.
///
/// Contract: `normalise` throws ConfigError for invalid options, no samples, inputs and targets
/// of different lengths, fewer samples than folds, a non-finite value or an input with
/// min == max (named by options.input_names or its index). Inputs map onto [0, 1] by the data's
/// min/max; each target to z = (y − mean)/std (population std; 1 for a constant output).
/// Samples with identical raw inputs form one design point.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/training/fnn_trainer.hpp>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace cmmcomp::training::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

inline std::size_t sz(Index i) { return static_cast<std::size_t>(i); }

inline bool all_finite(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

/// The rows `index` of `m`, in that order.
inline MatrixXd rows(const MatrixXd& m, const std::vector<Index>& index) {
  MatrixXd out(static_cast<Index>(index.size()), m.cols());
  for (std::size_t r = 0; r < index.size(); ++r) out.row(static_cast<Index>(r)) = m.row(index[r]);
  return out;
}

/// The training data in raw and normalised units. Refers to the caller's raw vectors, which
/// must outlive it.
template <int kInputs, int kOutputs>
struct NormalisedData {
  NormalisedData(const std::vector<std::array<double, kInputs>>& inputs,
                 const std::vector<std::array<double, kOutputs>>& targets)
      : raw_inputs(inputs), raw_targets(targets) {}

  const std::vector<std::array<double, kInputs>>& raw_inputs;
  const std::vector<std::array<double, kOutputs>>& raw_targets;
  double n = 0;  ///< sample count
  std::array<fuzzy::InputRange, kInputs> ranges{};
  std::vector<std::array<double, kInputs>> x;  ///< normalised inputs
  MatrixXd xm;                                 ///< x as an N × kInputs matrix
  MatrixXd z;                                  ///< normalised targets, N × kOutputs
  std::array<double, kOutputs> mean{}, scale{};
  /// Samples with identical inputs form a design point: group[k] is sample k's, of `groups`.
  std::vector<std::size_t> group;
  std::size_t groups = 0;
  /// A representative sample of each design point, in order of first appearance.
  std::vector<std::size_t> first;

  /// The model in raw units from normalised-unit parameters (premise: centres and widths as
  /// TskLayout; consequents: rule-major per output).
  template <int kSets>
  fuzzy::TskModel<double, kInputs, kSets, kOutputs> model(
      const std::vector<double>& premise, const std::vector<double>& consequents) const {
    using Layout = fuzzy::TskLayout<kInputs, kSets, kOutputs>;
    fuzzy::TskModel<double, kInputs, kSets, kOutputs> m;
    m.ranges = ranges;
    for (int k = 0; k < Layout::kConsequentsOffset; ++k) m.params.values[sz(k)] = premise[sz(k)];
    for (int o = 0; o < kOutputs; ++o) {
      for (int j = 0; j < Layout::kRules; ++j) {
        for (int t = 0; t < Layout::kTerms; ++t) {
          const double p = consequents[sz((o * Layout::kRules + j) * Layout::kTerms + t)];
          m.params.consequent(o, j, t) = scale[sz(o)] * p + (t == 0 ? mean[sz(o)] : 0.0);
        }
      }
    }
    return m;
  }

  /// RMSE per output [raw units] of `m` on the training samples (NaN where it cannot evaluate).
  template <int kSets>
  std::vector<double> rmse(const fuzzy::TskModel<double, kInputs, kSets, kOutputs>& m) const {
    std::vector<double> sum(static_cast<std::size_t>(kOutputs), 0.0);
    typename fuzzy::TskModel<double, kInputs, kSets, kOutputs>::RawOutput y{};
    for (std::size_t k = 0; k < raw_inputs.size(); ++k) {
      const Status st = fuzzy::evaluate(m, raw_inputs[k], y, fuzzy::DomainPolicy::kExtrapolate);
      for (int o = 0; o < kOutputs; ++o) {
        const double e =
            ok(st) ? y[sz(o)] - raw_targets[k][sz(o)] : std::numeric_limits<double>::quiet_NaN();
        sum[sz(o)] += e * e;
      }
    }
    for (double& v : sum) v = std::sqrt(v / n);
    return sum;
  }
};

/// "input 'PV'" or "input 2".
inline std::string input_name(const FnnTrainingOptions& options, int count, int i) {
  if (options.input_names.size() == static_cast<std::size_t>(count)) {
    return "input '" + options.input_names[sz(i)] + "'";
  }
  return "input " + std::to_string(i);
}

/// Stage 1: checks and normalises (see the file comment).
template <int kInputs, int kOutputs>
NormalisedData<kInputs, kOutputs> normalise(
    const std::vector<std::array<double, kInputs>>& inputs,
    const std::vector<std::array<double, kOutputs>>& targets,
    const FnnTrainingOptions& options) {
  std::string why;
  if (!options.is_valid(&why)) throw ConfigError("FNN training options: " + why);
  const std::size_t n = inputs.size();
  if (n == 0) throw ConfigError("FNN training: no samples");
  if (targets.size() != n) {
    throw ConfigError("FNN training: " + std::to_string(n) + " input rows but " +
                      std::to_string(targets.size()) + " target rows");
  }
  if (n < static_cast<std::size_t>(options.folds)) {
    throw ConfigError("FNN training: " + std::to_string(n) + " samples are fewer than the " +
                      std::to_string(options.folds) + " cross-validation folds");
  }
  for (std::size_t k = 0; k < n; ++k) {
    for (int i = 0; i < kInputs; ++i) {
      if (!std::isfinite(inputs[k][sz(i)])) {
        throw ConfigError("FNN training: sample " + std::to_string(k) + ": " +
                          input_name(options, kInputs, i) + " is not finite");
      }
    }
    for (int o = 0; o < kOutputs; ++o) {
      if (!std::isfinite(targets[k][sz(o)])) {
        throw ConfigError("FNN training: sample " + std::to_string(k) + ": target " +
                          std::to_string(o) + " is not finite");
      }
    }
  }
  NormalisedData<kInputs, kOutputs> d(inputs, targets);
  d.n = static_cast<double>(n);
  for (int i = 0; i < kInputs; ++i) {
    double lo = inputs[0][sz(i)], hi = lo;
    for (const auto& x : inputs) {
      lo = std::min(lo, x[sz(i)]);
      hi = std::max(hi, x[sz(i)]);
    }
    if (!(lo < hi) || !std::isfinite(hi - lo)) {
      throw ConfigError("FNN training: " + input_name(options, kInputs, i) +
                        " is constant in the data (min == max == " + std::to_string(lo) +
                        "); it cannot be normalised, drop it");
    }
    d.ranges[sz(i)] = fuzzy::InputRange{lo, hi};
  }
  d.x.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    for (int i = 0; i < kInputs; ++i)
      d.x[k][sz(i)] = fuzzy::normalise(inputs[k][sz(i)], d.ranges[sz(i)]);
  }
  d.z.resize(static_cast<Index>(n), kOutputs);
  for (int o = 0; o < kOutputs; ++o) {
    double mean = 0;
    for (const auto& t : targets) mean += t[sz(o)];
    mean /= d.n;
    double var = 0;
    for (const auto& t : targets) var += (t[sz(o)] - mean) * (t[sz(o)] - mean);
    const double sd = std::sqrt(var / d.n);
    d.mean[sz(o)] = mean;
    d.scale[sz(o)] = (sd > 0.0 && std::isfinite(sd)) ? sd : 1.0;
    for (std::size_t k = 0; k < n; ++k) {
      d.z(static_cast<Index>(k), o) = (targets[k][sz(o)] - mean) / d.scale[sz(o)];
    }
  }
  d.group.assign(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    std::size_t g = 0;
    while (g < d.first.size() && inputs[d.first[g]] != inputs[k]) ++g;
    if (g == d.first.size()) d.first.push_back(k);
    d.group[k] = g;
  }
  d.groups = d.first.size();
  d.xm.resize(static_cast<Index>(n), kInputs);
  for (std::size_t k = 0; k < n; ++k) {
    for (int i = 0; i < kInputs; ++i) d.xm(static_cast<Index>(k), i) = d.x[k][sz(i)];
  }
  return d;
}

}  // namespace cmmcomp::training::detail

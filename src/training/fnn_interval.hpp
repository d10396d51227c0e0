// SPDX-License-Identifier: MIT
/// @file Stage 5 of train_fnn (docs/uncertainty.md, docs/training.md "How the trainer works"):
/// the prediction interval's calibration (fuzzy/prediction_interval.hpp). Private to the
/// trainer.
///
/// Contract, with c = options.interval_coverage (0: nothing is calibrated):
///  - half-width and corner gain: a locally weighted split-conformal calibration of
///    |out-of-fold residual| [raw units] with weight 1 + gain·κ (κ the corner share, the gain
///    from the least-squares line of |r| on κ). Folds are made of whole design points; with
///    LM on no more design points than the premise has parameters, one design point per fold.
///    The fold models are the ridge fits of stage 2 and, unless options.interval_folds is
///    kRidge, networks trained as the served one; kNarrower takes per output the interval
///    with the smaller mean width (GD always takes the served folds).
///  - extrapolation gain: for each input and end, the samples in the outer third of its range
///    predicted by a ridge fit to the rest; the gain is the coverage quantile of the gains
///    (|r|/h(κ) − 1)/d each needs, d its distance from the rest's box.
/// Fills summary.interval_folds and interval_samples.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cmmcomp/detail/splitmix64.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/fuzzy/prediction_interval.hpp>
#include <cmmcomp/training/fnn_trainer.hpp>
#include <cstddef>
#include <utility>
#include <vector>

#include "fnn_normalise.hpp"
#include "fnn_ridge.hpp"

namespace cmmcomp::training::detail {

/// |raw residual| per output of every sample of `test[f]`, predicted by a network trained on
/// `train[f]` exactly as the served one (same options, λ fixed at the served λ, no interval),
/// in the order of the folds and their samples. False when a fold cannot be trained (an input
/// constant in it) or predicted: the ridge residuals then stand alone.
template <int kInputs, int kSets, int kOutputs>
bool served_fold_residuals(const NormalisedData<kInputs, kOutputs>& d,
                           const FnnTrainingOptions& options,
                           const std::vector<std::vector<Index>>& train,
                           const std::vector<std::vector<Index>>& test,
                           double lambda,
                           std::array<std::vector<double>, kOutputs>& residuals) {
  using Model = fuzzy::TskModel<double, kInputs, kSets, kOutputs>;
  FnnTrainingOptions fold_options = options;
  fold_options.lambda = lambda;
  fold_options.interval_coverage = 0.0;
  fold_options.progress = nullptr;
  for (std::size_t f = 0; f < train.size(); ++f) {
    if (train[f].size() < static_cast<std::size_t>(fold_options.folds)) return false;
    std::vector<std::array<double, kInputs>> inputs;
    std::vector<std::array<double, kOutputs>> targets;
    for (const Index k : train[f]) {
      inputs.push_back(d.raw_inputs[sz(k)]);
      targets.push_back(d.raw_targets[sz(k)]);
    }
    Model model;
    try {
      model = train_fnn<kInputs, kSets, kOutputs>(inputs, targets, fold_options).model;
    } catch (const ConfigError&) {
      return false;
    }
    typename Model::RawOutput y{};
    for (const Index k : test[f]) {
      if (!ok(fuzzy::evaluate(model, d.raw_inputs[sz(k)], y, fuzzy::DomainPolicy::kExtrapolate))) {
        return false;
      }
      for (int o = 0; o < kOutputs; ++o) {
        residuals[sz(o)].push_back(std::abs(y[sz(o)] - d.raw_targets[sz(k)][sz(o)]));
      }
    }
  }
  return true;
}

/// Stage 5 (see the file comment): `phi` and `u` are stage 2's, `lambda` the served one.
template <int kInputs, int kSets, int kOutputs>
void calibrate_interval(const RidgeFit<kInputs, kSets, kOutputs>& fit,
                        const MatrixXd& phi,
                        const MatrixXd& u,
                        double lambda,
                        fuzzy::IntervalCalibration<kOutputs>& cal,
                        TrainingSummary& s) {
  const NormalisedData<kInputs, kOutputs>& d = fit.data();
  const FnnTrainingOptions& options = fit.options();
  constexpr int kPremise = RidgeFit<kInputs, kSets, kOutputs>::kPremise;
  constexpr int kTerms = RidgeFit<kInputs, kSets, kOutputs>::kTerms;
  const double c = options.interval_coverage;
  if (c == 0.0) return;
  const std::size_t n = d.x.size();
  const std::vector<std::size_t>& group = d.group;  // design points: identical inputs
  const std::size_t groups = d.groups;
  if (groups < 2) return;  // nothing to hold out: no calibration
  // Few design points: leave one design point out, so that no fold empties a cell of the
  // design (a fold without both runs of a cell scores a fit the served model never has to
  // make). Not for GD, whose folds are trained as served (docs/uncertainty.md).
  const bool leave_one_out = groups <= static_cast<std::size_t>(kPremise) &&
                             options.method == FnnMethod::kLevenbergMarquardt;
  const std::size_t folds =
      leave_one_out ? groups : std::min(groups, static_cast<std::size_t>(options.folds));
  std::vector<std::size_t> order(groups);
  for (std::size_t g = 0; g < groups; ++g) order[g] = g;
  cmmcomp::detail::SplitMix64 rng{options.seed ^ 0x9e3779b97f4a7c15ULL};
  for (std::size_t g = groups; g > 1; --g) std::swap(order[g - 1], order[rng.below(g)]);
  std::vector<std::size_t> fold_of_group(groups);
  for (std::size_t g = 0; g < groups; ++g) fold_of_group[order[g]] = g % folds;

  // Out-of-fold |residual| of every sample, and its corner share κ.
  std::array<std::vector<double>, kOutputs> residuals;
  std::vector<double> corner;
  std::vector<std::vector<Index>> fold_train(folds), fold_test(folds);
  for (std::size_t f = 0; f < folds; ++f) {
    std::vector<Index>& train = fold_train[f];
    std::vector<Index>& test = fold_test[f];
    for (std::size_t k = 0; k < n; ++k) {
      (fold_of_group[group[k]] == f ? test : train).push_back(static_cast<Index>(k));
    }
    const MatrixXd pred = fit.predict(phi, u, train, test, lambda);
    for (std::size_t r = 0; r < test.size(); ++r) {
      corner.push_back(fuzzy::corner_share(d.ranges, d.raw_inputs[sz(test[r])]));
      for (int o = 0; o < kOutputs; ++o) {
        const double e = (pred(static_cast<Index>(r), o) - d.z(test[r], o)) * d.scale[sz(o)];
        residuals[sz(o)].push_back(std::abs(e));
      }
    }
  }
  // Corner gain: the least-squares line |r| = a + b·κ, gain b/a (0 when the residuals do not
  // grow towards the corners). Then the locally weighted conformal score |r| / (1 + gain·κ):
  // its quantile is the half-width. The weight depends on the input only, so the plain
  // interval's coverage argument holds for a fixed gain; fitted on the same residuals it holds
  // approximately (docs/uncertainty.md).
  double mean_k = 0.0;
  for (const double k : corner) mean_k += k;
  mean_k /= static_cast<double>(corner.size());
  double var_k = 0.0;
  for (const double k : corner) var_k += (k - mean_k) * (k - mean_k);
  struct Weighted {
    double gain = 0.0, half_width = 0.0;
  };
  const auto weighted_interval = [&](const std::vector<double>& r) {
    double mean_r = 0.0, cov = 0.0;
    for (const double v : r) mean_r += v;
    mean_r /= static_cast<double>(r.size());
    for (std::size_t j = 0; j < r.size(); ++j) cov += (corner[j] - mean_k) * (r[j] - mean_r);
    const double b = var_k > 0.0 ? cov / var_k : 0.0;
    // The intercept is floored at a tenth of the mean residual: residuals near 0 at the
    // centre and large at the corners must give a large, finite gain, not none.
    const double a = std::max(mean_r - b * mean_k, 0.1 * mean_r);
    Weighted w;
    w.gain = a > 0.0 && b > 0.0 ? b / a : 0.0;
    std::vector<double> scores(r.size());
    for (std::size_t j = 0; j < r.size(); ++j) scores[j] = r[j] / (1.0 + w.gain * corner[j]);
    w.half_width = conformal_quantile(std::move(scores), c);
    return w;
  };
  // The fold models trained as the served one, when they differ from the ridge fits. GD
  // starts from a random model, not from the ridge fit, so for it the ridge folds say nothing
  // about the served model: unless kRidge is asked for, its folds are trained as served.
  std::array<std::vector<double>, kOutputs> served;
  const bool lm = options.method == FnnMethod::kLevenbergMarquardt;
  const bool served_differs = !lm || options.max_iterations > 0;
  const bool have_served = options.interval_folds != IntervalFolds::kRidge && served_differs &&
                           served_fold_residuals<kInputs, kSets, kOutputs>(
                               d, options, fold_train, fold_test, lambda, served);
  const bool only_served = options.interval_folds == IntervalFolds::kAsServed || !lm;
  s.interval_folds.assign(static_cast<std::size_t>(kOutputs), IntervalFolds::kRidge);
  for (int o = 0; o < kOutputs; ++o) {
    Weighted w = weighted_interval(residuals[sz(o)]);
    if (have_served) {
      const Weighted w_served = weighted_interval(served[sz(o)]);
      // The mean half-width over the calibration moves, h·(1 + k·mean κ): the narrower one is
      // the less pessimistic estimate of the served model's error.
      const bool narrower = w_served.half_width * (1.0 + w_served.gain * mean_k) <
                            w.half_width * (1.0 + w.gain * mean_k);
      if (only_served || narrower) {
        w = w_served;
        s.interval_folds[sz(o)] = IntervalFolds::kAsServed;
      }
    }
    cal.corner_gain[sz(o)] = w.gain;
    cal.half_width[sz(o)] = w.half_width;
  }

  std::array<std::vector<double>, kOutputs> needs;
  for (int i = 0; i < kInputs; ++i) {
    for (const bool low : {true, false}) {
      std::vector<Index> train, test;
      for (std::size_t k = 0; k < n; ++k) {
        const double v = d.x[k][sz(i)];
        const bool outer = low ? v < 1.0 / 3.0 : v > 2.0 / 3.0;
        (outer ? test : train).push_back(static_cast<Index>(k));
      }
      if (test.empty() || train.size() < static_cast<std::size_t>(kTerms)) continue;
      std::array<fuzzy::InputRange, kInputs> box;
      for (int j = 0; j < kInputs; ++j) {
        double lo = d.x[sz(train[0])][sz(j)], hi = lo;
        for (const Index k : train) {
          lo = std::min(lo, d.x[sz(k)][sz(j)]);
          hi = std::max(hi, d.x[sz(k)][sz(j)]);
        }
        box[sz(j)] = fuzzy::InputRange{lo, hi > lo ? hi : lo + 1.0};
      }
      const MatrixXd pred = fit.predict(phi, u, train, test, lambda);
      for (std::size_t r = 0; r < test.size(); ++r) {
        const double dist = fuzzy::domain_distance(box, d.x[sz(test[r])]);
        if (!(dist > 0.0)) continue;
        const double kappa = fuzzy::corner_share(d.ranges, d.raw_inputs[sz(test[r])]);
        for (int o = 0; o < kOutputs; ++o) {
          const double h = cal.half_width[sz(o)] * (1.0 + cal.corner_gain[sz(o)] * kappa);
          const double e =
              std::abs(pred(static_cast<Index>(r), o) - d.z(test[r], o)) * d.scale[sz(o)];
          needs[sz(o)].push_back(h > 0.0 ? std::max(0.0, (e / h - 1.0) / dist) : 0.0);
        }
      }
    }
  }
  for (int o = 0; o < kOutputs; ++o) {
    cal.extrapolation_gain[sz(o)] = conformal_quantile(needs[sz(o)], c);
  }
  cal.coverage = c;
  s.interval_samples = n;
}

}  // namespace cmmcomp::training::detail

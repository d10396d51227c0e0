// SPDX-License-Identifier: MIT
/// @file Ceres training of the T-S network: ridge initialisation, k-fold CV, LM, GD baseline.
#include <ceres/ceres.h>
#include <ceres/dynamic_autodiff_cost_function.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cmmcomp/detail/splitmix64.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/training/fnn_trainer.hpp>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "ceres_progress.hpp"
#include "fnn_prior.hpp"

namespace cmmcomp::training {

/// The split-conformal quantile of `scores` at coverage `c`: the ⌈(n + 1)c⌉-th smallest (the
/// largest when that exceeds n: too few samples for the coverage, which then is not guaranteed).
double conformal_quantile(std::vector<double> scores, double c) {
  if (scores.empty()) return 0.0;
  std::sort(scores.begin(), scores.end());
  const double n = static_cast<double>(scores.size());
  const auto rank = static_cast<std::size_t>(std::ceil((n + 1.0) * c));
  return scores[std::min(std::max<std::size_t>(rank, 1), scores.size()) - 1];
}

namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

using cmmcomp::detail::SplitMix64;

std::size_t sz(Index i) { return static_cast<std::size_t>(i); }

bool all_finite(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

/// Ridge consequents in dual form for every output: P = Φᵀ U (Λ + λ)⁻¹ Uᵀ Z, with K = ΦΦᵀ = UΛUᵀ.
/// λ = 0 gives the minimum-norm least-squares solution (eigenvalues below a relative tolerance
/// are dropped).
class RidgeDual {
 public:
  RidgeDual(const MatrixXd& phi, const MatrixXd& z) : phi_(phi) {
    const MatrixXd k = phi * phi.transpose();
    Eigen::SelfAdjointEigenSolver<MatrixXd> eig(k);
    u_ = eig.eigenvectors();
    lambda_ = eig.eigenvalues();
    uz_ = u_.transpose() * z;
    const double top = lambda_.size() > 0 ? std::max(lambda_.maxCoeff(), 0.0) : 0.0;
    tol_ = top * static_cast<double>(k.rows()) * 1e-13;
  }

  /// Dual coefficients A = U (Λ + λ)⁻¹ Uᵀ Z (N × outputs); P = Φᵀ A, predictions at x: φ(x)ᵀP.
  MatrixXd dual(double lambda) const {
    VectorXd inv(lambda_.size());
    for (Index i = 0; i < lambda_.size(); ++i) {
      const double l = std::max(lambda_(i), 0.0);
      inv(i) = (lambda > 0.0) ? 1.0 / (l + lambda) : (l > tol_ ? 1.0 / l : 0.0);
    }
    return u_ * (inv.asDiagonal() * uz_);
  }

  MatrixXd consequents(double lambda) const { return phi_.transpose() * dual(lambda); }

 private:
  const MatrixXd& phi_;
  MatrixXd u_;
  VectorXd lambda_;
  MatrixXd uz_;
  double tol_ = 0;
};

/// √λ·(p − p̄) for the kTerms consequents of one rule, p̄ the prior (the global linear fit of
/// the output): linear, Jacobian √λ·I.
template <int kTerms>
class RidgeCost final : public ceres::SizedCostFunction<kTerms, kTerms> {
 public:
  RidgeCost(double lambda, const double* prior) : s_(std::sqrt(lambda)) {
    for (int t = 0; t < kTerms; ++t) prior_[static_cast<std::size_t>(t)] = prior[t];
  }
  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override {
    for (int t = 0; t < kTerms; ++t) {
      residuals[t] = s_ * (parameters[0][t] - prior_[static_cast<std::size_t>(t)]);
    }
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      for (int r = 0; r < kTerms; ++r) {
        for (int c = 0; c < kTerms; ++c) jacobians[0][r * kTerms + c] = (r == c) ? s_ : 0.0;
      }
    }
    return true;
  }

 private:
  double s_;
  std::array<double, static_cast<std::size_t>(kTerms)> prior_{};
};

/// Least-squares fit of z (N × outputs) on [1, x] (N × terms): the global first-order model,
/// one column of kTerms coefficients per output. A tiny ridge (1e-9 relative) keeps it defined
/// when the inputs are collinear.
MatrixXd global_linear_fit(const MatrixXd& u, const MatrixXd& z) {
  MatrixXd gram = u.transpose() * u;
  const double ridge = 1e-9 * std::max(gram.diagonal().maxCoeff(), 1.0);
  gram.diagonal().array() += ridge;
  return gram.ldlt().solve(u.transpose() * z);
}

using detail::ProgressCallback;

/// The rows `index` of `m`, in that order.
MatrixXd rows(const MatrixXd& m, const std::vector<Index>& index) {
  MatrixXd out(static_cast<Index>(index.size()), m.cols());
  for (std::size_t r = 0; r < index.size(); ++r) out.row(static_cast<Index>(r)) = m.row(index[r]);
  return out;
}

/// Everything one training run works on.
template <int kInputs, int kSets, int kOutputs>
class Trainer {
 public:
  using Model = fuzzy::TskModel<double, kInputs, kSets, kOutputs>;
  using Layout = fuzzy::TskLayout<kInputs, kSets, kOutputs>;
  using Single = fuzzy::TskLayout<kInputs, kSets, 1>;
  using Residual = FnnSampleResidual<kInputs, kSets>;
  static constexpr int kPremise = Layout::kConsequentsOffset;
  static constexpr int kRules = Layout::kRules;
  static constexpr int kTerms = Layout::kTerms;
  static constexpr int kBlock = Layout::kConsequentBlock;

  Trainer(const std::vector<std::array<double, kInputs>>& inputs,
          const std::vector<std::array<double, kOutputs>>& targets,
          const FnnTrainingOptions& options)
      : raw_inputs_(inputs), raw_targets_(targets), options_(options) {
    check_and_normalise();
    choose_prior();
  }

  FnnTrainingResult<kInputs, kSets, kOutputs> run() {
    const auto start = std::chrono::steady_clock::now();
    FnnTrainingResult<kInputs, kSets, kOutputs> result;
    TrainingSummary& s = result.summary;
    s.method = options_.method;

    // Steps 3 and 4: premise initialisation, CV of the ridge consequents, ridge init at λ.
    std::vector<double> premise = initial_premise();
    const MatrixXd phi = design_matrix(premise);
    const MatrixXd u = linear_terms();
    s.lambda_grid =
        options_.lambda < 0.0 ? options_.lambda_grid : std::vector<double>{options_.lambda};
    const MatrixXd sse = cross_validate(phi, u, s.lambda_grid);  // [grid][output]
    std::size_t best = 0;
    for (std::size_t g = 0; g < s.lambda_grid.size(); ++g) {
      const double mse = sse.row(static_cast<Index>(g)).sum() / (n_ * kOutputs);
      s.cv_mse_grid.push_back(mse);
      const double best_mse = s.cv_mse_grid[best];
      const bool better =
          mse < best_mse || (mse == best_mse && s.lambda_grid[g] > s.lambda_grid[best]);
      if (g == 0 || better || !std::isfinite(best_mse)) best = g;
    }
    s.lambda = s.lambda_grid[best];
    for (int o = 0; o < kOutputs; ++o) {
      s.cv_rmse.push_back(std::sqrt(sse(static_cast<Index>(best), o) / n_) * scale_[sz(o)]);
    }
    const MatrixXd prior = rule_prior(all_samples(), u);  // kBlock × kOutputs
    prior_.assign(static_cast<std::size_t>(kOutputs * kBlock), 0.0);
    for (int o = 0; o < kOutputs; ++o) {
      for (int k = 0; k < kBlock; ++k) prior_[sz(o * kBlock + k)] = prior(k, o);
    }
    for (int o = 0; o < kOutputs; ++o) s.prior.push_back(shapes_[sz(o)].describe(names()));
    s.design_points = groups_;
    const RidgeDual ridge(phi, z_ - phi * prior);
    const MatrixXd p0 = ridge.consequents(s.lambda);  // kBlock × kOutputs, deviations from it
    std::vector<double> consequents(static_cast<std::size_t>(kOutputs * kBlock));
    for (int o = 0; o < kOutputs; ++o) {
      for (int k = 0; k < kBlock; ++k) consequents[sz(o * kBlock + k)] = prior(k, o) + p0(k, o);
    }
    const Model init = make_model(premise, consequents);
    s.init_train_rmse = train_rmse(init);

    if (options_.method == FnnMethod::kLevenbergMarquardt) {
      run_lm(premise, consequents, s);
    } else {
      if (options_.lambda <= 0.0) s.lambda = 0.0;
      run_gd(premise, consequents, s);
    }

    result.model = make_model(premise, consequents);
    if (!(all_finite(premise) && all_finite(consequents)) || !fuzzy::validate(result.model)) {
      result.model = init;
      s.solution_usable = false;
      s.message += " (parameters not usable: returned the ridge initialisation)";
    }
    s.train_rmse = train_rmse(result.model);
    calibrate_interval(phi, u, s.lambda, result.interval, s);
    s.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  }

 private:
  std::string input_name(int i) const {
    if (options_.input_names.size() == static_cast<std::size_t>(kInputs)) {
      return "input '" + options_.input_names[sz(i)] + "'";
    }
    return "input " + std::to_string(i);
  }

  void check_and_normalise() {
    std::string why;
    if (!options_.is_valid(&why)) throw ConfigError("FNN training options: " + why);
    const std::size_t n = raw_inputs_.size();
    if (n == 0) throw ConfigError("FNN training: no samples");
    if (raw_targets_.size() != n) {
      throw ConfigError("FNN training: " + std::to_string(n) + " input rows but " +
                        std::to_string(raw_targets_.size()) + " target rows");
    }
    if (n < static_cast<std::size_t>(options_.folds)) {
      throw ConfigError("FNN training: " + std::to_string(n) + " samples are fewer than the " +
                        std::to_string(options_.folds) + " cross-validation folds");
    }
    for (std::size_t k = 0; k < n; ++k) {
      for (int i = 0; i < kInputs; ++i) {
        if (!std::isfinite(raw_inputs_[k][sz(i)])) {
          throw ConfigError("FNN training: sample " + std::to_string(k) + ": " + input_name(i) +
                            " is not finite");
        }
      }
      for (int o = 0; o < kOutputs; ++o) {
        if (!std::isfinite(raw_targets_[k][sz(o)])) {
          throw ConfigError("FNN training: sample " + std::to_string(k) + ": target " +
                            std::to_string(o) + " is not finite");
        }
      }
    }
    n_ = static_cast<double>(n);
    for (int i = 0; i < kInputs; ++i) {
      double lo = raw_inputs_[0][sz(i)], hi = lo;
      for (const auto& x : raw_inputs_) {
        lo = std::min(lo, x[sz(i)]);
        hi = std::max(hi, x[sz(i)]);
      }
      if (!(lo < hi) || !std::isfinite(hi - lo)) {
        throw ConfigError("FNN training: " + input_name(i) +
                          " is constant in the data (min == max == " + std::to_string(lo) +
                          "); it cannot be normalised, drop it");
      }
      ranges_[sz(i)] = fuzzy::InputRange{lo, hi};
    }
    x_.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      for (int i = 0; i < kInputs; ++i) {
        x_[k][sz(i)] = fuzzy::normalise(raw_inputs_[k][sz(i)], ranges_[sz(i)]);
      }
    }
    z_.resize(static_cast<Index>(n), kOutputs);
    for (int o = 0; o < kOutputs; ++o) {
      double mean = 0;
      for (const auto& t : raw_targets_) mean += t[sz(o)];
      mean /= n_;
      double var = 0;
      for (const auto& t : raw_targets_) var += (t[sz(o)] - mean) * (t[sz(o)] - mean);
      const double sd = std::sqrt(var / n_);
      mean_[sz(o)] = mean;
      scale_[sz(o)] = (sd > 0.0 && std::isfinite(sd)) ? sd : 1.0;
      for (std::size_t k = 0; k < n; ++k) {
        z_(static_cast<Index>(k), o) = (raw_targets_[k][sz(o)] - mean) / scale_[sz(o)];
      }
    }
  }

  std::vector<double> initial_premise() const {
    std::vector<double> premise(static_cast<std::size_t>(kPremise));
    const double spacing = kSets > 1 ? 1.0 / (kSets - 1) : 1.0;
    for (int i = 0; i < kInputs; ++i) {
      for (int s = 0; s < kSets; ++s) {
        premise[sz(Layout::centre_index(i, s))] = kSets > 1 ? s * spacing : 0.5;
        premise[sz(Layout::width_index(i, s))] = std::max(spacing, options_.min_width);
      }
    }
    return premise;
  }

  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (int i = 0; i < kInputs; ++i) {
      out.push_back(options_.input_names.size() == static_cast<std::size_t>(kInputs)
                        ? options_.input_names[sz(i)]
                        : "x" + std::to_string(i));
    }
    return out;
  }

  std::vector<Index> all_samples() const { return detail::all_rows(static_cast<Index>(x_.size())); }

  /// Design points (samples with identical inputs), and the prior's shape per output (step 3):
  /// on a designed experiment, every input at three levels, the shape with the lowest
  /// leave-one-design-point-out error (fnn_prior.hpp); otherwise the global first-order fit.
  void choose_prior() {
    const std::size_t n = x_.size();
    group_.assign(n, 0);
    std::vector<std::size_t> first;  // a representative sample of each design point
    for (std::size_t k = 0; k < n; ++k) {
      std::size_t g = 0;
      while (g < first.size() && raw_inputs_[first[g]] != raw_inputs_[k]) ++g;
      if (g == first.size()) first.push_back(k);
      group_[k] = g;
    }
    groups_ = first.size();
    bool three_levels = true;
    for (int i = 0; i < kInputs && three_levels; ++i) {
      std::vector<double> levels;
      for (const std::size_t k : first) levels.push_back(raw_inputs_[k][sz(i)]);
      std::sort(levels.begin(), levels.end());
      three_levels = std::unique(levels.begin(), levels.end()) - levels.begin() == 3;
    }
    xm_.resize(static_cast<Index>(n), kInputs);
    for (std::size_t k = 0; k < n; ++k) {
      for (int i = 0; i < kInputs; ++i) xm_(static_cast<Index>(k), i) = x_[k][sz(i)];
    }
    const std::vector<detail::PriorShape> candidates = detail::prior_candidates(kInputs);
    shapes_.assign(static_cast<std::size_t>(kOutputs), candidates.front());
    if (!three_levels) return;
    for (int o = 0; o < kOutputs; ++o) {
      shapes_[sz(o)] = detail::choose_prior_shape(xm_, z_.col(o), group_, groups_);
    }
  }

  /// The prior's consequents (kBlock × kOutputs) fitted to the samples `idx`: for a first-order
  /// shape the global first-order fit g in every rule; otherwise, in each rule, the tangent
  /// plane of the fitted shape at the rule's centre (the initial premise's), so the network
  /// starts as the shape, smoothed between the centres.
  /// On a part of the data (a CV fold, a held-out end) an output whose shape is not the
  /// first-order fit chooses its shape again from that part, as the whole fit would have had
  /// it been given only that part: a fold may lack a cell of the chosen pair or a level of an
  /// input, and the calibrated interval must score the fit, not a made-up cell.
  MatrixXd rule_prior(const std::vector<Index>& idx, const MatrixXd& u) const {
    MatrixXd prior(kBlock, kOutputs);
    const MatrixXd g = global_linear_fit(rows(u, idx), rows(z_, idx));  // kTerms × kOutputs
    const double spacing = kSets > 1 ? 1.0 / (kSets - 1) : 1.0;
    const bool part = idx.size() != x_.size();
    for (int o = 0; o < kOutputs; ++o) {
      const detail::PriorShape shape =
          part && !shapes_[sz(o)].first_order() &&
                  !detail::prior_identifiable(shapes_[sz(o)], xm_, idx)
              ? detail::choose_prior_shape(xm_, z_.col(o), group_, groups_, idx)
              : shapes_[sz(o)];
      if (shape.first_order()) {
        for (int k = 0; k < kBlock; ++k) prior(k, o) = g(k % kTerms, o);
        continue;
      }
      const Eigen::VectorXd b = detail::fit_prior(shape, xm_, z_.col(o), idx);
      for (int j = 0; j < kRules; ++j) {
        std::array<double, kInputs> c{};
        for (int i = 0; i < kInputs; ++i) {
          c[sz(i)] = kSets > 1 ? Layout::rule_set(j, i) * spacing : 0.5;
        }
        double p0 = detail::prior_features(shape, c.data()).dot(b);
        for (int i = 0; i < kInputs; ++i) {
          const double slope = detail::prior_feature_slopes(shape, c.data(), i).dot(b);
          prior(j * kTerms + 1 + i, o) = slope;
          p0 -= slope * c[sz(i)];
        }
        prior(j * kTerms, o) = p0;
      }
    }
    return prior;
  }

  /// U (N × kTerms): row n = [1, x_n], the regressors of the global first-order model.
  MatrixXd linear_terms() const {
    MatrixXd u(static_cast<Index>(x_.size()), kTerms);
    for (std::size_t k = 0; k < x_.size(); ++k) {
      u(static_cast<Index>(k), 0) = 1.0;
      for (int i = 0; i < kInputs; ++i) u(static_cast<Index>(k), 1 + i) = x_[k][sz(i)];
    }
    return u;
  }

  /// Φ (N × kBlock): row n = ᾱ_j(x_n)·[1, x_n] for every rule j, the consequent layout.
  MatrixXd design_matrix(const std::vector<double>& premise) const {
    using Net = fuzzy::TskEvaluator<double, kInputs, kSets, 1>;
    std::vector<double> params(static_cast<std::size_t>(Single::kParamCount), 0.0);
    std::copy(premise.begin(), premise.end(), params.begin());
    MatrixXd phi(static_cast<Index>(x_.size()), kBlock);
    typename Net::Firing alpha;
    for (std::size_t k = 0; k < x_.size(); ++k) {
      const double total = Net::firing(params.data(), x_[k], alpha);
      for (int j = 0; j < kRules; ++j) {
        const double a = alpha[sz(j)] / total;
        phi(static_cast<Index>(k), j * kTerms) = a;
        for (int i = 0; i < kInputs; ++i) {
          phi(static_cast<Index>(k), j * kTerms + 1 + i) = a * x_[k][sz(i)];
        }
      }
    }
    return phi;
  }

  /// Sum of squared CV errors [normalised], rows = grid values, columns = outputs.
  MatrixXd cross_validate(const MatrixXd& phi,
                          const MatrixXd& u,
                          const std::vector<double>& grid) const {
    const std::size_t n = x_.size();
    const auto folds = static_cast<std::size_t>(options_.folds);
    std::vector<std::size_t> order(n);
    for (std::size_t k = 0; k < n; ++k) order[k] = k;
    SplitMix64 rng{options_.seed};
    for (std::size_t k = n; k > 1; --k) std::swap(order[k - 1], order[rng.below(k)]);
    std::vector<std::size_t> fold_of(n);
    for (std::size_t k = 0; k < n; ++k) fold_of[order[k]] = k % folds;

    MatrixXd sse = MatrixXd::Zero(static_cast<Index>(grid.size()), kOutputs);
    for (std::size_t f = 0; f < folds; ++f) {
      std::vector<Index> train, test;
      for (std::size_t k = 0; k < n; ++k)
        (fold_of[k] == f ? test : train).push_back(static_cast<Index>(k));
      const MatrixXd phi_tr = rows(phi, train), z_tr = rows(z_, train);
      const MatrixXd phi_te = rows(phi, test), z_te = rows(z_, test);
      // The prior is refitted, and its shape chosen again, on the fold's training part too,
      // so CV scores the whole fit.
      const MatrixXd prior = rule_prior(train, u);
      const RidgeDual ridge(phi_tr, z_tr - phi_tr * prior);
      const MatrixXd cross = phi_te * phi_tr.transpose();
      const MatrixXd base = phi_te * prior;
      for (std::size_t g = 0; g < grid.size(); ++g) {
        const MatrixXd err = base + cross * ridge.dual(grid[g]) - z_te;
        sse.row(static_cast<Index>(g)) += err.colwise().squaredNorm();
      }
    }
    return sse;
  }

  /// Predictions [normalised] at the samples `test` of the ridge fit (prior refitted, premise
  /// at the initialisation, weight λ) to the samples `train`: the fit CV scores.
  MatrixXd ridge_predict(const MatrixXd& phi,
                         const MatrixXd& u,
                         const std::vector<Index>& train,
                         const std::vector<Index>& test,
                         double lambda) const {
    const MatrixXd phi_tr = rows(phi, train), z_tr = rows(z_, train);
    const MatrixXd prior = rule_prior(train, u);
    const RidgeDual ridge(phi_tr, z_tr - phi_tr * prior);
    return rows(phi, test) * (prior + phi_tr.transpose() * ridge.dual(lambda));
  }

  /// Step 7: the prediction interval's calibration (fuzzy/prediction_interval.hpp).
  ///  - half-width and corner gain: a locally weighted split-conformal calibration of
  ///    |out-of-fold residual| [raw units] with weight 1 + gain·κ (κ the corner share), the
  ///    gain from the least-squares line of |r| on κ; the folds made of whole design points
  ///    (every repeat of a move in the same fold), so that a residual is that of a move the fit
  ///    has not seen, as in service;
  ///  - extrapolation gain: for each input and each end, the samples in the outer third of its
  ///    range are predicted by a fit to the rest; each needs gain (|r|/h(κ) − 1)/d to be covered
  ///    (d its distance from the rest's box, in the rest's ranges); the gain is the coverage
  ///    quantile of those needs over every such sample (0 if they are covered already).
  /// The fits are the ridge initialisation at the chosen λ (milliseconds), not the LM
  /// refinement: where LM is more accurate than its initialisation the interval is
  /// conservative. The coverage ctest measures it (docs/uncertainty.md). A deletion residual
  /// of the final model at its premise (e = (I − H_GG)⁻¹ r) was tried and was wider still: a
  /// held-out design point of an orthogonal array is harder to predict than a random move.
  void calibrate_interval(const MatrixXd& phi,
                          const MatrixXd& u,
                          double lambda,
                          fuzzy::IntervalCalibration<kOutputs>& cal,
                          TrainingSummary& s) const {
    const double c = options_.interval_coverage;
    if (c == 0.0) return;
    const std::size_t n = x_.size();
    const std::vector<std::size_t>& group = group_;  // design points: identical inputs
    const std::size_t groups = groups_;
    if (groups < 2) return;  // nothing to hold out: no calibration
    // Few design points (no more than the premise's parameters, when LM does not run either):
    // leave one design point out. A fifth of an L18 is a large share of the design; a fold
    // without both runs of a cell scores a fit the served model never has to make, and the
    // interval came out up to 11 times wider than the served model's error. Not for gradient
    // descent, whose folds are trained as served: 18 GD runs instead of 5 (40 s each on the
    // L18), for a calibration that over-covers anyway (docs/uncertainty.md).
    const bool leave_one_out = groups <= static_cast<std::size_t>(kPremise) &&
                               options_.method == FnnMethod::kLevenbergMarquardt;
    const std::size_t folds =
        leave_one_out ? groups : std::min(groups, static_cast<std::size_t>(options_.folds));
    std::vector<std::size_t> order(groups);
    for (std::size_t g = 0; g < groups; ++g) order[g] = g;
    SplitMix64 rng{options_.seed ^ 0x9e3779b97f4a7c15ULL};
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
      const MatrixXd pred = ridge_predict(phi, u, train, test, lambda);
      for (std::size_t r = 0; r < test.size(); ++r) {
        corner.push_back(fuzzy::corner_share(ranges_, raw_inputs_[sz(test[r])]));
        for (int o = 0; o < kOutputs; ++o) {
          const double e = (pred(static_cast<Index>(r), o) - z_(test[r], o)) * scale_[sz(o)];
          residuals[sz(o)].push_back(std::abs(e));
        }
      }
    }
    // Corner gain: the least-squares line |r| = a + b·κ, gain b/a (0 when the residuals do not
    // grow towards the corners). Then the locally weighted conformal score
    // |r| / (1 + gain·κ): its quantile is the half-width. The weight depends on the input only,
    // so the plain interval's coverage argument holds for a fixed gain; fitted on the same
    // residuals it holds approximately (docs/uncertainty.md).
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
      // centre and large at the corners (the strongest case) must give a large, finite gain,
      // not a negative intercept and no gain at all.
      const double a = std::max(mean_r - b * mean_k, 0.1 * mean_r);
      Weighted w;
      w.gain = a > 0.0 && b > 0.0 ? b / a : 0.0;
      std::vector<double> scores(r.size());
      for (std::size_t j = 0; j < r.size(); ++j) scores[j] = r[j] / (1.0 + w.gain * corner[j]);
      w.half_width = conformal_quantile(std::move(scores), c);
      return w;
    };
    // The fold models trained as the served one, when they differ from the ridge fits.
    // Gradient descent starts from a random model, not from the ridge fit, so for it the ridge
    // folds say nothing about the served model: unless kRidge is asked for, its folds are
    // always trained as served (kNarrower behaves as kAsServed).
    std::array<std::vector<double>, kOutputs> served;
    const bool lm = options_.method == FnnMethod::kLevenbergMarquardt;
    const bool served_differs = !lm || options_.max_iterations > 0;
    const bool have_served = options_.interval_folds != IntervalFolds::kRidge && served_differs &&
                             served_fold_residuals(fold_train, fold_test, lambda, served);
    const bool only_served = options_.interval_folds == IntervalFolds::kAsServed || !lm;
    s.interval_folds.assign(static_cast<std::size_t>(kOutputs), IntervalFolds::kRidge);
    for (int o = 0; o < kOutputs; ++o) {
      Weighted w = weighted_interval(residuals[sz(o)]);
      if (have_served) {
        const Weighted w_served = weighted_interval(served[sz(o)]);
        // The mean half-width over the calibration moves, h·(1 + k·mean κ): the narrower one
        // is the less pessimistic estimate of the served model's error.
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
          const double v = x_[k][sz(i)];
          const bool outer = low ? v < 1.0 / 3.0 : v > 2.0 / 3.0;
          (outer ? test : train).push_back(static_cast<Index>(k));
        }
        if (test.empty() || train.size() < static_cast<std::size_t>(kTerms)) continue;
        std::array<fuzzy::InputRange, kInputs> box;
        for (int j = 0; j < kInputs; ++j) {
          double lo = x_[sz(train[0])][sz(j)], hi = lo;
          for (const Index k : train) {
            lo = std::min(lo, x_[sz(k)][sz(j)]);
            hi = std::max(hi, x_[sz(k)][sz(j)]);
          }
          box[sz(j)] = fuzzy::InputRange{lo, hi > lo ? hi : lo + 1.0};
        }
        const MatrixXd pred = ridge_predict(phi, u, train, test, lambda);
        for (std::size_t r = 0; r < test.size(); ++r) {
          const double d = fuzzy::domain_distance(box, x_[sz(test[r])]);
          if (!(d > 0.0)) continue;
          const double kappa = fuzzy::corner_share(ranges_, raw_inputs_[sz(test[r])]);
          for (int o = 0; o < kOutputs; ++o) {
            const double h = cal.half_width[sz(o)] * (1.0 + cal.corner_gain[sz(o)] * kappa);
            const double e =
                std::abs(pred(static_cast<Index>(r), o) - z_(test[r], o)) * scale_[sz(o)];
            needs[sz(o)].push_back(h > 0.0 ? std::max(0.0, (e / h - 1.0) / d) : 0.0);
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

  /// |raw residual| per output of every sample of `test[f]`, predicted by a network trained
  /// on `train[f]` exactly as the served one (same options, λ fixed at the served λ, no
  /// interval), in the order of the folds and their samples (that of the ridge residuals).
  /// False when a fold cannot be trained (an input constant in it) or predicted: the ridge
  /// residuals then stand alone.
  bool served_fold_residuals(const std::vector<std::vector<Index>>& train,
                             const std::vector<std::vector<Index>>& test,
                             double lambda,
                             std::array<std::vector<double>, kOutputs>& residuals) const {
    FnnTrainingOptions fold_options = options_;
    fold_options.lambda = lambda;
    fold_options.interval_coverage = 0.0;
    fold_options.progress = nullptr;
    for (std::size_t f = 0; f < train.size(); ++f) {
      if (train[f].size() < static_cast<std::size_t>(fold_options.folds)) return false;
      std::vector<std::array<double, kInputs>> inputs;
      std::vector<std::array<double, kOutputs>> targets;
      for (const Index k : train[f]) {
        inputs.push_back(raw_inputs_[sz(k)]);
        targets.push_back(raw_targets_[sz(k)]);
      }
      Model model;
      try {
        model = Trainer(inputs, targets, fold_options).run().model;
      } catch (const ConfigError&) {
        return false;
      }
      typename Model::RawOutput y{};
      for (const Index k : test[f]) {
        if (!ok(fuzzy::evaluate(model, raw_inputs_[sz(k)], y, fuzzy::DomainPolicy::kExtrapolate))) {
          return false;
        }
        for (int o = 0; o < kOutputs; ++o) {
          residuals[sz(o)].push_back(std::abs(y[sz(o)] - raw_targets_[sz(k)][sz(o)]));
        }
      }
    }
    return true;
  }

  /// The model in raw units from normalised-unit parameters.
  Model make_model(const std::vector<double>& premise,
                   const std::vector<double>& consequents) const {
    Model m;
    m.ranges = ranges_;
    for (int k = 0; k < kPremise; ++k) m.params.values[sz(k)] = premise[sz(k)];
    for (int o = 0; o < kOutputs; ++o) {
      for (int j = 0; j < kRules; ++j) {
        for (int t = 0; t < kTerms; ++t) {
          const double p = consequents[sz((o * kRules + j) * kTerms + t)];
          m.params.consequent(o, j, t) = scale_[sz(o)] * p + (t == 0 ? mean_[sz(o)] : 0.0);
        }
      }
    }
    return m;
  }

  std::vector<double> train_rmse(const Model& m) const {
    std::vector<double> sum(static_cast<std::size_t>(kOutputs), 0.0);
    typename Model::RawOutput y{};
    for (std::size_t k = 0; k < raw_inputs_.size(); ++k) {
      const Status st = fuzzy::evaluate(m, raw_inputs_[k], y, fuzzy::DomainPolicy::kExtrapolate);
      for (int o = 0; o < kOutputs; ++o) {
        const double e =
            ok(st) ? y[sz(o)] - raw_targets_[k][sz(o)] : std::numeric_limits<double>::quiet_NaN();
        sum[sz(o)] += e * e;
      }
    }
    for (double& v : sum) v = std::sqrt(v / n_);
    return sum;
  }

  /// Residual blocks: one per sample and output (FnnSampleResidual), then, when λ > 0, one
  /// ridge block per rule and output. Blocks point into `premise` and `consequents`.
  void build_problem(ceres::Problem& problem,
                     std::vector<double>& premise,
                     std::vector<double>& consequents,
                     double lambda,
                     std::vector<double*>& order) const {
    order.clear();
    order.push_back(premise.data());
    for (int b = 0; b < kOutputs * kRules; ++b) order.push_back(consequents.data() + b * kTerms);
    std::vector<double*> blocks(static_cast<std::size_t>(kRules + 1));
    for (int o = 0; o < kOutputs; ++o) {
      blocks[0] = premise.data();
      for (int j = 0; j < kRules; ++j) {
        blocks[sz(j + 1)] = consequents.data() + (o * kRules + j) * kTerms;
      }
      for (std::size_t k = 0; k < x_.size(); ++k) {
        auto* functor = new Residual;
        functor->input = x_[k];
        functor->target = z_(static_cast<Index>(k), o);
        auto* cost = new ceres::DynamicAutoDiffCostFunction<Residual, kFnnJetStride>(functor);
        cost->AddParameterBlock(kPremise);
        for (int j = 0; j < kRules; ++j) cost->AddParameterBlock(kTerms);
        cost->SetNumResiduals(1);
        problem.AddResidualBlock(cost, nullptr, blocks);
      }
    }
    if (lambda > 0.0) {
      for (int b = 0; b < kOutputs * kRules; ++b) {
        const double* prior = prior_.data() + b * kTerms;
        problem.AddResidualBlock(
            new RidgeCost<kTerms>(lambda, prior), nullptr, consequents.data() + b * kTerms);
      }
    }
  }

  void run_lm(std::vector<double>& premise,
              std::vector<double>& consequents,
              TrainingSummary& s) const {
    if (options_.max_iterations == 0) {
      s.message = "ridge initialisation only (max_iterations = 0)";
      s.solution_usable = true;
      s.converged = true;
      return;
    }
    if (groups_ <= static_cast<std::size_t>(kPremise)) {
      // Fewer design points than premise parameters: the data cannot place the centres and
      // widths, and moving them to fit the few points bends the network between them (on the
      // paper's L18 it cost RPE 3-5 points of reduction, docs/training.md).
      s.message = "ridge initialisation kept: " + std::to_string(groups_) +
                  " design points cannot place the premise's " + std::to_string(kPremise) +
                  " centres and widths";
      s.solution_usable = true;
      s.converged = true;
      return;
    }
    ceres::Problem problem;
    std::vector<double*> order;
    build_problem(problem, premise, consequents, s.lambda, order);
    for (int i = 0; i < kInputs; ++i) {
      for (int t = 0; t < kSets; ++t) {
        problem.SetParameterLowerBound(
            premise.data(), Layout::width_index(i, t), options_.min_width);
      }
    }
    ceres::Solver::Options so;
    so.minimizer_type = ceres::TRUST_REGION;
    so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    const int params = kPremise + kOutputs * kBlock;
    if (params <= 1000) {
      so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    } else if (ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE)) {
      so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
      so.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
    } else if (ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::EIGEN_SPARSE)) {
      so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
      so.sparse_linear_algebra_library_type = ceres::EIGEN_SPARSE;
    } else {
      so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    }
    so.max_num_iterations = options_.max_iterations;
    so.num_threads = 1;
    so.logging_type = ceres::SILENT;
    so.minimizer_progress_to_stdout = false;
    ProgressCallback callback(options_.progress);
    so.callbacks.push_back(&callback);
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    s.message = summary.message;
    s.iterations = static_cast<int>(summary.iterations.size()) - 1;  // iteration 0 = start
    s.initial_cost = summary.initial_cost;
    s.final_cost = summary.final_cost;
    s.solution_usable = summary.IsSolutionUsable();
    s.converged = summary.termination_type == ceres::CONVERGENCE;
  }

  void run_gd(std::vector<double>& premise,
              std::vector<double>& consequents,
              TrainingSummary& s) const {
    // The paper's random start (seeded), replacing the ridge initialisation.
    SplitMix64 rng{options_.seed ^ 0x5DEECE66DULL};
    const double spacing = kSets > 1 ? 1.0 / (kSets - 1) : 1.0;
    for (int i = 0; i < kInputs; ++i) {
      for (int t = 0; t < kSets; ++t) premise[sz(Layout::centre_index(i, t))] = rng.uniform();
      for (int t = 0; t < kSets; ++t) {
        premise[sz(Layout::width_index(i, t))] =
            std::max(rng.uniform(0.5, 1.5) * spacing, options_.min_width);
      }
    }
    for (double& p : consequents) p = rng.uniform(-0.5, 0.5);

    ceres::Problem problem;
    std::vector<double*> order;
    build_problem(problem, premise, consequents, s.lambda, order);
    ceres::Problem::EvaluateOptions eo;
    eo.parameter_blocks = order;
    eo.num_threads = 1;
    const std::size_t data_residuals = x_.size() * static_cast<std::size_t>(kOutputs);
    std::vector<double> residuals, gradient;
    std::vector<double> last_premise = premise, last_consequents = consequents;
    s.solution_usable = true;
    s.message = "epoch limit reached";
    int epoch = 0;
    for (;; ++epoch) {
      double cost = 0;
      const bool evaluated = problem.Evaluate(eo, &cost, &residuals, &gradient, nullptr);
      double sq = 0;
      for (std::size_t r = 0; r < data_residuals && r < residuals.size(); ++r)
        sq += residuals[r] * residuals[r];
      const double mse = sq / static_cast<double>(data_residuals);
      if (!evaluated || !std::isfinite(cost) || !all_finite(gradient)) {
        premise = last_premise;
        consequents = last_consequents;
        s.solution_usable = epoch > 0;
        s.message = "gradient descent: non-finite cost or gradient at epoch " +
                    std::to_string(epoch) + "; stopped at the last finite parameters";
        break;
      }
      if (epoch == 0) s.initial_cost = cost;
      s.final_cost = cost;
      if (options_.progress) options_.progress(epoch, cost);
      if (mse <= options_.goal) {
        s.converged = true;
        s.message = "gradient descent: goal reached (MSE " + std::to_string(mse) +
                    " <= " + std::to_string(options_.goal) + ")";
        break;
      }
      if (epoch >= options_.epochs) break;
      last_premise = premise;
      last_consequents = consequents;
      for (int k = 0; k < kPremise; ++k) premise[sz(k)] -= options_.learning_rate * gradient[sz(k)];
      for (std::size_t k = 0; k < consequents.size(); ++k) {
        consequents[k] -= options_.learning_rate * gradient[static_cast<std::size_t>(kPremise) + k];
      }
      for (int i = 0; i < kInputs; ++i) {
        for (int t = 0; t < kSets; ++t) {
          double& w = premise[sz(Layout::width_index(i, t))];
          w = std::max(w, options_.min_width);
        }
      }
    }
    s.iterations = epoch;
  }

  const std::vector<std::array<double, kInputs>>& raw_inputs_;
  const std::vector<std::array<double, kOutputs>>& raw_targets_;
  const FnnTrainingOptions& options_;
  double n_ = 0;
  std::array<fuzzy::InputRange, kInputs> ranges_{};
  std::vector<std::array<double, kInputs>> x_;  ///< normalised inputs
  MatrixXd z_;                                  ///< normalised targets, N × kOutputs
  std::array<double, kOutputs> mean_{}, scale_{};
  /// Samples with identical inputs form a design point: group_[k] is sample k's, of groups_.
  std::vector<std::size_t> group_;
  std::size_t groups_ = 0;
  MatrixXd xm_;                             ///< x_ as an N × kInputs matrix
  std::vector<detail::PriorShape> shapes_;  ///< the prior's shape per output (step 3)
  /// The prior's consequents, rule-major per output as `consequents` (normalised units).
  std::vector<double> prior_;
};

}  // namespace

const char* to_string(FnnMethod method) noexcept {
  switch (method) {
    case FnnMethod::kLevenbergMarquardt:
      return "levenberg-marquardt";
    case FnnMethod::kGradientDescent:
      return "gradient-descent";
  }
  return "unknown";
}

const char* to_string(IntervalFolds folds) noexcept {
  switch (folds) {
    case IntervalFolds::kRidge:
      return "ridge";
    case IntervalFolds::kAsServed:
      return "as-served";
    case IntervalFolds::kNarrower:
      return "narrower";
  }
  return "unknown";
}

std::string interval_method(const std::vector<IntervalFolds>& used,
                            const std::vector<std::string>& outputs) {
  std::string which;
  for (std::size_t o = 0; o < used.size(); ++o) {
    if (o > 0) which += ", ";
    which += (o < outputs.size() ? outputs[o] : "output " + std::to_string(o)) + " " +
             to_string(used[o]);
  }
  return "split-conformal on design-point-grouped CV residuals (" + which +
         "); extrapolation gain from held-out ends";
}

bool FnnTrainingOptions::is_valid(std::string* why) const {
  auto fail = [why](const std::string& msg) {
    if (why != nullptr) *why = msg;
    return false;
  };
  if (method != FnnMethod::kLevenbergMarquardt && method != FnnMethod::kGradientDescent) {
    return fail("method is not a FnnMethod value");
  }
  if (folds < 2) return fail("folds must be >= 2");
  if (std::isnan(lambda) || std::isinf(lambda))
    return fail("lambda must be finite (< 0: choose by CV)");
  if (lambda < 0.0) {
    if (lambda_grid.empty()) return fail("lambda_grid is empty (needed when lambda < 0)");
    for (double l : lambda_grid) {
      if (!(l >= 0.0) || !std::isfinite(l))
        return fail("lambda_grid values must be finite and >= 0");
    }
  }
  if (max_iterations < 0) return fail("max_iterations must be >= 0");
  if (!(min_width > 0.0) || !std::isfinite(min_width))
    return fail("min_width must be > 0 and finite");
  if (!(learning_rate > 0.0) || !std::isfinite(learning_rate)) {
    return fail("learning_rate must be > 0 and finite");
  }
  if (epochs < 0) return fail("epochs must be >= 0");
  if (!(goal >= 0.0) || !std::isfinite(goal)) return fail("goal must be >= 0 and finite");
  if (!(interval_coverage == 0.0 || (interval_coverage > 0.0 && interval_coverage < 1.0))) {
    return fail("interval_coverage must be 0 (no interval) or in (0, 1)");
  }
  if (interval_folds != IntervalFolds::kRidge && interval_folds != IntervalFolds::kAsServed &&
      interval_folds != IntervalFolds::kNarrower) {
    return fail("interval_folds is not an IntervalFolds value");
  }
  return true;
}

bool TrainingSummary::usable() const {
  if (!solution_usable || train_rmse.empty()) return false;
  return all_finite(train_rmse);
}

template <int kInputs, int kSets, int kOutputs>
FnnTrainingResult<kInputs, kSets, kOutputs> train_fnn(
    const std::vector<std::array<double, kInputs>>& inputs,
    const std::vector<std::array<double, kOutputs>>& targets,
    const FnnTrainingOptions& options) {
  Trainer<kInputs, kSets, kOutputs> trainer(inputs, targets, options);
  return trainer.run();
}

template FnnTrainingResult<5, 3, 4> train_fnn<5, 3, 4>(const std::vector<std::array<double, 5>>&,
                                                       const std::vector<std::array<double, 4>>&,
                                                       const FnnTrainingOptions&);
template FnnTrainingResult<4, 3, 4> train_fnn<4, 3, 4>(const std::vector<std::array<double, 4>>&,
                                                       const std::vector<std::array<double, 4>>&,
                                                       const FnnTrainingOptions&);
template FnnTrainingResult<4, 3, 1> train_fnn<4, 3, 1>(const std::vector<std::array<double, 4>>&,
                                                       const std::vector<std::array<double, 1>>&,
                                                       const FnnTrainingOptions&);
template FnnTrainingResult<1, 3, 1> train_fnn<1, 3, 1>(const std::vector<std::array<double, 1>>&,
                                                       const std::vector<std::array<double, 1>>&,
                                                       const FnnTrainingOptions&);
template FnnTrainingResult<1, 3, 2> train_fnn<1, 3, 2>(const std::vector<std::array<double, 1>>&,
                                                       const std::vector<std::array<double, 2>>&,
                                                       const FnnTrainingOptions&);
template FnnTrainingResult<2, 3, 1> train_fnn<2, 3, 1>(const std::vector<std::array<double, 2>>&,
                                                       const std::vector<std::array<double, 1>>&,
                                                       const FnnTrainingOptions&);
template FnnTrainingResult<2, 3, 2> train_fnn<2, 3, 2>(const std::vector<std::array<double, 2>>&,
                                                       const std::vector<std::array<double, 2>>&,
                                                       const FnnTrainingOptions&);
template FnnTrainingResult<2, 2, 1> train_fnn<2, 2, 1>(const std::vector<std::array<double, 2>>&,
                                                       const std::vector<std::array<double, 1>>&,
                                                       const FnnTrainingOptions&);

}  // namespace cmmcomp::training

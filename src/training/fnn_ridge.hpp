// SPDX-License-Identifier: MIT
/// @file Stage 2 of train_fnn (docs/training.md, "How the trainer works"): the premise's
/// deterministic start, the prior the consequents shrink towards (fnn_prior.hpp), the ridge
/// consequents and λ chosen by k-fold cross-validation. Private to the trainer.
///
/// Contract: the premise starts with the centres of every input evenly over [0, 1] and every
/// width the centre spacing (≥ min_width). With it fixed the consequents are linear: a ridge
/// solve p = p₀ + Φᵀ(ΦΦᵀ + λI)⁻¹(z − Φp₀) in dual form, p₀ the prior. λ (options.lambda < 0)
/// is the grid value with the lowest CV mean squared error over the outputs (ties: the larger);
/// inside CV the prior is refitted, and its shape chosen again, on each fold's training part.
/// Deterministic for a given options.seed (the fold shuffle).
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cmmcomp/detail/splitmix64.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/training/fnn_trainer.hpp>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "fnn_normalise.hpp"
#include "fnn_prior.hpp"

namespace cmmcomp::training::detail {

/// Ridge consequents in dual form for every output: P = Φᵀ U (Λ + λ)⁻¹ Uᵀ Z, with K = ΦΦᵀ = UΛUᵀ.
/// λ = 0 gives the minimum-norm least-squares solution (eigenvalues below a relative tolerance
/// are dropped). One eigen-decomposition serves every λ. Refers to `phi`, which must outlive it.
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

/// Least-squares fit of z (N × outputs) on [1, x] (N × terms): the global first-order model,
/// one column of kTerms coefficients per output. A tiny ridge (1e-9 relative) keeps it defined
/// when the inputs are collinear.
inline MatrixXd global_linear_fit(const MatrixXd& u, const MatrixXd& z) {
  MatrixXd gram = u.transpose() * u;
  const double ridge = 1e-9 * std::max(gram.diagonal().maxCoeff(), 1.0);
  gram.diagonal().array() += ridge;
  return gram.ldlt().solve(u.transpose() * z);
}

/// What stage 2 hands on, in normalised units.
struct RidgeStart {
  std::vector<double> premise;      ///< centres and widths (TskLayout)
  std::vector<double> consequents;  ///< prior + ridge deviations, rule-major per output
  std::vector<double> prior;        ///< the prior's consequents, same layout
  MatrixXd phi;                     ///< Φ at `premise` (N × kBlock)
  MatrixXd u;                       ///< [1, x] (N × kTerms)
};

/// The ridge fits of a network with its premise at the initialisation: the whole data's
/// (stage 2) and those of a part (CV, and the interval's folds in stage 5).
template <int kInputs, int kSets, int kOutputs>
class RidgeFit {
 public:
  using Data = NormalisedData<kInputs, kOutputs>;
  using Layout = fuzzy::TskLayout<kInputs, kSets, kOutputs>;
  using Single = fuzzy::TskLayout<kInputs, kSets, 1>;
  static constexpr int kPremise = Layout::kConsequentsOffset;
  static constexpr int kRules = Layout::kRules;
  static constexpr int kTerms = Layout::kTerms;
  static constexpr int kBlock = Layout::kConsequentBlock;

  /// Chooses the prior's shape per output: on a designed experiment (every input on exactly
  /// three levels) the shape with the lowest leave-one-design-point-out error (fnn_prior.hpp),
  /// otherwise the global first-order fit. `data` and `options` must outlive the fit.
  RidgeFit(const Data& data, const FnnTrainingOptions& options) : d_(data), options_(options) {
    bool three_levels = true;
    for (int i = 0; i < kInputs && three_levels; ++i) {
      std::vector<double> levels;
      for (const std::size_t k : d_.first) levels.push_back(d_.raw_inputs[k][sz(i)]);
      std::sort(levels.begin(), levels.end());
      three_levels = std::unique(levels.begin(), levels.end()) - levels.begin() == 3;
    }
    const std::vector<PriorShape> candidates = prior_candidates(kInputs);
    shapes_.assign(static_cast<std::size_t>(kOutputs), candidates.front());
    if (!three_levels) return;
    for (int o = 0; o < kOutputs; ++o) {
      shapes_[sz(o)] = choose_prior_shape(d_.xm, d_.z.col(o), d_.group, d_.groups);
    }
  }

  const Data& data() const { return d_; }
  const FnnTrainingOptions& options() const { return options_; }

  /// The input names for descriptions: options.input_names, or "x0", "x1", ….
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    out.reserve(static_cast<std::size_t>(kInputs));
    for (int i = 0; i < kInputs; ++i) {
      out.push_back(options_.input_names.size() == static_cast<std::size_t>(kInputs)
                        ? options_.input_names[sz(i)]
                        : "x" + std::to_string(i));
    }
    return out;
  }

  /// The premise's deterministic start (see the file comment).
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

  /// U (N × kTerms): row n = [1, x_n], the regressors of the global first-order model.
  MatrixXd linear_terms() const {
    MatrixXd u(static_cast<Index>(d_.x.size()), kTerms);
    for (std::size_t k = 0; k < d_.x.size(); ++k) {
      u(static_cast<Index>(k), 0) = 1.0;
      for (int i = 0; i < kInputs; ++i) u(static_cast<Index>(k), 1 + i) = d_.x[k][sz(i)];
    }
    return u;
  }

  /// Φ (N × kBlock): row n = ᾱ_j(x_n)·[1, x_n] for every rule j, the consequent layout.
  MatrixXd design_matrix(const std::vector<double>& premise) const {
    using Net = fuzzy::TskEvaluator<double, kInputs, kSets, 1>;
    std::vector<double> params(static_cast<std::size_t>(Single::kParamCount), 0.0);
    std::copy(premise.begin(), premise.end(), params.begin());
    MatrixXd phi(static_cast<Index>(d_.x.size()), kBlock);
    typename Net::Firing alpha;
    for (std::size_t k = 0; k < d_.x.size(); ++k) {
      const double total = Net::firing(params.data(), d_.x[k], alpha);
      for (int j = 0; j < kRules; ++j) {
        const double a = alpha[sz(j)] / total;
        phi(static_cast<Index>(k), Index{j} * kTerms) = a;
        for (int i = 0; i < kInputs; ++i) {
          phi(static_cast<Index>(k), Index{j} * kTerms + 1 + i) = a * d_.x[k][sz(i)];
        }
      }
    }
    return phi;
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
    const MatrixXd g = global_linear_fit(rows(u, idx), rows(d_.z, idx));  // kTerms × kOutputs
    const double spacing = kSets > 1 ? 1.0 / (kSets - 1) : 1.0;
    const bool part = idx.size() != d_.x.size();
    for (int o = 0; o < kOutputs; ++o) {
      const PriorShape shape =
          part && !shapes_[sz(o)].first_order() && !prior_identifiable(shapes_[sz(o)], d_.xm, idx)
              ? choose_prior_shape(d_.xm, d_.z.col(o), d_.group, d_.groups, idx)
              : shapes_[sz(o)];
      if (shape.first_order()) {
        for (int k = 0; k < kBlock; ++k) prior(k, o) = g(k % kTerms, o);
        continue;
      }
      const VectorXd b = fit_prior(shape, d_.xm, d_.z.col(o), idx);
      for (int j = 0; j < kRules; ++j) {
        std::array<double, kInputs> c{};
        for (int i = 0; i < kInputs; ++i) {
          c[sz(i)] = kSets > 1 ? Layout::rule_set(j, i) * spacing : 0.5;
        }
        double p0 = prior_features(shape, c.data()).dot(b);
        for (int i = 0; i < kInputs; ++i) {
          const double slope = prior_feature_slopes(shape, c.data(), i).dot(b);
          prior(Index{j} * kTerms + 1 + i, o) = slope;
          p0 -= slope * c[sz(i)];
        }
        prior(Index{j} * kTerms, o) = p0;
      }
    }
    return prior;
  }

  /// Sum of squared CV errors [normalised], rows = grid values, columns = outputs. Folds from a
  /// Fisher–Yates shuffle of the samples seeded with options.seed, sample at shuffled position
  /// k in fold k mod folds.
  MatrixXd cross_validate(const MatrixXd& phi,
                          const MatrixXd& u,
                          const std::vector<double>& grid) const {
    const std::size_t n = d_.x.size();
    const auto folds = static_cast<std::size_t>(options_.folds);
    std::vector<std::size_t> order(n);
    for (std::size_t k = 0; k < n; ++k) order[k] = k;
    cmmcomp::detail::SplitMix64 rng{options_.seed};
    for (std::size_t k = n; k > 1; --k) std::swap(order[k - 1], order[rng.below(k)]);
    std::vector<std::size_t> fold_of(n);
    for (std::size_t k = 0; k < n; ++k) fold_of[order[k]] = k % folds;

    MatrixXd sse = MatrixXd::Zero(static_cast<Index>(grid.size()), kOutputs);
    for (std::size_t f = 0; f < folds; ++f) {
      std::vector<Index> train, test;
      for (std::size_t k = 0; k < n; ++k)
        (fold_of[k] == f ? test : train).push_back(static_cast<Index>(k));
      const MatrixXd phi_tr = rows(phi, train), z_tr = rows(d_.z, train);
      const MatrixXd phi_te = rows(phi, test), z_te = rows(d_.z, test);
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
  MatrixXd predict(const MatrixXd& phi,
                   const MatrixXd& u,
                   const std::vector<Index>& train,
                   const std::vector<Index>& test,
                   double lambda) const {
    const MatrixXd phi_tr = rows(phi, train), z_tr = rows(d_.z, train);
    const MatrixXd prior = rule_prior(train, u);
    const RidgeDual ridge(phi_tr, z_tr - phi_tr * prior);
    return rows(phi, test) * (prior + phi_tr.transpose() * ridge.dual(lambda));
  }

  /// Stage 2 on the whole data: the premise's start, λ by CV, the prior and the ridge
  /// consequents. Fills `s`: lambda_grid, cv_mse_grid, lambda, cv_rmse [raw units], prior,
  /// design_points.
  RidgeStart start(TrainingSummary& s) const {
    RidgeStart r;
    r.premise = initial_premise();
    r.phi = design_matrix(r.premise);
    r.u = linear_terms();
    s.lambda_grid =
        options_.lambda < 0.0 ? options_.lambda_grid : std::vector<double>{options_.lambda};
    const MatrixXd sse = cross_validate(r.phi, r.u, s.lambda_grid);  // [grid][output]
    std::size_t best = 0;
    for (std::size_t g = 0; g < s.lambda_grid.size(); ++g) {
      const double mse = sse.row(static_cast<Index>(g)).sum() / (d_.n * kOutputs);
      s.cv_mse_grid.push_back(mse);
      const double best_mse = s.cv_mse_grid[best];
      const bool better =
          mse < best_mse || (mse == best_mse && s.lambda_grid[g] > s.lambda_grid[best]);
      if (g == 0 || better || !std::isfinite(best_mse)) best = g;
    }
    s.lambda = s.lambda_grid[best];
    for (int o = 0; o < kOutputs; ++o) {
      s.cv_rmse.push_back(std::sqrt(sse(static_cast<Index>(best), o) / d_.n) * d_.scale[sz(o)]);
    }
    const MatrixXd prior = rule_prior(all_rows(static_cast<Index>(d_.x.size())), r.u);
    r.prior.assign(std::size_t{kOutputs} * kBlock, 0.0);
    for (int o = 0; o < kOutputs; ++o) {
      for (int k = 0; k < kBlock; ++k) r.prior[sz(o * kBlock + k)] = prior(k, o);
    }
    for (int o = 0; o < kOutputs; ++o) s.prior.push_back(shapes_[sz(o)].describe(names()));
    s.design_points = d_.groups;
    const RidgeDual ridge(r.phi, d_.z - r.phi * prior);
    const MatrixXd p0 = ridge.consequents(s.lambda);  // kBlock × kOutputs, deviations from it
    r.consequents.resize(std::size_t{kOutputs} * kBlock);
    for (int o = 0; o < kOutputs; ++o) {
      for (int k = 0; k < kBlock; ++k) r.consequents[sz(o * kBlock + k)] = prior(k, o) + p0(k, o);
    }
    return r;
  }

 private:
  const Data& d_;
  const FnnTrainingOptions& options_;
  std::vector<PriorShape> shapes_;  ///< the prior's shape per output
};

}  // namespace cmmcomp::training::detail

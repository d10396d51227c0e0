// SPDX-License-Identifier: MIT
/// @file The prior the ridge consequents shrink towards (fnn_trainer.hpp, step 3), private to the
/// trainer: its shapes, their fit, the tangent planes that put a prior into the rules, and the
/// choice of one shape per output on a designed experiment (docs/training.md, "The prior").
///
/// Inputs here are normalised to [0, 1]; every shape is written in d = x − ½.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace cmmcomp::training::detail {

/// One output's prior: the tensor-product quadratic over the inputs in `quadratic` (every
/// product of 1, d, d² over them: 3^m terms, the constant among them) plus a first-order term in
/// each input of `linear`. No quadratic input and every input linear is the global first-order
/// fit g; with two quadratic inputs the shape is the quadratic interpolant of their 3 × 3 table
/// of cell means, the summary an ANOVA makes of a designed experiment.
struct PriorShape {
  std::vector<int> quadratic;
  std::vector<int> linear;

  int terms() const {
    int n = 1;
    for (std::size_t q = 0; q < quadratic.size(); ++q) n *= 3;
    return n + static_cast<int>(linear.size());
  }
  bool first_order() const { return quadratic.empty(); }

  /// e.g. "first-order", "quadratic(PV×PD)", "quadratic(AV)+first-order(PV, PD, AD)".
  std::string describe(const std::vector<std::string>& names) const {
    auto name = [&names](int i) {
      return static_cast<std::size_t>(i) < names.size() ? names[static_cast<std::size_t>(i)]
                                                        : "x" + std::to_string(i);
    };
    std::string out;
    if (!quadratic.empty()) {
      out = "quadratic(";
      for (std::size_t q = 0; q < quadratic.size(); ++q) {
        out += (q ? "×" : "") + name(quadratic[q]);
      }
      out += ")";
      if (linear.empty()) return out;
      out += "+";
    }
    out += "first-order";
    if (quadratic.empty()) return out;
    out += "(";
    for (std::size_t l = 0; l < linear.size(); ++l) out += (l ? ", " : "") + name(linear[l]);
    return out + ")";
  }
};

/// The regressors of `shape` at x (normalised inputs).
inline Eigen::VectorXd prior_features(const PriorShape& shape, const double* x) {
  Eigen::VectorXd f(shape.terms());
  const int tensor = shape.terms() - static_cast<int>(shape.linear.size());
  for (int t = 0; t < tensor; ++t) {
    double v = 1.0;
    int code = t;  // base-3 digits: the power of each quadratic input
    for (const int i : shape.quadratic) {
      const int power = code % 3;
      code /= 3;
      const double d = x[i] - 0.5;
      v *= power == 0 ? 1.0 : (power == 1 ? d : d * d);
    }
    f(t) = v;
  }
  for (std::size_t l = 0; l < shape.linear.size(); ++l) {
    f(tensor + static_cast<int>(l)) = x[shape.linear[l]] - 0.5;
  }
  return f;
}

/// ∂/∂x_input of the regressors of `shape` at x.
inline Eigen::VectorXd prior_feature_slopes(const PriorShape& shape, const double* x, int input) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(shape.terms());
  const int tensor = shape.terms() - static_cast<int>(shape.linear.size());
  const bool in_tensor =
      std::find(shape.quadratic.begin(), shape.quadratic.end(), input) != shape.quadratic.end();
  for (int t = 0; in_tensor && t < tensor; ++t) {
    double v = 1.0;
    int code = t;
    for (const int i : shape.quadratic) {
      const int power = code % 3;
      code /= 3;
      const double d = x[i] - 0.5;
      if (i == input) {
        v *= power == 0 ? 0.0 : (power == 1 ? 1.0 : 2.0 * d);
      } else {
        v *= power == 0 ? 1.0 : (power == 1 ? d : d * d);
      }
    }
    f(t) = v;
  }
  for (std::size_t l = 0; l < shape.linear.size(); ++l) {
    if (shape.linear[l] == input) f(tensor + static_cast<int>(l)) = 1.0;
  }
  return f;
}

/// Least-squares coefficients of `shape` for the targets z of the samples `rows` of x (n × inputs,
/// one row per sample). A tiny ridge (1e-9 relative, as the global first-order fit) keeps it
/// defined when the samples do not pin every term.
inline Eigen::VectorXd fit_prior(const PriorShape& shape,
                                 const Eigen::MatrixXd& x,
                                 const Eigen::VectorXd& z,
                                 const std::vector<Eigen::Index>& rows) {
  const int m = shape.terms();
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(m, m);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
  Eigen::VectorXd xr(x.cols());
  for (const Eigen::Index r : rows) {
    xr = x.row(r).transpose();
    const Eigen::VectorXd f = prior_features(shape, xr.data());
    gram.selfadjointView<Eigen::Lower>().rankUpdate(f);
    rhs += z(r) * f;
  }
  gram.triangularView<Eigen::StrictlyUpper>() = gram.transpose();
  gram.diagonal().array() += 1e-9 * std::max(gram.diagonal().maxCoeff(), 1.0);
  return gram.ldlt().solve(rhs);
}

/// The candidate shapes for `inputs` inputs, simplest first: the global first-order fit, then
/// for every input and every pair of inputs their tensor quadratic, alone and with first-order
/// terms in the other inputs.
inline std::vector<PriorShape> prior_candidates(int inputs) {
  std::vector<PriorShape> out;
  PriorShape g;
  for (int i = 0; i < inputs; ++i) g.linear.push_back(i);
  out.push_back(g);
  auto add = [&out, inputs](std::vector<int> quadratic) {
    PriorShape alone{quadratic, {}};
    PriorShape with_rest{quadratic, {}};
    for (int i = 0; i < inputs; ++i) {
      if (std::find(quadratic.begin(), quadratic.end(), i) == quadratic.end()) {
        with_rest.linear.push_back(i);
      }
    }
    out.push_back(alone);
    if (!with_rest.linear.empty()) out.push_back(with_rest);
  };
  for (int i = 0; i < inputs; ++i) add({i});
  for (int i = 0; i < inputs; ++i) {
    for (int j = i + 1; j < inputs; ++j) add({i, j});
  }
  return out;
}

/// Whether the samples `rows` pin every term of `shape`: its regressors over them have full
/// column rank. A tensor quadratic over two inputs needs all nine cells of their levels; a
/// held-out fold of an L18 can empty one, and a quadratic along an input of which only two
/// levels are left is not determined at all. The tiny ridge of fit_prior would then make up
/// the missing cell, and the fit would predict it wildly.
inline bool prior_identifiable(const PriorShape& shape,
                               const Eigen::MatrixXd& x,
                               const std::vector<Eigen::Index>& rows) {
  const int m = shape.terms();
  if (rows.size() < static_cast<std::size_t>(m)) return false;
  Eigen::MatrixXd f(static_cast<Eigen::Index>(rows.size()), m);
  Eigen::VectorXd xr(x.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    xr = x.row(rows[k]).transpose();
    f.row(static_cast<Eigen::Index>(k)) = prior_features(shape, xr.data()).transpose();
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(f);
  qr.setThreshold(1e-8);
  return qr.rank() == m;
}

/// Sum of squared errors of `shape` over the samples `rows` when each of their design points
/// (`group` of every sample, 0 … groups − 1) is predicted from the others in `rows`:
/// leave-one-design-point-out CV, which asks of a shape what the network's prior must do,
/// predict moves the design did not run. Infinite when a held-out fit cannot pin every term
/// (prior_identifiable).
inline double leave_one_point_out_sse(const PriorShape& shape,
                                      const Eigen::MatrixXd& x,
                                      const Eigen::VectorXd& z,
                                      const std::vector<std::size_t>& group,
                                      std::size_t groups,
                                      const std::vector<Eigen::Index>& rows) {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  std::vector<bool> present(groups, false);
  for (const Eigen::Index r : rows) present[group[static_cast<std::size_t>(r)]] = true;
  const auto points = static_cast<std::size_t>(std::count(present.begin(), present.end(), true));
  if (points < 2 || points - 1 < static_cast<std::size_t>(shape.terms())) return kNone;
  double sse = 0.0;
  std::vector<Eigen::Index> train, test;
  Eigen::VectorXd xr(x.cols());
  for (std::size_t g = 0; g < groups; ++g) {
    if (!present[g]) continue;
    train.clear();
    test.clear();
    for (const Eigen::Index r : rows) {
      (group[static_cast<std::size_t>(r)] == g ? test : train).push_back(r);
    }
    if (!prior_identifiable(shape, x, train)) return kNone;
    const Eigen::VectorXd b = fit_prior(shape, x, z, train);
    for (const Eigen::Index r : test) {
      xr = x.row(r).transpose();
      const double e = prior_features(shape, xr.data()).dot(b) - z(r);
      sse += e * e;
    }
  }
  return sse;
}

/// The main effect of `input` over the samples `rows`: Σ over its levels of n_level·(mean of z
/// at the level − mean of z)², the factor's sum of squares in an ANOVA of the design.
inline double main_effect_ss(const Eigen::MatrixXd& x,
                             const Eigen::VectorXd& z,
                             const std::vector<Eigen::Index>& rows,
                             int input) {
  std::vector<double> level, sum, count;
  double total = 0.0;
  for (const Eigen::Index r : rows) {
    const double v = x(r, input);
    std::size_t l = 0;
    while (l < level.size() && level[l] != v) ++l;
    if (l == level.size()) {
      level.push_back(v);
      sum.push_back(0.0);
      count.push_back(0.0);
    }
    sum[l] += z(r);
    count[l] += 1.0;
    total += z(r);
  }
  if (rows.empty()) return 0.0;
  const double mean = total / static_cast<double>(rows.size());
  double ss = 0.0;
  for (std::size_t l = 0; l < level.size(); ++l) {
    const double d = sum[l] / count[l] - mean;
    ss += count[l] * d * d;
  }
  return ss;
}

/// Whether `shape` respects effect heredity: a quadratic over a pair is
/// allowed only for `strongest_pair`, the inputs with the two largest main effects. An orthogonal
/// array of strength 2 estimates main effects cleanly but aliases the pair interactions with each
/// other: on the paper's L18 a response of PV and AV is fitted exactly at all 18 moves by the
/// quadratic over PV × AD and over AV × AD too, so leave-one-out cannot tell them apart, and
/// between the moves the aliases are wrong. Heredity (an interaction is active only where its
/// parents' main effects are; Wu & Hamada, Experiments, ch. 4) settles it from what the design
/// does estimate.
inline bool respects_heredity(const PriorShape& shape, const std::vector<int>& strongest_pair) {
  for (const int q : shape.quadratic) {
    if (shape.quadratic.size() > 1 &&
        std::find(strongest_pair.begin(), strongest_pair.end(), q) == strongest_pair.end()) {
      return false;
    }
  }
  return true;
}

/// The two inputs with the largest main effects on the samples `rows` (ties: the earlier input).
inline std::vector<int> strongest_pair(const Eigen::MatrixXd& x,
                                       const Eigen::VectorXd& z,
                                       const std::vector<Eigen::Index>& rows) {
  std::vector<int> order(static_cast<std::size_t>(x.cols()));
  std::vector<double> ss(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    order[i] = static_cast<int>(i);
    ss[i] = main_effect_ss(x, z, rows, static_cast<int>(i));
  }
  std::stable_sort(order.begin(), order.end(), [&ss](int a, int b) {
    return ss[static_cast<std::size_t>(a)] > ss[static_cast<std::size_t>(b)];
  });
  order.resize(std::min<std::size_t>(order.size(), 2));
  return order;
}

/// respects_heredity with the pair of the samples `rows`.
inline bool respects_heredity(const PriorShape& shape,
                              const Eigen::MatrixXd& x,
                              const Eigen::VectorXd& z,
                              const std::vector<Eigen::Index>& rows) {
  return respects_heredity(shape, strongest_pair(x, z, rows));
}

/// The shape with the lowest leave-one-design-point-out error over the samples `rows` (ties,
/// within 1e-9 relative: the simpler, earlier candidate), from the prior_candidates() that
/// respect heredity; the first-order fit when no other candidate can be judged.
inline PriorShape choose_prior_shape(const Eigen::MatrixXd& x,
                                     const Eigen::VectorXd& z,
                                     const std::vector<std::size_t>& group,
                                     std::size_t groups,
                                     const std::vector<Eigen::Index>& rows) {
  const std::vector<PriorShape> candidates = prior_candidates(static_cast<int>(x.cols()));
  const std::vector<int> pair = strongest_pair(x, z, rows);
  std::size_t best = 0;
  double best_sse = leave_one_point_out_sse(candidates[0], x, z, group, groups, rows);
  for (std::size_t c = 1; c < candidates.size(); ++c) {
    if (!respects_heredity(candidates[c], pair)) continue;
    const double sse = leave_one_point_out_sse(candidates[c], x, z, group, groups, rows);
    if (sse < best_sse * (1.0 - 1e-9)) {
      best = c;
      best_sse = sse;
    }
  }
  return candidates[best];
}

/// Every sample's row index, 0 … n − 1.
inline std::vector<Eigen::Index> all_rows(Eigen::Index n) {
  std::vector<Eigen::Index> rows(static_cast<std::size_t>(n));
  for (Eigen::Index k = 0; k < n; ++k) rows[static_cast<std::size_t>(k)] = k;
  return rows;
}

/// leave_one_point_out_sse over every sample.
inline double leave_one_point_out_sse(const PriorShape& shape,
                                      const Eigen::MatrixXd& x,
                                      const Eigen::VectorXd& z,
                                      const std::vector<std::size_t>& group,
                                      std::size_t groups) {
  return leave_one_point_out_sse(shape, x, z, group, groups, all_rows(x.rows()));
}

/// choose_prior_shape over every sample.
inline PriorShape choose_prior_shape(const Eigen::MatrixXd& x,
                                     const Eigen::VectorXd& z,
                                     const std::vector<std::size_t>& group,
                                     std::size_t groups) {
  return choose_prior_shape(x, z, group, groups, all_rows(x.rows()));
}

}  // namespace cmmcomp::training::detail

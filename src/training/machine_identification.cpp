// SPDX-License-Identifier: MIT
/// @file Machine identification with Ceres (Levenberg–Marquardt, finite-difference Jacobian).
#include <ceres/ceres.h>
#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cmmcomp/doe/anova.hpp>
#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <cmmcomp/training/machine_identification.hpp>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <thread>
#include <utility>

#include "ceres_progress.hpp"

namespace cmmcomp::training {
namespace {

using dynamics::Machine;
using dynamics::MachineParameters;
using Info = dynamics::ParameterInfo<MachineParameters>;

constexpr const std::array<const char*, 4>& kParamNames = paper::kParameters;
constexpr const std::array<const char*, 5>& kSourceNames = paper::kAnovaSources;

std::array<double, 4> errors_of(const DatasetRow& r, bool magnitudes) {
  return {r.mpe_um,
          magnitudes ? std::fabs(r.rpe_um) : r.rpe_um,
          r.mae_um,
          magnitudes ? std::fabs(r.rae_um) : r.rae_um};
}

/// Calls `line(line_no, cells)` for every line of a small CSV table that is neither empty nor a
/// '#' comment (the header included), with a trailing CR removed. ConfigError when `path` cannot
/// be opened (naming `what`).
template <typename Line>
void for_each_csv_line(const std::string& path, const char* what, Line line) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ": cannot open " + what);
  int line_no = 0;
  for (std::string text; std::getline(in, text);) {
    ++line_no;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    if (text.empty() || text[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(text);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    line(line_no, cells);
  }
}

/// Everything one evaluation of the residuals needs; evaluations are independent.
class Problem {
 public:
  Problem(const Machine& start,
          const IdentificationTargets& targets,
          const IdentificationOptions& options,
          std::vector<const Info*> free)
      : start_(start), targets_(targets), options_(options), free_(std::move(free)) {
    if (targets_.anova.enabled) {
      l18_ = doe::paper_l18_design();
      l18_rows_ = dynamics::rows_from_design(l18_, targets_.anova.fixed);
    }
    if (targets_.grid_mean.enabled) {
      grid_rows_ = dynamics::rows_from_design(doe::full_factorial(doe::paper_table3_factors()),
                                              targets_.grid_mean.fixed);
    }
  }

  int residual_count() const {
    return static_cast<int>(targets_.moves.size()) * 4 + (targets_.anova.enabled ? 20 : 0) +
           (targets_.grid_mean.enabled ? 4 : 0);
  }

  Machine machine_at(const double* log_values) const {
    Machine m = start_;
    for (std::size_t i = 0; i < free_.size(); ++i) {
      free_[i]->set(m.parameters, std::exp(log_values[i]));
    }
    return m;
  }

  /// Model values in residual order (µm for moves, % for shares). Throws on simulation failure.
  std::vector<double> model_values(const double* log_values, int threads) const {
    const Machine m = machine_at(log_values);
    dynamics::DatasetOptions opts;
    opts.threads = threads;
    // The exponential integrator with 1 ms steps: 7.5e-4 um from CVODE at rtol 1e-10 on the
    // baseline move (bench_simulation --benchmark_filter=ExponentialStep), far below the
    // finite-difference signal of a 1e-2 step in log(parameter) (~0.1 um), and about twice as
    // fast as the default 0.5 ms. Its work is bounded by the move's duration, so a trial step into
    // a corner of the parameter space (a very fast, undamped mode) costs no more than any other.
    opts.simulation.integration = dynamics::Integration::kExponential;
    opts.simulation.exponential_max_step_s = 1e-3;
    if (options_.cvode) {
      // CVODE, looser than its default (3e-3 um from a 1000x tighter solution); a trial step into
      // a corner of the parameter space is cut off after max_steps, and Levenberg–Marquardt
      // shrinks the step.
      opts.simulation.integration = dynamics::Integration::kCvode;
      opts.simulation.integrator.relative_tolerance = 1e-6;
      opts.simulation.integrator.absolute_tolerance = 1e-10;
      opts.simulation.integrator.max_steps = 20000;
    }
    opts.simulation.trace_rate_hz = 200.0;
    std::vector<DatasetRow> rows = targets_.moves;
    rows.insert(rows.end(), l18_rows_.begin(), l18_rows_.end());
    rows.insert(rows.end(), grid_rows_.begin(), grid_rows_.end());
    rows = dynamics::simulate_dataset(m, rows, opts);
    std::vector<double> values;
    for (std::size_t i = 0; i < targets_.moves.size(); ++i) {
      const auto e = errors_of(rows[i], targets_.compare_magnitudes);
      values.insert(values.end(), e.begin(), e.end());
    }
    if (targets_.anova.enabled) {
      const std::size_t first = targets_.moves.size();
      for (int p = 0; p < 4; ++p) {
        std::vector<double> response;
        for (std::size_t r = 0; r < l18_rows_.size(); ++r) {
          response.push_back(errors_of(rows[first + r], true)[static_cast<std::size_t>(p)]);
        }
        const doe::AnovaTable t = doe::anova(l18_, response);
        const double noise_var = options_.sigma_um[static_cast<std::size_t>(p)] *
                                 options_.sigma_um[static_cast<std::size_t>(p)] /
                                 targets_.anova.repeats;
        std::array<double, 5> ss{};
        double total = 0;
        for (std::size_t f = 0; f < 4; ++f) {
          ss[f] = t.factors[f].sum_of_squares + t.factors[f].dof * noise_var;
          total += ss[f];
        }
        ss[4] = t.error.sum_of_squares + t.error.dof * noise_var;
        total += ss[4];
        for (double s : ss) values.push_back(100.0 * s / total);
      }
    }
    if (targets_.grid_mean.enabled) {
      const std::size_t first = targets_.moves.size() + l18_rows_.size();
      std::array<double, 4> mean{};
      for (std::size_t r = 0; r < grid_rows_.size(); ++r) {
        const auto e = errors_of(rows[first + r], true);
        for (std::size_t p = 0; p < 4; ++p)
          mean[p] += e[p] / static_cast<double>(grid_rows_.size());
      }
      values.insert(values.end(), mean.begin(), mean.end());
    }
    return values;
  }

  std::vector<double> targets() const {
    std::vector<double> v;
    for (const DatasetRow& r : targets_.moves) {
      const auto e = errors_of(r, targets_.compare_magnitudes);
      v.insert(v.end(), e.begin(), e.end());
    }
    if (targets_.anova.enabled) {
      for (const auto& row : targets_.anova.weight_pct) v.insert(v.end(), row.begin(), row.end());
    }
    if (targets_.grid_mean.enabled) {
      v.insert(v.end(), targets_.grid_mean.mean_um.begin(), targets_.grid_mean.mean_um.end());
    }
    return v;
  }

  std::vector<double> sigmas() const {
    std::vector<double> v;
    for (const DatasetRow& r : targets_.moves) {
      if (options_.relative_move_sigma > 0.0) {
        const auto e = errors_of(r, targets_.compare_magnitudes);
        for (double x : e) {
          v.push_back(std::max(options_.relative_move_sigma * std::fabs(x), 1e-3));
        }
      } else {
        v.insert(v.end(), options_.sigma_um.begin(), options_.sigma_um.end());
      }
    }
    if (targets_.anova.enabled) v.insert(v.end(), 20, targets_.anova.sigma_pct);
    if (targets_.grid_mean.enabled) {
      for (double m : targets_.grid_mean.mean_um) {
        v.push_back(targets_.grid_mean.relative_sigma * m);
      }
    }
    return v;
  }

  std::vector<std::string> names() const {
    std::vector<std::string> v;
    for (std::size_t i = 0; i < targets_.moves.size(); ++i) {
      for (const char* p : kParamNames) {
        v.push_back(fmt::format("move {} (Y {:g} mm) {}", i + 1, targets_.moves[i].y_mm, p));
      }
    }
    if (targets_.anova.enabled) {
      for (const char* p : kParamNames) {
        for (const char* s : kSourceNames) v.push_back(fmt::format("ANOVA {} {} weight %", p, s));
      }
    }
    if (targets_.grid_mean.enabled) {
      for (const char* p : kParamNames) v.push_back(fmt::format("grid mean |{}| um", p));
    }
    return v;
  }

  const IdentificationOptions& options() const { return options_; }

 private:
  Machine start_;
  IdentificationTargets targets_;
  IdentificationOptions options_;
  std::vector<const Info*> free_;
  doe::Design l18_;
  std::vector<DatasetRow> l18_rows_;
  std::vector<DatasetRow> grid_rows_;
};

/// Residuals (model − target)/σ with a forward-difference Jacobian whose columns are simulated
/// in parallel (one perturbed machine per task).
class SimulationCost final : public ceres::CostFunction {
 public:
  SimulationCost(const Problem& problem, int parameter_count)
      : problem_(problem),
        targets_(problem.targets()),
        sigmas_(problem.sigmas()),
        n_(parameter_count) {
    mutable_parameter_block_sizes()->push_back(parameter_count);
    set_num_residuals(problem.residual_count());
  }

  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override {
    const double* x = parameters[0];
    const std::size_t m = targets_.size();
    const bool want_jacobian = jacobians != nullptr && jacobians[0] != nullptr;
    const int columns = want_jacobian ? n_ : 0;
    std::vector<std::vector<double>> values(static_cast<std::size_t>(columns) + 1);
    std::vector<char> good(values.size(), 0);
    const double h = problem_.options().log_step;
    auto task = [&](std::size_t k, int threads) {
      std::vector<double> xk(x, x + n_);
      if (k > 0) xk[k - 1] += h;
      try {
        values[k] = problem_.model_values(xk.data(), threads);
        good[k] = 1;
      } catch (const std::exception&) {
        good[k] = 0;
      }
    };
    if (columns == 0) {
      task(0, problem_.options().threads);
    } else {
      const unsigned workers = problem_.options().threads > 0
                                   ? static_cast<unsigned>(problem_.options().threads)
                                   : std::max(1u, std::thread::hardware_concurrency());
      std::atomic<std::size_t> next{0};
      std::vector<std::thread> pool;
      for (unsigned w = 0; w < workers; ++w) {
        pool.emplace_back([&]() {
          for (std::size_t k = next++; k < values.size(); k = next++) task(k, 1);
        });
      }
      for (std::thread& t : pool) t.join();
    }
    if (!std::all_of(good.begin(), good.end(), [](char g) { return g != 0; })) return false;
    for (std::size_t i = 0; i < m; ++i) residuals[i] = (values[0][i] - targets_[i]) / sigmas_[i];
    for (int j = 0; j < columns; ++j) {
      for (std::size_t i = 0; i < m; ++i) {
        jacobians[0][i * static_cast<std::size_t>(n_) + static_cast<std::size_t>(j)] =
            (values[static_cast<std::size_t>(j) + 1][i] - values[0][i]) / (h * sigmas_[i]);
      }
    }
    return true;
  }

 private:
  const Problem& problem_;
  std::vector<double> targets_, sigmas_;
  int n_;
};

/// Fills report.relative_sigma and report.residual_scale from the Jacobian at the fit `x` (log
/// parameters): the covariance (JᵀJ)⁻¹ of the normalised residuals, scaled by the reduced χ²
/// when the residuals spread more than their σ (the model misses something, or the σ are
/// optimistic), never scaled down. A direction the data do not determine (a singular value below
/// 1e-8 of the largest) makes every parameter that takes part in it infinite.
void parameter_uncertainty(const SimulationCost& cost,
                           int residuals,
                           const std::vector<double>& x,
                           double final_cost,
                           IdentificationReport& report) {
  const auto n = static_cast<Eigen::Index>(x.size());
  const auto m = static_cast<Eigen::Index>(residuals);
  report.relative_sigma.assign(x.size(), std::numeric_limits<double>::infinity());
  std::vector<double> r(static_cast<std::size_t>(m));
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> j(m, n);
  const double* parameters[] = {x.data()};
  double* jacobians[] = {j.data()};
  if (!cost.Evaluate(parameters, r.data(), jacobians)) return;
  const double dof = static_cast<double>(m - n);
  report.residual_scale = dof > 0 ? std::sqrt(std::max(1.0, 2.0 * final_cost / dof)) : 1.0;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(j, Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  const Eigen::MatrixXd& v = svd.matrixV();
  if (sv.size() == 0 || !(sv(0) > 0.0)) return;
  std::vector<bool> undetermined(x.size(), false);
  Eigen::VectorXd variance = Eigen::VectorXd::Zero(n);
  for (Eigen::Index k = 0; k < sv.size(); ++k) {
    if (sv(k) < 1e-8 * sv(0)) {
      for (Eigen::Index i = 0; i < n; ++i) {
        if (std::abs(v(i, k)) > 0.1) undetermined[static_cast<std::size_t>(i)] = true;
      }
      continue;
    }
    for (Eigen::Index i = 0; i < n; ++i) variance(i) += v(i, k) * v(i, k) / (sv(k) * sv(k));
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    if (undetermined[static_cast<std::size_t>(i)]) continue;
    // σ of log(value); the value's relative 1σ is exp(σ) − 1 above, 1 − exp(−σ) below: their
    // mean, which is σ to first order.
    const double sigma_log = std::sqrt(variance(i)) * report.residual_scale;
    report.relative_sigma[static_cast<std::size_t>(i)] =
        0.5 * (std::expm1(sigma_log) - std::expm1(-sigma_log));
  }
}

}  // namespace

bool IdentificationOptions::is_valid(std::string* why) const {
  auto fail = [why](const char* msg) {
    if (why != nullptr) *why = msg;
    return false;
  };
  for (double s : sigma_um) {
    if (!(s > 0.0 && std::isfinite(s))) return fail("sigma_um must be positive and finite");
  }
  if (max_iterations < 1) return fail("max_iterations must be >= 1");
  if (!(relative_move_sigma >= 0.0 && relative_move_sigma < 10.0)) {
    return fail("relative_move_sigma must be in [0, 10)");
  }
  if (threads < 0) return fail("threads must be >= 0");
  if (!(log_step > 0.0 && log_step < 0.1)) return fail("log_step must be in (0, 0.1)");
  return true;
}

IdentificationReport identify_machine(const Machine& start,
                                      const IdentificationTargets& targets,
                                      const IdentificationOptions& options) {
  std::string why;
  if (!options.is_valid(&why)) throw ConfigError("identification options: " + why);
  if (targets.moves.empty() && !targets.anova.enabled && !targets.grid_mean.enabled) {
    throw ConfigError("identification: no measured moves, ANOVA or grid-mean targets");
  }
  if (targets.anova.enabled && targets.anova.repeats < 1) {
    throw ConfigError("identification: ANOVA repeats must be >= 1");
  }
  if (!dynamics::is_physical(start.parameters, &why)) {
    throw ConfigError("start machine: " + why);
  }

  std::vector<const Info*> free;
  const auto& table = dynamics::machine_parameter_table();
  const auto key_of = [](const Info& info) { return std::string(info.section) + "." + info.key; };
  const auto is_fixed = [&](const std::string& key) {
    return std::find(options.fixed_parameters.begin(), options.fixed_parameters.end(), key) !=
           options.fixed_parameters.end();
  };
  for (const std::string& name : options.fixed_parameters) {
    if (std::none_of(
            table.begin(), table.end(), [&](const Info& i) { return key_of(i) == name; })) {
      throw ConfigError("identification: unknown fixed parameter '" + name + "'");
    }
  }
  if (options.free_parameters.empty()) {
    for (const Info& info : table) {
      if (info.identifiable && !is_fixed(key_of(info))) free.push_back(&info);
    }
  } else {
    for (const std::string& name : options.free_parameters) {
      if (is_fixed(name)) {
        throw ConfigError("identification: '" + name +
                          "' is both free and fixed (the controller timing is fixed by default: "
                          "the recordings measure it; free it with --fixed none)");
      }
    }
    for (const std::string& name : options.free_parameters) {
      const Info* found = nullptr;
      for (const Info& info : table) {
        if (name == std::string(info.section) + "." + info.key) found = &info;
      }
      if (found == nullptr) throw ConfigError("identification: unknown parameter '" + name + "'");
      free.push_back(found);
    }
  }
  std::vector<double> x;
  IdentificationReport report;
  for (const Info* info : free) {
    const double v = info->get(start.parameters);
    const std::string key = std::string(info->section) + "." + info->key;
    if (!(v > 0.0)) {
      throw ConfigError("identification: '" + key +
                        "' is 0 in the start machine; give it a positive start value to fit it");
    }
    if (v < info->plausible_min || v > info->plausible_max) {
      throw ConfigError(fmt::format(
          "identification: '{}' = {} in the start machine is outside its plausible range "
          "[{:g}, {:g}] ({})",
          key,
          v,
          info->plausible_min,
          info->plausible_max,
          info->basis));
    }
    x.push_back(std::log(v));
    report.free_parameters.push_back(key);
    report.start_values.push_back(v);
  }

  const Problem problem(start, targets, options, free);
  const int n = static_cast<int>(x.size());
  ceres::Problem ceres_problem;
  auto* cost = new SimulationCost(problem, n);  // owned by ceres_problem
  ceres_problem.AddResidualBlock(cost, nullptr, x.data());
  for (int i = 0; i < n; ++i) {
    const Info& info = *free[static_cast<std::size_t>(i)];
    // Identification stays inside the plausible range (docs/machine-file.md).
    const double lo_value = std::max(info.min, info.plausible_min);
    const double lo = lo_value > 0.0 ? std::log(lo_value) : x[static_cast<std::size_t>(i)] - 25.0;
    ceres_problem.SetParameterLowerBound(x.data(), i, lo);
    ceres_problem.SetParameterUpperBound(
        x.data(), i, std::log(std::min(info.max, info.plausible_max)));
  }
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = options.max_iterations;
  solver.minimizer_progress_to_stdout = false;
  solver.logging_type = ceres::SILENT;
  detail::ProgressCallback callback(options.progress);
  solver.callbacks.push_back(&callback);
  solver.update_state_every_iteration = false;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &ceres_problem, &summary);

  report.fitted = problem.machine_at(x.data());
  // A fitted controller timing (--fixed none) is what the controller ran, so its capabilities
  // hold it: a fixed range (a format-2 start) follows the fit, a wider one grows to it.
  const dynamics::MachineParameters& fp = report.fitted.parameters;
  for (const auto& [setting, value] :
       {std::pair{motion::Setting::kDwell, fp.controller_dwell_s},
        std::pair{motion::Setting::kSmoothing, fp.controller_smoothing_s}}) {
    motion::SettingRange& range = report.fitted.capabilities[setting];
    range = range.min == range.max
                ? motion::SettingRange{value, value}
                : motion::SettingRange{std::min(range.min, value), std::max(range.max, value)};
  }
  if (!report.fitted.description.empty()) report.fitted.description += "; ";
  report.fitted.description += fmt::format("identified ({} parameters, cost {:.4g} -> {:.4g})",
                                           n,
                                           summary.initial_cost,
                                           summary.final_cost);
  for (std::size_t k = 0; k < free.size(); ++k) {
    const double v = std::exp(x[k]);
    report.fitted_values.push_back(v);
    const Info& info = *free[k];
    const int bound = v <= info.plausible_min * 1.01 ? -1 : v >= info.plausible_max * 0.99 ? 1 : 0;
    report.at_bound.push_back(bound);
    report.bound_values.push_back(bound < 0   ? info.plausible_min
                                  : bound > 0 ? info.plausible_max
                                              : 0.0);
  }
  parameter_uncertainty(*cost, problem.residual_count(), x, summary.final_cost, report);
  report.initial_cost = summary.initial_cost;
  report.final_cost = summary.final_cost;
  report.iterations = static_cast<int>(summary.iterations.size());
  report.termination = summary.message;
  report.usable = summary.IsSolutionUsable();
  const std::vector<double> model = problem.model_values(x.data(), options.threads);
  const std::vector<double> target = problem.targets();
  const std::vector<double> sigma = problem.sigmas();
  const std::vector<std::string> names = problem.names();
  for (std::size_t i = 0; i < model.size(); ++i) {
    report.residuals.push_back({names[i], target[i], model[i], (model[i] - target[i]) / sigma[i]});
  }
  return report;
}

AnovaTargets read_anova_targets(const std::string& path) {
  AnovaTargets t;
  t.enabled = true;
  std::map<std::string, int> column;
  std::array<bool, 5> seen{};
  for_each_csv_line(path, "ANOVA targets", [&](int line_no, const std::vector<std::string>& cells) {
    if (column.empty()) {
      for (std::size_t i = 0; i < cells.size(); ++i) column[cells[i]] = static_cast<int>(i);
      for (const char* c :
           {"factor", "mpe_weight_pct", "rpe_weight_pct", "mae_weight_pct", "rae_weight_pct"}) {
        if (column.count(c) == 0) {
          throw ConfigError(fmt::format("{}:{}: missing column '{}'", path, line_no, c));
        }
      }
      return;
    }
    const std::string factor = cells.at(static_cast<std::size_t>(column["factor"]));
    int source = -1;
    for (int s = 0; s < 5; ++s) {
      if (factor == kSourceNames[static_cast<std::size_t>(s)]) source = s;
    }
    if (source < 0) {
      throw ConfigError(
          fmt::format("{}:{}: unknown factor '{}' (PV, PD, AV, AD, error)", path, line_no, factor));
    }
    const char* cols[4] = {"mpe_weight_pct", "rpe_weight_pct", "mae_weight_pct", "rae_weight_pct"};
    for (std::size_t p = 0; p < 4; ++p) {
      const std::size_t c = static_cast<std::size_t>(column[cols[p]]);
      try {
        if (c >= cells.size()) throw ConfigError("short row");
        t.weight_pct[p][static_cast<std::size_t>(source)] = std::stod(cells[c]);
      } catch (const std::exception&) {
        throw ConfigError(
            fmt::format("{}:{}: column '{}' is not a number", path, line_no, cols[p]));
      }
    }
    seen[static_cast<std::size_t>(source)] = true;
  });
  for (int s = 0; s < 5; ++s) {
    if (!seen[static_cast<std::size_t>(s)]) {
      throw ConfigError(
          fmt::format("{}: no row for '{}'", path, kSourceNames[static_cast<std::size_t>(s)]));
    }
  }
  return t;
}

GridMeanTargets read_grid_mean_targets(const std::string& path) {
  GridMeanTargets t;
  t.enabled = true;
  int parameter_col = -1, mean_col = -1;
  std::array<bool, 4> seen{};
  for_each_csv_line(
      path, "grid-mean targets", [&](int line_no, const std::vector<std::string>& cells) {
        if (parameter_col < 0) {
          for (std::size_t i = 0; i < cells.size(); ++i) {
            if (cells[i] == "parameter") parameter_col = static_cast<int>(i);
            if (cells[i] == "mean_before_um") mean_col = static_cast<int>(i);
          }
          if (parameter_col < 0 || mean_col < 0) {
            throw ConfigError(fmt::format(
                "{}:{}: needs the columns 'parameter' and 'mean_before_um'", path, line_no));
          }
          return;
        }
        const auto at = [&](int c) -> std::string {
          return static_cast<std::size_t>(c) < cells.size() ? cells[static_cast<std::size_t>(c)]
                                                            : "";
        };
        int p = -1;
        for (int k = 0; k < 4; ++k) {
          if (at(parameter_col) == kParamNames[static_cast<std::size_t>(k)]) p = k;
        }
        if (p < 0) {
          throw ConfigError(fmt::format("{}:{}: unknown parameter '{}' (MPE, RPE, MAE, RAE)",
                                        path,
                                        line_no,
                                        at(parameter_col)));
        }
        try {
          const double v = std::stod(at(mean_col));
          if (!(v > 0.0 && std::isfinite(v))) throw ConfigError("not positive");
          t.mean_um[static_cast<std::size_t>(p)] = v;
        } catch (const std::exception&) {
          throw ConfigError(
              fmt::format("{}:{}: 'mean_before_um' must be a positive number", path, line_no));
        }
        seen[static_cast<std::size_t>(p)] = true;
      });
  for (int p = 0; p < 4; ++p) {
    if (!seen[static_cast<std::size_t>(p)]) {
      throw ConfigError(
          fmt::format("{}: no row for '{}'", path, kParamNames[static_cast<std::size_t>(p)]));
    }
  }
  return t;
}

std::string format_identification_report(const IdentificationReport& r,
                                         const std::string& machine_name,
                                         const std::string& data_label) {
  std::string out = fmt::format(
      "identification of '{}' from {}: {} iterations, cost {:.6g} -> "
      "{:.6g} ({})\n\n",
      machine_name,
      data_label,
      r.iterations,
      r.initial_cost,
      r.final_cost,
      r.termination);
  out += fmt::format("{:<42} {:>14} {:>14} {:>10}\n", "parameter", "start", "fitted", "1 sigma");
  for (std::size_t i = 0; i < r.free_parameters.size(); ++i) {
    const double rel =
        i < r.relative_sigma.size() ? r.relative_sigma[i] : std::numeric_limits<double>::infinity();
    out += fmt::format(
        "{:<42} {:14.6g} {:14.6g} {:>10}{}\n",
        r.free_parameters[i],
        r.start_values[i],
        r.fitted_values[i],
        std::isfinite(rel) ? fmt::format("{:.3g} %", 100.0 * rel) : std::string("undetermined"),
        r.at_bound[i] < 0   ? "  AT PLAUSIBLE MIN"
        : r.at_bound[i] > 0 ? "  AT PLAUSIBLE MAX"
                            : "");
  }
  out += fmt::format(
      "(1 sigma: from the Jacobian at the fit, scaled by the residuals' spread {:.3g}; "
      "undetermined: the data do not fix it)\n",
      r.residual_scale);
  out +=
      fmt::format("\n{:<42} {:>10} {:>10} {:>10}\n", "residual", "target", "fitted", "(f-t)/sigma");
  for (const IdentificationResidual& res : r.residuals) {
    out += fmt::format(
        "{:<42} {:10.3f} {:10.3f} {:10.2f}\n", res.name, res.target, res.fitted, res.normalized);
  }
  return out;
}

std::vector<std::string> bound_warnings(const IdentificationReport& r) {
  std::vector<std::string> out;
  if (r.residual_scale > 2.0) {
    out.push_back(fmt::format(
        "the residuals at the fit spread {:.3g} times their sigma: a mechanism is missing from "
        "the model, a fixed key is wrong, the fit stopped in a local minimum, or the sigmas are "
        "optimistic; the 1 sigma column is widened by that factor but assumes the model is right",
        r.residual_scale));
  }
  for (std::size_t i = 0; i < r.free_parameters.size(); ++i) {
    if (r.at_bound[i] == 0) continue;
    out.push_back(fmt::format(
        "{} ended at its plausible {} {:g}: the data want a value outside the plausible range, "
        "so a mechanism is missing from the model or a fixed key is wrong (check the "
        "controller timing measured by cmmcomp-measure extract); the machine file is written, "
        "but treat it with care",
        r.free_parameters[i],
        r.at_bound[i] < 0 ? "minimum" : "maximum",
        r.bound_values[i]));
  }
  return out;
}

}  // namespace cmmcomp::training

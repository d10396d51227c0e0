// SPDX-License-Identifier: MIT
/// @file The bodies of include/cmmcomp/doe/anova.hpp.
#include <cmmcomp/doe/anova.hpp>

namespace cmmcomp::doe {

bool AnovaOptions::is_valid(std::string* why) const {
  if (!std::isfinite(pool_below_percent) || pool_below_percent < 0.0 ||
      pool_below_percent > 100.0) {
    if (why != nullptr) *why = "pool_below_percent must be in [0, 100]";
    return false;
  }
  return true;
}

AnovaTable anova_from_sums_of_squares(const std::vector<std::string>& factor_names,
                                      const std::vector<double>& factor_ss,
                                      const std::vector<int>& factor_dof,
                                      double total_ss,
                                      int total_dof,
                                      const AnovaOptions& options) {
  const std::string where = "doe::anova: ";
  std::string why;
  if (!options.is_valid(&why)) throw ConfigError(where + why);
  const std::size_t nf = factor_names.size();
  if (nf == 0) throw ConfigError(where + "no factors");
  if (factor_ss.size() != nf || factor_dof.size() != nf) {
    throw ConfigError(where + "names, sums of squares and dofs differ in size");
  }
  detail::require_unique_names(factor_names, "doe::anova");
  if (!std::isfinite(total_ss) || total_ss < 0.0) {
    throw ConfigError(where + "total SS must be finite and >= 0");
  }
  int dof_sum = 0;
  double ss_sum = 0.0;
  for (std::size_t f = 0; f < nf; ++f) {
    if (factor_names[f].empty()) throw ConfigError(where + "empty factor name");
    if (!std::isfinite(factor_ss[f]) || factor_ss[f] < 0.0) {
      throw ConfigError(where + "SS of '" + factor_names[f] + "' must be finite, >= 0");
    }
    if (factor_dof[f] < 1) {
      throw ConfigError(where + "dof of '" + factor_names[f] + "' must be >= 1");
    }
    dof_sum += factor_dof[f];
    ss_sum += factor_ss[f];
  }
  if (total_dof < dof_sum) {
    throw ConfigError(where + "total dof " + std::to_string(total_dof) +
                      " is less than the factors' " + std::to_string(dof_sum));
  }
  const double zero_tol = kAnovaRelativeZero * total_ss;
  double residual = total_ss - ss_sum;
  if (residual < -zero_tol) {
    throw ConfigError(where + "factor sums of squares exceed the total");
  }
  if (residual <= zero_tol) residual = 0.0;
  for (const auto& name : options.pool_factors) {
    bool found = false;
    for (const auto& n : factor_names) found = found || n == name;
    if (!found) throw ConfigError(where + "cannot pool unknown factor '" + name + "'");
  }

  const auto percent = [total_ss](double ss) {
    return total_ss > 0.0 ? ss / total_ss * 100.0 : 0.0;
  };
  AnovaTable t;
  for (std::size_t f = 0; f < nf; ++f) {
    AnovaRow row;
    row.source = factor_names[f];
    row.sum_of_squares = factor_ss[f] <= zero_tol ? 0.0 : factor_ss[f];
    row.dof = factor_dof[f];
    row.mean_square = row.sum_of_squares / row.dof;
    row.weight_percent = percent(row.sum_of_squares);
    for (const auto& name : options.pool_factors) row.pooled = row.pooled || name == row.source;
    row.pooled = row.pooled || row.weight_percent < options.pool_below_percent;
    t.factors.push_back(std::move(row));
  }

  const auto error_dof = [&t, total_dof, dof_sum] {
    int dof = total_dof - dof_sum;
    for (const auto& row : t.factors) dof += row.pooled ? row.dof : 0;
    return dof;
  };
  if (options.pool_smallest_when_saturated && error_dof() == 0) {
    AnovaRow* smallest = nullptr;
    for (auto& row : t.factors) {
      if (!row.pooled && (smallest == nullptr || row.sum_of_squares < smallest->sum_of_squares)) {
        smallest = &row;
      }
    }
    if (smallest != nullptr) smallest->pooled = true;
  }

  t.error.source = "error";
  t.error.sum_of_squares = residual;
  for (const auto& row : t.factors) t.error.sum_of_squares += row.pooled ? row.sum_of_squares : 0.0;
  t.error.dof = error_dof();
  t.error.mean_square = t.error.dof > 0 ? t.error.sum_of_squares / t.error.dof : 0.0;
  t.error.weight_percent = percent(t.error.sum_of_squares);

  for (auto& row : t.factors) {
    row.has_f = !row.pooled && t.error.dof > 0;
    if (!row.has_f) continue;
    if (t.error.mean_square > 0.0) {
      row.f_value = row.mean_square / t.error.mean_square;
    } else {
      row.f_value = row.mean_square > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
    }
  }

  t.total.source = "total";
  t.total.sum_of_squares = total_ss;
  t.total.dof = total_dof;
  t.total.mean_square = total_dof > 0 ? total_ss / total_dof : 0.0;
  t.total.weight_percent = total_ss > 0.0 ? 100.0 : 0.0;
  return t;
}

AnovaTable anova(const std::vector<std::string>& factor_names,
                 const std::vector<int>& level_counts,
                 const std::vector<std::vector<int>>& level_indices,
                 const std::vector<double>& responses,
                 const AnovaOptions& options) {
  const std::string where = "doe::anova: ";
  const std::size_t nf = factor_names.size();
  const std::size_t n = responses.size();
  if (nf == 0) throw ConfigError(where + "no factors");
  if (level_counts.size() != nf) throw ConfigError(where + "level_counts size mismatch");
  if (n < 2) throw ConfigError(where + "needs at least 2 runs");
  if (level_indices.size() != n) {
    throw ConfigError(where + std::to_string(level_indices.size()) + " runs but " +
                      std::to_string(n) + " responses");
  }
  for (std::size_t f = 0; f < nf; ++f) {
    if (level_counts[f] < 2) {
      throw ConfigError(where + "factor '" + factor_names[f] + "' has fewer than 2 levels");
    }
  }
  for (std::size_t r = 0; r < n; ++r) {
    if (!std::isfinite(responses[r])) {
      throw ConfigError(where + "response of run " + std::to_string(r) + " not finite");
    }
    if (level_indices[r].size() != nf) {
      throw ConfigError(where + "run " + std::to_string(r) + " has the wrong number of " +
                        "level indices");
    }
    for (std::size_t f = 0; f < nf; ++f) {
      if (level_indices[r][f] < 0 || level_indices[r][f] >= level_counts[f]) {
        throw ConfigError(where + "run " + std::to_string(r) + ": level of '" + factor_names[f] +
                          "' out of range");
      }
    }
  }
  const auto at = [&level_indices](std::size_t r, std::size_t f) {
    return static_cast<std::size_t>(level_indices[r][f]);
  };
  // Orthogonality: every level of a factor equally often, every level pair of two factors
  // equally often. Without it the factor SS do not partition the total.
  for (std::size_t f = 0; f < nf; ++f) {
    for (std::size_t g = f; g < nf; ++g) {
      const auto lf = static_cast<std::size_t>(level_counts[f]);
      const std::size_t lg = g == f ? 1 : static_cast<std::size_t>(level_counts[g]);
      std::vector<std::size_t> count(lf * lg, 0);
      for (std::size_t r = 0; r < n; ++r) ++count[at(r, f) * lg + (g == f ? 0 : at(r, g))];
      for (const std::size_t c : count) {
        if (c * lf * lg != n) {
          throw ConfigError(where + (g == f ? "factor '" + factor_names[f] + "' is not balanced"
                                            : "factors '" + factor_names[f] + "' and '" +
                                                  factor_names[g] + "' are not orthogonal"));
        }
      }
    }
  }

  // Two passes: centre first, so the sums of squares are of small numbers.
  double mean = 0.0;
  for (const double y : responses) mean += y;
  mean /= static_cast<double>(n);
  std::vector<double> d(n);
  double dmean = 0.0;
  for (std::size_t r = 0; r < n; ++r) {
    d[r] = responses[r] - mean;
    dmean += d[r];
  }
  dmean /= static_cast<double>(n);
  double total_ss = 0.0;
  for (const double v : d) total_ss += (v - dmean) * (v - dmean);

  std::vector<double> ss(nf, 0.0);
  std::vector<int> dof(nf, 0);
  std::vector<std::vector<double>> level_means(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const auto lf = static_cast<std::size_t>(level_counts[f]);
    std::vector<double> sum(lf, 0.0);
    std::vector<double> cnt(lf, 0.0);
    for (std::size_t r = 0; r < n; ++r) {
      sum[at(r, f)] += d[r];
      cnt[at(r, f)] += 1.0;
    }
    for (std::size_t l = 0; l < lf; ++l) {
      const double dev = sum[l] / cnt[l] - dmean;
      ss[f] += cnt[l] * dev * dev;
      level_means[f].push_back(mean + sum[l] / cnt[l]);
    }
    dof[f] = level_counts[f] - 1;
  }
  AnovaTable t =
      anova_from_sums_of_squares(factor_names, ss, dof, total_ss, static_cast<int>(n) - 1, options);
  t.grand_mean = mean + dmean;
  t.level_means = std::move(level_means);
  return t;
}

AnovaTable anova(const Design& design,
                 const std::vector<double>& responses,
                 const AnovaOptions& options) {
  detail::require_valid(design, "doe::anova");
  if (!design.has_levels) {
    throw ConfigError("doe::anova: the design has no level indices (e.g. an LHS)");
  }
  if (responses.size() != design.values.size()) {
    throw ConfigError("doe::anova: " + std::to_string(design.values.size()) + " runs but " +
                      std::to_string(responses.size()) + " responses");
  }
  return anova(design.factor_names, design.level_counts, design.level_indices, responses, options);
}

ReplicateAverage average_replicates(const Design& design, const std::vector<double>& responses) {
  detail::require_valid(design, "doe::average_replicates");
  if (responses.size() != design.values.size()) {
    throw ConfigError("doe::average_replicates: " + std::to_string(design.values.size()) +
                      " runs but " + std::to_string(responses.size()) + " responses");
  }
  ReplicateAverage out;
  out.design.factor_names = design.factor_names;
  out.design.has_levels = design.has_levels;
  out.design.level_counts = design.level_counts;
  std::map<int, std::size_t> slot;  // run_index -> output row
  std::vector<double> sums;
  for (std::size_t r = 0; r < design.values.size(); ++r) {
    if (!std::isfinite(responses[r])) {
      throw ConfigError("doe::average_replicates: response of run " + std::to_string(r) +
                        " not finite");
    }
    const int key = design.run_index[r];
    const auto it = slot.find(key);
    if (it == slot.end()) {
      slot.emplace(key, out.design.values.size());
      out.design.values.push_back(design.values[r]);
      if (design.has_levels) out.design.level_indices.push_back(design.level_indices[r]);
      out.design.run_index.push_back(key);
      sums.push_back(responses[r]);
      out.repeats.push_back(1);
      continue;
    }
    const std::size_t k = it->second;
    if (out.design.values[k] != design.values[r] ||
        (design.has_levels && out.design.level_indices[k] != design.level_indices[r])) {
      throw ConfigError("doe::average_replicates: rows with run_index " + std::to_string(key) +
                        " differ in their factor settings");
    }
    sums[k] += responses[r];
    ++out.repeats[k];
  }
  for (std::size_t k = 0; k < sums.size(); ++k) out.means.push_back(sums[k] / out.repeats[k]);
  return out;
}

std::string format_anova_table(const AnovaTable& table, int precision) {
  std::ostringstream os;
  const auto num = [precision](double v) {
    if (std::isinf(v)) return std::string(v > 0 ? "inf" : "-inf");
    std::ostringstream s;
    s << std::setprecision(precision) << v;
    return s.str();
  };
  const auto line = [&os](const std::string& a,
                          const std::string& b,
                          const std::string& c,
                          const std::string& d,
                          const std::string& e,
                          const std::string& f) {
    os << std::left << std::setw(12) << a << std::right << std::setw(14) << b << std::setw(6) << c
       << std::setw(14) << d << std::setw(10) << e << std::setw(10) << f << '\n';
  };
  line("source", "SS", "dof", "MS", "weight %", "F");
  const auto row_line = [&](const AnovaRow& row) {
    std::string f = "-";
    if (row.pooled) {
      f = "pooled";
    } else if (row.has_f) {
      f = num(row.f_value);
    }
    line(row.source,
         num(row.sum_of_squares),
         std::to_string(row.dof),
         num(row.mean_square),
         num(row.weight_percent),
         f);
  };
  for (const auto& row : table.factors) row_line(row);
  row_line(table.error);
  row_line(table.total);
  return os.str();
}

}  // namespace cmmcomp::doe

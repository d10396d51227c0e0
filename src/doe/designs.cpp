// SPDX-License-Identifier: MIT
/// @file The bodies of include/cmmcomp/doe/designs.hpp.
#include <cmmcomp/doe/designs.hpp>

namespace cmmcomp::doe {

bool Design::is_valid(std::string* why) const {
  const auto fail = [why](const std::string& reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (factor_names.empty()) return fail("no factors");
  if (values.empty()) return fail("no runs");
  std::set<std::string> names;
  for (const auto& n : factor_names) {
    if (n.empty()) return fail("a factor has an empty name");
    if (!names.insert(n).second) return fail("factor name '" + n + "' used twice");
  }
  const std::size_t nf = factor_names.size();
  for (std::size_t r = 0; r < values.size(); ++r) {
    if (values[r].size() != nf) {
      return fail("run " + std::to_string(r) + " has " + std::to_string(values[r].size()) +
                  " values, expected " + std::to_string(nf));
    }
    for (std::size_t f = 0; f < nf; ++f) {
      if (!std::isfinite(values[r][f])) {
        return fail("run " + std::to_string(r) + ": value of '" + factor_names[f] +
                    "' is not finite");
      }
    }
  }
  if (run_index.size() != values.size()) return fail("run_index size differs from runs");
  for (const int i : run_index) {
    if (i < 0) return fail("negative run_index");
  }
  if (!has_levels) {
    if (!level_indices.empty() || !level_counts.empty()) {
      return fail("level members filled but has_levels is false");
    }
    return true;
  }
  if (level_counts.size() != nf) return fail("level_counts size differs from factors");
  for (std::size_t f = 0; f < nf; ++f) {
    if (level_counts[f] < 1) return fail("factor '" + factor_names[f] + "' has no levels");
  }
  if (level_indices.size() != values.size()) return fail("level_indices size differs from runs");
  for (std::size_t r = 0; r < level_indices.size(); ++r) {
    if (level_indices[r].size() != nf) {
      return fail("run " + std::to_string(r) + " has the wrong number of level indices");
    }
    for (std::size_t f = 0; f < nf; ++f) {
      const int l = level_indices[r][f];
      if (l < 0 || l >= level_counts[f]) {
        return fail("run " + std::to_string(r) + ": level " + std::to_string(l) + " of '" +
                    factor_names[f] + "' outside [0, " + std::to_string(level_counts[f]) + ")");
      }
    }
  }
  return true;
}

namespace detail {

void require_valid(const Design& design, const char* where) {
  std::string why;
  if (!design.is_valid(&why)) throw ConfigError(std::string(where) + ": " + why);
}

void require_factor_ok(const Factor& factor, const char* where) {
  if (factor.name.empty()) throw ConfigError(std::string(where) + ": empty factor name");
  if (factor.levels.empty()) {
    throw ConfigError(std::string(where) + ": factor '" + factor.name + "' has no levels");
  }
  for (const double v : factor.levels) {
    if (!std::isfinite(v)) {
      throw ConfigError(std::string(where) + ": factor '" + factor.name +
                        "' has a non-finite level");
    }
  }
}

void require_unique_names(const std::vector<std::string>& names, const char* where) {
  std::set<std::string> seen;
  for (const auto& n : names) {
    if (!seen.insert(n).second) {
      throw ConfigError(std::string(where) + ": factor name '" + n + "' used twice");
    }
  }
}

double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

std::uint64_t uniform_below(std::mt19937_64& rng, std::uint64_t bound) {
  // Accept r < 2^64 - (2^64 mod bound), a multiple of bound.
  const std::uint64_t rem = (std::numeric_limits<std::uint64_t>::max() % bound + 1) % bound;
  const std::uint64_t max_ok = std::numeric_limits<std::uint64_t>::max() - rem;
  std::uint64_t r = rng();
  while (r > max_ok) r = rng();
  return r % bound;
}

std::vector<int> identity_runs(std::size_t n) {
  std::vector<int> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<int>(i);
  return out;
}

}  // namespace detail

}  // namespace cmmcomp::doe

namespace cmmcomp::doe {

Design assign(const OrthogonalArray& oa,
              const std::vector<Factor>& factors,
              const std::vector<int>& columns) {
  constexpr const char* kWhere = "doe::assign";
  if (factors.empty()) throw ConfigError("doe::assign: no factors");
  if (factors.size() != columns.size()) {
    throw ConfigError("doe::assign: " + std::to_string(factors.size()) + " factors but " +
                      std::to_string(columns.size()) + " columns");
  }
  std::set<int> used;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < factors.size(); ++i) {
    const Factor& f = factors[i];
    detail::require_factor_ok(f, kWhere);
    const int c = columns[i];
    if (c < 0 || c >= oa.columns()) {
      throw ConfigError("doe::assign: column " + std::to_string(c) + " for factor '" + f.name +
                        "' is outside [0, " + std::to_string(oa.columns()) + ") of " + oa.name());
    }
    if (!used.insert(c).second) {
      throw ConfigError("doe::assign: column " + std::to_string(c) + " for factor '" + f.name +
                        "' is already used by another factor");
    }
    if (static_cast<int>(f.levels.size()) != oa.levels(c)) {
      throw ConfigError("doe::assign: factor '" + f.name + "' has " +
                        std::to_string(f.levels.size()) + " levels but column " +
                        std::to_string(c) + " of " + oa.name() + " has " +
                        std::to_string(oa.levels(c)));
    }
    names.push_back(f.name);
  }
  detail::require_unique_names(names, kWhere);

  Design d;
  d.factor_names = std::move(names);
  d.has_levels = true;
  for (const Factor& f : factors) d.level_counts.push_back(static_cast<int>(f.levels.size()));
  for (int r = 0; r < oa.runs(); ++r) {
    std::vector<double> row;
    std::vector<int> lev;
    for (std::size_t i = 0; i < factors.size(); ++i) {
      const int l = oa.level(r, columns[i]);
      lev.push_back(l);
      row.push_back(factors[i].levels[static_cast<std::size_t>(l)]);
    }
    d.values.push_back(std::move(row));
    d.level_indices.push_back(std::move(lev));
  }
  d.run_index = detail::identity_runs(d.values.size());
  return d;
}

std::vector<int> paper_l18_assignment() { return {1, 2, 3, 4}; }

std::vector<Factor> paper_table3_factors() {
  std::vector<Factor> factors;
  for (std::size_t f = 0; f < paper::kTable3Levels.size(); ++f) {
    Factor factor{PaperInputs::labels()[f], {}};
    // mm / 1000: the double nearest the SI value, the same bits as the literal (0.040).
    for (const double level : paper::kTable3Levels[f]) factor.levels.push_back(level / 1000.0);
    factors.push_back(std::move(factor));
  }
  return factors;
}

Design paper_l18_design() {
  return assign(taguchi_l18(), paper_table3_factors(), paper_l18_assignment());
}

Design full_factorial(const std::vector<Factor>& factors) {
  constexpr const char* kWhere = "doe::full_factorial";
  if (factors.empty()) throw ConfigError("doe::full_factorial: no factors");
  long long total = 1;
  std::vector<std::string> names;
  for (const Factor& f : factors) {
    detail::require_factor_ok(f, kWhere);
    total *= static_cast<long long>(f.levels.size());
    if (total > kMaxFullFactorialRuns) {
      throw ConfigError("doe::full_factorial: more than " + std::to_string(kMaxFullFactorialRuns) +
                        " runs");
    }
    names.push_back(f.name);
  }
  detail::require_unique_names(names, kWhere);

  Design d;
  d.factor_names = std::move(names);
  d.has_levels = true;
  for (const Factor& f : factors) d.level_counts.push_back(static_cast<int>(f.levels.size()));
  std::vector<int> lev(factors.size(), 0);
  for (long long r = 0; r < total; ++r) {
    std::vector<double> row;
    for (std::size_t i = 0; i < factors.size(); ++i) {
      row.push_back(factors[i].levels[static_cast<std::size_t>(lev[i])]);
    }
    d.values.push_back(std::move(row));
    d.level_indices.push_back(lev);
    // Odometer increment, last factor fastest.
    for (std::size_t i = factors.size(); i-- > 0;) {
      if (++lev[i] < d.level_counts[i]) break;
      lev[i] = 0;
    }
  }
  d.run_index = detail::identity_runs(d.values.size());
  return d;
}

Design latin_hypercube(const std::vector<std::string>& names,
                       const std::vector<double>& lower,
                       const std::vector<double>& upper,
                       int samples,
                       std::uint64_t seed) {
  if (names.empty()) throw ConfigError("doe::latin_hypercube: no factors");
  if (lower.size() != names.size() || upper.size() != names.size()) {
    throw ConfigError("doe::latin_hypercube: names, lower and upper differ in size");
  }
  if (samples < 1) throw ConfigError("doe::latin_hypercube: samples must be >= 1");
  for (std::size_t f = 0; f < names.size(); ++f) {
    if (names[f].empty()) throw ConfigError("doe::latin_hypercube: empty factor name");
    if (!std::isfinite(lower[f]) || !std::isfinite(upper[f]) || lower[f] > upper[f]) {
      throw ConfigError("doe::latin_hypercube: factor '" + names[f] +
                        "' needs finite bounds with lower <= upper");
    }
  }
  detail::require_unique_names(names, "doe::latin_hypercube");

  const auto n = static_cast<std::size_t>(samples);
  Design d;
  d.factor_names = names;
  d.values.assign(n, std::vector<double>(names.size(), 0.0));
  std::mt19937_64 rng(seed);
  std::vector<int> strata(n);
  for (std::size_t f = 0; f < names.size(); ++f) {
    for (std::size_t i = 0; i < n; ++i) strata[i] = static_cast<int>(i);
    for (std::size_t i = n - 1; i > 0; --i) {
      const auto j = static_cast<std::size_t>(detail::uniform_below(rng, i + 1));
      std::swap(strata[i], strata[j]);
    }
    const double width = upper[f] - lower[f];
    for (std::size_t r = 0; r < n; ++r) {
      const double u = detail::uniform01(rng);
      d.values[r][f] = lower[f] + width * ((strata[r] + u) / static_cast<double>(samples));
    }
  }
  d.run_index = detail::identity_runs(n);
  return d;
}

Design replicate(const Design& design, int repeats) {
  detail::require_valid(design, "doe::replicate");
  if (repeats < 1) throw ConfigError("doe::replicate: repeats must be >= 1");
  Design d;
  d.factor_names = design.factor_names;
  d.has_levels = design.has_levels;
  d.level_counts = design.level_counts;
  for (std::size_t r = 0; r < design.values.size(); ++r) {
    for (int k = 0; k < repeats; ++k) {
      d.values.push_back(design.values[r]);
      if (design.has_levels) d.level_indices.push_back(design.level_indices[r]);
      d.run_index.push_back(design.run_index[r]);
    }
  }
  return d;
}

Design design_by_name(const std::string& name,
                      const std::vector<Factor>& factors,
                      int lhs_samples,
                      std::uint64_t seed) {
  auto require_levels = [&factors, &name](std::size_t n) {
    for (const Factor& f : factors) {
      if (f.levels.size() != n) {
        throw ConfigError("design " + name + " needs " + std::to_string(n) +
                          " levels per factor; " + f.name + " has " +
                          std::to_string(f.levels.size()));
      }
    }
  };
  const bool with_y = factors.size() == 5;
  if (name == "l18") {
    require_levels(3);
    std::vector<int> columns = paper_l18_assignment();
    if (with_y) columns.push_back(5);  // c6, the next free 3-level column
    return assign(taguchi_l18(), factors, columns);
  }
  if (with_y && (name == "l9" || name == "l27")) {
    throw ConfigError("design " + name +
                      " has no column for y; use l18, full or lhs with y levels");
  }
  if (name == "l9") {
    require_levels(3);
    return assign(taguchi_l9(), factors, {0, 1, 2, 3});
  }
  if (name == "l27") {
    require_levels(3);
    return assign(taguchi_l27(), factors, {0, 1, 4, 12});
  }
  if (name == "full") return full_factorial(factors);
  if (name == "lhs") {
    std::vector<std::string> names;
    std::vector<double> lo, hi;
    for (const Factor& f : factors) {
      names.push_back(f.name);
      lo.push_back(*std::min_element(f.levels.begin(), f.levels.end()));
      hi.push_back(*std::max_element(f.levels.begin(), f.levels.end()));
    }
    return latin_hypercube(names, lo, hi, lhs_samples, seed);
  }
  throw ConfigError("design must be one of l18, l9, l27, full, lhs (got '" + name + "')");
}

}  // namespace cmmcomp::doe

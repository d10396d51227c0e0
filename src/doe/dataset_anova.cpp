// SPDX-License-Identifier: MIT
/// @file The bodies of include/cmmcomp/doe/dataset_anova.hpp.
#include <fmt/format.h>

#include <cmath>
#include <cmmcomp/doe/dataset_anova.hpp>
#include <nlohmann/json.hpp>
#include <string>

namespace cmmcomp::doe {

DatasetAnova anova_of_dataset(const std::vector<DatasetRow>& rows,
                              const doe::AnovaOptions& options) {
  if (rows.empty()) throw ConfigError("anova: the dataset is empty");
  for (const DatasetRow& r : rows) {
    if (r.pa_mm_s2 != rows[0].pa_mm_s2 || r.aa_mm_s2 != rows[0].aa_mm_s2 ||
        r.y_mm != rows[0].y_mm) {
      throw ConfigError(
          "anova: pa_mm_s2, aa_mm_s2 and y_mm must be the same in every row (the ANOVA covers "
          "PV, PD, AV, AD)");
    }
  }
  using Key = std::array<double, 4>;
  auto key_of = [](const DatasetRow& r) { return PaperInputs::gather(r); };
  std::map<Key, std::array<double, 5>> sums;  // mpe, |rpe|, mae, |rae|, count
  std::vector<Key> order;
  for (const DatasetRow& r : rows) {
    auto [it, inserted] = sums.try_emplace(key_of(r), std::array<double, 5>{});
    if (inserted) order.push_back(key_of(r));
    it->second[0] += r.mpe_um;
    it->second[1] += std::fabs(r.rpe_um);
    it->second[2] += r.mae_um;
    it->second[3] += std::fabs(r.rae_um);
    it->second[4] += 1.0;
  }
  std::array<std::vector<double>, 4> levels;
  for (std::size_t f = 0; f < 4; ++f) {
    for (const Key& k : order) levels[f].push_back(k[f]);
    std::sort(levels[f].begin(), levels[f].end());
    levels[f].erase(std::unique(levels[f].begin(), levels[f].end()), levels[f].end());
    if (levels[f].size() < 2) {
      throw ConfigError(std::string("anova: factor ") + kAnovaFactors[f] + " has a single level");
    }
  }
  std::vector<std::string> names(kAnovaFactors.begin(), kAnovaFactors.end());
  std::vector<int> counts;
  counts.reserve(levels.size());
  for (const auto& l : levels) counts.push_back(static_cast<int>(l.size()));
  std::vector<std::vector<int>> indices;
  std::array<std::vector<double>, 4> means;
  for (const Key& k : order) {
    std::vector<int> idx;
    for (std::size_t f = 0; f < 4; ++f) {
      idx.push_back(static_cast<int>(std::lower_bound(levels[f].begin(), levels[f].end(), k[f]) -
                                     levels[f].begin()));
    }
    indices.push_back(idx);
    const auto& s = sums.at(k);
    for (std::size_t p = 0; p < 4; ++p) means[p].push_back(s[p] / s[4]);
  }
  DatasetAnova out;
  out.mpe = doe::anova(names, counts, indices, means[0], options);
  out.rpe = doe::anova(names, counts, indices, means[1], options);
  out.mae = doe::anova(names, counts, indices, means[2], options);
  out.rae = doe::anova(names, counts, indices, means[3], options);
  out.runs = static_cast<int>(order.size());
  out.samples = static_cast<int>(rows.size());
  return out;
}

namespace {

nlohmann::json table_json(const AnovaTable& t) {
  nlohmann::json j;
  const auto row = [](const AnovaRow& r) {
    nlohmann::json o{{"ss", r.sum_of_squares},
                     {"dof", r.dof},
                     {"weight_pct", r.weight_percent},
                     {"pooled", r.pooled}};
    o["f"] = r.has_f && std::isfinite(r.f_value) ? nlohmann::json(r.f_value) : nlohmann::json();
    return o;
  };
  for (const auto& f : t.factors) j[f.source] = row(f);
  j["error"] = row(t.error);
  j["total"] = row(t.total);
  return j;
}

}  // namespace

std::string format_dataset_anova_json(const DatasetAnova& a) {
  const nlohmann::json j{{"runs", a.runs},
                         {"samples", a.samples},
                         {"mpe", table_json(a.mpe)},
                         {"rpe", table_json(a.rpe)},
                         {"mae", table_json(a.mae)},
                         {"rae", table_json(a.rae)}};
  return j.dump(2);
}

std::string format_dataset_anova(const DatasetAnova& a, const std::string& source) {
  std::string out = fmt::format(
      "ANOVA of {}: {} runs (repeats averaged), {} samples; responses MPE, |RPE|, MAE, "
      "|RAE| [um]\n\n",
      source,
      a.runs,
      a.samples);
  out += fmt::format("{:<8} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}\n",
                     "factor",
                     "MPE w%",
                     "MPE F",
                     "RPE w%",
                     "RPE F",
                     "MAE w%",
                     "MAE F",
                     "RAE w%",
                     "RAE F");
  const AnovaTable* tables[] = {&a.mpe, &a.rpe, &a.mae, &a.rae};
  for (std::size_t f = 0; f <= a.mpe.factors.size(); ++f) {
    const bool error_row = f == a.mpe.factors.size();
    out += fmt::format("{:<8}", error_row ? std::string("error") : a.mpe.factors[f].source);
    for (const AnovaTable* t : tables) {
      const AnovaRow& r = error_row ? t->error : t->factors[f];
      if (!error_row && r.has_f && std::isfinite(r.f_value)) {
        out += fmt::format(" {:9.2f} {:9.2f}", r.weight_percent, r.f_value);
      } else {
        out += fmt::format(" {:9.2f} {:>9}", r.weight_percent, "-");
      }
    }
    out += "\n";
  }
  return out;
}

}  // namespace cmmcomp::doe

// SPDX-License-Identifier: MIT
/// @file The bodies of include/cmmcomp/doe/dataset_anova.hpp.
#include <cmmcomp/doe/dataset_anova.hpp>

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

}  // namespace cmmcomp::doe

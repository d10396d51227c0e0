// SPDX-License-Identifier: MIT
/// @file ANOVA of a dataset, as in the paper's Table 4 (offline).
///
/// Rows with the same move settings are one run (their repeats are averaged, as the paper does
/// with its 3 repeats); the factors are PV, PD, AV, AD, their levels the distinct values found.
/// PA, AA and Y must be constant. The responses are MPE, |RPE|, MAE and |RAE| (the paper reports
/// magnitudes).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cmmcomp/doe/anova.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/schema.hpp>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace cmmcomp::doe {

/// One ANOVA table per parameter.
struct DatasetAnova {
  AnovaTable mpe, rpe, mae, rae;
  int runs = 0;     ///< distinct move settings
  int samples = 0;  ///< rows
};

/// Factor names in the tables: PaperInputs' labels (schema.hpp).
inline constexpr std::array<const char*, 4> kAnovaFactors = PaperInputs::labels();

/// Throws ConfigError when PA, AA or Y vary, when a factor has a single level, or when
/// the runs are not an orthogonal design (the message names the factors).
DatasetAnova anova_of_dataset(const std::vector<DatasetRow>& rows,
                              const doe::AnovaOptions& options = {});

/// The four tables as cmmcomp-sim anova prints them: one row per factor and the error, the
/// weight [%] and F of each parameter ("-" where F is undefined); `source` names the data.
std::string format_dataset_anova(const DatasetAnova& anova, const std::string& source);
/// The same as JSON text (2-space indent): runs, samples, and per parameter (its key) each
/// source's ss, dof, weight_pct, pooled and f (null where undefined).
std::string format_dataset_anova_json(const DatasetAnova& anova);

}  // namespace cmmcomp::doe

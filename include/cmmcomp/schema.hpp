// SPDX-License-Identifier: MIT
/// @file The project's vocabulary, defined once: the move quantities a model may take as inputs
/// (features), the four dynamic-error parameters, the dataset row and its CSV columns, and the
/// input sets a compensation model is keyed on.
///
/// Every list of names, labels, units and CSV columns in the library, the tools and the model
/// files is read from the tables here (docs/dataset-csv.md, docs/model-file.md); tests check the
/// tables against those documents. Constexpr, no dependency beyond the move request, so the
/// real-time core and firmware use it as they are.
///
/// Adding a model input is one line in kFeatures (and, if datasets carry it, one field in
/// DatasetRow with one line in kDatasetColumns); a model keyed on a new set is then
/// `InputSet<…, Feature::kZ>`. tests/compensation/test_schema.cpp proves it with Z.
#pragma once

#include <array>
#include <cmmcomp/compensation/move_request.hpp>
#include <cstddef>
#include <cstdint>

namespace cmmcomp {

/// One probing move and its measured (or simulated) dynamic errors, in file units: one row of
/// the dataset CSV (docs/dataset-csv.md; the columns are kDatasetColumns).
struct DatasetRow {
  double pv_mm_s = 0;   ///< positioning speed PV
  double pd_mm = 0;     ///< positioning distance PD
  double av_mm_s = 0;   ///< approach speed AV
  double ad_mm = 0;     ///< approach distance AD
  double pa_mm_s2 = 0;  ///< positioning acceleration PA
  double aa_mm_s2 = 0;  ///< approach acceleration AA
  double y_mm = 0;      ///< carriage position along the beam Y
  double mpe_um = 0;    ///< maximum positioning error
  double rpe_um = 0;    ///< residual positioning error (signed, + = tip ahead)
  double mae_um = 0;    ///< maximum approach error
  double rae_um = 0;    ///< residual approach error (signed, + = tip ahead)
};

/// A move quantity a model can take as an input.
enum class Feature : std::uint8_t { kPv, kPd, kAv, kAd, kY, kZ };

/// How a feature is named and where it is read.
struct FeatureSpec {
  Feature feature;
  const char* label;   ///< short name for people and tables: "PV"
  const char* column;  ///< dataset CSV column and model-file input name: "pv_mm_s"
  const char* unit;    ///< model-file unit (ASCII): "mm/s"
  double compensation::MoveRequest::*request;  ///< where a MoveRequest carries it
  double DatasetRow::*row;  ///< where a DatasetRow carries it; nullptr: datasets do not (yet)
};

/// Every feature, indexed by its enum value.
inline constexpr std::array<FeatureSpec, 6> kFeatures = {{
    {Feature::kPv,
     "PV",
     "pv_mm_s",
     "mm/s",
     &compensation::MoveRequest::pv_mm_s,
     &DatasetRow::pv_mm_s},
    {Feature::kPd, "PD", "pd_mm", "mm", &compensation::MoveRequest::pd_mm, &DatasetRow::pd_mm},
    {Feature::kAv,
     "AV",
     "av_mm_s",
     "mm/s",
     &compensation::MoveRequest::av_mm_s,
     &DatasetRow::av_mm_s},
    {Feature::kAd, "AD", "ad_mm", "mm", &compensation::MoveRequest::ad_mm, &DatasetRow::ad_mm},
    {Feature::kY, "Y", "y_mm", "mm", &compensation::MoveRequest::y_mm, &DatasetRow::y_mm},
    {Feature::kZ, "Z", "z_mm", "mm", &compensation::MoveRequest::z_mm, nullptr},
}};

/// The table entry of `f`.
constexpr const FeatureSpec& spec(Feature f) noexcept {
  return kFeatures[static_cast<std::size_t>(f)];
}

/// The four dynamic-error parameters (docs/dynamic-errors.md), in the order of every model's
/// outputs, of a Correction's fields and of the paper's tables.
enum class ErrorParameter : std::uint8_t { kMpe, kRpe, kMae, kRae };

/// How an error parameter is named and where it is read.
struct ErrorSpec {
  ErrorParameter parameter;
  const char* label;   ///< "MPE"
  const char* column;  ///< dataset CSV column and model-file output name: "mpe_um"
  const char* unit;    ///< model-file unit (ASCII): "um"
  const char* key;     ///< lower-case key of JSON reports: "mpe"
  double DatasetRow::*row;
  double compensation::Correction::*correction;
};

/// Every error parameter, indexed by its enum value.
inline constexpr std::array<ErrorSpec, 4> kErrors = {{
    {ErrorParameter::kMpe,
     "MPE",
     "mpe_um",
     "um",
     "mpe",
     &DatasetRow::mpe_um,
     &compensation::Correction::mpe_um},
    {ErrorParameter::kRpe,
     "RPE",
     "rpe_um",
     "um",
     "rpe",
     &DatasetRow::rpe_um,
     &compensation::Correction::rpe_um},
    {ErrorParameter::kMae,
     "MAE",
     "mae_um",
     "um",
     "mae",
     &DatasetRow::mae_um,
     &compensation::Correction::mae_um},
    {ErrorParameter::kRae,
     "RAE",
     "rae_um",
     "um",
     "rae",
     &DatasetRow::rae_um,
     &compensation::Correction::rae_um},
}};

/// Number of error parameters: the outputs of every compensation model.
inline constexpr int kErrorCount = static_cast<int>(kErrors.size());

/// The table entry of `p`.
constexpr const ErrorSpec& spec(ErrorParameter p) noexcept {
  return kErrors[static_cast<std::size_t>(p)];
}

/// The values a dataset cell may hold (docs/dataset-csv.md): wide enough for any CMM, narrow
/// enough that one absurd row (a PV of 1e308) cannot widen a trained model's input range until
/// its out-of-domain flag never fires.
struct DatasetColumnRange {
  double min;
  double max;
  bool min_exclusive;  ///< true: min itself is refused (speeds, distances, accelerations > 0)
};

/// One column of the dataset CSV.
struct DatasetColumn {
  const char* name;  ///< header cell
  double DatasetRow::*field;
  DatasetColumnRange range;
};

namespace detail {
constexpr DatasetColumn column_of(Feature f, DatasetColumnRange r) noexcept {
  return {spec(f).column, spec(f).row, r};
}
constexpr DatasetColumn column_of(ErrorParameter p, DatasetColumnRange r) noexcept {
  return {spec(p).column, spec(p).row, r};
}
}  // namespace detail

/// The dataset CSV's columns in the order they are written, each with its range.
inline constexpr std::array<DatasetColumn, 11> kDatasetColumns = {{
    detail::column_of(Feature::kPv, {0, 2000, true}),
    detail::column_of(Feature::kPd, {0, 10000, true}),
    detail::column_of(Feature::kAv, {0, 2000, true}),
    detail::column_of(Feature::kAd, {0, 10000, true}),
    // PA and AA are move settings, not model inputs (the paper's Table 3 holds them fixed).
    {"pa_mm_s2", &DatasetRow::pa_mm_s2, {0, 50000, true}},
    {"aa_mm_s2", &DatasetRow::aa_mm_s2, {0, 50000, true}},
    detail::column_of(Feature::kY, {-10000, 10000, false}),
    detail::column_of(ErrorParameter::kMpe, {0, 10000, false}),  // a magnitude
    detail::column_of(ErrorParameter::kRpe, {-10000, 10000, false}),
    detail::column_of(ErrorParameter::kMae, {0, 10000, false}),  // a magnitude
    detail::column_of(ErrorParameter::kRae, {-10000, 10000, false}),
}};

namespace detail {
constexpr bool tables_are_indexed_by_enum() noexcept {
  for (std::size_t i = 0; i < kFeatures.size(); ++i) {
    if (static_cast<std::size_t>(kFeatures[i].feature) != i) return false;
  }
  for (std::size_t i = 0; i < kErrors.size(); ++i) {
    if (static_cast<std::size_t>(kErrors[i].parameter) != i) return false;
  }
  return true;
}
/// Every DatasetRow field is one column, and every feature a dataset carries has its column.
constexpr bool dataset_columns_are_complete() noexcept {
  for (std::size_t a = 0; a < kDatasetColumns.size(); ++a) {
    if (kDatasetColumns[a].field == nullptr) return false;
    for (std::size_t b = a + 1; b < kDatasetColumns.size(); ++b) {
      if (kDatasetColumns[a].field == kDatasetColumns[b].field) return false;
    }
  }
  for (const FeatureSpec& f : kFeatures) {
    if (f.row == nullptr) continue;
    bool found = false;
    for (const DatasetColumn& c : kDatasetColumns) found = found || c.field == f.row;
    if (!found) return false;
  }
  return kDatasetColumns.size() * sizeof(double) == sizeof(DatasetRow);
}
}  // namespace detail
static_assert(detail::tables_are_indexed_by_enum(), "kFeatures/kErrors follow their enums");
static_assert(detail::dataset_columns_are_complete(),
              "each DatasetRow field is exactly one column of kDatasetColumns");

/// The inputs of a model, in order: what a compensation model is keyed on. A model file names
/// them (its `inputs[].name` are the features' columns), and the compensator gathers them from
/// each MoveRequest.
template <Feature... kF>
struct InputSet {
  static constexpr int kCount = static_cast<int>(sizeof...(kF));
  static constexpr std::array<Feature, sizeof...(kF)> kOrder{kF...};  ///< the features, in order
  static_assert(kCount > 0, "an input set has at least one feature");

  /// The model's raw inputs for `move`, in this set's order. RT-safe.
  static constexpr std::array<double, sizeof...(kF)> gather(
      const compensation::MoveRequest& move) noexcept {
    return {(move.*(spec(kF).request))...};
  }

  /// The same from a dataset row (training, evaluation). Only for features datasets carry.
  static std::array<double, sizeof...(kF)> gather(const DatasetRow& row) noexcept {
    static_assert(((spec(kF).row != nullptr) && ...),
                  "a feature of this set has no dataset column yet (schema.hpp, kFeatures)");
    return {(row.*(spec(kF).row))...};
  }

  /// The features' labels ("PV", …), dataset columns ("pv_mm_s", …) and units.
  static constexpr std::array<const char*, sizeof...(kF)> labels() noexcept {
    return {spec(kF).label...};
  }
  static constexpr std::array<const char*, sizeof...(kF)> columns() noexcept {
    return {spec(kF).column...};
  }
  static constexpr std::array<const char*, sizeof...(kF)> units() noexcept {
    return {spec(kF).unit...};
  }

 private:
  static constexpr bool distinct() noexcept {
    for (std::size_t a = 0; a < kOrder.size(); ++a) {
      for (std::size_t b = a + 1; b < kOrder.size(); ++b) {
        if (kOrder[a] == kOrder[b]) return false;
      }
    }
    return true;
  }
  static_assert(distinct(), "an input set names each feature once");
};

/// The paper's inputs: PV, PD, AV, AD (81 rules with 3 sets each).
using PaperInputs = InputSet<Feature::kPv, Feature::kPd, Feature::kAv, Feature::kAd>;
/// The paper's inputs and the carriage position Y (243 rules): the dynamic errors grow with Y
/// (the paper's Table 2), which the paper's 4-input model cannot see.
using CarriageInputs =
    InputSet<Feature::kPv, Feature::kPd, Feature::kAv, Feature::kAd, Feature::kY>;

/// A list of input sets (a type, not a value): what a compensator or a model loader serves.
template <typename... Sets>
struct InputSetList {
  static constexpr std::size_t kSize = sizeof...(Sets);
};

/// The input sets the compensator, the model file loader, training and the tools serve, in the
/// order they are tried. Serving a new set is one entry here.
using ServedInputSets = InputSetList<PaperInputs, CarriageInputs>;

/// Calls `f(Set{})` for each set of `list`, in order (InputSet is an empty tag type).
template <typename... Sets, typename F>
constexpr void for_each_input_set(InputSetList<Sets...> /*list*/, F&& f) {
  (f(Sets{}), ...);
}

/// `Template<Sets...>` for `InputSetList<Sets...>`.
template <template <typename...> class Template, typename List>
struct apply_input_sets;
template <template <typename...> class Template, typename... Sets>
struct apply_input_sets<Template, InputSetList<Sets...>> {
  using type = Template<Sets...>;
};

/// The error parameters of a dataset row as model targets, in kErrors order.
inline std::array<double, kErrors.size()> gather_errors(const DatasetRow& row) noexcept {
  std::array<double, kErrors.size()> out{};
  for (std::size_t p = 0; p < kErrors.size(); ++p) out[p] = row.*(kErrors[p].row);
  return out;
}

}  // namespace cmmcomp

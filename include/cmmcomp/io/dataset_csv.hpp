// SPDX-License-Identifier: MIT
/// @file The dataset CSV: one probing move per row, its settings and its four dynamic errors.
///
/// The one schema every tool reads and writes (docs/dataset-csv.md; the columns are defined in
/// schema.hpp): `pv_mm_s,pd_mm,av_mm_s,ad_mm,pa_mm_s2,aa_mm_s2,y_mm,mpe_um,rpe_um,mae_um,rae_um`.
/// Reading accepts the columns in any order and ignores extra columns; blank lines and lines
/// starting with `#` are skipped.
#pragma once

#include <cmmcomp/io/model_file.hpp>
#include <cmmcomp/schema.hpp>
#include <string>
#include <vector>

namespace cmmcomp::io {

/// One dataset row; its columns, their order and ranges are schema.hpp's kDatasetColumns.
using cmmcomp::DatasetColumnRange;
using cmmcomp::DatasetRow;
using cmmcomp::kDatasetColumns;

/// The training conditions a dataset itself states: the range of its PA and of its AA (every
/// other condition unknown). Empty rows: nothing known.
TrainingConditions dataset_conditions(const std::vector<DatasetRow>& rows);

/// Parses CSV text; `source` names it in messages. A UTF-8 byte-order mark before the header
/// is skipped. Throws ConfigError "source:line: column 'name': what is wrong" for a missing
/// column, a non-numeric, NaN or infinite cell, a value outside its column's range, a short row, a
/// last line without its line end (the file may have been cut inside a cell), or a file
/// without data rows.
std::vector<DatasetRow> parse_dataset_csv(const std::string& text, const std::string& source);
/// Reads a file (ConfigError when it cannot be opened, or as parse_dataset_csv).
std::vector<DatasetRow> read_dataset_csv(const std::string& path);
/// CSV text with the header and 10 significant digits. Throws ConfigError for a row the
/// reader would refuse (a value outside its column's range, or not finite), naming row and column.
std::string format_dataset_csv(const std::vector<DatasetRow>& rows);
/// Writes a file atomically (format_dataset_csv, then io::write_file_atomically); throws
/// ConfigError as format_dataset_csv, Error when it cannot write.
void write_dataset_csv(const std::string& path, const std::vector<DatasetRow>& rows);

}  // namespace cmmcomp::io

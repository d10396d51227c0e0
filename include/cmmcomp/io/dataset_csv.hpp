// SPDX-License-Identifier: MIT
/// @file The dataset CSV: one probing move per row, its settings and its four dynamic errors.
///
/// The one schema every tool reads and writes (docs/dataset-csv.md):
/// `pv_mm_s,pd_mm,av_mm_s,ad_mm,pa_mm_s2,aa_mm_s2,y_mm,mpe_um,rpe_um,mae_um,rae_um`.
/// Reading accepts the columns in any order and ignores extra columns; blank lines and lines
/// starting with `#` are skipped.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace cmmcomp::io {

/// One probing move and its measured (or simulated) dynamic errors, in file units.
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

/// Column names, in the order they are written.
inline constexpr std::array<const char*, 11> kDatasetColumns = {"pv_mm_s",
                                                                "pd_mm",
                                                                "av_mm_s",
                                                                "ad_mm",
                                                                "pa_mm_s2",
                                                                "aa_mm_s2",
                                                                "y_mm",
                                                                "mpe_um",
                                                                "rpe_um",
                                                                "mae_um",
                                                                "rae_um"};

/// The values a cell may hold, per column of kDatasetColumns (docs/dataset-csv.md): wide enough
/// for any CMM, narrow enough that one absurd row (a PV of 1e308) cannot widen a trained model's
/// input range until its out-of-domain flag never fires.
struct DatasetColumnRange {
  double min;
  double max;
  bool min_exclusive;  ///< true: min itself is refused (speeds, distances, accelerations > 0)
};
inline constexpr std::array<DatasetColumnRange, 11> kDatasetRanges = {{
    {0, 2000, true},         // pv_mm_s
    {0, 10000, true},        // pd_mm
    {0, 2000, true},         // av_mm_s
    {0, 10000, true},        // ad_mm
    {0, 50000, true},        // pa_mm_s2
    {0, 50000, true},        // aa_mm_s2
    {-10000, 10000, false},  // y_mm
    {0, 10000, false},       // mpe_um (a magnitude)
    {-10000, 10000, false},  // rpe_um
    {0, 10000, false},       // mae_um (a magnitude)
    {-10000, 10000, false},  // rae_um
}};

/// Parses CSV text; `source` names it in messages. A UTF-8 byte-order mark before the header
/// is skipped. Throws ConfigError "source:line: column 'name': what is wrong" for a missing
/// column, a non-numeric, NaN or infinite cell, a value outside kDatasetRanges, a short row, a
/// last line without its line end (the file may have been cut inside a cell), or a file
/// without data rows.
std::vector<DatasetRow> parse_dataset_csv(const std::string& text, const std::string& source);
/// Reads a file (ConfigError when it cannot be opened, or as parse_dataset_csv).
std::vector<DatasetRow> read_dataset_csv(const std::string& path);
/// CSV text with the header and 10 significant digits. Throws ConfigError for a row the
/// reader would refuse (a value outside kDatasetRanges, or not finite), naming row and column.
std::string format_dataset_csv(const std::vector<DatasetRow>& rows);
/// Writes a file atomically (format_dataset_csv, then io::write_file_atomically); throws
/// ConfigError as format_dataset_csv, Error when it cannot write.
void write_dataset_csv(const std::string& path, const std::vector<DatasetRow>& rows);

}  // namespace cmmcomp::io

// SPDX-License-Identifier: MIT
/// @file What the length test reports: the table, JSON, the point log (CSV) and the plots.
#pragma once

#include <cmmcomp/vc/length_test.hpp>
#include <nlohmann/json.hpp>
#include <string>

namespace cmmcomp::vc {

/// The human-readable report: per case, per Y, and the headline.
std::string format_report(const LengthProgram& program, const LengthTestResult& result);

/// The headline sentence alone (also in the report and the JSON).
std::string headline(const LengthTestResult& result);

/// The machine-readable report (docs/recordings.md describes the recordings, this the results:
/// keys are self-describing, units in the names).
nlohmann::json report_json(const LengthProgram& program, const LengthTestResult& result);

/// Every point, one row per point and agent (the reference setting: one row, agent "-").
/// Throws Error when the file cannot be written.
void write_points_csv(const std::string& path, const LengthTestResult& result);

/// PNGs with gnuplot into `dir` (created): length error vs length, one file per Y, with the
/// ±MPE_E envelope. Returns the files written. Throws Error when gnuplot fails.
std::vector<std::string> write_plots(const std::string& dir,
                                     const LengthProgram& program,
                                     const LengthTestResult& result);

/// "0123456789abcdef" (16 hex digits), the agents' model id as the protocol carried it.
std::string model_id_hex(std::uint64_t id);

}  // namespace cmmcomp::vc

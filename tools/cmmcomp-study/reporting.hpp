// SPDX-License-Identifier: MIT
/// @file How every cmmcomp-study experiment reports: its reporting options (the known-unmet list,
/// JSON, the results page and block), its publication on stdout and stderr, and its progress.
#pragma once

#include <CLI/CLI.hpp>
#include <cmmcomp/study/accuracy.hpp>
#include <cmmcomp/study/report.hpp>
#include <vector>

namespace cmmcomp::tools::study {

using Output = cmmcomp::study::ReportOptions;

/// Adds the reporting options of an experiment to `sub`, bound to `out`.
void add_reporting(CLI::App* sub, Output& out);

/// Prints the experiment's publication and returns its exit status.
int finish(const cmmcomp::study::Document& result,
           const std::vector<cmmcomp::study::Target>& targets,
           const Output& out);

/// The experiments' run options: progress lines on stderr when it is a terminal.
cmmcomp::study::RunOptions run_options();

}  // namespace cmmcomp::tools::study

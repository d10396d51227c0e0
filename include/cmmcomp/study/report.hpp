// SPDX-License-Identifier: MIT
/// @file Experiment results as documents, and the results page they render into
/// (docs/results.md, docs/study.md "The results page").
///
/// Contract:
///  - a *document* is the JSON an experiment's result becomes (`*_document`): {"experiment",
///    "block", "command", the experiment's numbers, "targets", "passed", "failures"}. It is what
///    `cmmcomp-study … --json` prints and what `cmmcomp-study render` reads;
///  - render_markdown(doc) renders any document this layer writes: the tool's human output and
///    the page's block are the same text, so the page cannot say what the tool does not;
///  - a page holds a document's rendering between `<!-- study: BLOCK -->` and
///    `<!-- /study: BLOCK -->` lines; splice_block() replaces what is between them and leaves the
///    rest of the page byte for byte. BLOCK is the document's "block" (default: its experiment).
/// Setup-time code; throws ConfigError for a document of unknown experiment, a missing field or
/// a page without the block's markers.
#pragma once

#include <cmmcomp/study/acceptance.hpp>
#include <cmmcomp/study/accuracy.hpp>
#include <cmmcomp/study/calibration.hpp>
#include <cmmcomp/study/cross_machine.hpp>
#include <cmmcomp/study/cycle_speedup.hpp>
#include <cmmcomp/study/identify_multistart.hpp>
#include <cmmcomp/study/interval_calibration.hpp>
#include <cmmcomp/study/interval_coverage.hpp>
#include <cmmcomp/study/qualified_sweep.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace cmmcomp::study {

using Document = nlohmann::ordered_json;

/// The documents of the experiments (file comment); "command" and "block" are left to the
/// caller, the verdict to add_verdict().
Document accuracy_document(const std::vector<AccuracyResult>& results);
Document cell_interpolant_document(const std::vector<CellInterpolantResult>& results);
Document interval_coverage_document(const CoverageResult& result);
Document qualified_sweep_document(const SweepResult& result);
Document cross_machine_document(const CrossMachineResult& result);
Document calibration_document(const CalibrationResult& result);
Document identify_multistart_document(const MultistartResult& result);
Document interval_calibration_document(const IntervalCalibrationResult& result);
Document cycle_speedup_document(const CycleSpeedupResult& result);

/// Adds the targets and check()'s verdict to `doc`.
void add_verdict(Document& doc, const std::vector<Target>& targets, const Verdict& verdict);

/// The Markdown rendering of a document: the command that produced it, its table(s) and its
/// verdict (the failures and the known-unmet targets by name; every target is in the JSON).
std::string render_markdown(const Document& doc);

/// `page` with the block of `doc` (file comment) replaced by render_markdown(doc).
std::string splice_block(const std::string& page, const Document& doc);

/// What sync_page() found: whether the page's block was the document's rendering, and if not,
/// the first line that differs ("page: …" / "now: …").
struct PageSync {
  bool current = true;
  std::string first_difference;
};

/// Compares the block of `doc` in the page file `path` with its rendering; with `update`, writes
/// the page (atomically) when it differs. ConfigError when the page cannot be read or has no
/// block.
PageSync sync_page(const std::string& path, const Document& doc, bool update);

/// The command line that ran an experiment, as a user types it: "cmmcomp-study" and the
/// arguments after the program name, the reporting options (`--json`, `--page P`,
/// `--update-page`) left out, so that checking and writing a block see the same command; an
/// argument with a space quoted.
std::string command_line(int argc, const char* const* argv);

/// How an experiment reports: the command that ran it, JSON or Markdown, the known-unmet list
/// (a path; empty: none) and the results page's block it checks or updates (empty page: none).
struct ReportOptions {
  std::string command, block, known_unmet, page;
  bool json = false, update_page = false;
};

/// What publish() produced: the text for standard output, a note for standard error (empty:
/// none) and the exit status (1 when a target fails or the page's block is stale).
struct Publication {
  std::string text, note;
  int status = 0;
};

/// Judges `targets` against the known-unmet list, adds the verdict to `result` (named by its
/// block), renders it (Markdown or JSON) and checks or updates the page's block.
Publication publish(const Document& result,
                    std::vector<Target> targets,
                    const ReportOptions& options);

}  // namespace cmmcomp::study

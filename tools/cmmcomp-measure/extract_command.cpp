// SPDX-License-Identifier: MIT
/// @file cmmcomp-measure extract: the machine's recordings into the dataset CSV cmmcomp-train
/// reads, with a per-move report and a campaign summary.
#include <cmath>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/measure/campaign.hpp>
#include <cmmcomp/measure/extract.hpp>
#include <cmmcomp/measure/plan.hpp>
#include <cmmcomp/schema.hpp>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "commands.hpp"

namespace cmmcomp::tools::measure {
namespace {

namespace measure = cmmcomp::measure;

struct ExtractCommand {
  std::string plan, recordings, machine_path, output, report, summary, plot;
  measure::ExtractOptions options;
  double offset_ms = 0, drift_ppm = 0;
  double timing_tolerance_ms = 10.0;
};

int run_extract(ExtractCommand cmd) {
  if (!cmd.machine_path.empty()) {
    const cmmcomp::dynamics::Machine m = cmmcomp::dynamics::load_machine(cmd.machine_path);
    for (const std::string& w : cmmcomp::dynamics::implausible_parameters(m.parameters)) {
      std::fprintf(stderr, "warning: %s: %s\n", cmd.machine_path.c_str(), w.c_str());
    }
    if (std::isnan(cmd.options.dwell_s)) cmd.options.dwell_s = m.parameters.controller_dwell_s;
    if (std::isnan(cmd.options.smoothing_s))
      cmd.options.smoothing_s = m.parameters.controller_smoothing_s;
  }
  const std::vector<measure::PlannedMove> plan = measure::read_plan_csv(cmd.plan);
  const measure::CampaignRecordings recordings =
      measure::read_campaign_recordings(plan, cmd.recordings, cmd.options);
  if (!recordings.session_line.empty()) std::printf("%s\n", recordings.session_line.c_str());
  const measure::Extraction ex = measure::extract_moves(plan, recordings.moves, cmd.options);
  const std::vector<cmmcomp::DatasetRow> rows = ex.rows();
  // The report and the summary are written whatever happens next: a refused run is explained.
  const std::string report = cmd.report.empty() ? cmd.output + ".report.csv" : cmd.report;
  const std::string summary = cmd.summary.empty() ? cmd.output + ".summary.json" : cmd.summary;
  cmmcomp::io::write_file_atomically(report, measure::format_extraction_report(ex));
  cmmcomp::io::write_file_atomically(summary, measure::format_extraction_summary(ex));
  if (!cmd.plot.empty()) {
    const std::string script = cmd.plot + ".gp";
    cmmcomp::io::write_file_atomically(script, measure::campaign_plot_script(ex, cmd.plot));
    if (std::system(("gnuplot '" + script + "'").c_str()) != 0) {
      std::fprintf(
          stderr, "warning: gnuplot could not draw %s (is gnuplot installed?)\n", cmd.plot.c_str());
    }
  }
  for (const std::string& w : ex.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  if (!ex.refusal.empty()) {
    std::fprintf(stderr,
                 "cmmcomp-measure: refused: %s\n(per-move report: %s; summary: %s; no dataset "
                 "written)\n",
                 ex.refusal.c_str(),
                 report.c_str(),
                 summary.c_str());
    return 1;
  }
  if (rows.empty()) {
    std::fprintf(stderr,
                 "cmmcomp-measure: %s\n",
                 measure::format_nothing_extracted(ex, report, summary).c_str());
    return 1;
  }
  cmmcomp::io::write_dataset_csv(cmd.output, rows);
  std::printf("%s", measure::format_extraction_outcome(ex, cmd.output, report, summary).c_str());
  return 0;
}

/// The options whose presence counts: --dwell and --smoothing (one given as NaN is a usage
/// error), --clock-offset-ms and --drift-ppm (either given: a known clock).
struct GivenOptions {
  CLI::Option *dwell, *smoothing, *offset, *drift;
};

/// The options the parser could not check, checked (a bad one: exit status 2, after a
/// "cmmcomp-measure extract:" message) and in SI; then the extraction.
int check_and_run(ExtractCommand& ec, const GivenOptions& given) {
  ec.options.known_clock = given.offset->count() > 0 || given.drift->count() > 0;
  ec.options.clock_offset_s = ec.offset_ms * 1e-3;
  ec.options.clock_drift = ec.drift_ppm * 1e-6;
  ec.options.timing_tolerance_s = ec.timing_tolerance_ms * 1e-3;
  try {
    for (const auto& [option, value] : {std::pair{given.dwell, ec.options.dwell_s},
                                        std::pair{given.smoothing, ec.options.smoothing_s}}) {
      if (option->count() > 0 && !std::isfinite(value)) {
        throw cmmcomp::ConfigError(option->get_name() + " " + option->as<std::string>() +
                                   ": not a number of seconds (leave it out to measure it)");
      }
    }
    measure::check_extract_options(ec.options);
  } catch (const cmmcomp::ConfigError& e) {
    std::fprintf(stderr, "cmmcomp-measure extract: %s\n", e.what());
    return 2;
  }
  return run_extract(ec);
}

}  // namespace

Command add_extract(CLI::App& app) {
  auto ec = std::make_shared<ExtractCommand>();
  CLI::App* extract =
      app.add_subcommand("extract", "recordings → the dataset CSV, with a per-move report");
  extract->add_option("--plan", ec->plan, "plan.csv")->required();
  extract->add_option("--recordings", ec->recordings, "directory of move-NNNN*.csv")->required();
  extract->add_option("--machine",
                      ec->machine_path,
                      "machine file whose [controller] dwell and smoothing the moves ran with");
  GivenOptions given{};
  given.dwell =
      extract->add_option("--dwell",
                          ec->options.dwell_s,
                          "controller dwell [s] (default: the machine file's, else measured)");
  given.smoothing =
      extract->add_option("--smoothing",
                          ec->options.smoothing_s,
                          "controller smoothing [s] (default: the machine file's, else measured)");
  extract
      ->add_option("--timing-tolerance-ms",
                   ec->timing_tolerance_ms,
                   "refuse a given dwell or smoothing further than this from the measured [ms]")
      ->capture_default_str();
  extract
      ->add_option("--max-profile-rms",
                   ec->options.max_profile_rms_um,
                   "skip a move whose scale is off its planned profile by more [µm]")
      ->capture_default_str();
  extract
      ->add_option("--max-alignment-residual",
                   ec->options.max_alignment_residual_ms,
                   "skip a move whose clock offset is off the session fit by more [ms]")
      ->capture_default_str();
  extract
      ->add_option("--max-gap",
                   ec->options.max_gap_ms,
                   "skip a move with a longer tracker dropout inside it [ms]")
      ->capture_default_str();
  given.offset = extract->add_option(
      "--clock-offset-ms",
      ec->offset_ms,
      "tracker clock offset known from a sync event [ms]: t_c = (t_t + offset)/(1 - drift)");
  given.drift =
      extract->add_option("--drift-ppm", ec->drift_ppm, "tracker clock drift known with it [ppm]");
  extract->add_flag("--accept-clock-uncertainty",
                    ec->options.accept_clock_uncertainty,
                    "two clocks without a sync: warn instead of refusing when the alignment's "
                    "uncertainty moves a parameter by more than the allowance");
  extract->add_option("-o,--output", ec->output, "dataset CSV")->required();
  extract->add_option("--report", ec->report, "per-move report CSV (default OUTPUT.report.csv)");
  extract->add_option(
      "--summary", ec->summary, "campaign summary JSON (default OUTPUT.summary.json)");
  extract->add_option("--plot", ec->plot, "draw the campaign summary to this PNG (gnuplot)");
  return {extract, [ec, given] { return check_and_run(*ec, given); }};
}

}  // namespace cmmcomp::tools::measure

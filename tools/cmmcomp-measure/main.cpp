// SPDX-License-Identifier: MIT
/// @file cmmcomp-measure: the experiment on a real machine (docs/measurement.md). `plan` writes
/// the designed moves in randomised run order as plan.csv and an I++ DME program; `extract` turns
/// the machine's recordings into the dataset CSV cmmcomp-train reads, with a per-move report.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cmmcomp/doe/levels.hpp>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/measure/campaign.hpp>
#include <cmmcomp/measure/extract.hpp>
#include <cmmcomp/measure/plan.hpp>
#include <cmmcomp/measure/twin_recording.hpp>
#include <cmmcomp/version.hpp>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "../common/usage.hpp"

namespace {

namespace measure = cmmcomp::measure;

/// "a,b,c" → a point.
measure::Vec3 parse_vec3(const std::string& text, const char* option) {
  std::vector<double> v;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t comma = std::min(text.find(',', pos), text.size());
    const std::string cell = text.substr(pos, comma - pos);
    char* end = nullptr;
    const double x = std::strtod(cell.c_str(), &end);
    if (cell.empty() || end != cell.c_str() + cell.size() || !std::isfinite(x)) {
      throw cmmcomp::ConfigError(std::string(option) + " " + text + ": not three numbers a,b,c");
    }
    v.push_back(x);
    pos = comma + 1;
  }
  if (v.size() != 3) throw cmmcomp::ConfigError(std::string(option) + " " + text + ": not a,b,c");
  return {v[0], v[1], v[2]};
}

struct PlanCommand {
  measure::PlanOptions options;
  std::string nominal, normal = "1,0,0", out;
  int holdout = 0;                 ///< moves of a held-out Latin-hypercube campaign (0: none)
  std::uint64_t holdout_seed = 0;  ///< its seed (0: the plan's seed + 1)
};

/// Writes plan.csv and plan.ipp of `options` into `dir`; returns the moves.
std::vector<measure::PlannedMove> write_plan(const measure::PlanOptions& options,
                                             const std::string& dir) {
  std::vector<measure::PlannedMove> moves = measure::plan_experiment(options);
  std::filesystem::create_directories(dir);
  cmmcomp::io::write_file_atomically(dir + "/plan.csv", measure::format_plan_csv(moves));
  cmmcomp::io::write_file_atomically(dir + "/plan.ipp",
                                     measure::format_ipp_program(moves, options));
  return moves;
}

int run_plan(PlanCommand cmd) {
  if (!cmd.nominal.empty()) cmd.options.nominal = parse_vec3(cmd.nominal, "--nominal");
  cmd.options.normal = parse_vec3(cmd.normal, "--normal");
  const std::vector<measure::PlannedMove> moves = write_plan(cmd.options, cmd.out);
  std::printf(
      "planned %zu moves (%s design, %d repeat(s), seed %llu) in randomised run order:\n"
      "  %s/plan.csv  the moves (docs/measurement.md)\n"
      "  %s/plan.ipp  the I++ DME program\n",
      moves.size(),
      cmd.options.design.c_str(),
      cmd.options.repeats,
      static_cast<unsigned long long>(cmd.options.seed),
      cmd.out.c_str(),
      cmd.out.c_str());
  if (cmd.holdout > 0) {
    // The check on the user's machine: moves the model never sees, spread over the same box.
    const measure::PlanOptions held =
        measure::holdout_plan(cmd.options, cmd.holdout, cmd.holdout_seed);
    const std::vector<measure::PlannedMove> check = write_plan(held, cmd.out + "/holdout");
    std::printf(
        "planned %zu held-out moves (lhs design, seed %llu) to %s/holdout: record and extract "
        "them like the training campaign, then cmmcomp-train eval MODEL HOLDOUT.csv --check\n",
        check.size(),
        static_cast<unsigned long long>(held.seed),
        cmd.out.c_str());
  }
  return 0;
}

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

}  // namespace

static int run_tool(int argc, char** argv) {
  CLI::App app{
      "cmmcomp-measure: plan the experiment for a real machine, and extract its "
      "recordings into the four parameters"};
  app.set_version_flag("--version", std::string("cmmcomp ") + CMMCOMP_VERSION_STRING);
  app.require_subcommand(1);

  PlanCommand pc;
  pc.options.levels = cmmcomp::doe::table3_levels_text();
  CLI::App* plan = app.add_subcommand("plan", "the designed moves as plan.csv and an I++ program");
  plan->add_option("--design", pc.options.design, "l18 | l9 | l27 | full | lhs")
      ->check(CLI::IsMember({"l18", "l9", "l27", "full", "lhs"}))
      ->capture_default_str();
  plan->add_option("--repeats", pc.options.repeats, "repeats of every run")->capture_default_str();
  plan->add_option("--samples", pc.options.lhs_samples, "runs of an lhs design")
      ->capture_default_str();
  plan->add_option("--levels", pc.options.levels, "factor levels [mm, mm/s]; y= adds Y")
      ->capture_default_str();
  plan->add_option("--pa", pc.options.fixed.pa_mm_s2, "positioning acceleration [mm/s^2]")
      ->capture_default_str();
  plan->add_option("--aa", pc.options.fixed.aa_mm_s2, "approach acceleration [mm/s^2]")
      ->capture_default_str();
  plan->add_option("--y", pc.options.fixed.y_mm, "carriage Y without y levels [mm]")
      ->capture_default_str();
  plan->add_option("--seed", pc.options.seed, "run order (and lhs) seed")->capture_default_str();
  plan->add_option("--nominal", pc.nominal, "probed point x,y,z [mm] (y: each move's Y)");
  plan->add_option("--normal", pc.normal, "surface normal IJK: ±X, ±Y or ±Z")
      ->capture_default_str();
  plan->add_option("--search", pc.options.search_mm, "I++ PtMeasPar.Search [mm]")
      ->capture_default_str();
  plan->add_option("--retract", pc.options.retract_mm, "I++ PtMeasPar.Retract [mm]")
      ->capture_default_str();
  plan->add_option("-o,--out", pc.out, "output directory")->required();
  plan->add_option("--holdout",
                   pc.holdout,
                   "also plan N held-out Latin-hypercube moves in OUT/holdout (the check of a "
                   "model on this machine)")
      ->check(CLI::Range(0, 100000));
  plan->add_option(
      "--holdout-seed", pc.holdout_seed, "the held-out plan's seed (default SEED + 1)");

  ExtractCommand ec;
  CLI::App* extract =
      app.add_subcommand("extract", "recordings → the dataset CSV, with a per-move report");
  extract->add_option("--plan", ec.plan, "plan.csv")->required();
  extract->add_option("--recordings", ec.recordings, "directory of move-NNNN*.csv")->required();
  extract->add_option("--machine",
                      ec.machine_path,
                      "machine file whose [controller] dwell and smoothing the moves ran with");
  CLI::Option* dwell =
      extract->add_option("--dwell",
                          ec.options.dwell_s,
                          "controller dwell [s] (default: the machine file's, else measured)");
  CLI::Option* smoothing =
      extract->add_option("--smoothing",
                          ec.options.smoothing_s,
                          "controller smoothing [s] (default: the machine file's, else measured)");
  extract
      ->add_option("--timing-tolerance-ms",
                   ec.timing_tolerance_ms,
                   "refuse a given dwell or smoothing further than this from the measured [ms]")
      ->capture_default_str();
  extract
      ->add_option("--max-profile-rms",
                   ec.options.max_profile_rms_um,
                   "skip a move whose scale is off its planned profile by more [µm]")
      ->capture_default_str();
  extract
      ->add_option("--max-alignment-residual",
                   ec.options.max_alignment_residual_ms,
                   "skip a move whose clock offset is off the session fit by more [ms]")
      ->capture_default_str();
  extract
      ->add_option("--max-gap",
                   ec.options.max_gap_ms,
                   "skip a move with a longer tracker dropout inside it [ms]")
      ->capture_default_str();
  CLI::Option* offset = extract->add_option(
      "--clock-offset-ms",
      ec.offset_ms,
      "tracker clock offset known from a sync event [ms]: t_c = (t_t + offset)/(1 - drift)");
  CLI::Option* drift =
      extract->add_option("--drift-ppm", ec.drift_ppm, "tracker clock drift known with it [ppm]");
  extract->add_flag("--accept-clock-uncertainty",
                    ec.options.accept_clock_uncertainty,
                    "two clocks without a sync: warn instead of refusing when the alignment's "
                    "uncertainty moves a parameter by more than the allowance");
  extract->add_option("-o,--output", ec.output, "dataset CSV")->required();
  extract->add_option("--report", ec.report, "per-move report CSV (default OUTPUT.report.csv)");
  extract->add_option(
      "--summary", ec.summary, "campaign summary JSON (default OUTPUT.summary.json)");
  extract->add_option("--plot", ec.plot, "draw the campaign summary to this PNG (gnuplot)");

  try {
    app.parse(argc, argv);
    if (plan->parsed()) return run_plan(pc);
    if (extract->parsed()) {
      ec.options.known_clock = offset->count() > 0 || drift->count() > 0;
      ec.options.clock_offset_s = ec.offset_ms * 1e-3;
      ec.options.clock_drift = ec.drift_ppm * 1e-6;
      ec.options.timing_tolerance_s = ec.timing_tolerance_ms * 1e-3;
      try {
        for (const auto& [option, value] :
             {std::pair{dwell, ec.options.dwell_s}, std::pair{smoothing, ec.options.smoothing_s}}) {
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
  } catch (const CLI::ParseError& e) {
    return cmmcomp::tools::usage_exit(app, e);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cmmcomp-measure: %s\n", e.what());
    return 1;
  }
  return 0;
}

int main(int argc, char** argv) {
  return cmmcomp::tools::guarded_main("cmmcomp-measure", run_tool, argc, argv);
}

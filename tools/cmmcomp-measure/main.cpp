// SPDX-License-Identifier: MIT
/// @file cmmcomp-measure: the experiment on a real machine (docs/measurement.md). `plan` writes
/// the designed moves in randomised run order as plan.csv and an I++ DME program; `extract` turns
/// the machine's recordings into the dataset CSV cmmcomp-train reads, with a per-move report.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cmmcomp/doe/levels.hpp>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/measure/extract.hpp>
#include <cmmcomp/measure/plan.hpp>
#include <cmmcomp/measure/twin_recording.hpp>
#include <cmmcomp/version.hpp>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

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
};

int run_plan(PlanCommand cmd) {
  if (!cmd.nominal.empty()) cmd.options.nominal = parse_vec3(cmd.nominal, "--nominal");
  cmd.options.normal = parse_vec3(cmd.normal, "--normal");
  const std::vector<measure::PlannedMove> moves = measure::plan_experiment(cmd.options);
  std::filesystem::create_directories(cmd.out);
  cmmcomp::io::write_file_atomically(cmd.out + "/plan.csv", measure::format_plan_csv(moves));
  cmmcomp::io::write_file_atomically(cmd.out + "/plan.ipp",
                                     measure::format_ipp_program(moves, cmd.options));
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
  return 0;
}

struct ExtractCommand {
  std::string plan, recordings, machine_path, output, report;
  measure::ExtractOptions options;
  double offset_ms = 0, drift_ppm = 0;
};

int run_extract(ExtractCommand cmd) {
  if (!cmd.machine_path.empty()) {
    const cmmcomp::dynamics::Machine m = cmmcomp::dynamics::load_machine(cmd.machine_path);
    cmd.options.dwell_s = m.parameters.controller_dwell_s;
    cmd.options.smoothing_s = m.parameters.controller_smoothing_s;
  }
  cmd.options.clock_offset_s = cmd.offset_ms * 1e-3;
  cmd.options.clock_drift = cmd.drift_ppm * 1e-6;
  const std::vector<measure::PlannedMove> plan = measure::read_plan_csv(cmd.plan);
  std::vector<measure::MoveRecording> recordings;
  const std::string dir = cmd.recordings + "/";
  const bool session_one = std::filesystem::exists(dir + measure::kSessionFile);
  const bool session_two = std::filesystem::exists(dir + measure::kSessionControllerFile);
  if (session_one || session_two) {
    // One continuous recording of the whole plan: the moves are found in it in run order.
    const measure::SessionRecording session = measure::read_session_recording(
        dir + (session_one ? measure::kSessionFile : measure::kSessionControllerFile),
        session_one ? "" : dir + measure::kSessionTrackerFile,
        plan.front().axis);
    const measure::SessionSplit split = measure::split_session(plan, session, cmd.options);
    recordings = split.moves;
    int found = 0;
    for (const measure::MoveRecording& r : recordings) found += r.problem.empty();
    std::printf(
        "session %s: %d of %zu planned moves found", session.source.c_str(), found, plan.size());
    if (!session.one_clock)
      std::printf(", tracker offset %.1f ms from the speeds", split.coarse_offset_s * 1e3);
    std::printf("\n");
  } else {
    for (const measure::PlannedMove& m : plan) {
      const std::string one = dir + measure::one_clock_file(m.move_id);
      const std::string ctl = dir + measure::controller_file(m.move_id);
      const std::string trk = dir + measure::tracker_file(m.move_id);
      if (std::filesystem::exists(one)) {
        recordings.push_back(measure::read_move_recording(one, "", m.axis, m.move_id));
      } else if (std::filesystem::exists(ctl) && std::filesystem::exists(trk)) {
        recordings.push_back(measure::read_move_recording(ctl, trk, m.axis, m.move_id));
      } else {
        measure::MoveRecording empty;
        empty.move_id = m.move_id;
        empty.problem = "a stream is missing: no " + measure::one_clock_file(m.move_id) +
                        ", or not both " + measure::controller_file(m.move_id) + " and " +
                        measure::tracker_file(m.move_id);
        recordings.push_back(empty);
      }
    }
  }
  const measure::Extraction ex = measure::extract_moves(plan, recordings, cmd.options);
  const std::vector<cmmcomp::DatasetRow> rows = ex.rows();
  if (rows.empty()) throw cmmcomp::Error("no move could be extracted (see the report)");
  const std::string report = cmd.report.empty() ? cmd.output + ".report.csv" : cmd.report;
  cmmcomp::io::write_file_atomically(report, measure::format_extraction_report(ex));
  cmmcomp::io::write_dataset_csv(cmd.output, rows);
  std::printf("extracted %zu of %zu moves to %s; per-move report: %s\n",
              rows.size(),
              ex.moves.size(),
              cmd.output.c_str(),
              report.c_str());
  if (ex.clock.fitted && !cmd.options.known_clock) {
    std::printf("tracker clock: offset %.3f ms, drift %.1f ppm\n",
                ex.clock.offset_s * 1e3,
                ex.clock.drift * 1e6);
  }
  std::map<std::string, int> reasons;
  for (const measure::MoveExtraction& m : ex.moves) {
    if (!m.ok) reasons[m.reason]++;
  }
  for (const auto& [reason, n] : reasons) std::printf("skipped %d: %s\n", n, reason.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
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

  ExtractCommand ec;
  CLI::App* extract =
      app.add_subcommand("extract", "recordings → the dataset CSV, with a per-move report");
  extract->add_option("--plan", ec.plan, "plan.csv")->required();
  extract->add_option("--recordings", ec.recordings, "directory of move-NNNN*.csv")->required();
  extract->add_option("--machine",
                      ec.machine_path,
                      "machine file whose [controller] dwell and smoothing the moves ran with");
  extract->add_option("--dwell", ec.options.dwell_s, "controller dwell [s]")->capture_default_str();
  extract->add_option("--smoothing", ec.options.smoothing_s, "controller smoothing [s]")
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
  extract->add_option("-o,--output", ec.output, "dataset CSV")->required();
  extract->add_option("--report", ec.report, "per-move report CSV (default OUTPUT.report.csv)");

  try {
    app.parse(argc, argv);
    if (plan->parsed()) return run_plan(pc);
    if (extract->parsed()) {
      ec.options.known_clock = offset->count() > 0 || drift->count() > 0;
      return run_extract(ec);
    }
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cmmcomp-measure: %s\n", e.what());
    return 1;
  }
  return 0;
}

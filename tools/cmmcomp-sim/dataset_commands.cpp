// SPDX-License-Identifier: MIT
/// @file cmmcomp-sim dataset (a designed experiment on the twin, to a CSV), record (a measurement
/// campaign on the twin, as recordings) and anova (Table 4 of a dataset CSV).
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmmcomp/doe/dataset_anova.hpp>
#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/doe/levels.hpp>
#include <cmmcomp/dynamics/dataset.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/measure/plan.hpp>
#include <cmmcomp/measure/twin_recording.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <cmmcomp/schema.hpp>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "shared.hpp"

namespace cmmcomp::tools::sim {
namespace {

/// The paper's Table 3 as a --levels value: "pv=40,70,100;pd=40,60,80;av=8,12,16;ad=5,10,15".
struct DatasetCommand {
  std::string design = "l18";
  int repeats = 1;
  int samples = 270;
  std::string levels = cmmcomp::doe::table3_levels_text();
  double pa = cmmcomp::paper::kBaseline.pa_mm_s2, aa = cmmcomp::paper::kBaseline.aa_mm_s2,
         y_mm = cmmcomp::paper::kBaseline.y_mm;
  std::string machine_path, output;
  bool noise = false;
  std::uint64_t seed = 1;
  int threads = 0;
};

cmmcomp::doe::Design design_from(const DatasetCommand& cmd) {
  return cmmcomp::doe::design_from_text(cmd.design, cmd.levels, cmd.samples, cmd.seed);
}

int run_dataset(const DatasetCommand& cmd) {
  using namespace cmmcomp::dynamics;
  const cmmcomp::doe::Design design =
      cmmcomp::doe::replicate(design_from(cmd), std::max(1, cmd.repeats));
  DatasetOptions options;
  options.noise.enabled = cmd.noise;
  options.noise.seed = cmd.seed;
  options.threads = cmd.threads;
  const bool tty = isatty(fileno(stderr)) != 0;
  if (tty) {
    options.progress = [](std::size_t done, std::size_t total) {
      std::fprintf(stderr, "\rsimulating %zu/%zu moves", done, total);
      if (done == total) std::fputc('\n', stderr);
    };
  }
  const std::vector<cmmcomp::DatasetRow> rows =
      simulate_dataset(machine_from(cmd.machine_path),
                       rows_from_design(design, FixedSettings{cmd.pa, cmd.aa, cmd.y_mm}),
                       options);
  cmmcomp::io::write_dataset_csv(cmd.output, rows);
  std::printf("wrote %zu rows (%s design, %d repeat(s), noise %s) to %s\n",
              rows.size(),
              cmd.design.c_str(),
              std::max(1, cmd.repeats),
              cmd.noise ? "on" : "off",
              cmd.output.c_str());
  return 0;
}

struct RecordCommand {
  std::string plan, machine_path, out;
  cmmcomp::measure::RecordingSetup setup;
  double drift_ppm = 0, offset_ms = 0;
  bool session = false;
};

/// A measurement campaign on the twin: every move of plan.csv, recorded as a real set-up would.
int run_record(RecordCommand cmd) {
  namespace measure = cmmcomp::measure;
  cmd.setup.drift = cmd.drift_ppm * 1e-6;
  cmd.setup.clock_offset_s = cmd.offset_ms * 1e-3;
  const std::vector<measure::PlannedMove> plan = measure::read_plan_csv(cmd.plan);
  const std::vector<measure::TwinMove> moves =
      measure::record_on_twin(machine_from(cmd.machine_path), plan, cmd.setup);
  std::filesystem::create_directories(cmd.out);
  std::string exact = "move_id,mpe_um,rpe_um,mae_um,rae_um\n";
  if (cmd.session) {
    measure::write_session_recording(cmd.out, measure::as_session(moves), plan.front().axis);
  }
  for (std::size_t i = 0; i < moves.size(); ++i) {
    if (!cmd.session) measure::write_move_recording(cmd.out, moves[i].recording, plan[i].axis);
    const auto& e = moves[i].exact_um;
    exact += fmt::format(
        "{},{:.6f},{:.6f},{:.6f},{:.6f}\n", plan[i].move_id, e.mpe, e.rpe, e.mae, e.rae);
  }
  cmmcomp::io::write_file_atomically(cmd.out + "/twin-exact.csv", exact);
  std::printf("recorded %zu moves (%s) to %s; the twin's exact parameters: %s/twin-exact.csv\n",
              moves.size(),
              cmd.setup.two_clocks ? "controller + tracker files" : "one clock",
              cmd.out.c_str(),
              cmd.out.c_str());
  return 0;
}

struct AnovaCommand {
  std::string path;
  bool json = false;
};

int run_anova(const AnovaCommand& cmd) {
  const cmmcomp::doe::DatasetAnova a =
      cmmcomp::doe::anova_of_dataset(cmmcomp::io::read_dataset_csv(cmd.path));
  std::printf("%s%s",
              cmd.json ? cmmcomp::doe::format_dataset_anova_json(a).c_str()
                       : cmmcomp::doe::format_dataset_anova(a, cmd.path).c_str(),
              cmd.json ? "\n" : "");
  return 0;
}

}  // namespace

Command add_dataset(CLI::App& app) {
  auto ds = std::make_shared<DatasetCommand>();
  CLI::App* dataset = app.add_subcommand("dataset", "simulate a designed experiment to a CSV");
  dataset->add_option("--design", ds->design, "l18 | l9 | l27 | full | lhs")
      ->check(CLI::IsMember({"l18", "l9", "l27", "full", "lhs"}))
      ->capture_default_str();
  dataset->add_option("--repeats", ds->repeats, "repeats of every run")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  dataset->add_option("--samples", ds->samples, "samples of an lhs design")
      ->check(CLI::Range(1, 10000000))
      ->capture_default_str();
  dataset
      ->add_option("--levels",
                   ds->levels,
                   "factor levels [mm, mm/s] (lhs: min and max); add ';y=0,250,500' to vary "
                   "the carriage position (then --y is not used)")
      ->capture_default_str();
  dataset->add_option("--pa", ds->pa, "positioning acceleration [mm/s^2]")->capture_default_str();
  dataset->add_option("--aa", ds->aa, "approach acceleration [mm/s^2]")->capture_default_str();
  dataset->add_option("--y", ds->y_mm, "carriage position [mm]")->capture_default_str();
  dataset->add_option("--machine", ds->machine_path, "machine file (default: embedded)");
  dataset->add_flag("--noise", ds->noise, "add Table 1 measurement noise");
  dataset->add_option("--seed", ds->seed, "noise and lhs seed")->capture_default_str();
  dataset->add_option("--threads", ds->threads, "worker threads (0 = all cores)")
      ->check(CLI::Range(0, 1024));
  dataset->add_option("-o,--output", ds->output, "output CSV")->required();
  return {dataset, [ds] { return run_dataset(*ds); }};
}

Command add_record(CLI::App& app) {
  auto rec = std::make_shared<RecordCommand>();
  CLI::App* record = app.add_subcommand(
      "record", "simulate a measurement campaign: every move of a plan.csv as recordings");
  record->add_option("--plan", rec->plan, "plan.csv (cmmcomp-measure plan)")->required();
  record->add_option("-o,--out", rec->out, "directory for the recordings")->required();
  record->add_option("--machine", rec->machine_path, "machine file (default: embedded)");
  record->add_flag(
      "--two-clocks", rec->setup.two_clocks, "controller and tracker files on independent clocks");
  record->add_flag("--sync",
                   rec->setup.sync,
                   "a sync marker row in both streams at one trigger per move (with --two-clocks; "
                   "docs/measurement.md, \"Sync\")");
  record->add_option("--controller-rate", rec->setup.controller_rate_hz, "scale log rate [Hz]")
      ->capture_default_str();
  record->add_option("--tracker-rate", rec->setup.tracker_rate_hz, "tracker rate [Hz]")
      ->capture_default_str();
  record->add_option("--clock-offset-ms", rec->offset_ms, "tracker clock offset [ms]")
      ->capture_default_str();
  record->add_option("--drift-ppm", rec->drift_ppm, "tracker clock drift [ppm]")
      ->capture_default_str();
  record->add_option("--white-noise-um", rec->setup.white_noise_um, "tracker white noise σ [µm]")
      ->capture_default_str();
  record->add_option("--pink-noise-um", rec->setup.pink_noise_um, "tracker 1/f noise σ [µm]")
      ->capture_default_str();
  record->add_option("--dropouts", rec->setup.dropout_fraction, "share of tracker samples lost")
      ->capture_default_str();
  record
      ->add_option("--tracker-jitter",
                   rec->setup.tracker_jitter,
                   "uneven tracker sampling: each sample off its even grid by up to this share of "
                   "the period (0-0.45, with --two-clocks)")
      ->capture_default_str();
  record->add_option("--seed", rec->setup.seed, "noise seed")->capture_default_str();
  record->add_flag("--session",
                   rec->session,
                   "one continuous recording of the whole plan (session*.csv), not one per move");
  return {record, [rec] { return run_record(*rec); }};
}

Command add_anova(CLI::App& app) {
  auto cmd = std::make_shared<AnovaCommand>();
  CLI::App* anova = app.add_subcommand("anova", "Table 4 ANOVA of a dataset CSV");
  anova->add_option("data", cmd->path, "dataset CSV")->required();
  anova->add_flag("--json", cmd->json, "print JSON");
  return {anova, [cmd] { return run_anova(*cmd); }};
}

}  // namespace cmmcomp::tools::sim

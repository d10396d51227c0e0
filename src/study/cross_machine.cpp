// SPDX-License-Identifier: MIT
/// @file The real-machine workflow on several twins (cross_machine.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/measure/extract.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <cmmcomp/study/cross_machine.hpp>
#include <cmmcomp/study/train.hpp>
#include <cstdlib>
#include <filesystem>

namespace cmmcomp::study {

namespace {

/// The recipe that stands for one machine's campaign: its machine, Table 1 noise on the test
/// moves, the paper's four inputs, the fit's seed.
Recipe campaign_recipe(const StudyMachine& m, const CampaignSetup& setup) {
  Recipe r;
  r.name = m.name;
  r.source = m.path;
  r.machine = m.path;
  r.noise = true;
  r.test = setup.test;
  r.test_seeds = {setup.test.seed};
  r.fit.seed = setup.fit_seed;
  return r;
}

}  // namespace

CampaignSetup::CampaignSetup() {
  recording.two_clocks = true;
  recording.clock_offset_s = 37e-3;
  recording.drift = 100e-6;
  recording.controller_rate_hz = 1000;
  recording.tracker_rate_hz = 2000;
  recording.white_noise_um = 0.3;
  recording.pink_noise_um = 0.2;
  recording.seed = 1;
}

CrossMachineResult cross_machine(const std::vector<StudyMachine>& machines,
                                 const io::CompensationModelFile& shipped,
                                 const CampaignSetup& setup,
                                 const std::string& work,
                                 const RunOptions& options) {
  if (machines.empty()) throw ConfigError("cross-machine: no machine");
  // Without a work folder, a temporary one that is removed afterwards.
  std::string work_dir = work;
  if (work_dir.empty()) {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "cmmcomp-cross-machine-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) {
      throw Error("cannot create a temporary folder in " +
                  std::filesystem::temp_directory_path().string());
    }
    work_dir = pattern;
  }
  struct Remove {
    bool on;
    std::string dir;
    ~Remove() {
      std::error_code ec;
      if (on) std::filesystem::remove_all(dir, ec);
    }
  } remove{work.empty(), work_dir};
  CrossMachineResult out;
  out.shipped_model_id = io::model_id(shipped);
  std::string design = setup.plan.design;
  for (char& c : design) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  out.plan = design == "LHS" ? fmt::format("LHS {}", setup.plan.lhs_samples)
                             : fmt::format("{} × {}", design, setup.plan.repeats);
  const auto say = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  for (const StudyMachine& m : machines) {
    const std::string dir = work_dir + "/" + m.name;
    std::filesystem::create_directories(dir + "/rec");
    const Recipe recipe = campaign_recipe(m, setup);
    const dynamics::Machine machine = recipe_machine(recipe);
    // The plan as the user's files carry it: written and read back.
    const std::string plan_csv = dir + "/plan.csv";
    io::write_file_atomically(plan_csv,
                              measure::format_plan_csv(measure::plan_experiment(setup.plan)));
    const std::vector<measure::PlannedMove> plan = measure::read_plan_csv(plan_csv);
    say(fmt::format("{}: recording {} moves", m.name, plan.size()));
    const std::vector<measure::TwinMove> moves =
        measure::record_on_twin(machine, plan, setup.recording);
    for (std::size_t i = 0; i < moves.size(); ++i) {
      measure::write_move_recording(dir + "/rec", moves[i].recording, plan[i].axis);
    }
    std::vector<measure::MoveRecording> recordings;
    recordings.reserve(plan.size());
    for (const measure::PlannedMove& p : plan) {
      recordings.push_back(measure::read_planned_recording(dir + "/rec", p));
    }
    measure::ExtractOptions extract;
    extract.dwell_s = machine.parameters.controller_dwell_s;
    extract.smoothing_s = machine.parameters.controller_smoothing_s;
    extract.known_clock = true;  // from a sync event (docs/measurement.md, "Clock alignment")
    extract.clock_offset_s = setup.recording.clock_offset_s;
    extract.clock_drift = setup.recording.drift;
    const measure::Extraction ex = measure::extract_moves(plan, recordings, extract);
    const std::string dataset = dir + "/dataset.csv";
    io::write_dataset_csv(dataset, ex.rows());
    const std::vector<DatasetRow> rows = io::read_dataset_csv(dataset);
    say(fmt::format("{}: extracted {} of {} moves, training", m.name, rows.size(), plan.size()));
    const TrainedModel own = train_model(recipe, rows);
    const std::vector<DatasetRow> test =
        simulate_part(recipe, machine, setup.test, options.threads);
    CrossMachineRow row;
    row.machine = m.name;
    row.planned = plan.size();
    row.extracted = rows.size();
    row.own = evaluate_model_file(own.file, test, m.name + " own");
    row.shipped = evaluate_model_file(shipped, test, m.name + " shipped");
    for (std::size_t p = 0; p < kErrorCount; ++p) {
      out.targets.push_back({m.name + ": own " + kErrors[p].key + "_reduction",
                             row.own.table[p].reduction_pct,
                             paper::kTable5Reduction[p],
                             Target::Kind::kAtLeast,
                             "%"});
    }
    if (m.dynamics_differ) {
      // The largest ratio shipped / own mean residual over the parameters whose own residual is
      // a positive number (a zero residual has no ratio).
      double worst = 0;
      for (std::size_t p = 0; p < kErrorCount; ++p) {
        const double own_um = row.own.table[p].mean_after;
        const double ratio = row.shipped.table[p].mean_after / own_um;
        if (own_um > 0 && std::isfinite(ratio)) worst = std::max(worst, ratio);
      }
      out.targets.push_back(
          {m.name + ": shipped model loses", worst, 1.5, Target::Kind::kAtLeast, "x"});
    }
    out.rows.push_back(std::move(row));
  }
  return out;
}

void parse_campaign_plan(const std::string& text, CampaignSetup& setup) {
  // "l18x3" or "lhsN": N digits, 1 to 999999 moves (no std::regex: GCC's maybe-uninitialized).
  const std::string digits = text.rfind("lhs", 0) == 0 ? text.substr(3) : std::string();
  const bool lhs = !digits.empty() && digits.size() <= 6 &&
                   digits.find_first_not_of("0123456789") == std::string::npos &&
                   std::stoi(digits) > 0;
  if (lhs) {
    setup.plan.design = "lhs";
    setup.plan.lhs_samples = std::stoi(digits);
    setup.plan.repeats = 1;
  } else if (text != "l18x3") {
    throw ConfigError("--plan takes l18x3 or lhsN (N moves, 1 to 999999), not '" + text + "'");
  }
}

std::vector<StudyMachine> study_machines(const std::vector<std::string>& paths,
                                         const std::vector<std::string>& differ) {
  std::vector<StudyMachine> list;
  list.reserve(paths.size());
  for (const std::string& m : paths) {
    StudyMachine sm;
    sm.path = m;
    sm.name = m == "default" ? m : std::filesystem::path(m).stem().string();
    sm.dynamics_differ = std::find(differ.begin(), differ.end(), sm.name) != differ.end();
    list.push_back(sm);
  }
  for (const std::string& d : differ) {
    if (std::none_of(
            list.begin(), list.end(), [&](const StudyMachine& m) { return m.name == d; })) {
      throw ConfigError("--dynamics-differ " + d + ": no --machine of that name");
    }
  }
  return list;
}

}  // namespace cmmcomp::study

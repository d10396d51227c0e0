// SPDX-License-Identifier: MIT
/// @file The real-machine workflow on several twins, as a user runs it on a machine
/// (docs/training.md, "Other machines"; docs/study.md).
///
/// For each machine: the plan (measure::plan_experiment, written and read back as plan.csv) →
/// the campaign recorded on the twin (two clocks 37 ms apart with 100 ppm drift, a 2 kHz tracker
/// with 0.3 µm white and 0.2 µm 1/f noise; the files written to the work folder and read back) →
/// extraction with the clock known from a sync event and the machine's controller timing → the
/// dataset CSV → the network trained as `cmmcomp-train fit --seed 1` trains it → tested on 270
/// Latin-hypercube moves of that machine (Table 1 noise, seed 2), next to the shipped model on
/// the same moves.
/// Targets: on every machine the own model meets the paper's Table 5 reductions; on a machine
/// marked `dynamics_differ` the shipped model is measurably worse (a mean residual ≥ 1.5 × the
/// own model's in some parameter). Setup-time code: writes files, simulates, trains; throws
/// ConfigError or Error.
#pragma once

#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/measure/plan.hpp>
#include <cmmcomp/measure/twin_recording.hpp>
#include <cmmcomp/study/acceptance.hpp>
#include <cmmcomp/study/accuracy.hpp>
#include <cmmcomp/study/recipe.hpp>
#include <string>
#include <vector>

namespace cmmcomp::study {

/// One machine of the study.
struct StudyMachine {
  std::string name;              ///< "default", or a machine file's stem
  std::string path = "default";  ///< "default" (embedded) or the machine file
  bool dynamics_differ = false;  ///< the shipped model must lose here (a mode, a drag changed)
};

/// How each campaign runs (the defaults: the file comment).
struct CampaignSetup {
  measure::PlanOptions plan;           ///< L18 × 3, run order seed 1
  measure::RecordingSetup recording;   ///< two clocks, the tracker and its noise, seed 1
  DatasetPart test{"lhs", 1, 270, 2};  ///< the held-out moves
  std::uint64_t fit_seed = 1;
  CampaignSetup();
};

struct CrossMachineRow {
  std::string machine;
  std::size_t planned = 0, extracted = 0;
  training::TestSetEvaluation own, shipped;
};

struct CrossMachineResult {
  std::string shipped_model_id;
  std::string plan;  ///< "L18 × 3" or "LHS N"
  std::vector<CrossMachineRow> rows;
  std::vector<Target> targets;  ///< "MACHINE: own mpe_reduction", "MACHINE: shipped model loses"
};

/// Runs the workflow (file comment) on each machine, its files under `work_dir/NAME/` (empty: a
/// temporary folder, removed afterwards).
CrossMachineResult cross_machine(const std::vector<StudyMachine>& machines,
                                 const io::CompensationModelFile& shipped,
                                 const CampaignSetup& setup,
                                 const std::string& work_dir,
                                 const RunOptions& options = {});

/// "l18x3" (the default: L18 × 3) or "lhsN" (N Latin-hypercube moves, 1 to 999999, one
/// repeat) into `setup.plan`. ConfigError naming the text otherwise.
void parse_campaign_plan(const std::string& text, CampaignSetup& setup);

/// The machines at `paths` ("default": the embedded one), each named by its file's stem;
/// `differ` names those whose dynamics differ from the shipped model's machine. ConfigError for
/// a name in `differ` that is no machine's.
std::vector<StudyMachine> study_machines(const std::vector<std::string>& paths,
                                         const std::vector<std::string>& differ);

}  // namespace cmmcomp::study

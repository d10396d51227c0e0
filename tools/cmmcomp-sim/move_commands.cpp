// SPDX-License-Identifier: MIT
/// @file cmmcomp-sim profile (plan a probing move, print its instants) and move (simulate one on
/// the digital twin, print MPE RPE MAE RAE).
#include <cmmcomp/dynamics/bridge_model.hpp>
#include <cmmcomp/dynamics/noise.hpp>
#include <cmmcomp/dynamics/trace_csv.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/io/profile_report.hpp>
#include <cmmcomp/motion/move_profile.hpp>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "commands.hpp"
#include "shared.hpp"

namespace cmmcomp::tools::sim {
namespace {

struct ProfileCommand {
  MoveFlags flags;
  std::string csv_path;
  int samples = 201;
};

int run_profile(const ProfileCommand& cmd) {
  cmmcomp::motion::MoveProfile profile;
  const cmmcomp::Status st = cmmcomp::motion::MoveProfile::plan(cmd.flags.to_move(), profile);
  if (!cmmcomp::ok(st)) {
    std::fprintf(stderr,
                 "cmmcomp-sim: cannot plan this move: %s (all values must be positive and "
                 "finite; distances 0.001..10000 mm, speeds 0.01..10000 mm/s)\n",
                 cmmcomp::to_string(st));
    return 1;
  }
  std::fputs(cmmcomp::io::describe_profile(profile).c_str(), stdout);
  if (!cmd.csv_path.empty()) {
    try {
      cmmcomp::io::write_file_atomically(cmd.csv_path,
                                         cmmcomp::io::profile_csv(profile, cmd.samples));
    } catch (const cmmcomp::Error& e) {
      std::fprintf(stderr, "cmmcomp-sim: %s\n", e.what());
      return 1;
    }
    std::printf("wrote %s\n", cmd.csv_path.c_str());
  }
  return 0;
}

struct MoveCommand {
  MoveFlags move;
  double y_mm = 250;
  std::string machine_path, trace_path;
  bool noise = false, json = false;
  std::uint64_t seed = 1;
  bool cvode = false;
  /// The cycle's controller timing [s]; unset: the machine's [controller] setting.
  std::optional<double> dwell_s, smoothing_s;
};

int run_move(const MoveCommand& cmd) {
  using namespace cmmcomp::dynamics;
  SimulationOptions options;
  options.record_trace = !cmd.trace_path.empty();
  if (cmd.cvode) options.integration = Integration::kCvode;
  BridgeSimulator sim(machine_from(cmd.machine_path), options);
  cmmcomp::motion::ProbingMove cycle =
      controlled_move(sim.machine().parameters, cmd.move.to_move());
  if (cmd.dwell_s) cycle.dwell = *cmd.dwell_s;
  if (cmd.smoothing_s) cycle.smoothing = *cmd.smoothing_s;
  const SimulationResult r = sim.simulate_cycle(cycle, cmd.y_mm * kMm);
  MeasurementNoise noise;
  noise.enabled = cmd.noise;
  noise.seed = cmd.seed;
  const cmmcomp::errors::DynamicErrors e = add_noise(r.errors_um, noise, 0);
  if (cmd.json) {
    std::printf("%s\n", format_move_json(e).c_str());
  } else {
    std::printf("%s", format_move_report(sim.machine(), r, e, cmd.cvode).c_str());
  }
  if (!cmd.trace_path.empty()) {
    const std::string csv = cmmcomp::dynamics::format_trace_csv(r.trace);
    cmmcomp::io::write_file_atomically(cmd.trace_path, csv);
  }
  return 0;
}

}  // namespace

Command add_profile(CLI::App& app) {
  auto cmd = std::make_shared<ProfileCommand>();
  CLI::App* profile = app.add_subcommand("profile", "plan a probing move; print its instants");
  cmd->flags.add_to(*profile);
  profile->add_option("--csv", cmd->csv_path, "write the sampled profile to this CSV file");
  profile->add_option("--samples", cmd->samples, "samples in the CSV")
      ->check(CLI::Range(2, 10000000))
      ->capture_default_str();
  return {profile, [cmd] { return run_profile(*cmd); }};
}

Command add_move(CLI::App& app) {
  auto cmd = std::make_shared<MoveCommand>();
  CLI::App* move = app.add_subcommand("move", "simulate one probing move; print MPE RPE MAE RAE");
  cmd->move.add_to(*move);
  move->add_option("--y", cmd->y_mm, "carriage position along the beam [mm]")
      ->capture_default_str();
  move->add_option("--machine", cmd->machine_path, "machine file (default: embedded)");
  move->add_flag("--noise", cmd->noise, "add Table 1 measurement noise");
  move->add_option("--seed", cmd->seed, "noise seed")->capture_default_str();
  move->add_option("--trace", cmd->trace_path, "write the simulated trace to this CSV");
  move->add_flag("--json", cmd->json, "print one JSON object");
  move->add_option("--dwell",
                   cmd->dwell_s,
                   "settling dwell before the approach [s] (default: the machine's; within its "
                   "[capabilities])")
      ->check(finite_number() & CLI::Range(0.0, motion::MoveLimits::kMaxDwell));
  move->add_option("--smoothing",
                   cmd->smoothing_s,
                   "command smoothing [s] (default: the machine's; within its [capabilities])")
      ->check(finite_number() & CLI::Range(0.0, motion::MoveLimits::kMaxSmoothing));
  move->add_flag("--cvode",
                 cmd->cvode,
                 "integrate with SUNDIALS CVODE (the reference) instead of the exponential "
                 "integrator");
  return {move, [cmd] { return run_move(*cmd); }};
}

}  // namespace cmmcomp::tools::sim

// SPDX-License-Identifier: MIT
/// @file cmmcomp-measure plan: the designed moves in randomised run order as plan.csv and an I++
/// DME program (and, with --holdout, a held-out campaign next to them).
#include <algorithm>
#include <cmath>
#include <cmmcomp/doe/levels.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/measure/campaign.hpp>
#include <cmmcomp/measure/plan.hpp>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"

namespace cmmcomp::tools::measure {
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

}  // namespace

Command add_plan(CLI::App& app) {
  auto pc = std::make_shared<PlanCommand>();
  pc->options.levels = cmmcomp::doe::table3_levels_text();
  CLI::App* plan = app.add_subcommand("plan", "the designed moves as plan.csv and an I++ program");
  plan->add_option("--design", pc->options.design, "l18 | l9 | l27 | full | lhs")
      ->check(CLI::IsMember({"l18", "l9", "l27", "full", "lhs"}))
      ->capture_default_str();
  plan->add_option("--repeats", pc->options.repeats, "repeats of every run")->capture_default_str();
  plan->add_option("--samples", pc->options.lhs_samples, "runs of an lhs design")
      ->capture_default_str();
  plan->add_option("--levels", pc->options.levels, "factor levels [mm, mm/s]; y= adds Y")
      ->capture_default_str();
  plan->add_option("--pa", pc->options.fixed.pa_mm_s2, "positioning acceleration [mm/s^2]")
      ->capture_default_str();
  plan->add_option("--aa", pc->options.fixed.aa_mm_s2, "approach acceleration [mm/s^2]")
      ->capture_default_str();
  plan->add_option("--y", pc->options.fixed.y_mm, "carriage Y without y levels [mm]")
      ->capture_default_str();
  plan->add_option("--seed", pc->options.seed, "run order (and lhs) seed")->capture_default_str();
  plan->add_option("--nominal", pc->nominal, "probed point x,y,z [mm] (y: each move's Y)");
  plan->add_option("--normal", pc->normal, "surface normal IJK: ±X, ±Y or ±Z")
      ->capture_default_str();
  plan->add_option("--search", pc->options.search_mm, "I++ PtMeasPar.Search [mm]")
      ->capture_default_str();
  plan->add_option("--retract", pc->options.retract_mm, "I++ PtMeasPar.Retract [mm]")
      ->capture_default_str();
  plan->add_option("-o,--out", pc->out, "output directory")->required();
  plan->add_option("--holdout",
                   pc->holdout,
                   "also plan N held-out Latin-hypercube moves in OUT/holdout (the check of a "
                   "model on this machine)")
      ->check(CLI::Range(0, 100000));
  plan->add_option(
      "--holdout-seed", pc->holdout_seed, "the held-out plan's seed (default SEED + 1)");
  return {plan, [pc] { return run_plan(*pc); }};
}

}  // namespace cmmcomp::tools::measure

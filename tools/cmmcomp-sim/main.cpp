// SPDX-License-Identifier: MIT
/// @file cmmcomp-sim: plan probing moves (and, with the digital twin, simulate them).
#include <CLI/CLI.hpp>
#include <cmmcomp/io/profile_report.hpp>
#include <cmmcomp/motion/move_profile.hpp>
#include <cmmcomp/version.hpp>
#include <cstdio>
#include <exception>
#include <fstream>
#include <string>

namespace {

constexpr double kMm = 1e-3;  // mm -> m

/// Move flags in the paper's units (mm, mm/s, mm/s^2), defaults = the paper's baseline.
struct MoveFlags {
  double pv = 40, pa = 200, pd = 40, av = 12, aa = 60, ad = 10, jerk = 0;

  void add_to(CLI::App& app) {
    app.add_option("--pv", pv, "positioning speed PV [mm/s]")->capture_default_str();
    app.add_option("--pa", pa, "positioning acceleration PA [mm/s^2]")->capture_default_str();
    app.add_option("--pd", pd, "positioning distance PD [mm]")->capture_default_str();
    app.add_option("--av", av, "approach speed AV [mm/s]")->capture_default_str();
    app.add_option("--aa", aa, "approach acceleration AA [mm/s^2]")->capture_default_str();
    app.add_option("--ad", ad, "approach distance AD [mm]")->capture_default_str();
    app.add_option("--jerk", jerk, "jerk limit [mm/s^3]; 0 = trapezoidal")->capture_default_str();
  }
  cmmcomp::motion::ProbingMove to_move() const {
    return {pv * kMm, pa * kMm, pd * kMm, av * kMm, aa * kMm, ad * kMm, jerk * kMm};
  }
};

int run_profile(const MoveFlags& flags, const std::string& csv_path, int samples) {
  cmmcomp::motion::MoveProfile profile;
  const cmmcomp::Status st = cmmcomp::motion::MoveProfile::plan(flags.to_move(), profile);
  if (!cmmcomp::ok(st)) {
    std::fprintf(stderr,
                 "cmmcomp-sim: cannot plan this move: %s (all values must be positive and "
                 "finite; distances 0.001..10000 mm, speeds 0.01..10000 mm/s)\n",
                 cmmcomp::to_string(st));
    return 1;
  }
  std::fputs(cmmcomp::io::describe_profile(profile).c_str(), stdout);
  if (!csv_path.empty()) {
    std::ofstream out(csv_path);
    out << cmmcomp::io::profile_csv(profile, samples);
    if (!out) {
      std::fprintf(stderr, "cmmcomp-sim: cannot write %s\n", csv_path.c_str());
      return 1;
    }
    std::printf("wrote %s\n", csv_path.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"cmmcomp-sim: probing-move profiles and the CMM digital twin"};
  app.set_version_flag("--version", std::string("cmmcomp ") + CMMCOMP_VERSION_STRING);
  app.require_subcommand(1);

  MoveFlags profile_flags;
  std::string csv_path;
  int samples = 201;
  CLI::App* profile = app.add_subcommand("profile", "plan a probing move; print its instants");
  profile_flags.add_to(*profile);
  profile->add_option("--csv", csv_path, "write the sampled profile to this CSV file");
  profile->add_option("--samples", samples, "samples in the CSV")
      ->check(CLI::Range(2, 10000000))
      ->capture_default_str();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (profile->parsed()) return run_profile(profile_flags, csv_path, samples);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cmmcomp-sim: %s\n", e.what());
    return 1;
  }
  return 0;
}

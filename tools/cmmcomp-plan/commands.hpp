// SPDX-License-Identifier: MIT
/// @file cmmcomp-plan's one command: its options (options.cpp) and the planning they run
/// (run.cpp), wired by main.cpp through tools/common/command.hpp.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "../common/command.hpp"

namespace cmmcomp::tools::plan {

/// The command line of cmmcomp-plan (its --help says what each option means).
struct Options {
  std::string model;
  std::vector<std::string> model_at;  // Y=PATH, a model per Y
  double budget_um = 0.0;
  std::string mpe_e = "1.9,300";
  double length_mm = 20.0;
  double share = 0.5;
  double mae_limit_um = 25.0;
  std::string pv = "0:1e9";
  std::string av = "0:1e9";
  std::string pa = "0:1e9";
  std::string aa = "0:1e9";
  std::string pd = "0:1e9";
  std::string ad = "0:1e9";
  std::string y = "250";
  double z_mm = 0.0;
  std::string machine;
  int grid = 11;
  double edge_margin = 0.0;
  int brute_force = 0;
  double trained_pa = 200.0;
  double trained_aa = 60.0;
  bool trained_pa_given = false, trained_aa_given = false;
  double coverage = 0.95;
  std::string vc_settings;
  bool json = false;
  std::string reversal_map;  // Y=UM,…: the qualified reference's map (cmmcomp-vc --qualify)
  double sphere_y_mm = 250.0;
};

/// Declares the options on the tool's app; the Command plans with them.
Command add_options(CLI::App& app);

/// Plans the fastest settings with and without the model's correction and prints them; 0 when
/// a compensated setting was found, 1 otherwise. `y_given`: --y was given (else the per-Y
/// models' Y). Throws ConfigError for a bad option or file.
int run(const Options& opt, bool y_given);

}  // namespace cmmcomp::tools::plan

// SPDX-License-Identifier: MIT
/// @file cmmcomp-vc's one command: its options (options.cpp) and the length test they run
/// (run.cpp), wired by main.cpp through tools/common/command.hpp.
#pragma once

#include <CLI/CLI.hpp>
#include <cmmcomp/plugins/can_server.hpp>
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

#include "../common/command.hpp"

namespace cmmcomp::tools::vc {

/// The command line of cmmcomp-vc (its --help says what each option means).
struct Options {
  std::string modbus;
  int modbus_unit = 1;
  std::string can;
  std::string can_base_id =
      cmmcomp::plugins::format_can_base_id(cmmcomp::plugins::can::kDefaultBaseId);
  std::vector<std::string> agents;
  std::string lengths = "20,50,100,200,400";
  std::string y = "0,250,500";
  int repeats = 3;
  double x0_mm = 100;
  std::string fast;
  std::string slow;
  std::uint64_t seed = 1;
  bool no_noise = false;
  std::string machine;
  std::string ipp;
  bool ipp_proxied = false;  ///< --ipp is a compensating proxy: its corrections are an agent
  std::string csv;
  bool json = false;
  std::string plot;
  std::string record;
  int timeout_ms = 2000;
  bool qualify = false;
  bool map_only = false;
  double sphere_y_mm = 250;
  int qualify_touches = 10;
  std::string map_setting;
};

/// Declares the options on the tool's app; the Command runs the test they describe.
Command add_options(CLI::App& app);

/// Runs the length test (or, with --map-only, the reversal map) against the agents; 0 when
/// every agent answered every point usably, 1 otherwise. Throws ConfigError for a bad option,
/// vc::UnreachableError for an agent that cannot be reached.
int run(const Options& opt);

/// The exit status of a failure: 2 for a usage-level one (a bad option or file, an agent that
/// cannot be reached), 1 for any other.
int failure_status(const std::exception& e);

}  // namespace cmmcomp::tools::vc

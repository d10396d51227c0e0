// SPDX-License-Identifier: MIT
/// @file cmmcomp-replay's one command: its options (options.cpp) and the replay they run
/// (run.cpp), wired by main.cpp through tools/common/command.hpp.
#pragma once

#include <CLI/CLI.hpp>
#include <cmmcomp/plugins/can_server.hpp>
#include <cstddef>
#include <string>
#include <vector>

#include "../common/command.hpp"

namespace cmmcomp::tools::replay {

/// The command line of cmmcomp-replay (its --help says what each option means).
struct Options {
  std::string session;
  std::vector<std::string> models;
  bool json = false;
  bool quiet = false;
  std::size_t max_mismatches = 1;
  std::string live;
  std::string outside_domain = "clamp";
  int modbus_unit = 1;
  std::string can_base_id =
      cmmcomp::plugins::format_can_base_id(cmmcomp::plugins::can::kDefaultBaseId);
  int can_part_timeout_ms = 50;
};

/// Declares the options on the tool's app; the Command replays the session they name.
Command add_options(CLI::App& app);

/// Replays the session and prints the result; 0 when every answer matches, 1 on a mismatch, 2
/// for an unreadable recording, a model that fails to load or options that do not fit it.
/// Throws ConfigError for a bad option.
int run(const Options& opt);

}  // namespace cmmcomp::tools::replay

// SPDX-License-Identifier: MIT
/// @file cmmcomp-sim's subcommands: each add_NAME declares its options on the tool's app and
/// returns the Command that runs it (tools/common/command.hpp).
#pragma once

#include <CLI/CLI.hpp>

#include "../common/command.hpp"

namespace cmmcomp::tools::sim {

Command add_profile(CLI::App& app);    ///< plan a probing move (move_commands.cpp)
Command add_move(CLI::App& app);       ///< simulate one move (move_commands.cpp)
Command add_dataset(CLI::App& app);    ///< a designed experiment to a CSV (dataset_commands.cpp)
Command add_record(CLI::App& app);     ///< a campaign on the twin (dataset_commands.cpp)
Command add_anova(CLI::App& app);      ///< Table 4 of a dataset (dataset_commands.cpp)
Command add_identify(CLI::App& app);   ///< fit a machine file (identify_command.cpp)
Command add_machine(CLI::App& app);    ///< print a machine file (machine_commands.cpp)
Command add_paper(CLI::App& app);      ///< the machine next to the paper (machine_commands.cpp)
Command add_serve_ipp(CLI::App& app);  ///< the twin as an I++ DME server (serve_ipp_command.cpp)

}  // namespace cmmcomp::tools::sim

// SPDX-License-Identifier: MIT
/// @file cmmcomp-study's subcommands: each add_NAME declares its options on the tool's app and
/// returns the Command that runs it (tools/common/command.hpp). `command` is the command line
/// as the experiments record it (cmmcomp::study::command_line).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "../common/command.hpp"

namespace cmmcomp::tools::study {

// accuracy_commands.cpp
Command add_accuracy(CLI::App& app, const std::string& command);
Command add_cell_interpolant(CLI::App& app, const std::string& command);
// recipe_commands.cpp
Command add_dataset(CLI::App& app);
Command add_train(CLI::App& app);
// interval_commands.cpp
Command add_interval_coverage(CLI::App& app, const std::string& command);
Command add_interval_calibration(CLI::App& app, const std::string& command);
// calibration_commands.cpp
Command add_calibration(CLI::App& app, const std::string& command);
Command add_identify_multistart(CLI::App& app, const std::string& command);
// workflow_commands.cpp
Command add_cross_machine(CLI::App& app, const std::string& command);
Command add_qualified_sweep(CLI::App& app, const std::string& command);
// cycle_command.cpp
Command add_cycle_speedup(CLI::App& app, const std::string& command);
// render_command.cpp
Command add_render(CLI::App& app, const std::string& command);

}  // namespace cmmcomp::tools::study

// SPDX-License-Identifier: MIT
/// @file cmmcomp-train's subcommands: each add_NAME declares its options on the tool's app and
/// returns the Command that runs it (tools/common/command.hpp).
#pragma once

#include <CLI/CLI.hpp>

#include "../common/command.hpp"

namespace cmmcomp::tools::train {

Command add_fit(CLI::App& app);         ///< train on a dataset (fit_command.cpp)
Command add_conditions(CLI::App& app);  ///< a model's training conditions (conditions_command.cpp)
Command add_eval(CLI::App& app);        ///< Table 5 of a model (model_commands.cpp)
Command add_export(CLI::App& app);      ///< a model for the firmware (model_commands.cpp)

}  // namespace cmmcomp::tools::train

// SPDX-License-Identifier: MIT
/// @file cmmcomp-measure's subcommands: each add_NAME declares its options on the tool's app and
/// returns the Command that runs it (tools/common/command.hpp).
#pragma once

#include <CLI/CLI.hpp>

#include "../common/command.hpp"

namespace cmmcomp::tools::measure {

Command add_plan(CLI::App& app);     ///< plan.csv and an I++ program (plan_command.cpp)
Command add_extract(CLI::App& app);  ///< recordings -> the dataset CSV (extract_command.cpp)

}  // namespace cmmcomp::tools::measure

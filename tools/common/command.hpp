// SPDX-License-Identifier: MIT
/// @file A tool as its commands, git-builtin style: each subcommand (or, for a tool without
/// subcommands, the tool's app itself) is a Command, declared with its options on the app and
/// run by run_commands, which parses the command line, ends a usage error as usage_exit does
/// (status 2; 0 for --help and --version), runs the parsed command and prints what it throws as
/// "TOOL: WHAT" with exit status 1 (2 for the failures the tool calls usage-level). Header-only,
/// for the tools' mains.
#pragma once

#include <CLI/CLI.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cstdio>
#include <exception>
#include <functional>
#include <vector>

#include "usage.hpp"

namespace cmmcomp::tools {

/// One command of a tool: where its options are declared, and its body.
struct Command {
  CLI::App* app = nullptr;   ///< the subcommand, or the tool's app for a tool without subcommands
  std::function<int()> run;  ///< the body, run once the command line parsed; the exit status
};

/// The exit status of a failure `e` a command threw: 1 (a failure) or 2 (a usage-level one).
using FailureStatus = int (*)(const std::exception& e);

/// A failure's status for the tools where a cmmcomp::ConfigError (a bad file or option value)
/// is a usage error: 2 for it, 1 for any other.
inline int config_error_is_usage(const std::exception& e) {
  return dynamic_cast<const cmmcomp::ConfigError*>(&e) != nullptr ? 2 : 1;
}

/// Parses `argv` into `app` (a usage error: usage_exit's status), then runs the first command
/// whose app was parsed and returns its status; 0 when none was. An exception the command
/// throws is printed as "TOOL: WHAT" on stderr and gives `status_of(e)`, or 1 without it.
inline int run_commands(CLI::App& app,
                        const std::vector<Command>& commands,
                        const char* tool,
                        int argc,
                        char** argv,
                        FailureStatus status_of = nullptr) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return usage_exit(app, e);
  }
  for (const Command& c : commands) {
    if (!c.app->parsed()) continue;
    try {
      return c.run();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: %s\n", tool, e.what());
      return status_of != nullptr ? status_of(e) : 1;
    }
  }
  return 0;
}

}  // namespace cmmcomp::tools

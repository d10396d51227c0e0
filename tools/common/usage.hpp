// SPDX-License-Identifier: MIT
/// @file How every tool ends on a usage error: CLI11's message, a "did you mean" for a misspelt
/// option, and exit status 2 (0 for --help and --version); and how no exception leaves a tool's
/// main. Header-only, for the tools' mains.
#pragma once

#include <CLI/CLI.hpp>
#include <cmmcomp/detail/did_you_mean.hpp>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

namespace cmmcomp::tools {

/// The long option names ("--pv") of `app` and of its parsed subcommands.
inline void option_names(const CLI::App& app, std::vector<std::string>& out) {
  for (const CLI::Option* o : app.get_options()) {
    for (const std::string& name : o->get_lnames()) out.push_back("--" + name);
  }
  for (const CLI::App* sub : app.get_subcommands()) option_names(*sub, out);
}

/// Prints the error as CLI11 does, and for each unexpected word that looks like an option the
/// closest option; returns the exit status: 0 for --help and --version, 2 otherwise.
inline int usage_exit(CLI::App& app, const CLI::ParseError& e) {
  if (app.exit(e) == 0) return 0;
  if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) {
    std::vector<std::string> names;
    option_names(app, names);
    for (const std::string& word : app.remaining(true)) {
      if (word.size() < 2 || word[0] != '-') continue;
      const std::string key = word.substr(0, word.find('='));
      const std::string hint = detail::did_you_mean(key, names);
      if (!hint.empty())
        std::fprintf(stderr, "'%s' is not an option%s\n", key.c_str(), hint.c_str());
    }
  }
  return 2;
}

/// Runs a tool's body `run(argc, argv)` so that no exception leaves main: one that escapes it (a
/// failure while setting up the options, or a bug; the bodies catch what they expect) is printed
/// as "TOOL: internal error: WHAT" and gives exit status 1.
template <typename Run>
int guarded_main(const char* tool, Run run, int argc, char** argv) noexcept {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: internal error: %s\n", tool, e.what());
  } catch (...) {
    std::fprintf(stderr, "%s: internal error\n", tool);
  }
  return 1;
}

}  // namespace cmmcomp::tools

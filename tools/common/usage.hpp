// SPDX-License-Identifier: MIT
/// @file How every tool ends on a usage error: CLI11's message, a "did you mean" for a misspelt
/// option, and exit status 2 (0 for --help and --version). Header-only, for the tools' mains.
#pragma once

#include <CLI/CLI.hpp>
#include <cmmcomp/detail/did_you_mean.hpp>
#include <cstdio>
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

}  // namespace cmmcomp::tools

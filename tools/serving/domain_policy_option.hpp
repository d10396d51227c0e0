// SPDX-License-Identifier: MIT
/// @file The --outside-domain option's validator, shared by cmmcomp-agent and cmmcomp-replay so
/// both accept exactly the names fuzzy::parse_domain_policy accepts.
#pragma once

#include <CLI/CLI.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <string>

namespace cmmcomp::serving {

/// CLI11 validator: passes "clamp", "extrapolate" and "reject", names anything else.
inline CLI::Validator domain_policy_name() {
  return CLI::Validator(
      [](std::string& text) {
        fuzzy::DomainPolicy ignored{};
        return fuzzy::parse_domain_policy(text, &ignored)
                   ? std::string()
                   : "expected clamp, extrapolate or reject, got '" + text + "'";
      },
      "POLICY");
}

}  // namespace cmmcomp::serving

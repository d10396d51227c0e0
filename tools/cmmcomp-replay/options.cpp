// SPDX-License-Identifier: MIT
/// @file cmmcomp-replay's options: the session, the models or the live agent, and the agent's
/// settings the recording was made with.
#include <memory>

#include "commands.hpp"
#include "domain_policy_option.hpp"

namespace cmmcomp::tools::replay {

Command add_options(CLI::App& app) {
  auto opt = std::make_shared<Options>();
  app.add_option("SESSION", opt->session, "the recording")->required();
  app.add_option("--model",
                 opt->models,
                 "model file, [AXIS=]PATH as for cmmcomp-agent (default: the shipped model)");
  app.add_flag("--json", opt->json, "print the result as JSON");
  app.add_flag("--quiet", opt->quiet, "no line per request, only mismatches and the summary");
  app.add_option("--max-mismatches",
                 opt->max_mismatches,
                 "stop after this many mismatching requests, 0 = report all")
      ->capture_default_str();
  app.add_option("--live",
                 opt->live,
                 "replay against a running agent instead: modbus:tcp:HOST:PORT or can:IFACE");
  app.add_option("--outside-domain",
                 opt->outside_domain,
                 "as the agent that was recorded: clamp, extrapolate or reject")
      ->capture_default_str()
      ->check(cmmcomp::serving::domain_policy_name());
  app.add_option("--modbus-unit", opt->modbus_unit, "the agent's Modbus unit id")
      ->capture_default_str()
      ->check(CLI::Range(1, 247));
  app.add_option("--can-base-id", opt->can_base_id, "the agent's 11-bit base identifier")
      ->capture_default_str();
  app.add_option("--can-part-timeout-ms",
                 opt->can_part_timeout_ms,
                 "the agent's longest gap between the frames of one request")
      ->capture_default_str()
      ->check(CLI::Range(1, 60'000));
  return {&app, [opt] { return run(*opt); }};
}

}  // namespace cmmcomp::tools::replay

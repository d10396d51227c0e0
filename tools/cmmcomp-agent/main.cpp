// SPDX-License-Identifier: MIT
/// @file cmmcomp-agent: serves the per-move compensator to a CMM controller over SocketCAN
/// (docs/protocol-can.md) and/or Modbus TCP/RTU (docs/protocol-modbus.md).
/// The runtime (threads, signals, reload) is tools/serving/agent.hpp.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/plugins/can_server.hpp>
#include <cmmcomp/plugins/modbus_server.hpp>
#include <cmmcomp/version.hpp>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "../common/usage.hpp"
#include "agent.hpp"
#include "agent_config.hpp"
#include "domain_policy_option.hpp"

namespace {

using cmmcomp::serving::AgentSettings;

/// The command line: either --config FILE, or the serving options themselves.
struct Options {
  std::string config;
  bool check = false;  ///< --check: validate the settings and models, then exit
  std::vector<std::string> models;
  std::string can_interface;
  std::string can_base_id =
      cmmcomp::plugins::format_can_base_id(cmmcomp::plugins::can::kDefaultBaseId);
  int can_heartbeat_ms = 1000;
  int can_part_timeout_ms = 50;
  std::string modbus;
  int modbus_unit = 1;
  std::string outside_domain = "clamp";
  std::string log_level = "info";
  std::string ipp_proxy;
  std::string ipp_upstream;

  /// The settings the options say (setup; throws ConfigError for a bad --model or base id).
  AgentSettings settings() const {
    if (!config.empty()) return cmmcomp::serving::load_agent_config(config);
    AgentSettings s;
    for (const std::string& m : models) {
      s.models.push_back(cmmcomp::serving::parse_model_argument(m));
    }
    s.can.interface = can_interface;
    std::string why;
    if (!can_interface.empty() &&
        !cmmcomp::plugins::is_valid_can_interface_name(can_interface, &why)) {
      throw cmmcomp::ConfigError("--can: " + why);
    }
    s.can.base_id = cmmcomp::plugins::parse_can_base_id(can_base_id);
    s.can.heartbeat_ms = can_heartbeat_ms;
    s.can.part_timeout_ms = can_part_timeout_ms;
    s.modbus.endpoint = modbus;
    s.modbus.unit = modbus_unit;
    // CLI11 admits only the three names, so the parse cannot fail here.
    (void)cmmcomp::fuzzy::parse_domain_policy(outside_domain, &s.outside_domain);
    s.log_level = log_level;
    return s;
  }
};

}  // namespace

static int run_tool(int argc, char** argv) {
  CLI::App app{
      "cmmcomp-agent: serves the per-move dynamic-error compensator to a CMM controller over "
      "SocketCAN (docs/protocol-can.md) and/or Modbus TCP/RTU (docs/protocol-modbus.md).\n"
      "SIGHUP reloads the model files (a file that fails keeps the old model serving); SIGTERM "
      "stops."};
  Options opt;
  auto* config = app.add_option(
      "--config",
      opt.config,
      "read every setting from this file (docs/agent.md), e.g. /etc/cmmcomp/agent.toml; SIGHUP "
      "re-reads it. Excludes the options below");
  app.add_flag("--check",
               opt.check,
               "validate the settings and load the models, then exit (0: valid) without serving");
  auto* models =
      app.add_option("--model",
                     opt.models,
                     "model file from cmmcomp-train, [AXIS=]PATH, AXIS 0-3 (default 0); repeat for "
                     "several axes. Default: the shipped model of the simulated default machine");
  auto* can = app.add_option("--can", opt.can_interface, "serve on this CAN interface (vcan0)");
  app.add_option("--can-base-id", opt.can_base_id, "11-bit base identifier")->capture_default_str();
  app.add_option("--can-heartbeat-ms", opt.can_heartbeat_ms, "heartbeat period, 0 = off")
      ->capture_default_str()
      ->check(CLI::Range(0, 3'600'000));
  app.add_option("--can-part-timeout-ms",
                 opt.can_part_timeout_ms,
                 "longest gap between the frames of one request")
      ->capture_default_str()
      ->check(CLI::Range(1, 60'000));
  auto* modbus = app.add_option(
      "--modbus", opt.modbus, "serve Modbus on tcp:HOST:PORT or rtu:DEVICE:BAUD[,8N1]");
  auto* unit = app.add_option("--modbus-unit", opt.modbus_unit, "Modbus unit id")
                   ->capture_default_str()
                   ->check(CLI::Range(1, 247));
  auto* policy = app.add_option("--outside-domain",
                                opt.outside_domain,
                                "moves outside the training ranges: clamp, extrapolate or reject")
                     ->capture_default_str()
                     ->check(cmmcomp::serving::domain_policy_name());
  auto* level =
      app.add_option("--log-level", opt.log_level, "trace, debug, info, warn, error, critical, off")
          ->capture_default_str()
          ->check(CLI::IsMember(std::vector<std::string>(std::begin(cmmcomp::serving::kLogLevels),
                                                         std::end(cmmcomp::serving::kLogLevels))));
  auto* ipp_proxy = app.add_option(
      "--ipp-proxy",
      opt.ipp_proxy,
      "run the compensating I++ DME proxy listening on HOST:PORT (docs/protocol-ippdme.md) "
      "instead of serving a bus; needs --ipp-upstream");
  auto* ipp_upstream = app.add_option(
      "--ipp-upstream", opt.ipp_upstream, "the I++ DME server the proxy forwards to, HOST:PORT");
  app.set_version_flag("--version", std::string("cmmcomp-agent ") + CMMCOMP_VERSION_STRING);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cmmcomp::tools::usage_exit(app, e);
  }
  for (CLI::Option* o : {models, can, modbus, unit, policy, level}) {
    if (config->count() > 0 && o->count() > 0) {
      std::fprintf(stderr,
                   "cmmcomp-agent: %s and --config: give every setting in the file\n",
                   o->get_name().c_str());
      return 2;
    }
  }
  if (ipp_proxy->count() > 0 || ipp_upstream->count() > 0) {
    if (ipp_proxy->count() == 0 || ipp_upstream->count() == 0) {
      std::fprintf(stderr, "cmmcomp-agent: --ipp-proxy and --ipp-upstream go together\n");
      return 2;
    }
    for (CLI::Option* o : {config, can, modbus, unit}) {
      if (o->count() > 0) {
        std::fprintf(stderr,
                     "cmmcomp-agent: %s and --ipp-proxy: the proxy serves no bus\n",
                     o->get_name().c_str());
        return 2;
      }
    }
    try {
      cmmcomp::serving::IppProxyOptions p;
      cmmcomp::serving::parse_host_port(opt.ipp_proxy, "--ipp-proxy", p.listen_host, p.listen_port);
      cmmcomp::serving::parse_host_port(
          opt.ipp_upstream, "--ipp-upstream", p.upstream_host, p.upstream_port);
      return cmmcomp::serving::run_ipp_proxy(opt.settings(), p, opt.check);
    } catch (const cmmcomp::ConfigError& e) {
      std::fprintf(stderr, "cmmcomp-agent: %s\n", e.what());
      return 2;
    } catch (const std::exception& e) {
      spdlog::critical("{}", e.what());
      return 2;
    }
  }
  if (config->count() == 0 && can->count() == 0 && modbus->count() == 0) {
    std::fprintf(stderr,
                 "cmmcomp-agent: nothing to serve: give --can IFACE and/or --modbus ENDPOINT, or "
                 "--config FILE\n");
    return 2;
  }
  try {
    return cmmcomp::serving::run_agent(opt.settings(), opt.config, opt.check);
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return 2;
  }
}

int main(int argc, char** argv) {
  return cmmcomp::tools::guarded_main("cmmcomp-agent", run_tool, argc, argv);
}

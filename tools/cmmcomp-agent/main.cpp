// SPDX-License-Identifier: MIT
/// @file cmmcomp-agent: serves the per-move compensator to a CMM controller over SocketCAN
/// (docs/protocol-can.md) and/or Modbus TCP/RTU (docs/protocol-modbus.md).
///
/// Threads: one per bus, each running its server's loop; the main thread only waits for
/// signals (blocked everywhere, taken with sigtimedwait, so no handler runs in a server
/// thread). SIGHUP reloads every model file: a file that fails keeps the old model serving
/// (the compensator's publish is a wait-free hot swap for the serving threads). SIGTERM and
/// SIGINT stop the servers and exit 0 after logging their counters.
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
#include "agent_config.hpp"
#include "domain_policy_option.hpp"
#include "model_slots.hpp"
#include "outcome_logger.hpp"

namespace {

using cmmcomp::serving::AgentSettings;
using cmmcomp::serving::ModelSlot;
using cmmcomp::serving::SlotOutcome;

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

/// The default model's slot, with the warning that it is the twin's, when none is given.
std::vector<ModelSlot> slots_of(const AgentSettings& s) {
  if (!s.models.empty()) return s.models;
  spdlog::warn(
      "no model given: serving the shipped default model on axis 0. It was trained on the "
      "simulated default machine (digital twin), NOT on your machine; train one with "
      "cmmcomp-train on your own measurements");
  return {ModelSlot{0, ""}};
}

/// Logs what a load or reload did; returns true when every slot was loaded.
bool report(const std::vector<SlotOutcome>& outcomes, bool reload) {
  bool all = true;
  for (const SlotOutcome& o : outcomes) {
    if (o.loaded) {
      spdlog::info("axis {}: {} model {} from {}",
                   o.axis,
                   reload ? "reloaded" : "serving",
                   o.model_id,
                   o.source);
    } else {
      all = false;
      if (o.model_id.empty()) {
        spdlog::error(
            "axis {}: cannot load {}: {}; the axis has no model", o.axis, o.source, o.error);
      } else {
        spdlog::error("axis {}: cannot load {}: {}; model {} keeps serving",
                      o.axis,
                      o.source,
                      o.error,
                      o.model_id);
      }
    }
  }
  return all;
}

/// A server loop on its own thread; an exception ends it and asks the agent to stop.
class ServerThread {
 public:
  template <typename Server>
  ServerThread(std::unique_ptr<Server> server, std::atomic<bool>& stop, std::atomic<bool>& failed)
      : name_(server->where()) {
    thread_ = std::thread([s = std::move(server), &stop, &failed, name = name_] {
      try {
        s->run(stop);
      } catch (const std::exception& e) {
        spdlog::critical("{}: {}", name, e.what());
        failed = true;
      }
      log_counters(*s);
    });
  }
  ~ServerThread() {
    if (thread_.joinable()) thread_.join();
  }
  ServerThread(const ServerThread&) = delete;
  ServerThread& operator=(const ServerThread&) = delete;

 private:
  static void log_counters(const cmmcomp::plugins::CanServer& s) {
    const auto c = s.counters();
    spdlog::info(
        "{}: {} requests, {} answered ({} with the interval), {} rejected ({} malformed, {} "
        "timeouts, {} out of range, {} refused), {} outside the model's domain, {} heartbeats",
        s.where(),
        c.requests,
        c.answered,
        c.intervals,
        c.rejected,
        c.malformed,
        c.timeouts,
        c.out_of_range,
        c.refused,
        c.outside_domain,
        c.heartbeats);
  }
  static void log_counters(const cmmcomp::plugins::ModbusServer& s) {
    const auto c = s.counters();
    spdlog::info(
        "{}: {} requests, {} answered, {} computations ({} refused by the compensator, {} "
        "outside the model's domain), {} exceptions ({} bad values), {} clients, {} receive "
        "errors",
        s.where(),
        c.requests,
        c.answered,
        c.computations,
        c.refused,
        c.outside_domain,
        c.exceptions,
        c.rejected,
        c.clients_connected,
        c.receive_errors);
  }

  std::string name_;
  std::thread thread_;
};

/// Re-reads the config file for SIGHUP. A config that fails keeps everything as it was (the
/// models are not reloaded either); settings that need a restart are reported and left as they
/// are. Returns the model slots to reload, or nothing.
bool reload_config(const std::string& path, AgentSettings& running, std::vector<ModelSlot>& slots) {
  AgentSettings next;
  try {
    next = cmmcomp::serving::load_agent_config(path);
  } catch (const std::exception& e) {
    spdlog::error("SIGHUP: {}; the agent keeps serving as it was", e.what());
    return false;
  }
  for (const std::string& what : cmmcomp::serving::restart_needed(running, next)) {
    spdlog::warn("SIGHUP: {} changed in {}: it takes effect at the next start", what, path);
  }
  for (const ModelSlot& old : slots) {
    bool kept = false;
    for (const ModelSlot& s : next.models) kept = kept || s.axis == old.axis;
    if (!kept && !next.models.empty()) {
      spdlog::warn("SIGHUP: axis {} is no longer in {}; its model keeps serving", old.axis, path);
    }
  }
  spdlog::set_level(spdlog::level::from_str(next.log_level));
  running.models = next.models;
  running.log_level = next.log_level;
  slots = slots_of(running);
  return true;
}

int serve(const Options& opt) {
  AgentSettings settings = opt.settings();
  spdlog::set_level(spdlog::level::from_str(settings.log_level));
  spdlog::info("cmmcomp-agent {}{}",
               CMMCOMP_VERSION_STRING,
               opt.config.empty() ? "" : " (config " + opt.config + ")");
  std::vector<ModelSlot> slots = slots_of(settings);

  cmmcomp::compensation::CompensatorOptions copt;
  copt.outside_domain = settings.outside_domain;
  cmmcomp::compensation::MoveCompensator compensator(copt);
  if (!report(cmmcomp::serving::load_slots(slots, compensator), false)) return 2;
  if (opt.check) {
    // The buses' endpoints parse (settings() checked them); binding them is for the real start.
    std::printf("cmmcomp-agent: settings and %zu model(s) are valid\n", slots.size());
    return 0;
  }

  // Block the signals before any thread starts, so that every thread inherits the mask.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGHUP);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  std::atomic<bool> stop{false};
  std::atomic<bool> failed{false};
  std::vector<std::unique_ptr<ServerThread>> threads;
  // Servers are constructed here (bind errors are reported before anything serves).
  std::unique_ptr<cmmcomp::plugins::CanServer> can;
  std::unique_ptr<cmmcomp::plugins::ModbusServer> modbus;
  // Each server reports its refused requests and outside-domain answers here; the signal loop
  // below logs them, rate-limited (docs/agent.md, "Log"). Declared before the servers' threads,
  // so they outlive them.
  cmmcomp::compensation::ServerOutcomeLog can_outcomes, modbus_outcomes;
  std::vector<std::unique_ptr<cmmcomp::serving::OutcomeLogger>> outcome_loggers;
  if (!settings.can.interface.empty()) {
    cmmcomp::plugins::CanServerOptions o;
    o.outcome_log = &can_outcomes;
    o.interface = settings.can.interface;
    o.base_id = settings.can.base_id;
    o.heartbeat_period = std::chrono::milliseconds(settings.can.heartbeat_ms);
    o.part_timeout = std::chrono::milliseconds(settings.can.part_timeout_ms);
    can = std::make_unique<cmmcomp::plugins::CanServer>(compensator, o);
  }
  if (!settings.modbus.endpoint.empty()) {
    cmmcomp::plugins::ModbusServerOptions o;
    o.unit_id = settings.modbus.unit;
    o.outcome_log = &modbus_outcomes;
    modbus = std::make_unique<cmmcomp::plugins::ModbusServer>(
        compensator, cmmcomp::plugins::ModbusEndpoint::parse(settings.modbus.endpoint), o);
  }
  // Start serving only once every server is set up; announce each on stdout too, one line
  // each, for scripts that wait for the agent to be ready.
  const auto serve_on_thread = [&](auto server) {
    const std::string where = server->where();
    threads.push_back(std::make_unique<ServerThread>(std::move(server), stop, failed));
    std::printf("cmmcomp-agent: listening on %s\n", where.c_str());
    std::fflush(stdout);
    spdlog::info("listening on {}", where);
  };
  if (can) {
    outcome_loggers.push_back(
        std::make_unique<cmmcomp::serving::OutcomeLogger>(can->where(), can_outcomes));
    serve_on_thread(std::move(can));
  }
  if (modbus) {
    outcome_loggers.push_back(
        std::make_unique<cmmcomp::serving::OutcomeLogger>(modbus->where(), modbus_outcomes));
    serve_on_thread(std::move(modbus));
  }

  // Reloads run on their own thread, so the signal loop always sees SIGTERM at once, whatever
  // a reload is reading (issue 16 D6). SIGHUPs that arrive during a reload are folded into one
  // more reload after it. The reloader is the only publisher once the servers run.
  std::mutex reload_mutex;
  std::condition_variable reload_wanted;
  bool reload_pending = false;
  bool reloader_stop = false;
  std::thread reloader([&] {
    std::unique_lock<std::mutex> lock(reload_mutex);
    while (true) {
      reload_wanted.wait(lock, [&] { return reload_pending || reloader_stop; });
      if (reloader_stop) return;
      reload_pending = false;
      lock.unlock();
      if (opt.config.empty() || reload_config(opt.config, settings, slots)) {
        spdlog::info("SIGHUP: reloading {} model(s)", slots.size());
        report(cmmcomp::serving::load_slots(slots, compensator), true);
      }
      lock.lock();
    }
  });

  int exit_code = 0;
  while (true) {
    const timespec tick{0, 200'000'000};
    const int sig = sigtimedwait(&signals, nullptr, &tick);
    for (auto& l : outcome_loggers) l->drain(std::chrono::steady_clock::now());
    if (failed) {
      exit_code = 1;
      break;
    }
    if (sig == SIGHUP) {
      {
        const std::lock_guard<std::mutex> lock(reload_mutex);
        reload_pending = true;
      }
      reload_wanted.notify_one();
    } else if (sig == SIGTERM || sig == SIGINT) {
      spdlog::info("{}: stopping", sig == SIGTERM ? "SIGTERM" : "SIGINT");
      break;
    } else if (sig < 0 && errno != EAGAIN && errno != EINTR) {
      spdlog::critical("sigtimedwait failed: errno {}", errno);
      exit_code = 1;
      break;
    }
  }
  stop = true;
  threads.clear();  // joins; each thread logs its counters
  for (auto& l : outcome_loggers) l->finish(std::chrono::steady_clock::now());
  {
    const std::lock_guard<std::mutex> lock(reload_mutex);
    reloader_stop = true;
  }
  reload_wanted.notify_one();
  // A reload in progress finishes first: every read is bounded (a regular file of at most
  // 4 MiB, opened non-blocking: docs/fuzzing.md, "Files").
  reloader.join();
  spdlog::info("stopped");
  return exit_code;
}

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
  if (config->count() == 0 && can->count() == 0 && modbus->count() == 0) {
    std::fprintf(stderr,
                 "cmmcomp-agent: nothing to serve: give --can IFACE and/or --modbus ENDPOINT, or "
                 "--config FILE\n");
    return 2;
  }
  try {
    return serve(opt);
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return 2;
  }
}

int main(int argc, char** argv) {
  return cmmcomp::tools::guarded_main("cmmcomp-agent", run_tool, argc, argv);
}

// SPDX-License-Identifier: MIT
/// @file The agent's runtime (agent.hpp).
#include "agent.hpp"

#include <spdlog/spdlog.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/plugins/can_server.hpp>
#include <cmmcomp/plugins/modbus_server.hpp>
#include <cmmcomp/version.hpp>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "ipp_proxy.hpp"
#include "model_slots.hpp"
#include "outcome_logger.hpp"

namespace cmmcomp::serving {
namespace {

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

}  // namespace

int run_agent(AgentSettings settings, const std::string& config_path, bool check) {
  spdlog::set_level(spdlog::level::from_str(settings.log_level));
  spdlog::info("cmmcomp-agent {}{}",
               CMMCOMP_VERSION_STRING,
               config_path.empty() ? "" : " (config " + config_path + ")");
  std::vector<ModelSlot> slots = slots_of(settings);

  cmmcomp::compensation::CompensatorOptions copt;
  copt.outside_domain = settings.outside_domain;
  cmmcomp::compensation::MoveCompensator compensator(copt);
  if (!report(cmmcomp::serving::load_slots(slots, compensator), false)) return 2;
  if (check) {
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
      if (config_path.empty() || reload_config(config_path, settings, slots)) {
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

int run_ipp_proxy(const AgentSettings& settings, const IppProxyOptions& proxy_options, bool check) {
  spdlog::set_level(spdlog::level::from_str(settings.log_level));
  spdlog::info("cmmcomp-agent {} (I++ DME proxy)", CMMCOMP_VERSION_STRING);
  const std::vector<ModelSlot> slots = slots_of(settings);
  cmmcomp::compensation::CompensatorOptions copt;
  copt.outside_domain = settings.outside_domain;
  cmmcomp::compensation::MoveCompensator compensator(copt);
  if (!report(cmmcomp::serving::load_slots(slots, compensator), false)) return 2;
  if (check) {
    std::printf("cmmcomp-agent: settings and %zu model(s) are valid\n", slots.size());
    return 0;
  }
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGHUP);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  IppProxyOptions o = proxy_options;
  o.log = [](const std::string& line) {
    if (line.rfind("a point passed uncorrected", 0) == 0) {
      spdlog::warn("I++ proxy: {}", line);
    } else {
      spdlog::info("I++ proxy: {}", line);
    }
  };
  IppProxy proxy(compensator, o);
  const std::string where = o.listen_host + ":" + std::to_string(proxy.port());
  std::atomic<bool> failed{false};
  std::thread serving([&] {
    try {
      proxy.run();
    } catch (const std::exception& e) {
      spdlog::critical("I++ proxy: {}", e.what());
      failed = true;
    }
  });
  std::printf("cmmcomp-agent: I++ proxy listening on %s, upstream %s:%u\n",
              where.c_str(),
              o.upstream_host.c_str(),
              static_cast<unsigned>(o.upstream_port));
  std::fflush(stdout);
  spdlog::info(
      "I++ proxy listening on {}, upstream {}:{}", where, o.upstream_host, o.upstream_port);
  int exit_code = 0;
  while (true) {
    const timespec tick{0, 200'000'000};
    const int sig = sigtimedwait(&signals, nullptr, &tick);
    if (failed) {
      exit_code = 1;
      break;
    }
    if (sig == SIGHUP) {
      // The proxy's thread keeps serving: publish is a wait-free swap for its readers.
      spdlog::info("SIGHUP: reloading {} model(s)", slots.size());
      report(cmmcomp::serving::load_slots(slots, compensator), true);
    } else if (sig == SIGTERM || sig == SIGINT) {
      spdlog::info("{}: stopping", sig == SIGTERM ? "SIGTERM" : "SIGINT");
      break;
    } else if (sig < 0 && errno != EAGAIN && errno != EINTR) {
      spdlog::critical("sigtimedwait failed: errno {}", errno);
      exit_code = 1;
      break;
    }
  }
  proxy.request_stop();
  serving.join();
  const IppProxyCounters c = proxy.counters();
  spdlog::info("I++ proxy: {} points, {} corrected", c.points, c.corrected);
  spdlog::info("stopped");
  return exit_code;
}

}  // namespace cmmcomp::serving

// SPDX-License-Identifier: MIT
/// @file cmmcomp-sim serve-ipp: the twin as an I++ DME server (docs/protocol-ippdme.md).
#include <cmmcomp/dynamics/noise.hpp>
#include <cmmcomp/ipp/server.hpp>
#include <cmmcomp/ipp/session.hpp>
#include <cmmcomp/vc/ipp_twin_machine.hpp>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include "commands.hpp"
#include "shared.hpp"

namespace cmmcomp::tools::sim {
namespace {

struct ServeIppCommand {
  std::string listen;
  std::string machine;
  bool noise = false;
  std::uint64_t seed = 1;
  bool realtime = false;
};

/// HOST:PORT split at the last colon; false when it is not that.
bool split_listen(const std::string& text, std::string& host, std::uint16_t& port) {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size()) return false;
  const std::string digits = text.substr(colon + 1);
  if (digits.size() > 5 || digits.find_first_not_of("0123456789") != std::string::npos) {
    return false;
  }
  const long p = std::stol(digits);
  if (p > 65535) return false;
  host = text.substr(0, colon);
  port = static_cast<std::uint16_t>(p);
  return true;
}

/// The server SIGINT and SIGTERM stop (request_stop is async-signal-safe).
ipp::Server* g_serve_ipp_server = nullptr;

extern "C" void serve_ipp_on_signal(int) {
  if (g_serve_ipp_server != nullptr) g_serve_ipp_server->request_stop();
}

int run_serve_ipp(const ServeIppCommand& cmd) {
  std::string host;
  std::uint16_t port = 0;
  split_listen(cmd.listen, host, port);  // checked by the option's validator
  dynamics::MeasurementNoise noise;
  noise.enabled = cmd.noise;
  noise.seed = cmd.seed;
  vc::IppTwinMachine machine(machine_from(cmd.machine), noise);
  ipp::Session session(machine);
  ipp::ServerOptions options;
  options.host = host;
  options.port = port;
  options.realtime = cmd.realtime;
  options.log = [](const std::string& s) {
    std::fprintf(stderr, "cmmcomp-sim serve-ipp: %s\n", s.c_str());
  };
  ipp::Server server(session, options);
  g_serve_ipp_server = &server;
  struct sigaction action {};
  action.sa_handler = serve_ipp_on_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  std::signal(SIGPIPE, SIG_IGN);
  std::printf("listening on %s:%u\n", host.c_str(), static_cast<unsigned>(server.port()));
  std::fflush(stdout);
  server.run();
  g_serve_ipp_server = nullptr;
  std::fprintf(stderr, "cmmcomp-sim serve-ipp: stopped\n");
  return 0;
}

}  // namespace

Command add_serve_ipp(CLI::App& app) {
  auto cmd = std::make_shared<ServeIppCommand>();
  CLI::App* serve = app.add_subcommand(
      "serve-ipp",
      "serve the twin as an I++ DME server: PtMeas results carry the twin's dynamic error "
      "(docs/protocol-ippdme.md)");
  serve->add_option("--listen", cmd->listen, "HOST:PORT to listen on (port 0: a free one, printed)")
      ->required()
      ->check(CLI::Validator(
          [](std::string& text) {
            std::string host;
            std::uint16_t port = 0;
            return split_listen(text, host, port) ? std::string()
                                                  : "'" + text + "' is not HOST:PORT";
          },
          "HOST:PORT"));
  serve->add_option("--machine", cmd->machine, "machine file (default: embedded)");
  serve->add_flag("--noise", cmd->noise, "add the seeded repeatability noise to every point");
  serve->add_option("--seed", cmd->seed, "noise seed")->capture_default_str();
  serve->add_flag("--realtime", cmd->realtime, "answer after the moves' machine time");
  return {serve, [cmd] { return run_serve_ipp(*cmd); }};
}

}  // namespace cmmcomp::tools::sim

// SPDX-License-Identifier: MIT
/// @file The compensating I++ DME proxy (docs/protocol-ippdme.md, "The compensating proxy"):
/// between an I++ client (measuring software) and an I++ server (a controller, or cmmcomp-sim
/// serve-ipp), every line passes through byte for byte in both directions, in order, except the
/// data line of each PtMeas, whose X, Y, Z it corrects along the approach direction with the
/// compensator's prediction for the probing move it rebuilds (ipp::ProbingMoveTracker, the rule
/// the server uses), and to which it appends `CmmcompCorrection(dx, dy, dz)` (what it added [mm]),
/// `CmmcompU95(mm)` and `CmmcompFlags(n)`; an uncorrected point gets `CmmcompFlags(n)` only.
///
/// IppProxyLogic is the line side without sockets (what the tests and the benchmark drive);
/// IppProxy the socket side: one client at a time (a second connection gets `E0000 ! Error(3,
/// 0508, …)` and is closed), one upstream connection per client, bounded buffers, a client that
/// does not read is dropped, the upstream is always read.
#pragma once

#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/ipp/line.hpp>
#include <cmmcomp/ipp/move_rule.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

namespace cmmcomp::serving {

/// Proxy bits of CmmcompFlags beside the compensator's CorrectionFlag bits (kFlagOk clear: the
/// point passed uncorrected).
enum IppProxyFlag : std::uint32_t {
  kIppFlagNotRebuilt = 1u << 8,    ///< the probing move could not be rebuilt (position, property)
  kIppFlagReportFormat = 1u << 9,  ///< the data line has no X(), Y() and Z() to rewrite
};

/// What the proxy did to the points, for the log and the tests.
struct IppProxyCounters {
  std::uint64_t points = 0;     ///< PtMeas data lines seen
  std::uint64_t corrected = 0;  ///< of them corrected
};

/// The line side of the proxy: one session's reconstruction and rewriting. Not thread-safe.
/// Per line: no lock, no allocation beyond the numbers' text (bounded) once constructed.
class IppProxyLogic {
 public:
  /// `log` gets one line per cause of an uncorrected point, the first time it occurs.
  IppProxyLogic(const compensation::MoveCompensator& compensator,
                std::function<void(const std::string&)> log = {});
  ~IppProxyLogic();
  IppProxyLogic(const IppProxyLogic&) = delete;
  IppProxyLogic& operator=(const IppProxyLogic&) = delete;

  /// A new client session: nothing is known.
  void reset() noexcept;
  /// A line the client sent (without its LF). Only observed: it passes as it is.
  void from_client(std::string_view line) noexcept;
  /// A line the server sent (without its LF). Returns the line to pass on: `line` itself, or a
  /// view of the rewritten PtMeas data line (valid until the next call).
  std::string_view from_server(std::string_view line);

  const IppProxyCounters& counters() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct IppProxyOptions {
  std::string listen_host = "127.0.0.1";
  std::uint16_t listen_port = 1294;  ///< 0: a free port (IppProxy::port())
  std::string upstream_host = "127.0.0.1";
  std::uint16_t upstream_port = 1294;
  std::size_t max_buffered_bytes = 1u << 20;  ///< unsent bytes to the client above this drop it
  double send_timeout_s = 5.0;                ///< nothing sent to the client for this long drops it
  double connect_timeout_s = 5.0;             ///< the upstream connection
  /// Connections, drops and the first occurrence of each cause of an uncorrected point.
  std::function<void(const std::string&)> log;
};

class IppProxy {
 public:
  /// Binds and listens; throws cmmcomp::Error naming the address when it cannot.
  IppProxy(const compensation::MoveCompensator& compensator, const IppProxyOptions& options);
  ~IppProxy();
  IppProxy(const IppProxy&) = delete;
  IppProxy& operator=(const IppProxy&) = delete;

  std::uint16_t port() const noexcept;
  /// Serves until request_stop().
  void run();
  /// Ends run() from another thread or a signal handler (async-signal-safe).
  void request_stop() noexcept;
  /// The points of every session so far (read after run() returned, or racy).
  IppProxyCounters counters() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Parses "HOST:PORT" (PORT 0..65535); throws ConfigError naming `what`.
void parse_host_port(const std::string& text,
                     const char* what,
                     std::string& host,
                     std::uint16_t& port);

}  // namespace cmmcomp::serving

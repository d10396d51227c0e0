// SPDX-License-Identifier: MIT
/// @file The I++ DME server's socket side: one TCP client session at a time over a Session
/// (POSIX sockets and poll, one thread).
///
/// - A second connection while a client is connected gets `E0000 ! Error(3, 0508, …, "Bad
///   context: another client session is active")` and is closed.
/// - Lines end at LF (a CR before it is dropped). A client that sends more than kMaxLineBytes
///   without a LF gets `E0000 ! Error(3, 0008, …)` and is closed; binary junk gets an error per
///   line (Session).
/// - A client that does not read: when more than `max_output_bytes` wait to be sent, or nothing
///   could be sent for `send_timeout_s`, it is dropped. The server never blocks on a client.
/// - `realtime`: a command's answers go out when its machine time (Executed::seconds) has
///   passed; meanwhile lines are still read, normal commands acknowledged and queued, and
///   fast-queue commands (GetErrStatusE, GetPropE, AbortE) answered at once. Without it the
///   answers go out as fast as they are computed.
/// Setup-level code: the constructor throws cmmcomp::Error when it cannot listen.
#pragma once

#include <cmmcomp/ipp/session.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace cmmcomp::ipp {

struct ServerOptions {
  std::string host = "127.0.0.1";           ///< an IPv4 address or a host name to listen on
  std::uint16_t port = 1294;                ///< 0: a free port (Server::port() says which)
  bool realtime = false;                    ///< answers after the moves' machine time
  std::size_t max_output_bytes = 1u << 20;  ///< unsent answers above this drop the client
  double send_timeout_s = 5.0;              ///< no byte sent for this long drops the client
  /// Where the server reports connections and drops (one line each; nothing when empty).
  std::function<void(const std::string&)> log;
};

class Server {
 public:
  /// Binds and listens; throws cmmcomp::Error naming the address when it cannot.
  Server(Session& session, const ServerOptions& options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// The port it listens on.
  std::uint16_t port() const noexcept;
  /// Serves until request_stop(); then closes the client (its session ends) and returns.
  void run();
  /// Ends run() from another thread or a signal handler (async-signal-safe).
  void request_stop() noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cmmcomp::ipp

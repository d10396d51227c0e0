// SPDX-License-Identifier: MIT
/// @file The POSIX socket steps the I++ server, the client and the compensating proxy share
/// (IPv4, TCP): resolving a host, listening, poll timeouts. Setup-time code: listen_tcp and
/// resolve throw Error naming `who` ("I++ server", "I++ proxy", …); the rest never throws.
#pragma once

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmmcomp/exceptions.hpp>
#include <cstdint>
#include <cstring>
#include <string>

namespace cmmcomp::ipp::net {

/// The IPv4 address of `host` (a dotted address or a name) at `port`; throws Error
/// "<who>: cannot resolve host '<host>'".
inline sockaddr_in resolve(const std::string& host, std::uint16_t port, const char* who = "I++") {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  if (inet_pton(AF_INET, host.c_str(), &a.sin_addr) == 1) return a;
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (getaddrinfo(host.c_str(), nullptr, &hints, &found) != 0 || found == nullptr) {
    throw Error(std::string(who) + ": cannot resolve host '" + host + "'");
  }
  a.sin_addr = reinterpret_cast<sockaddr_in*>(found->ai_addr)->sin_addr;
  freeaddrinfo(found);
  return a;
}

inline void set_nonblocking(int fd) noexcept {
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL, 0) | O_NONBLOCK);
}

/// Lines go out at once (no Nagle delay): an I++ answer is a short line waited for.
inline void no_delay(int fd) noexcept {
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
}

/// A listening socket and the port it got.
struct Listener {
  int fd = -1;
  std::uint16_t port = 0;  ///< the bound port (the one picked when asked for port 0)
};

/// Listens on `host`:`port` (0: a free port), non-blocking, close-on-exec, SO_REUSEADDR; throws
/// Error "<who>: cannot listen on HOST:PORT: why".
inline Listener listen_tcp(const std::string& host, std::uint16_t port, const char* who) {
  const sockaddr_in a = resolve(host, port, who);
  const std::string where = host + ":" + std::to_string(port);
  Listener l;
  l.fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (l.fd < 0) throw Error(std::string(who) + ": socket: " + std::strerror(errno));
  const int one = 1;
  ::setsockopt(l.fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (::bind(l.fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0 ||
      ::listen(l.fd, 4) != 0) {
    const std::string why = std::strerror(errno);
    ::close(l.fd);
    throw Error(std::string(who) + ": cannot listen on " + where + ": " + why);
  }
  set_nonblocking(l.fd);
  sockaddr_in bound{};
  socklen_t len = sizeof bound;
  ::getsockname(l.fd, reinterpret_cast<sockaddr*>(&bound), &len);
  l.port = ntohs(bound.sin_port);
  return l;
}

using Clock = std::chrono::steady_clock;

/// Milliseconds from now until `deadline`, at least 0, rounded up, at most 10⁶ (a poll timeout).
inline int ms_until(Clock::time_point deadline) noexcept {
  const auto left =
      std::chrono::duration_cast<std::chrono::microseconds>(deadline - Clock::now()).count();
  if (left <= 0) return 0;
  const long long ms = (left + 999) / 1000;
  return ms > 1000000 ? 1000000 : static_cast<int>(ms);
}

/// Now plus `s` seconds.
inline Clock::time_point after_seconds(double s) noexcept {
  return Clock::now() + std::chrono::microseconds(static_cast<long long>(s * 1e6));
}

}  // namespace cmmcomp::ipp::net

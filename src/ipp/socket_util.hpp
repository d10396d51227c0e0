// SPDX-License-Identifier: MIT
/// @file What the I++ server and client share of POSIX sockets (private).
#pragma once

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <chrono>
#include <cmmcomp/exceptions.hpp>
#include <cstdint>
#include <cstring>
#include <string>

namespace cmmcomp::ipp::detail {

/// The IPv4 address of `host` (a dotted address or a name); throws Error.
inline sockaddr_in resolve(const std::string& host, std::uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  if (inet_pton(AF_INET, host.c_str(), &a.sin_addr) == 1) return a;
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (getaddrinfo(host.c_str(), nullptr, &hints, &found) != 0 || found == nullptr) {
    throw Error("I++: cannot resolve host '" + host + "'");
  }
  a.sin_addr = reinterpret_cast<sockaddr_in*>(found->ai_addr)->sin_addr;
  freeaddrinfo(found);
  return a;
}

using Clock = std::chrono::steady_clock;

/// Milliseconds from now until `deadline`, at least 0, rounded up (a poll timeout).
inline int ms_until(Clock::time_point deadline) {
  const auto left =
      std::chrono::duration_cast<std::chrono::microseconds>(deadline - Clock::now()).count();
  if (left <= 0) return 0;
  const long long ms = (left + 999) / 1000;
  return ms > 1000000 ? 1000000 : static_cast<int>(ms);
}

inline Clock::time_point after_seconds(double s) {
  return Clock::now() + std::chrono::microseconds(static_cast<long long>(s * 1e6));
}

}  // namespace cmmcomp::ipp::detail

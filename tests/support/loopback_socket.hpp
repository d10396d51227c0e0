// SPDX-License-Identifier: MIT
/// @file A raw TCP connection to 127.0.0.1, for tests that send what a well-behaved client
/// library would not (malformed frames, half frames, idle connections).
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <cstdint>

namespace cmmcomp::test {

/// A blocking TCP connection to 127.0.0.1:`port` whose receives time out after
/// `receive_timeout_s` (0: never); -1 when it cannot connect.
inline int raw_connect(int port, int receive_timeout_s = 0) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
    ::close(fd);
    return -1;
  }
  if (receive_timeout_s > 0) {
    timeval tv{receive_timeout_s, 0};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  }
  return fd;
}

}  // namespace cmmcomp::test

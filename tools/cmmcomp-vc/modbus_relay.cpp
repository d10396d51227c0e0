// SPDX-License-Identifier: MIT
/// @file The recording relay. Runs on its own thread; the client blocks on its answers, so at
/// most one request is in flight and the transcript is in wire order.
#include "modbus_relay.hpp"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmmcomp/vc/correction_source.hpp>
#include <cstring>

#include "recording_format.hpp"

namespace cmmcomp::vc {

std::vector<std::vector<std::uint8_t>> MbapSplitter::feed(const std::uint8_t* data,
                                                          std::size_t size) {
  buffer_.insert(buffer_.end(), data, data + size);
  std::vector<std::vector<std::uint8_t>> out;
  constexpr std::size_t kHeader = 6;
  while (buffer_.size() >= kHeader) {
    const std::size_t length = (static_cast<std::size_t>(buffer_[4]) << 8) | buffer_[5];
    const std::size_t total = kHeader + length;
    if (buffer_.size() < total) break;
    out.emplace_back(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(total));
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(total));
  }
  return out;
}

namespace {

int connect_tcp(const std::string& host, int port) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* list = nullptr;
  const std::string service = std::to_string(port);
  const int rc = getaddrinfo(host.c_str(), service.c_str(), &hints, &list);
  if (rc != 0) {
    throw UnreachableError("agent " + host + ":" + service + ": " + gai_strerror(rc));
  }
  int fd = -1;
  int last = 0;
  for (addrinfo* a = list; a != nullptr && fd < 0; a = a->ai_next) {
    fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) {
      last = errno;
      continue;
    }
    if (::connect(fd, a->ai_addr, a->ai_addrlen) != 0) {
      last = errno;
      ::close(fd);
      fd = -1;
    }
  }
  freeaddrinfo(list);
  if (fd < 0) {
    throw UnreachableError("agent " + host + ":" + service +
                           " unreachable: " + std::strerror(last));
  }
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  return fd;
}

bool write_all(int fd, const std::uint8_t* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::send(fd, data, size, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

}  // namespace

ModbusRecordingRelay::ModbusRecordingRelay(const std::string& host,
                                           int port,
                                           const std::string& path,
                                           const std::string& header) {
  upstream_ = connect_tcp(host, port);
  out_.open(path, std::ios::binary | std::ios::trunc);
  if (!out_) {
    ::close(upstream_);
    throw Error("cannot write the recording " + path);
  }
  out_ << header;
  listener_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = 0;
  socklen_t len = sizeof addr;
  // sockaddr_in is the address family's view of sockaddr: the cast is what the API expects.
  auto* sa = reinterpret_cast<sockaddr*>(&addr);
  if (listener_ < 0 || ::bind(listener_, sa, sizeof addr) != 0 || ::listen(listener_, 1) != 0 ||
      ::getsockname(listener_, sa, &len) != 0) {
    const int e = errno;
    if (listener_ >= 0) ::close(listener_);
    ::close(upstream_);
    throw Error(std::string("recording relay: cannot listen on loopback: ") + std::strerror(e));
  }
  port_ = ntohs(addr.sin_port);
  thread_ = std::thread([this] { run(); });
}

ModbusRecordingRelay::~ModbusRecordingRelay() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  if (listener_ >= 0) ::close(listener_);
  if (upstream_ >= 0) ::close(upstream_);
  out_.flush();
}

void ModbusRecordingRelay::run() noexcept {
  int client = -1;
  while (!stop_ && client < 0) {
    pollfd p{listener_, POLLIN, 0};
    if (::poll(&p, 1, 50) > 0) client = ::accept4(listener_, nullptr, nullptr, SOCK_CLOEXEC);
  }
  if (client < 0) return;
  const int one = 1;
  ::setsockopt(client, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  MbapSplitter from_client;
  MbapSplitter from_agent;
  std::uint8_t buf[4096];
  bool open = true;
  while (open && !stop_) {
    pollfd fds[2] = {{client, POLLIN, 0}, {upstream_, POLLIN, 0}};
    const int n = ::poll(fds, 2, 50);
    if (n <= 0) continue;
    for (int i = 0; i < 2 && open; ++i) {
      if ((fds[i].revents & (POLLIN | POLLHUP | POLLERR)) == 0) continue;
      const ssize_t got = ::recv(fds[i].fd, buf, sizeof buf, 0);
      if (got <= 0) {
        open = false;
        break;
      }
      const auto size = static_cast<std::size_t>(got);
      const std::int64_t t = now_us();
      MbapSplitter& splitter = i == 0 ? from_client : from_agent;
      const WireDirection dir = i == 0 ? WireDirection::kTx : WireDirection::kRx;
      for (const auto& adu : splitter.feed(buf, size)) {
        out_ << modbus_transcript_line(t, dir, adu.data(), adu.size());
      }
      if (!write_all(i == 0 ? upstream_ : client, buf, size)) open = false;
    }
  }
  out_.flush();
  ::shutdown(upstream_, SHUT_RDWR);
  ::close(client);
}

}  // namespace cmmcomp::vc

// SPDX-License-Identifier: MIT
/// @file A raw CAN socket playing the controller in HIL tests and the latency benchmark.
#pragma once

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmmcomp/error.hpp>
#include <cmmcomp/plugins/can_protocol.hpp>
#include <cstring>
#include <string>

namespace cmmcomp::test {

/// A CAN_RAW socket on `interface` that receives identifiers base … base + 3 (not its own).
class CanPeer {
 public:
  CanPeer(const std::string& interface, std::uint32_t base_id) {
    fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
    if (fd_ < 0) throw Error("peer: socket(PF_CAN) failed: " + std::string(std::strerror(errno)));
    can_filter filter{};
    filter.can_id = base_id;
    filter.can_mask = (CAN_SFF_MASK & ~0x3u) | CAN_EFF_FLAG | CAN_RTR_FLAG;
    sockaddr_can address{};
    address.can_family = AF_CAN;
    address.can_ifindex = static_cast<int>(::if_nametoindex(interface.c_str()));
    if (address.can_ifindex == 0 ||
        ::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, &filter, sizeof filter) != 0 ||
        ::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
      ::close(fd_);
      throw Error("peer: cannot bind to " + interface);
    }
  }
  ~CanPeer() { ::close(fd_); }
  CanPeer(const CanPeer&) = delete;
  CanPeer& operator=(const CanPeer&) = delete;

  /// Sends a classic frame; `raw_id` may carry CAN_EFF_FLAG / CAN_RTR_FLAG.
  bool send(const plugins::can::Frame& f, std::uint32_t raw_id_flags = 0) const {
    can_frame k{};
    k.can_id = f.id | raw_id_flags;
    k.can_dlc = f.dlc;
    std::memcpy(k.data, f.data.data(), 8);
    return ::write(fd_, &k, sizeof k) == static_cast<ssize_t>(sizeof k);
  }

  /// Receives one frame within `timeout_ms`; false on timeout.
  bool receive(plugins::can::Frame& f, int timeout_ms) const {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, timeout_ms) <= 0) return false;
    can_frame k{};
    if (::read(fd_, &k, sizeof k) != static_cast<ssize_t>(sizeof k)) return false;
    f = plugins::can::Frame{};
    f.id = k.can_id & CAN_SFF_MASK;
    f.dlc = k.can_dlc;
    std::memcpy(f.data.data(), k.data, 8);
    return true;
  }

  /// Receives the next frame whose identifier is not `skip_id` (e.g. the heartbeat).
  bool receive_except(plugins::can::Frame& f, std::uint32_t skip_id, int timeout_ms) const {
    for (int i = 0; i < 64; ++i) {
      if (!receive(f, timeout_ms)) return false;
      if (f.id != skip_id) return true;
    }
    return false;
  }

 private:
  int fd_ = -1;
};

}  // namespace cmmcomp::test

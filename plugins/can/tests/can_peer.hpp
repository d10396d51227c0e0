// SPDX-License-Identifier: MIT
/// @file A raw CAN socket playing the controller in HIL tests and the latency benchmark.
#pragma once

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/plugins/can_protocol.hpp>
#include <cstring>
#include <string>

namespace cmmcomp::test {

/// A CAN_RAW socket on `interface` that receives identifiers base … base + 3 (not its own).
class CanPeer {
 public:
  /// With `fd`, the socket also sends and receives CAN FD frames (the interface must allow them).
  CanPeer(const std::string& interface, std::uint32_t base_id, bool fd = false) {
    fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
    if (fd_ < 0) throw Error("peer: socket(PF_CAN) failed: " + std::string(std::strerror(errno)));
    can_filter filter{};
    filter.can_id = base_id;
    filter.can_mask = (CAN_SFF_MASK & ~0x3u) | CAN_EFF_FLAG | CAN_RTR_FLAG;
    sockaddr_can address{};
    address.can_family = AF_CAN;
    address.can_ifindex = static_cast<int>(::if_nametoindex(interface.c_str()));
    const int on = 1;
    if (address.can_ifindex == 0 ||
        ::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, &filter, sizeof filter) != 0 ||
        (fd && ::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on) != 0) ||
        ::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
      ::close(fd_);
      throw Error("peer: cannot bind to " + interface);
    }
  }
  ~CanPeer() { ::close(fd_); }
  CanPeer(const CanPeer&) = delete;
  CanPeer& operator=(const CanPeer&) = delete;

  /// Sends `f` as a classic frame, or as a CAN FD frame of length f.dlc (≤ 64; bytes past the
  /// 8th are 0xAA) with `as_fd`; `raw_id_flags` may add CAN_EFF_FLAG / CAN_RTR_FLAG.
  bool send(const plugins::can::Frame& f,
            std::uint32_t raw_id_flags = 0,
            bool as_fd = false) const {
    canfd_frame k{};
    k.can_id = f.id | raw_id_flags;
    k.len = f.dlc;
    k.flags = as_fd ? CANFD_BRS : 0;
    std::memset(k.data, 0xAA, sizeof k.data);
    std::memcpy(k.data, f.data.data(), 8);
    const std::size_t size = as_fd ? CANFD_MTU : CAN_MTU;
    return ::write(fd_, &k, size) == static_cast<ssize_t>(size);
  }

  /// Receives one frame within `timeout_ms`; false on timeout. `*was_fd` (if given) tells
  /// whether it was a CAN FD frame.
  bool receive(plugins::can::Frame& f, int timeout_ms, bool* was_fd = nullptr) const {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, timeout_ms) <= 0) return false;
    canfd_frame k{};
    const ssize_t n = ::read(fd_, &k, sizeof k);
    if (n != static_cast<ssize_t>(CAN_MTU) && n != static_cast<ssize_t>(CANFD_MTU)) return false;
    if (was_fd != nullptr) *was_fd = n == static_cast<ssize_t>(CANFD_MTU);
    f = plugins::can::Frame{};
    f.id = k.can_id & CAN_SFF_MASK;
    f.dlc = k.len;
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

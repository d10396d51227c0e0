// SPDX-License-Identifier: MIT
/// @file SocketCAN client of the virtual controller.
#include "can_link.hpp"

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cmmcomp/plugins/can_protocol.hpp>
#include <cstdio>
#include <cstring>

#include "recording_format.hpp"

namespace cmmcomp::vc {

namespace can = plugins::can;

CanLink::CanLink(std::string label,
                 const std::string& interface,
                 std::uint32_t base_id,
                 int timeout_ms,
                 const std::string& record_path)
    : label_(std::move(label)), interface_(interface), base_id_(base_id), timeout_ms_(timeout_ms) {
  char id[16];
  std::snprintf(id, sizeof id, "0x%03X", base_id);
  where_ = "can " + interface + " " + id;
  if (base_id > can::kMaxStandardId - (can::kMessageCount - 1)) {
    throw ConfigError("CAN base id must be ≤ 0x7FC");
  }
  fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
  if (fd_ < 0) {
    const int e = errno;
    if (e == EAFNOSUPPORT) {
      throw UnreachableError(
          "no CAN support in this kernel (EAFNOSUPPORT): run inside scripts/uml-run.sh");
    }
    throw UnreachableError(std::string("CAN socket: ") + std::strerror(e));
  }
  const unsigned index = if_nametoindex(interface.c_str());
  if (index == 0) {
    ::close(fd_);
    fd_ = -1;
    throw UnreachableError("no such interface " + interface);
  }
  // Only the answers: base + 1 (response) and base + 2 (reject), standard data frames.
  can_filter filters[2];
  for (int i = 0; i < 2; ++i) {
    filters[i].can_id = base_id + can::kResponseOffset + static_cast<std::uint32_t>(i);
    filters[i].can_mask = CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG;
  }
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = static_cast<int>(index);
  // sockaddr_can is AF_CAN's view of sockaddr: the cast is what bind() expects.
  if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, filters, sizeof filters) != 0 ||
      ::bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
    const int e = errno;
    ::close(fd_);
    fd_ = -1;
    throw UnreachableError("CAN " + interface + ": " + std::strerror(e));
  }
  if (!record_path.empty()) {
    record_.open(record_path, std::ios::binary | std::ios::trunc);
    if (!record_) {
      ::close(fd_);
      fd_ = -1;
      throw Error("cannot write the recording " + record_path);
    }
  }
}

CanLink::~CanLink() {
  if (fd_ >= 0) ::close(fd_);
}

Answer CanLink::ask(const compensation::MoveRequest& move) {
  compensation::MoveRequest m = move;
  m.sequence = sequence_++ & can::kSequenceMask;
  can::RequestFrames frames{};
  can::RequestField bad = can::RequestField::kNone;
  Answer a;
  // Protocol version 2: WantInterval, so the answer carries U95 (response part 3).
  if (can::encode_request(m, base_id_, frames, &bad, /*want_interval=*/true) != Status::kOk) {
    a.note = "the move does not fit the CAN request (field " +
             std::to_string(static_cast<int>(bad)) + ")";
    a.status = -1;
    return a;
  }
  for (const can::Frame& f : frames) {
    can_frame raw{};
    raw.can_id = f.id;
    raw.can_dlc = f.dlc;
    std::memcpy(raw.data, f.data.data(), f.dlc);
    if (::write(fd_, &raw, sizeof raw) != static_cast<ssize_t>(sizeof raw)) {
      throw Error("agent '" + label_ + "' (" + where_ + "): send: " + std::strerror(errno));
    }
    if (record_.is_open()) record_ << candump_line(now_us(), interface_, f);
  }
  // Parts 0-2 (the result) and part 3 (the interval).
  constexpr int kParts = can::kIntervalPart + 1;
  std::array<can::Frame, kParts> parts{};
  int next_part = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms_);
  while (next_part < kParts) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                          deadline - std::chrono::steady_clock::now())
                          .count();
    if (left <= 0) {
      throw Error("agent '" + label_ + "' (" + where_ + "): no answer to sequence " +
                  std::to_string(m.sequence) + " within " + std::to_string(timeout_ms_) + " ms");
    }
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(left)) <= 0) continue;
    can_frame raw{};
    if (::read(fd_, &raw, sizeof raw) != static_cast<ssize_t>(sizeof raw)) continue;
    can::Frame f;
    f.id = raw.can_id & CAN_SFF_MASK;
    f.dlc = static_cast<std::uint8_t>(raw.can_dlc > 8 ? 8 : raw.can_dlc);
    std::memcpy(f.data.data(), raw.data, f.dlc);
    if (record_.is_open()) record_ << candump_line(now_us(), interface_, f);
    if (f.id == base_id_ + can::kRejectOffset) {
      can::RejectInfo r;
      if (can::decode_reject(f, base_id_, r) && r.sequence == m.sequence) {
        a.status = static_cast<int>(r.reason);
        a.note = std::string("rejected: ") + can::to_string(r.reason);
        if (r.reason == can::RejectReason::kReservedBits && r.part == 0) {
          a.note += " (an agent of CAN protocol version 1? the vc sets WantInterval)";
        }
        return a;
      }
      continue;
    }
    // A response part: keep it if it is the next part of our sequence (bits 0–1 part, 2–7 seq).
    const int part = f.data[0] & 0x3;
    const unsigned seq = static_cast<unsigned>(f.data[0] >> 2);
    if (seq != m.sequence) continue;
    if (part != next_part) {
      next_part = 0;
      if (part != 0) continue;
    }
    parts[static_cast<std::size_t>(part)] = f;
    ++next_part;
  }
  can::DecodedResponse d;
  if (!can::decode_response({parts[0], parts[1], parts[2]}, base_id_, d) ||
      !can::decode_interval(parts[can::kIntervalPart], base_id_, d)) {
    a.note = "malformed response";
    a.status = -1;
    return a;
  }
  // As over Modbus: `flags` has the version-1 bits, `interval_flags` every flag (with
  // kFlagNoUncertainty when the model has no calibration). A saturated U95 reads 81.9 µm.
  a.flags = d.correction.flags & compensation::kFlagsVersion1;
  a.interval_flags = d.correction.flags;
  a.u95_um = d.correction.u95_um;
  a.rae_um = d.correction.rae_um;
  a.correction_um = d.correction.correction_um;
  a.model_id = d.correction.model_id;
  if ((a.flags & compensation::kFlagOk) == 0) {
    a.note = "flags without OK";
  } else {
    a.usable = true;
  }
  return a;
}

}  // namespace cmmcomp::vc

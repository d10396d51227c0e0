// SPDX-License-Identifier: MIT
/// @file A raw SocketCAN server (PF_CAN/CAN_RAW) that answers move requests with the
/// corrections of a compensation::MoveCompensator (protocol: docs/protocol-can.md).
#pragma once

#include <atomic>
#include <chrono>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/compensation/outcome_log.hpp>
#include <cmmcomp/plugins/can_protocol.hpp>
#include <cmmcomp/plugins/can_request_handler.hpp>
#include <cstdint>
#include <string>

namespace cmmcomp::plugins {

/// Parses a base identifier as a user writes it ("0x300", "768"): digits only (no blank, no
/// sign), an 11-bit standard id that leaves room for the protocol's four messages (≤ 0x7FC). Setup
/// only. Throws ConfigError
/// "--can-base-id '…': expected an 11-bit id ≤ 0x7FC, e.g. 0x300".
std::uint32_t parse_can_base_id(const std::string& text);

/// Whether `name` can name a Linux network interface: 1 to 15 bytes (IFNAMSIZ − 1), no '/', no
/// blank or control character, not "." or "..". Setup only; `why` gets the reason when not.
bool is_valid_can_interface_name(const std::string& name, std::string* why = nullptr);

/// A base identifier as users write it and the tools print it: "0x300". parse_can_base_id reads
/// it back; the tools' --can-base-id defaults are format_can_base_id(can::kDefaultBaseId).
std::string format_can_base_id(std::uint32_t id);

/// Options of a CanServer, fixed at construction.
struct CanServerOptions {
  std::string interface = "vcan0";              ///< CAN network interface (vcan0, can0, …)
  std::uint32_t base_id = can::kDefaultBaseId;  ///< 11-bit base identifier; base + 3 ≤ 0x7FF
  /// Longest gap allowed between two parts of a request; > 0.
  std::chrono::milliseconds part_timeout{50};
  /// Period of the heartbeat (five frames); 0 turns it off.
  std::chrono::milliseconds heartbeat_period{1000};
  /// CAN FD bus: also accept the protocol's frames as CAN FD frames (CAN_RAW_FD_FRAMES) and
  /// answer each request in the format it came in (FD frames with 8 data bytes and bit-rate
  /// switch). The interface must have the CAN FD MTU (72). The payload layout is the classic
  /// one either way; a frame longer than 8 bytes is rejected (reason 1, wrong DLC).
  bool fd = false;
  /// Where the handler reports every refused request and outside-domain answer (null: nowhere);
  /// it must outlive the server. cmmcomp-agent logs them, rate-limited.
  compensation::ServerOutcomeLog* outcome_log = nullptr;

  /// True when every field is usable; otherwise false and, if `why` is given, the reason.
  bool is_valid(std::string* why = nullptr) const;
};

/// Serves one compensator on one CAN interface from the thread that calls run().
class CanServer {
 public:
  /// Opens a PF_CAN/CAN_RAW socket, keeps only the request identifier (CAN_RAW_FILTER) and
  /// binds it to `options.interface` (with `options.fd`: enables CAN_RAW_FD_FRAMES and checks
  /// that the interface is a CAN FD one). Setup only. Throws cmmcomp::ConfigError for invalid
  /// options and cmmcomp::Error when the socket cannot be set up, with the reason ("no CAN
  /// support in this kernel (EAFNOSUPPORT) …", "no such interface vcan9", …).
  /// `compensator` must outlive the server; models may be published into it at any time.
  CanServer(const compensation::MoveCompensator& compensator, const CanServerOptions& options);
  ~CanServer();
  CanServer(const CanServer&) = delete;
  CanServer& operator=(const CanServer&) = delete;

  /// Where it serves, e.g. "SocketCAN vcan0, base id 0x300".
  std::string where() const;

  /// Serves until `stop` becomes true (noticed within 100 ms): answers requests, expires
  /// incomplete ones, sends the heartbeat. Per frame it allocates nothing and throws nothing.
  /// Throws cmmcomp::Error only if the socket fails for good (e.g. the interface is deleted).
  void run(const std::atomic<bool>& stop);

  /// The counters so far. Any thread.
  CanCounters counters() const noexcept { return handler_.counters(); }

  /// The options given at construction.
  const CanServerOptions& options() const noexcept { return options_; }

 private:
  void send(const CanFrameBatch& batch, bool as_fd) noexcept;
  void send_heartbeat() noexcept;

  CanServerOptions options_;
  CanRequestHandler handler_;
  int socket_ = -1;
  bool last_request_fd_ = false;  ///< format of the last request frame: rejects by timeout use it
};

}  // namespace cmmcomp::plugins

// SPDX-License-Identifier: MIT
/// @file The virtual controller's SocketCAN client (raw socket), optionally recording a candump
/// log.
#pragma once

#include <cmmcomp/vc/correction_source.hpp>
#include <cstdint>
#include <fstream>
#include <string>

namespace cmmcomp::vc {

/// Asks one agent over CAN (docs/protocol-can.md, protocol version 2): three request frames with
/// WantInterval, then waits for the four response frames of the same sequence (the result and
/// the interval: U95 and its flags, as over Modbus) or a reject. The socket's kernel filter passes
/// only the response and reject identifiers, so heartbeats and other traffic never reach it
/// (and never reach the recording: it stays deterministic).
class CanLink final : public CorrectionSource {
 public:
  /// Opens a raw CAN socket on `interface`. Throws UnreachableError for a kernel without CAN
  /// or a missing interface, ConfigError for a bad base id, Error when `record_path` cannot be
  /// written.
  CanLink(std::string label,
          const std::string& interface,
          std::uint32_t base_id,
          int timeout_ms,
          const std::string& record_path);
  ~CanLink() override;
  CanLink(const CanLink&) = delete;
  CanLink& operator=(const CanLink&) = delete;

  Answer ask(const compensation::MoveRequest& move) override;
  const std::string& label() const noexcept override { return label_; }
  const std::string& where() const noexcept override { return where_; }

 private:
  std::string label_;
  std::string where_;
  std::string interface_;
  std::uint32_t base_id_;
  int timeout_ms_;
  int fd_ = -1;
  std::uint32_t sequence_ = 0;
  std::ofstream record_;
};

}  // namespace cmmcomp::vc

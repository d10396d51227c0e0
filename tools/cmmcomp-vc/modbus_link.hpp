// SPDX-License-Identifier: MIT
/// @file The virtual controller's Modbus TCP client (libmodbus), optionally through the
/// recording relay.
#pragma once

#include <cmmcomp/vc/correction_source.hpp>
#include <memory>
#include <string>

namespace cmmcomp::vc {

/// Asks one agent over Modbus TCP: one FC23 transaction per move (write holding 0–24, read the
/// result copy 25–47), so no other client's result can come between (docs/protocol-modbus.md).
class ModbusLink final : public CorrectionSource {
 public:
  /// Connects (throws UnreachableError when the agent does not answer the connection, ConfigError
  /// for a bad endpoint). With `record_path` non-empty the session goes through a recording
  /// relay into that transcript.
  ModbusLink(std::string label,
             const std::string& endpoint,
             int unit_id,
             int timeout_ms,
             const std::string& record_path);
  ~ModbusLink() override;
  ModbusLink(const ModbusLink&) = delete;
  ModbusLink& operator=(const ModbusLink&) = delete;

  Answer ask(const compensation::MoveRequest& move) override;
  const std::string& label() const noexcept override { return label_; }
  const std::string& where() const noexcept override { return where_; }

 private:
  struct Impl;  // the libmodbus context and the relay: libmodbus's header stays in the .cpp
  std::string label_;
  std::string where_;
  std::unique_ptr<Impl> impl_;
  std::uint16_t sequence_ = 0;
};

}  // namespace cmmcomp::vc

// SPDX-License-Identifier: MIT
/// @file A recording TCP relay between the virtual controller's libmodbus client and an agent:
/// forwards every byte unchanged and writes each Modbus TCP ADU to a transcript.
#pragma once

#include <atomic>
#include <cstdint>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace cmmcomp::vc {

/// Splits a Modbus TCP byte stream into ADUs by the MBAP length field (bytes 4–5: the number of
/// bytes that follow it, unit id included).
class MbapSplitter {
 public:
  /// Appends `size` bytes; returns the ADUs completed by them, in order.
  std::vector<std::vector<std::uint8_t>> feed(const std::uint8_t* data, std::size_t size);
  /// Bytes of an incomplete ADU still held.
  std::size_t pending() const noexcept { return buffer_.size(); }

 private:
  std::vector<std::uint8_t> buffer_;
};

/// Listens on 127.0.0.1 (a port the kernel picks), accepts one client, connects it to the agent
/// and relays until either side closes or the relay is destroyed. Every ADU goes to `path` as a
/// transcript line (docs/recordings.md), stamped when its last byte arrived.
class ModbusRecordingRelay {
 public:
  /// Connects to the agent at HOST:PORT first (throws UnreachableError when that fails), then
  /// listens and starts the relay thread. Throws Error when `path` cannot be written.
  ModbusRecordingRelay(const std::string& host,
                       int port,
                       const std::string& path,
                       const std::string& header);
  ~ModbusRecordingRelay();
  ModbusRecordingRelay(const ModbusRecordingRelay&) = delete;
  ModbusRecordingRelay& operator=(const ModbusRecordingRelay&) = delete;

  /// The local port to connect the client to.
  int port() const noexcept { return port_; }

 private:
  void run() noexcept;

  int upstream_ = -1;
  int listener_ = -1;
  int port_ = 0;
  std::ofstream out_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace cmmcomp::vc

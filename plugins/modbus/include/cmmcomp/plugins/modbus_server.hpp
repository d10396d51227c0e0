// SPDX-License-Identifier: MIT
/// @file A libmodbus server (Modbus TCP with several clients, or RTU on a serial line) that
/// serves a compensation::MoveCompensator with the register map of docs/protocol-modbus.md.
///
/// libmodbus types stay in modbus_server.cpp (dependency wall: only plugins see libmodbus).
#pragma once

#include <atomic>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/compensation/outcome_log.hpp>
#include <cmmcomp/plugins/modbus_request_handler.hpp>
#include <cstdint>
#include <memory>
#include <string>

namespace cmmcomp::plugins {

/// Where the server listens: "tcp:HOST:PORT" (HOST an IPv4 address, a name, or [IPv6]) or
/// "rtu:DEVICE:BAUD[,FRAMING]" with FRAMING = data bits (7|8), parity (N|E|O), stop bits (1|2),
/// e.g. "rtu:/dev/ttyUSB0:115200,8N1" (default framing 8E1, the Modbus default).
struct ModbusEndpoint {
  enum class Kind : std::uint8_t { kTcp, kRtu };
  Kind kind = Kind::kTcp;
  std::string host = "127.0.0.1";  ///< TCP: address or name to bind
  int port = 502;                  ///< TCP: port, 1 .. 65535
  std::string device;              ///< RTU: serial device, e.g. /dev/ttyUSB0
  int baud = 19200;                ///< RTU: bits per second
  int data_bits = 8;               ///< RTU: 7 or 8
  char parity = 'E';               ///< RTU: 'N', 'E' or 'O'
  int stop_bits = 1;               ///< RTU: 1 or 2

  /// Parses `text` (format above). Setup only. Throws cmmcomp::ConfigError naming the part that
  /// is wrong, e.g. "Modbus endpoint 'tcp:localhost:99999': port must be 1..65535".
  static ModbusEndpoint parse(const std::string& text);

  /// "tcp:HOST:PORT" or "rtu:DEVICE:BAUD,8E1" — parse(to_string()) gives the same endpoint.
  std::string to_string() const;
};

/// Options of a ModbusServer, fixed at construction.
/// TCP frames are assembled per client without blocking, so no client delays another; the
/// timeouts only decide when a connection is closed (docs/protocol-modbus.md, "Connections and
/// timeouts").
struct ModbusServerOptions {
  int unit_id = 1;  ///< unit id (slave address) served, 1 .. 247
  /// TCP connections served at once. When all are taken, a new connection replaces the one
  /// idle longest if that one has been idle evict_idle_ms; otherwise it is closed at once.
  int max_tcp_clients = 16;
  /// Longest gap between two bytes of one frame [ms] (TCP and RTU): then the frame is dropped
  /// (TCP: with its connection; RTU: the line is flushed). On RTU, libmodbus reads a frame
  /// with this byte timeout, so a stalled frame holds the line for at most this.
  int byte_timeout_ms = 100;
  /// TCP: longest time from a frame's first byte to its last [ms], byte_timeout_ms .. 60000:
  /// a client trickling bytes just inside the byte timeout is closed after this.
  int frame_timeout_ms = 1000;
  /// TCP: a connection without a complete request for this long is closed [ms]; 0 = never.
  int idle_timeout_ms = 60000;
  /// TCP: how long a connection must have been idle before a new one may replace it when all
  /// max_tcp_clients are taken [ms].
  int evict_idle_ms = 1000;
  /// Longest the server waits for I/O before looking at the stop flag and the timeouts again
  /// [ms] (the timeouts above are kept to within this).
  int poll_interval_ms = 50;
  /// Where the handler reports every refused request and outside-domain answer (null: nowhere);
  /// it must outlive the server. cmmcomp-agent logs them, rate-limited.
  compensation::ServerOutcomeLog* outcome_log = nullptr;

  /// True when every field is usable; otherwise false and, if `why` is given, the reason.
  bool is_valid(std::string* why = nullptr) const;
};

/// Serves one compensator on one endpoint, from the thread that calls `run`.
class ModbusServer {
 public:
  /// Binds and listens (TCP) or opens and configures the serial device (RTU). Setup only.
  /// Throws cmmcomp::ConfigError for invalid options and cmmcomp::Error with the endpoint and the
  /// system's reason when it cannot (port in use, no such device, permission denied).
  /// `compensator` must outlive the server; its models may be republished from other threads.
  ModbusServer(const compensation::MoveCompensator& compensator,
               const ModbusEndpoint& endpoint,
               const ModbusServerOptions& options = {});
  ~ModbusServer();
  ModbusServer(const ModbusServer&) = delete;
  ModbusServer& operator=(const ModbusServer&) = delete;

  /// e.g. "Modbus TCP 127.0.0.1:1502, unit 1" or "Modbus RTU /dev/ttyUSB0 115200 8N1, unit 1".
  std::string where() const;

  /// Serves requests until `stop` is true (noticed within poll_interval_ms; on RTU plus one
  /// frame's byte timeout). Call from one thread at a time. Throws cmmcomp::Error only when the
  /// listening socket or the serial device fails (not for a client's error: that client is
  /// dropped and counted).
  void run(const std::atomic<bool>& stop);

  /// What the server has done so far. Any thread.
  ModbusCounters counters() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cmmcomp::plugins

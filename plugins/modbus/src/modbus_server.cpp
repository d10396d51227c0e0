// SPDX-License-Identifier: MIT
/// @file ModbusServer: libmodbus framing and sockets around ModbusRequestHandler.
#include <fcntl.h>
#include <modbus.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/plugins/modbus_server.hpp>
#include <cstring>
#include <vector>

#include "modbus_frame.hpp"

namespace cmmcomp::plugins {

namespace {

bool all_digits(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
  }
  return true;
}

[[noreturn]] void bad_endpoint(const std::string& text, const std::string& why) {
  throw ConfigError("Modbus endpoint '" + text + "': " + why +
                    " (expected tcp:HOST:PORT or rtu:DEVICE:BAUD[,8N1])");
}

/// Parses a decimal number in [lo, hi] or throws naming `what`.
int parse_int(const std::string& text, const std::string& s, const char* what, long lo, long hi) {
  if (!all_digits(s) || s.size() > 9) {
    bad_endpoint(text, std::string(what) + " '" + s + "' is not a number");
  }
  const long v = std::stol(s);
  if (v < lo || v > hi) {
    bad_endpoint(text,
                 std::string(what) + " must be " + std::to_string(lo) + ".." + std::to_string(hi) +
                     ", not " + s);
  }
  return static_cast<int>(v);
}

std::string errno_text(int err) { return modbus_strerror(err); }

}  // namespace

// ---- endpoint

ModbusEndpoint ModbusEndpoint::parse(const std::string& text) {
  ModbusEndpoint e;
  if (text.rfind("tcp:", 0) == 0) {
    e.kind = Kind::kTcp;
    const std::string rest = text.substr(4);
    std::string port;
    if (!rest.empty() && rest[0] == '[') {  // [IPv6]:PORT
      const std::size_t close = rest.find(']');
      if (close == std::string::npos || close + 1 >= rest.size() || rest[close + 1] != ':') {
        bad_endpoint(text, "an IPv6 address must be written [ADDRESS]:PORT");
      }
      e.host = rest.substr(1, close - 1);
      port = rest.substr(close + 2);
    } else {
      const std::size_t colon = rest.rfind(':');
      if (colon == std::string::npos) bad_endpoint(text, "no port after the host");
      e.host = rest.substr(0, colon);
      port = rest.substr(colon + 1);
    }
    if (e.host.empty()) bad_endpoint(text, "the host is empty");
    e.port = parse_int(text, port, "port", 1, 65535);
    return e;
  }
  if (text.rfind("rtu:", 0) == 0) {
    e.kind = Kind::kRtu;
    const std::string rest = text.substr(4);
    const std::size_t colon = rest.rfind(':');
    if (colon == std::string::npos) bad_endpoint(text, "no baud rate after the device");
    e.device = rest.substr(0, colon);
    if (e.device.empty()) bad_endpoint(text, "the serial device is empty");
    std::string settings = rest.substr(colon + 1);
    std::string framing = "8E1";
    const std::size_t comma = settings.find(',');
    if (comma != std::string::npos) {
      framing = settings.substr(comma + 1);
      settings = settings.substr(0, comma);
    }
    e.baud = parse_int(text, settings, "baud rate", 50, 4000000);
    if (framing.size() != 3 || (framing[0] != '7' && framing[0] != '8') ||
        (framing[2] != '1' && framing[2] != '2')) {
      bad_endpoint(text, "framing '" + framing + "' is not DATA PARITY STOP, e.g. 8N1 or 8E1");
    }
    const char parity = framing[1] == 'n'   ? 'N'
                        : framing[1] == 'e' ? 'E'
                        : framing[1] == 'o' ? 'O'
                                            : framing[1];
    if (parity != 'N' && parity != 'E' && parity != 'O') {
      bad_endpoint(text, std::string("parity '") + framing[1] + "' is not N, E or O");
    }
    e.data_bits = framing[0] - '0';
    e.parity = parity;
    e.stop_bits = framing[2] - '0';
    return e;
  }
  bad_endpoint(text, "unknown transport");
}

std::string ModbusEndpoint::to_string() const {
  if (kind == Kind::kTcp) {
    const bool v6 = host.find(':') != std::string::npos;
    return "tcp:" + (v6 ? "[" + host + "]" : host) + ":" + std::to_string(port);
  }
  return "rtu:" + device + ":" + std::to_string(baud) + "," + std::to_string(data_bits) + parity +
         std::to_string(stop_bits);
}

bool ModbusServerOptions::is_valid(std::string* why) const {
  const auto fail = [why](const char* reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (unit_id < 1 || unit_id > 247) return fail("unit_id must be 1..247");
  if (max_tcp_clients < 1 || max_tcp_clients > 1024) return fail("max_tcp_clients must be 1..1024");
  if (byte_timeout_ms < 1 || byte_timeout_ms > 10000)
    return fail("byte_timeout_ms must be 1..10000");
  if (poll_interval_ms < 1 || poll_interval_ms > 1000) {
    return fail("poll_interval_ms must be 1..1000");
  }
  if (frame_timeout_ms < byte_timeout_ms || frame_timeout_ms > 60000) {
    return fail("frame_timeout_ms must be byte_timeout_ms..60000");
  }
  if (idle_timeout_ms < 0 || idle_timeout_ms > 86400000) {
    return fail("idle_timeout_ms must be 0 (never)..86400000");
  }
  if (evict_idle_ms < 0 || evict_idle_ms > 86400000) {
    return fail("evict_idle_ms must be 0..86400000");
  }
  return true;
}

// ---- server

struct ModbusServer::Impl {
  using Clock = std::chrono::steady_clock;

  /// One Modbus TCP connection: the frame it is sending, assembled without blocking.
  struct Client {
    int fd = -1;
    std::array<std::uint8_t, detail::kMaxTcpAduLength> frame{};
    std::size_t have = 0;            // bytes of the current frame so far
    Clock::time_point frame_start;   // its first byte
    Clock::time_point last_byte;     // its latest byte
    Clock::time_point last_request;  // the last complete request (or the connection)
  };

  Impl(const compensation::MoveCompensator& compensator,
       const ModbusEndpoint& ep,
       const ModbusServerOptions& opts)
      : endpoint(ep),
        options(opts),
        handler(
            compensator,
            static_cast<std::uint8_t>(opts.unit_id),
            ep.kind == ModbusEndpoint::Kind::kTcp ? ModbusTransport::kTcp : ModbusTransport::kRtu) {
    handler.set_outcome_log(opts.outcome_log);
    mapping.tab_registers = handler.holding().data();
    mapping.nb_registers = modbus::kHoldingCount;
    mapping.tab_input_registers = handler.input().data();
    mapping.nb_input_registers = modbus::kInputCount;
  }

  ~Impl() {
    if (ctx != nullptr) {
      modbus_set_socket(ctx, tcp() ? -1 : serial_fd);  // our client sockets are closed below
      if (!tcp()) modbus_close(ctx);
      modbus_free(ctx);
    }
    for (const Client& c : clients) ::close(c.fd);
    if (listen_fd >= 0) ::close(listen_fd);
  }

  bool tcp() const { return endpoint.kind == ModbusEndpoint::Kind::kTcp; }

  std::string where() const {
    if (tcp()) {  // HOST:PORT, an IPv6 address in brackets
      return "Modbus TCP " + endpoint.to_string().substr(4) + ", unit " +
             std::to_string(options.unit_id);
    }
    return "Modbus RTU " + endpoint.device + " " + std::to_string(endpoint.baud) + " " +
           std::to_string(endpoint.data_bits) + endpoint.parity +
           std::to_string(endpoint.stop_bits) + ", unit " + std::to_string(options.unit_id);
  }

  void open() {
    const std::string name = where();
    if (tcp()) {
      const std::string port = std::to_string(endpoint.port);
      ctx = modbus_new_tcp_pi(endpoint.host.c_str(), port.c_str());
      if (ctx == nullptr) throw Error(name + ": cannot create the context: " + errno_text(errno));
      listen_fd = modbus_tcp_pi_listen(ctx, options.max_tcp_clients);
      if (listen_fd < 0) throw Error(name + ": cannot listen: " + errno_text(errno));
      ::fcntl(listen_fd, F_SETFD, FD_CLOEXEC);
      ::fcntl(listen_fd, F_SETFL, ::fcntl(listen_fd, F_GETFL) | O_NONBLOCK);
      clients.reserve(static_cast<std::size_t>(options.max_tcp_clients));
      // Frames are assembled here; libmodbus reads each complete one from the loopback.
      loopback = std::make_unique<detail::AduLoopback>();
      detail::set_loopback_timeouts(ctx);
    } else {
      ctx = modbus_new_rtu(endpoint.device.c_str(),
                           endpoint.baud,
                           endpoint.parity,
                           endpoint.data_bits,
                           endpoint.stop_bits);
      if (ctx == nullptr) throw Error(name + ": invalid serial settings: " + errno_text(errno));
      if (modbus_set_slave(ctx, options.unit_id) != 0 || modbus_connect(ctx) != 0) {
        throw Error(name + ": cannot open " + endpoint.device + ": " + errno_text(errno));
      }
      serial_fd = modbus_get_socket(ctx);
      const auto us = static_cast<std::uint32_t>(options.byte_timeout_ms) * 1000u;
      modbus_set_byte_timeout(ctx, us / 1000000u, us % 1000000u);
      modbus_set_indication_timeout(ctx, us / 1000000u, us % 1000000u);
    }
    fds.reserve(static_cast<std::size_t>(options.max_tcp_clients) + 1);
  }

  void run(const std::atomic<bool>& stop) {
    while (!stop.load(std::memory_order_relaxed)) {
      fds.clear();  // capacity reserved in open(): no allocation here
      if (tcp()) {
        fds.push_back({listen_fd, POLLIN, 0});
        for (const Client& c : clients) fds.push_back({c.fd, POLLIN, 0});
      } else {
        fds.push_back({serial_fd, POLLIN, 0});
      }
      const int n = ::poll(fds.data(), static_cast<nfds_t>(fds.size()), options.poll_interval_ms);
      if (n < 0) {
        if (errno == EINTR) continue;
        throw Error(where() + ": poll failed: " + errno_text(errno));
      }
      if (!tcp()) {
        if (n == 0) continue;
        if ((fds[0].revents & POLLIN) != 0) {
          serve_serial_frame();
        } else if ((fds[0].revents & (POLLHUP | POLLERR | POLLNVAL)) != 0) {
          throw Error(where() + ": the serial device hung up or failed");
        }
        continue;
      }
      // Clients first (their indexes in `fds` match `clients` before accept or a drop changes
      // it; a drop moves the last client into the slot, which this backward walk has seen).
      // Each client gets at most one frame's work per round, so none can hold the others.
      const Clock::time_point now = Clock::now();
      for (std::size_t i = fds.size(); i-- > 1;) {
        const bool keep = fds[i].revents != 0 ? serve_client(clients[i - 1], now)
                                              : within_timeouts(clients[i - 1], now);
        if (!keep) drop_client(i - 1);
      }
      if ((fds[0].revents & POLLIN) != 0) accept_client(now);
    }
  }

  static long long ms_between(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration_cast<std::chrono::milliseconds>(b - a).count();
  }

  /// False when the client's frame has stalled or trickled too long, or it has been idle too
  /// long (docs/protocol-modbus.md, "Connections and timeouts").
  bool within_timeouts(const Client& c, Clock::time_point now) {
    if (c.have > 0 && (ms_between(c.last_byte, now) > options.byte_timeout_ms ||
                       ms_between(c.frame_start, now) > options.frame_timeout_ms)) {
      handler.note_receive_error();
      return false;
    }
    if (c.have == 0 && options.idle_timeout_ms > 0 &&
        ms_between(c.last_request, now) > options.idle_timeout_ms) {
      handler.note_client_idle_closed();
      return false;
    }
    return true;
  }

  void accept_client(Clock::time_point now) {
    const int fd = ::accept4(listen_fd, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
    if (fd < 0) return;  // the peer gave up already, or out of descriptors: try again later
    if (clients.size() >= static_cast<std::size_t>(options.max_tcp_clients)) {
      // Full: the connection idle longest gives way, if it has been idle evict_idle_ms.
      std::size_t oldest = 0;
      for (std::size_t i = 1; i < clients.size(); ++i) {
        if (clients[i].last_request < clients[oldest].last_request) oldest = i;
      }
      if (clients[oldest].have > 0 ||
          ms_between(clients[oldest].last_request, now) < options.evict_idle_ms) {
        ::close(fd);
        handler.note_client_refused();
        return;
      }
      handler.note_client_evicted();
      drop_client(oldest);
    }
    const int one = 1;
    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    Client c;
    c.fd = fd;
    c.last_request = now;
    clients.push_back(c);  // capacity reserved in open()
    handler.note_client_connected();
  }

  void drop_client(std::size_t index) {
    ::close(clients[index].fd);
    clients[index] = clients.back();
    clients.pop_back();
    handler.note_client_closed();
  }

  /// Reads what the client sent, up to the end of its current frame, and answers the frame
  /// when it is complete; false when the client must be dropped.
  bool serve_client(Client& c, Clock::time_point now) {
    // Read only up to the end of the current frame: the next one stays in the socket for the
    // next round. Before the header is complete, read up to the header.
    const detail::MbapVerdict before = detail::judge_mbap(c.frame.data(), c.have);
    const std::size_t want =
        c.have < detail::kMbapHeaderLength ? detail::kMbapHeaderLength : before.adu_length;
    const ssize_t got = ::recv(c.fd, c.frame.data() + c.have, want - c.have, MSG_DONTWAIT);
    if (got == 0) {  // the peer closed: normal between frames, a lost frame inside one
      if (c.have > 0) handler.note_receive_error();
      return false;
    }
    if (got < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return within_timeouts(c, now);
      if (c.have > 0) handler.note_receive_error();
      return false;  // reset by the peer
    }
    if (c.have == 0) c.frame_start = now;
    c.have += static_cast<std::size_t>(got);
    c.last_byte = now;
    const detail::MbapVerdict v = detail::judge_mbap(c.frame.data(), c.have);
    if (v.kind == detail::MbapVerdict::Kind::kInvalid) {
      handler.note_receive_error();
      return false;  // a TCP stream cannot be resynchronised
    }
    if (v.kind == detail::MbapVerdict::Kind::kNeedMore) return within_timeouts(c, now);
    c.have = 0;
    c.last_request = now;
    std::size_t reply_size = 0;
    const detail::FrameOutcome o = loopback->serve(
        ctx, handler, mapping, query.data(), c.frame.data(), v.adu_length, reply, reply_size);
    if (o == detail::FrameOutcome::kReceiveError || o == detail::FrameOutcome::kSendError) {
      return false;
    }
    if (reply_size == 0) return true;
    // An answer is at most 260 bytes; a client whose socket buffer cannot take it is not
    // reading its answers, and waiting for it would hold the others.
    const ssize_t sent = ::send(c.fd, reply.data(), reply_size, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (sent != static_cast<ssize_t>(reply_size)) {
      if (o == detail::FrameOutcome::kAnswered) handler.note_reply_failed();
      return false;
    }
    return true;
  }

  /// RTU: libmodbus receives one frame from the line (bounded by the byte timeout) and answers.
  void serve_serial_frame() {
    if (detail::serve_one_frame(ctx, serial_fd, handler, mapping, query.data()) ==
        detail::FrameOutcome::kReceiveError) {
      modbus_flush(ctx);
    }
  }

  ModbusEndpoint endpoint;
  ModbusServerOptions options;
  ModbusRequestHandler handler;
  modbus_mapping_t mapping{};
  modbus_t* ctx = nullptr;
  int listen_fd = -1;
  int serial_fd = -1;
  std::vector<Client> clients;
  std::vector<pollfd> fds;
  std::unique_ptr<detail::AduLoopback> loopback;
  std::array<std::uint8_t, MODBUS_MAX_ADU_LENGTH> query{};
  std::array<std::uint8_t, detail::kMaxTcpAduLength> reply{};
};

ModbusServer::ModbusServer(const compensation::MoveCompensator& compensator,
                           const ModbusEndpoint& endpoint,
                           const ModbusServerOptions& options) {
  std::string why;
  if (!options.is_valid(&why)) throw ConfigError("ModbusServerOptions: " + why);
  impl_ = std::make_unique<Impl>(compensator, endpoint, options);
  impl_->open();
}

ModbusServer::~ModbusServer() = default;

std::string ModbusServer::where() const { return impl_->where(); }

void ModbusServer::run(const std::atomic<bool>& stop) { impl_->run(stop); }

ModbusCounters ModbusServer::counters() const noexcept { return impl_->handler.counters(); }

}  // namespace cmmcomp::plugins

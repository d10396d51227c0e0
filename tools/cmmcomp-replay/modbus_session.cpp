// SPDX-License-Identifier: MIT
/// @file Modbus sessions: classification and decoding shared, the answering part per target.
#include "modbus_session.hpp"

#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/plugins/modbus_adu_responder.hpp>
#include <cmmcomp/plugins/modbus_server.hpp>
#include <cstring>

#include "modbus_decode.hpp"

namespace cmmcomp::replay {

namespace {

/// What both Modbus targets share: tx lines are requests, rx lines answers.
class ModbusSessionBase : public Session {
 public:
  Role classify(const WireMessage& m) const override {
    return m.from_controller ? Role::kRequest : Role::kAnswer;
  }
  std::string describe_request(const WireMessage& request) override {
    return summarize_modbus_request(request.bytes);
  }
  std::string describe_answers(const WireMessage& request,
                               const std::vector<WireMessage>& answers) const override {
    if (answers.empty()) return "no answer";
    std::string s;
    for (const WireMessage& a : answers) {
      s += (s.empty() ? "" : "; ") + summarize_modbus_answer(request.bytes, a.bytes);
    }
    return s;
  }
  std::vector<FieldValue> decode_answer(const WireMessage& request,
                                        const WireMessage& answer) const override {
    return decode_modbus_answer(request.bytes, answer.bytes);
  }
  std::string format(const WireMessage& m) const override { return hex_bytes(m.bytes); }
};

class InProcessModbusSession final : public ModbusSessionBase {
 public:
  InProcessModbusSession(const compensation::MoveCompensator& compensator, std::uint8_t unit)
      : responder_(compensator, unit) {}

  std::vector<WireMessage> answer(const WireMessage& request,
                                  std::int64_t /*next_time_us*/,
                                  std::size_t /*expected*/) override {
    const plugins::ModbusTcpAduResponder::Answer a =
        responder_.respond(request.bytes.data(), request.bytes.size());
    std::vector<WireMessage> out;
    if (!a.adu.empty()) {
      WireMessage m;
      m.line = request.line;
      m.bytes = a.adu;
      out.push_back(std::move(m));
    }
    return out;
  }
  std::string target() const override {
    return "in process (libmodbus + ModbusRequestHandler, as cmmcomp-agent's Modbus server)";
  }

 private:
  plugins::ModbusTcpAduResponder responder_;
};

class LiveModbusSession final : public ModbusSessionBase {
 public:
  explicit LiveModbusSession(const std::string& endpoint) : endpoint_(endpoint) {
    // The agent's own endpoint grammar, so "tcp:[::1]:1502" means what it means there.
    const plugins::ModbusEndpoint where = plugins::ModbusEndpoint::parse(endpoint);
    if (where.kind != plugins::ModbusEndpoint::Kind::kTcp) {
      throw ConfigError("--live modbus:" + endpoint + ": only tcp:HOST:PORT is supported");
    }
    const std::string& host = where.host;
    const std::string port = std::to_string(where.port);
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    if (::getaddrinfo(host.c_str(), port.c_str(), &hints, &found) != 0 || found == nullptr) {
      throw Error("Modbus agent " + endpoint + ": cannot resolve " + host);
    }
    int err = 0;
    for (addrinfo* a = found; a != nullptr && fd_ < 0; a = a->ai_next) {
      const int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
      if (fd < 0) continue;
      if (::connect(fd, a->ai_addr, a->ai_addrlen) == 0) {
        fd_ = fd;
      } else {
        err = errno;
        ::close(fd);
      }
    }
    ::freeaddrinfo(found);
    if (fd_ < 0)
      throw Error("Modbus agent " + endpoint + ": cannot connect: " + std::strerror(err));
  }
  ~LiveModbusSession() override {
    if (fd_ >= 0) ::close(fd_);
  }
  LiveModbusSession(const LiveModbusSession&) = delete;
  LiveModbusSession& operator=(const LiveModbusSession&) = delete;

  std::vector<WireMessage> answer(const WireMessage& request,
                                  std::int64_t /*next_time_us*/,
                                  std::size_t expected) override {
    if (::send(fd_, request.bytes.data(), request.bytes.size(), MSG_NOSIGNAL) !=
        static_cast<ssize_t>(request.bytes.size())) {
      throw Error("Modbus agent " + endpoint_ + ": send failed: " + std::strerror(errno));
    }
    std::vector<WireMessage> out;
    // An agent that stays silent is waited for briefly; an expected answer up to 2 s.
    const int timeout_ms = expected > 0 ? 2000 : 100;
    std::vector<std::uint8_t> adu;
    if (!read_exact(adu, 7, timeout_ms)) return out;
    const std::size_t length = static_cast<std::size_t>(adu[4] << 8 | adu[5]);
    if (length < 1 || !read_exact(adu, length - 1, timeout_ms)) {
      throw Error("Modbus agent " + endpoint_ + ": answer truncated after " +
                  std::to_string(adu.size()) + " bytes");
    }
    WireMessage m;
    m.line = request.line;
    m.bytes = std::move(adu);
    out.push_back(std::move(m));
    return out;
  }
  std::string target() const override { return "live Modbus agent " + endpoint_; }

 private:
  /// Appends `n` bytes; false when none came within `timeout_ms` (or the peer closed).
  bool read_exact(std::vector<std::uint8_t>& out, std::size_t n, int timeout_ms) {
    while (n > 0) {
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, timeout_ms) <= 0) return false;
      std::uint8_t buffer[260];
      const ssize_t got = ::recv(fd_, buffer, n < sizeof buffer ? n : sizeof buffer, 0);
      if (got <= 0) return false;
      out.insert(out.end(), buffer, buffer + got);
      n -= static_cast<std::size_t>(got);
    }
    return true;
  }

  std::string endpoint_;
  int fd_ = -1;
};

}  // namespace

std::unique_ptr<Session> make_modbus_session(const compensation::MoveCompensator& compensator,
                                             std::uint8_t unit_id) {
  return std::make_unique<InProcessModbusSession>(compensator, unit_id);
}

std::unique_ptr<Session> make_modbus_live_session(const std::string& endpoint) {
  return std::make_unique<LiveModbusSession>(endpoint);
}

}  // namespace cmmcomp::replay

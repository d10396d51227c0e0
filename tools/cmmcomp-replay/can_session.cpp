// SPDX-License-Identifier: MIT
/// @file CAN sessions: classification and decoding shared, the answering part per target.
#include "can_session.hpp"

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/plugins/can_request_handler.hpp>
#include <cstring>
#include <thread>

#include "can_decode.hpp"
#include "value_format.hpp"

namespace cmmcomp::replay {

namespace {

namespace can = plugins::can;

/// What both CAN targets share: identifiers relative to the base id decide the role.
class CanSessionBase : public Session {
 public:
  explicit CanSessionBase(std::uint32_t base_id) : base_id_(base_id) {}

  Role classify(const WireMessage& m) const override {
    if (m.can_id == base_id_ + can::kRequestOffset) return Role::kRequest;
    if (m.can_id == base_id_ + can::kResponseOffset || m.can_id == base_id_ + can::kRejectOffset) {
      return Role::kAnswer;
    }
    if (m.can_id == base_id_ + can::kHeartbeatOffset) return Role::kHeartbeat;
    return Role::kOther;
  }

  std::string describe_request(const WireMessage& request) override {
    const std::vector<FieldValue> f = decode_can_frame(base_id_, request.can_id, request.bytes);
    const std::string part = value(f, "ReqPart");
    const std::string sequence = value(f, "ReqSequence");
    std::string s = "request seq " + sequence + " part " + part;
    if (part == "0") parts_.clear();
    parts_.insert(parts_.end(), f.begin(), f.end());
    if (part == "2") {
      s += ": axis " + value(parts_, "Axis") + " dir (" + value(parts_, "DirX") + ", " +
           value(parts_, "DirY") + ", " + value(parts_, "DirZ") + ") PV " + value(parts_, "PV") +
           " PD " + value(parts_, "PD") + " AV " + value(parts_, "AV") + " AD " +
           value(parts_, "AD") + " Y " + value(parts_, "Y");
      if (value(parts_, "WantInterval") == "1") s += " +interval";
    }
    return s;
  }

  std::string describe_answers(const WireMessage& /*request*/,
                               const std::vector<WireMessage>& answers) const override {
    std::vector<std::uint32_t> ids;
    std::vector<std::vector<std::uint8_t>> frames;
    for (const WireMessage& a : answers) {
      ids.push_back(a.can_id);
      frames.push_back(a.bytes);
    }
    return summarize_can_answer(base_id_, ids, frames);
  }

  std::vector<FieldValue> decode_answer(const WireMessage& /*request*/,
                                        const WireMessage& answer) const override {
    return decode_can_frame(base_id_, answer.can_id, answer.bytes);
  }

  std::string format(const WireMessage& m) const override {
    return format_can_frame(m.can_id, m.bytes);
  }

 protected:
  static can::Frame to_frame(const WireMessage& m) {
    can::Frame f;
    f.id = m.can_id;
    f.dlc = static_cast<std::uint8_t>(m.bytes.size() > 8 ? 8 : m.bytes.size());
    for (std::size_t i = 0; i < f.dlc; ++i) f.data[i] = m.bytes[i];
    return f;
  }
  static WireMessage to_message(const can::Frame& f, const WireMessage& request) {
    WireMessage m;
    m.line = request.line;
    m.interface = request.interface;
    m.can_id = f.id;
    m.bytes.assign(f.data.begin(), f.data.begin() + f.dlc);
    return m;
  }

  std::uint32_t base_id_;

 private:
  /// The value of signal `name` without its unit, "?" when absent.
  static std::string value(const std::vector<FieldValue>& fields, const char* name) {
    return number_of(field_named(fields, name));
  }

  std::vector<FieldValue> parts_;  // the signals of the request being assembled
};

class InProcessCanSession final : public CanSessionBase {
 public:
  InProcessCanSession(const compensation::MoveCompensator& compensator,
                      std::uint32_t base_id,
                      std::chrono::nanoseconds part_timeout)
      : CanSessionBase(base_id), handler_(compensator, base_id, part_timeout) {}

  std::vector<WireMessage> answer(const WireMessage& request,
                                  std::int64_t next_time_us,
                                  std::size_t /*expected*/) override {
    plugins::CanFrameBatch batch;
    handler_.on_frame(to_frame(request), request.time_us * 1000, batch);
    // The server expires an unfinished request at its deadline, before the next frame comes:
    // that reject belongs after this request in the log, so it is produced here.
    if (handler_.assembling() && handler_.deadline_ns() <= next_time_us * 1000) {
      handler_.on_time(handler_.deadline_ns(), batch);
    }
    std::vector<WireMessage> out;
    for (std::size_t i = 0; i < batch.size; ++i)
      out.push_back(to_message(batch.frames[i], request));
    return out;
  }
  std::string target() const override {
    return "in process (CanRequestHandler, as cmmcomp-agent's CAN server, base id 0x" +
           format_hex(base_id_, 3) + ")";
  }

 private:
  plugins::CanRequestHandler handler_;
};

class LiveCanSession final : public CanSessionBase {
 public:
  LiveCanSession(const std::string& interface, std::uint32_t base_id)
      : CanSessionBase(base_id), interface_(interface) {
    fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
    if (fd_ < 0) {
      throw Error("CAN " + interface + ": cannot open a raw CAN socket: " + std::strerror(errno) +
                  " (no AF_CAN in this kernel? run it inside scripts/uml-run.sh)");
    }
    const std::array<can_filter, 2> filters{
        can_filter{base_id + can::kResponseOffset, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG},
        can_filter{base_id + can::kRejectOffset, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG}};
    ::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, filters.data(), sizeof filters);
    sockaddr_can addr{};
    addr.can_family = AF_CAN;
    addr.can_ifindex = static_cast<int>(::if_nametoindex(interface.c_str()));
    if (addr.can_ifindex == 0 ||
        ::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
      const int err = errno;
      ::close(fd_);
      throw Error("CAN " + interface + ": cannot bind: " + std::strerror(err));
    }
  }
  ~LiveCanSession() override { ::close(fd_); }
  LiveCanSession(const LiveCanSession&) = delete;
  LiveCanSession& operator=(const LiveCanSession&) = delete;

  std::vector<WireMessage> answer(const WireMessage& request,
                                  std::int64_t /*next_time_us*/,
                                  std::size_t expected) override {
    pace(request.time_us);
    can_frame frame{};
    frame.can_id = request.can_id;
    frame.len = static_cast<std::uint8_t>(request.bytes.size() > 8 ? 8 : request.bytes.size());
    std::memcpy(frame.data, request.bytes.data(), frame.len);
    if (::write(fd_, &frame, sizeof frame) != static_cast<ssize_t>(sizeof frame)) {
      throw Error("CAN " + interface_ + ": write failed: " + std::strerror(errno));
    }
    std::vector<WireMessage> out;
    // Expected answers are waited for (1 s each, generous for UML); then anything else that
    // is already queued is taken too, so an extra frame shows as a mismatch here.
    while (true) {
      const int timeout_ms = out.size() < expected ? 1000 : 0;
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, timeout_ms) <= 0) break;
      can_frame in{};
      if (::read(fd_, &in, sizeof in) != static_cast<ssize_t>(sizeof in)) break;
      WireMessage m;
      m.line = request.line;
      m.interface = interface_;
      m.can_id = in.can_id & CAN_SFF_MASK;
      m.bytes.assign(in.data, in.data + in.len);
      out.push_back(std::move(m));
    }
    return out;
  }
  std::string target() const override {
    return "live CAN agent on " + interface_ + " (base id 0x" + format_hex(base_id_, 3) + ")";
  }

 private:
  /// Sends with the recording's gaps (as canplayer does), so part timeouts see the same time.
  void pace(std::int64_t recorded_us) {
    const auto now = std::chrono::steady_clock::now();
    if (!started_) {
      started_ = true;
      first_recorded_us_ = recorded_us;
      first_sent_ = now;
      return;
    }
    const auto due = first_sent_ + std::chrono::microseconds(recorded_us - first_recorded_us_);
    if (due > now) std::this_thread::sleep_until(due);
  }

  std::string interface_;
  int fd_ = -1;
  bool started_ = false;
  std::int64_t first_recorded_us_ = 0;
  std::chrono::steady_clock::time_point first_sent_;
};

}  // namespace

std::unique_ptr<Session> make_can_session(const compensation::MoveCompensator& compensator,
                                          std::uint32_t base_id,
                                          std::chrono::nanoseconds part_timeout) {
  return std::make_unique<InProcessCanSession>(compensator, base_id, part_timeout);
}

std::unique_ptr<Session> make_can_live_session(const std::string& interface,
                                               std::uint32_t base_id) {
  return std::make_unique<LiveCanSession>(interface, base_id);
}

}  // namespace cmmcomp::replay

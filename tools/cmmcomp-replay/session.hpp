// SPDX-License-Identifier: MIT
/// @file What replay needs from a protocol: which recorded messages are requests and which are
/// answers, something that answers a request (the plugin's handler in process, or a live agent),
/// and how to print and decode the messages. One implementation per protocol and target.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "field_value.hpp"
#include "recording.hpp"

namespace cmmcomp::replay {

class Session {
 public:
  /// What a recorded message is to the replay.
  enum class Role : std::uint8_t {
    kRequest,    ///< controller → agent, addressed to the plugin: replayed
    kAnswer,     ///< agent → controller: compared with what the replay answers
    kHeartbeat,  ///< CAN heartbeat: skipped
    kOther,      ///< anything else (other identifiers): skipped
  };

  virtual ~Session() = default;

  virtual Role classify(const WireMessage& m) const = 0;

  /// The answers to `request` (what the agent sends before the next request arrives).
  /// `next_time_us`: the recorded time of the next request (or of the last message), so a
  /// handler with timers sees the time pass as it did on the wire. `expected`: how many answers
  /// the recording holds (a live target waits for that many). Throws cmmcomp::Error when a live
  /// target fails.
  virtual std::vector<WireMessage> answer(const WireMessage& request,
                                          std::int64_t next_time_us,
                                          std::size_t expected) = 0;

  /// One line about a request (may remember earlier requests: a CAN request has three frames).
  virtual std::string describe_request(const WireMessage& request) = 0;

  /// One line about the answers to a request.
  virtual std::string describe_answers(const WireMessage& request,
                                       const std::vector<WireMessage>& answers) const = 0;

  /// Every field of one answer, by name, with the bytes it spans.
  virtual std::vector<FieldValue> decode_answer(const WireMessage& request,
                                                const WireMessage& answer) const = 0;

  /// A message as the recording writes it ("00 01 …" or "301#0001…").
  virtual std::string format(const WireMessage& m) const = 0;

  /// What answers: e.g. "in process (ModbusRequestHandler)" or "live tcp:127.0.0.1:1502".
  virtual std::string target() const = 0;
};

}  // namespace cmmcomp::replay

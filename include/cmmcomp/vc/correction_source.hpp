// SPDX-License-Identifier: MIT
/// @file What the virtual controller asks before each approach: an agent behind a protocol.
#pragma once

#include <array>
#include <cmmcomp/compensation/move_request.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cstdint>
#include <string>

namespace cmmcomp::vc {

/// The agent cannot be reached (connection refused, no such interface): a usage-level problem,
/// the tool exits with status 2.
class UnreachableError : public Error {
 public:
  using Error::Error;
};

/// One answer as the controller decodes it from the wire.
struct Answer {
  bool usable = false;      ///< the OK flag is set and the sequence matches: apply the correction
  int status = 0;           ///< cmmcomp::Status value (Modbus) or the reject's reason (CAN), 0 = ok
  std::uint32_t flags = 0;  ///< CorrectionFlag bits as received
  double rae_um = 0;        ///< predicted RAE [µm]
  std::array<double, 3> correction_um{0, 0, 0};  ///< +RAE·d [µm]
  std::uint64_t model_id = 0;                    ///< as the protocol carries it (CAN: low 32 bits)
  /// The 95 % interval's half-widths of MPE, RPE, MAE, RAE [µm] and every flag, as protocol
  /// version 2 of Modbus (float32) and of CAN (response part 3: 0.02 µm steps, 81.9 µm meaning
  /// "at least that") carry them.
  std::array<double, 4> u95_um{0, 0, 0, 0};
  std::uint32_t interval_flags = 0;
  std::string note;  ///< why it is not usable, empty when usable
};

/// An agent the controller talks to. The sequence of `move` is assigned by the source.
class CorrectionSource {
 public:
  virtual ~CorrectionSource() = default;
  /// Asks for the correction of `move` (sequence ignored). Throws Error on a transport failure
  /// (timeout, connection lost); a refusal by the agent is an Answer with usable = false.
  virtual Answer ask(const compensation::MoveRequest& move) = 0;
  /// The label in reports ("4in", "agent", …).
  virtual const std::string& label() const noexcept = 0;
  /// Where it is, for reports ("modbus tcp:127.0.0.1:1502", "can vcan0 0x300").
  virtual const std::string& where() const noexcept = 0;
};

}  // namespace cmmcomp::vc

// SPDX-License-Identifier: MIT
/// @file A correction source in the same process: a MoveCompensator serving one model file, as
/// `cmmcomp-agent --model AXIS=FILE` serves it, without a protocol in between.
///
/// Contract: the model is published as the agent publishes it (io::publish: its interval at the
/// served 95 % coverage, its conditions and the compensator's default outside-domain policy).
/// ask() answers exactly what the compensator computes: usable when the status is ok and the
/// correction carries kFlagOk; a refusal is an Answer with usable = false, its status and a note.
/// The answers are the double-precision values; an agent's protocol rounds them to its wire
/// format (float32 on Modbus, fixed point on CAN), well below a micrometre.
/// Setup-time construction (throws ConfigError when the model cannot be published); ask() never
/// throws.
#pragma once

#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/vc/correction_source.hpp>
#include <cstdint>
#include <string>

namespace cmmcomp::vc {

class LocalSource final : public CorrectionSource {
 public:
  /// Publishes `file` on `axis` of its own compensator; `where` names it in reports (e.g. the
  /// file's path).
  LocalSource(std::string label,
              const io::CompensationModelFile& file,
              std::string where,
              int axis = 0,
              const compensation::CompensatorOptions& options = {});

  Answer ask(const compensation::MoveRequest& move) override;
  const std::string& label() const noexcept override { return label_; }
  const std::string& where() const noexcept override { return where_; }

 private:
  std::string label_;
  std::string where_;
  compensation::MoveCompensator compensator_;
  std::uint32_t sequence_ = 0;
};

}  // namespace cmmcomp::vc

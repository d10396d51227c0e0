// SPDX-License-Identifier: MIT
/// @file A correction source in the same process (local_source.hpp).
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/status.hpp>
#include <cmmcomp/vc/local_source.hpp>
#include <utility>

namespace cmmcomp::vc {

LocalSource::LocalSource(std::string label,
                         const io::CompensationModelFile& file,
                         std::string where,
                         int axis,
                         const compensation::CompensatorOptions& options)
    : label_(std::move(label)), where_(std::move(where)), compensator_(options) {
  std::string why;
  const Status s = io::publish(compensator_, axis, file, &why);
  if (s != Status::kOk) {
    throw ConfigError("model of '" + label_ + "' (" + where_ + "): " + to_string(s) +
                      (why.empty() ? "" : ": " + why));
  }
}

Answer LocalSource::ask(const compensation::MoveRequest& move) {
  compensation::MoveRequest m = move;
  m.sequence = ++sequence_;
  compensation::Correction c;
  const Status s = compensator_.before_approach(m, c);
  Answer a;
  a.status = static_cast<int>(s);
  if (!ok(s)) {
    a.flags = compensation::flags_for(s);
    a.note = to_string(s);
    return a;
  }
  a.flags = c.flags & compensation::kFlagsVersion1;  // as the protocols' result flags
  a.rae_um = c.rae_um;
  a.correction_um = c.correction_um;
  a.model_id = c.model_id;
  a.u95_um = c.u95_um;
  a.interval_flags = c.flags;
  a.usable = (c.flags & compensation::kFlagOk) != 0;
  if (!a.usable) a.note = "flags without OK";
  return a;
}

}  // namespace cmmcomp::vc

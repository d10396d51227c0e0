// SPDX-License-Identifier: MIT
/// @file cmmcomp-replay's run: the recording, the models (loaded as cmmcomp-agent loads them) or
/// the live agent, the replay and its report.
#include <chrono>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/plugins/can_server.hpp>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "can_session.hpp"
#include "commands.hpp"
#include "domain_policy_option.hpp"
#include "modbus_session.hpp"
#include "model_slots.hpp"
#include "recording.hpp"
#include "replay.hpp"

namespace cmmcomp::tools::replay {

namespace replay = cmmcomp::replay;

namespace {

/// Loads the models as cmmcomp-agent does; false (with the reasons on stderr) when one fails.
bool load_models(const Options& opt, cmmcomp::compensation::MoveCompensator& compensator) {
  std::vector<cmmcomp::serving::ModelSlot> slots;
  for (const std::string& m : opt.models)
    slots.push_back(cmmcomp::serving::parse_model_argument(m));
  if (slots.empty()) slots.push_back(cmmcomp::serving::ModelSlot{0, ""});
  bool all = true;
  for (const cmmcomp::serving::SlotOutcome& o : cmmcomp::serving::load_slots(slots, compensator)) {
    if (!o.loaded) {
      std::fprintf(stderr,
                   "cmmcomp-replay: axis %d: cannot load %s: %s\n",
                   o.axis,
                   o.source.c_str(),
                   o.error.c_str());
      all = false;
    } else if (!opt.json) {
      std::printf("axis %d: model %s (%d inputs) from %s\n",
                  o.axis,
                  o.model_id.c_str(),
                  o.inputs,
                  o.source.c_str());
    }
  }
  return all;
}

}  // namespace

int run(const Options& opt) {
  replay::Recording recording;
  try {
    recording = replay::load_recording(opt.session);
  } catch (const replay::RecordingError& e) {
    std::fprintf(stderr, "cmmcomp-replay: %s\n", e.what());
    return 2;
  }
  const std::uint32_t base_id = cmmcomp::plugins::parse_can_base_id(opt.can_base_id);
  const bool modbus = recording.format == replay::RecordingFormat::kModbusTranscript;

  cmmcomp::compensation::CompensatorOptions copt;
  // CLI11 admits only the three names, so the parse cannot fail here.
  (void)cmmcomp::fuzzy::parse_domain_policy(opt.outside_domain, &copt.outside_domain);
  cmmcomp::compensation::MoveCompensator compensator(copt);
  std::unique_ptr<replay::Session> session;
  if (opt.live.empty()) {
    if (!load_models(opt, compensator)) return 2;
    session =
        modbus
            ? replay::make_modbus_session(compensator, static_cast<std::uint8_t>(opt.modbus_unit))
            : replay::make_can_session(
                  compensator, base_id, std::chrono::milliseconds(opt.can_part_timeout_ms));
  } else if (!opt.models.empty()) {
    std::fprintf(stderr,
                 "cmmcomp-replay: --model and --live exclude each other: a live agent answers "
                 "with the model it serves\n");
    return 2;
  } else if (opt.live.rfind("modbus:", 0) == 0 && modbus) {
    session = replay::make_modbus_live_session(opt.live.substr(7));
  } else if (opt.live.rfind("can:", 0) == 0 && !modbus) {
    session = replay::make_can_live_session(opt.live.substr(4), base_id);
  } else {
    std::fprintf(stderr,
                 "cmmcomp-replay: --live '%s' does not fit a %s (Modbus transcript: "
                 "modbus:tcp:HOST:PORT; candump log: can:IFACE)\n",
                 opt.live.c_str(),
                 replay::to_string(recording.format));
    return 2;
  }

  replay::ReplayOptions ropt;
  ropt.max_mismatches = opt.max_mismatches;
  ropt.verbose = !opt.quiet && !opt.json;
  if (!opt.json) {
    std::printf("replaying %s (%s, %zu messages) %s\n",
                recording.source.c_str(),
                replay::to_string(recording.format),
                recording.messages.size(),
                session->target().c_str());
  }
  const replay::ReplayResult r = replay::run_replay(recording, *session, ropt, &std::cout);
  if (opt.json) {
    std::printf("%s\n", replay::result_json(r).c_str());
  } else {
    for (const replay::Mismatch& m : r.mismatches) {
      std::printf("%s", replay::format_mismatch(r.source, m).c_str());
    }
    std::printf(
        "%s: %zu request messages, %zu recorded answers, %zu matched%s; skipped %zu "
        "heartbeats, %zu other\n",
        r.source.c_str(),
        r.requests,
        r.answers,
        r.matched,
        r.mismatches.empty() ? " (every answer byte for byte)"
                             : (", " + std::to_string(r.mismatches.size()) + " MISMATCHED" +
                                (r.stopped_early ? " (stopped)" : ""))
                                   .c_str(),
        r.heartbeats,
        r.other);
  }
  std::fflush(stdout);
  return r.mismatches.empty() ? 0 : 1;
}

}  // namespace cmmcomp::tools::replay

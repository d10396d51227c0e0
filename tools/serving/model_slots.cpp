// SPDX-License-Identifier: MIT
/// @file Parses --model [AXIS=]PATH and loads each file into its axis of the compensator.
#include "model_slots.hpp"

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/io/default_model.hpp>
#include <cstdio>
#include <cstdlib>
#include <exception>

namespace cmmcomp::serving {

ModelSlot parse_model_argument(const std::string& text) {
  ModelSlot slot;
  const auto eq = text.find('=');
  std::string path = text;
  if (eq != std::string::npos) {
    const std::string axis = text.substr(0, eq);
    path = text.substr(eq + 1);
    char* end = nullptr;
    const long value = std::strtol(axis.c_str(), &end, 10);
    if (axis.empty() || end == nullptr || *end != '\0' || value < 0 ||
        value >= compensation::kMaxAxes) {
      throw ConfigError("--model '" + text + "': axis '" + axis + "' is not 0.." +
                        std::to_string(compensation::kMaxAxes - 1));
    }
    slot.axis = static_cast<int>(value);
  }
  if (path.empty()) throw ConfigError("--model '" + text + "': no file named");
  slot.path = path;
  return slot;
}

std::vector<SlotOutcome> load_slots(const std::vector<ModelSlot>& slots,
                                    compensation::MoveCompensator& compensator) {
  std::vector<SlotOutcome> outcomes;
  for (const ModelSlot& slot : slots) {
    SlotOutcome out;
    out.axis = slot.axis;
    out.source = slot.path.empty() ? io::kDefaultModelSource : slot.path;
    try {
      const io::CompensationModelFile file =
          slot.path.empty() ? io::CompensationModelFile{io::default_model_file()}
                            : io::load_compensation_model(slot.path);
      out.inputs = io::model_inputs(file);
      std::string why;
      if (io::publish(compensator, slot.axis, file, &why) != Status::kOk) {
        out.error = "refused by the compensator: " + why;
      } else {
        out.loaded = true;
      }
    } catch (const std::exception& e) {
      out.error = e.what();
    }
    const std::uint64_t serving = compensator.model_id(slot.axis);
    if (compensator.has_model(slot.axis)) {
      char hex[17];
      std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(serving));
      out.model_id = hex;
    }
    outcomes.push_back(std::move(out));
  }
  return outcomes;
}

}  // namespace cmmcomp::serving

// SPDX-License-Identifier: MIT
/// @file Which model file serves which axis, loading them into a MoveCompensator and reloading
/// them on SIGHUP without ever leaving an axis worse off.
#pragma once

#include <cmmcomp/compensation/move_compensator.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace cmmcomp::serving {

/// One `--model [AXIS=]PATH` argument.
struct ModelSlot {
  int axis = 0;
  std::string path;  ///< empty: the compiled-in default model (io::default_model_file)
};

/// Parses "PATH" (axis 0) or "AXIS=PATH" (AXIS 0 .. kMaxAxes-1). Throws ConfigError naming the
/// argument when AXIS is not a valid axis or PATH is empty.
ModelSlot parse_model_argument(const std::string& text);

/// What happened to one slot in a load or reload.
struct SlotOutcome {
  int axis = 0;
  std::string source;    ///< file path or the default model's source
  std::string model_id;  ///< id now serving the axis (16 hex), empty if none
  int inputs = 0;        ///< inputs of the file's network (4, or 5 with Y); 0 if unreadable
  bool loaded = false;   ///< true: the file was (re)loaded and published
  std::string error;     ///< why not, when !loaded; the previous model keeps serving
};

/// Loads every slot's file and publishes it into `compensator`. A file that fails to load or
/// validate is reported in its SlotOutcome and the axis keeps what it had (at start: nothing).
/// Setup only. The id published is the first 16 hex digits of the file's checksum.
std::vector<SlotOutcome> load_slots(const std::vector<ModelSlot>& slots,
                                    compensation::MoveCompensator& compensator);

}  // namespace cmmcomp::serving

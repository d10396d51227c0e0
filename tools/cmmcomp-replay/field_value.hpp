// SPDX-License-Identifier: MIT
/// @file A decoded field of a wire message, for reports: which bytes, what name, what value.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace cmmcomp::replay {

/// One field of a message, decoded.
struct FieldValue {
  std::string name;       ///< e.g. "RAE", "model id", "transaction id"
  std::size_t begin = 0;  ///< first byte (Modbus: in the ADU; CAN: in the data)
  std::size_t end = 0;    ///< one past the last byte
  std::string value;      ///< e.g. "-5.298 µm", "c2fc35069149ab07"
  std::string precise;    ///< the value with every digit, shown when `value`s are equal
};

/// The field that covers byte `offset`, or nullptr.
inline const FieldValue* field_at(const std::vector<FieldValue>& fields, std::size_t offset) {
  for (const FieldValue& f : fields) {
    if (offset >= f.begin && offset < f.end) return &f;
  }
  return nullptr;
}

/// The field called `name`, or nullptr.
inline const FieldValue* field_named(const std::vector<FieldValue>& fields,
                                     const std::string& name) {
  for (const FieldValue& f : fields) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

/// The value of `f` without its unit ("-5.298" of "-5.298 µm"); "?" when `f` is null.
inline std::string number_of(const FieldValue* f) {
  if (f == nullptr) return "?";
  return f->value.substr(0, f->value.find(' '));
}

}  // namespace cmmcomp::replay

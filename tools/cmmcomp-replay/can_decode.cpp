// SPDX-License-Identifier: MIT
/// @file Signal-by-signal decoding of cmmcomp CAN frames from the protocol's signal tables.
#include "can_decode.hpp"

#include <cctype>
#include <cmmcomp/plugins/can_protocol.hpp>
#include <cstring>

#include "value_format.hpp"

namespace cmmcomp::replay {

namespace {

namespace can = plugins::can;

can::Frame to_frame(std::uint32_t id, const std::vector<std::uint8_t>& data) {
  can::Frame f;
  f.id = id;
  f.dlc = static_cast<std::uint8_t>(data.size() > 8 ? 8 : data.size());
  for (std::size_t i = 0; i < f.dlc; ++i) f.data[i] = data[i];
  return f;
}

}  // namespace

std::vector<FieldValue> decode_can_frame(std::uint32_t base_id,
                                         std::uint32_t id,
                                         const std::vector<std::uint8_t>& data) {
  std::vector<FieldValue> out;
  if (id < base_id || id >= base_id + can::kMessageCount) return out;
  const can::MessageSpec& message = can::kMessages[id - base_id];
  const can::Frame frame = to_frame(id, data);
  const std::uint64_t w = can::load_word(frame);
  std::int64_t mux = -1;
  for (std::size_t i = 0; i < message.signal_count; ++i) {
    if (message.signals[i].mux == can::kMultiplexor) mux = can::get_raw(w, message.signals[i]);
  }
  for (std::size_t i = 0; i < message.signal_count; ++i) {
    const can::SignalSpec& s = message.signals[i];
    if (s.mux >= 0 && s.mux != mux) continue;
    const std::size_t begin = s.start / 8u;
    const std::size_t end = (s.start + s.length - 1u) / 8u + 1u;
    if (end > data.size()) continue;  // not in a short frame
    const std::int64_t raw = can::get_raw(w, s);
    FieldValue f;
    f.name = s.name;
    f.begin = begin;
    f.end = end;
    const std::string name = s.name;
    if (name.rfind("ModelId", 0) == 0) {
      f.value = format_hex(static_cast<std::uint64_t>(raw), 8);
    } else if (name == "IntervalFlags") {
      std::string bits;
      if ((raw & can::response::kIntervalNoUncertainty) != 0) bits += " NO_UNCERTAINTY";
      if ((raw & can::response::kIntervalSaturated) != 0) bits += " SATURATED";
      f.value = std::to_string(raw) + (bits.empty() ? "" : " (" + bits.substr(1) + ")");
    } else if (name == "Reason") {
      f.value = std::to_string(raw) + " (" +
                can::to_string(static_cast<can::RejectReason>(static_cast<std::uint8_t>(raw))) +
                ")";
    } else {
      const double v = can::to_physical(s, raw);
      const std::string unit = std::strcmp(s.unit, "um") == 0 ? "µm" : s.unit;
      f.value = format_number(v, 6) + (unit.empty() ? "" : " " + unit);
      f.precise = f.value + " (raw " + std::to_string(raw) + ")";
    }
    if (f.precise.empty()) f.precise = f.value;
    out.push_back(std::move(f));
  }
  return out;
}

std::string format_can_frame(std::uint32_t id, const std::vector<std::uint8_t>& data) {
  std::string s = format_hex(id, 3);
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  s += '#';
  for (std::uint8_t b : data) {
    std::string h = format_hex(b, 2);
    for (char& c : h) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    s += h;
  }
  return s;
}

std::string summarize_can_answer(std::uint32_t base_id,
                                 const std::vector<std::uint32_t>& ids,
                                 const std::vector<std::vector<std::uint8_t>>& frames) {
  if (frames.empty()) return "no answer";
  std::vector<FieldValue> all;
  std::string rejects;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const std::vector<FieldValue> f = decode_can_frame(base_id, ids[i], frames[i]);
    if (ids[i] == base_id + can::kRejectOffset) {
      rejects += (rejects.empty() ? "reject: " : "; reject: ") +
                 (field_named(f, "Reason") != nullptr ? field_named(f, "Reason")->value : "?") +
                 " (seq " + number_of(field_named(f, "RejSequence")) + ", part " +
                 number_of(field_named(f, "RejPart")) + ")";
    } else {
      all.insert(all.end(), f.begin(), f.end());
    }
  }
  std::string s;
  if (field_named(all, "RAE") != nullptr) {
    s = "RAE " + field_named(all, "RAE")->value + " corr (" + number_of(field_named(all, "CorrX")) +
        ", " + number_of(field_named(all, "CorrY")) + ", " + number_of(field_named(all, "CorrZ")) +
        ") µm";
    if (const FieldValue* id = field_named(all, "ModelId")) s += " model " + id->value;
  }
  // Part 3 (protocol version 2, the request set WantInterval): U95 of RAE and any flag.
  if (const FieldValue* u = field_named(all, "U95RAE")) {
    const FieldValue* flags = field_named(all, "IntervalFlags");
    s += (s.empty() ? "" : " ") + std::string("U95 RAE ") + u->value;
    if (flags != nullptr && flags->value != "0") s += " interval flags " + flags->value;
  }
  if (!rejects.empty()) s += (s.empty() ? "" : "; ") + rejects;
  return s.empty() ? "answer frames without a result" : s;
}

}  // namespace cmmcomp::replay

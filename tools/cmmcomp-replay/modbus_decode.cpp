// SPDX-License-Identifier: MIT
/// @file Field-by-field decoding of Modbus TCP ADUs, by the plugin's register map (the one table
/// of addresses, types, labels and units; docs/protocol-modbus.md).
#include "modbus_decode.hpp"

#include <cmmcomp/plugins/modbus_register_map.hpp>
#include <cmmcomp/status.hpp>
#include <cstring>

#include "value_format.hpp"

namespace cmmcomp::replay {

namespace {

namespace map = plugins::modbus;

using map::Field;
using map::FieldType;

std::uint64_t be(const std::vector<std::uint8_t>& b, std::size_t at, std::size_t n) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < n; ++i) v = (v << 8) | b[at + i];
  return v;
}

const char* exception_name(std::uint8_t code) {
  switch (code) {
    case 0x01:
      return "illegal function";
    case 0x02:
      return "illegal data address";
    case 0x03:
      return "illegal data value";
    case 0x0B:
      return "gateway target failed";
    default:
      return "unknown exception";
  }
}

void add(std::vector<FieldValue>& out,
         const std::string& name,
         std::size_t begin,
         std::size_t size,
         const std::string& value,
         const std::string& precise = "") {
  out.push_back(FieldValue{name, begin, begin + size, value, precise.empty() ? value : precise});
}

/// Decodes a field of `t` at byte `at` and appends it.
void add_typed(std::vector<FieldValue>& out,
               const std::vector<std::uint8_t>& b,
               std::size_t at,
               const Field& f) {
  const auto size = static_cast<std::size_t>(2 * map::words(f.type));
  const std::string unit = f.unit[0] == '\0' ? std::string() : std::string(" ") + f.unit;
  const std::uint64_t raw = be(b, at, size);
  switch (f.type) {
    case FieldType::kU16:
    case FieldType::kU32:
      add(out, f.label, at, size, std::to_string(raw));
      return;
    case FieldType::kI16: {
      const auto v = static_cast<std::int16_t>(static_cast<std::uint16_t>(raw));
      std::string text = std::to_string(v);
      if (f.address == map::kResultStatus) {
        text += std::string(" (") + to_string(static_cast<Status>(v)) + ")";
      }
      add(out, f.label, at, size, text);
      return;
    }
    case FieldType::kF32: {
      const auto bits = static_cast<std::uint32_t>(raw);
      float v = 0;
      std::memcpy(&v, &bits, sizeof v);
      add(out,
          f.label,
          at,
          size,
          format_number(v, 4) + unit,
          format_number(v, 9) + unit + " (" + format_hex(bits, 8) + ")");
      return;
    }
    case FieldType::kU64:
      add(out, f.label, at, size, format_hex(raw, 16));
      return;
  }
}

/// Appends the registers `first` .. `first + count` - 1 stored from byte `at` of `b`, by name.
/// `holding`: the holding-register space (request block, then the result and interval copies).
void add_registers(std::vector<FieldValue>& out,
                   const std::vector<std::uint8_t>& b,
                   std::size_t at,
                   std::uint32_t first,
                   std::uint32_t count,
                   bool holding) {
  const std::uint32_t end = first + count;
  std::uint32_t r = first;
  while (r < end && at + 2 <= b.size()) {
    // Holding registers 25 .. 47 are a copy of input registers 1 .. 23 (the result block), and
    // 48 .. 57 of input registers 52 .. 61 (the interval block, protocol version 2).
    const bool request_space = holding && r < map::kRequestCount;
    const std::uint32_t input_reg = !holding ? r
                                    : r < map::kIntervalCopy
                                        ? r - map::kResultCopy + map::kResultSequence
                                        : r - map::kIntervalCopy + map::kIntervalFlags;
    const Field* match = nullptr;
    if (request_space) {
      for (const Field& f : map::kHoldingFields) {
        if (f.address == r && f.count == 1) match = &f;
      }
    } else {
      for (const Field& f : map::kInputFields) {
        if (f.address == input_reg) match = &f;
      }
    }
    const auto n = match == nullptr ? 1u : static_cast<std::uint32_t>(match->registers());
    if (match != nullptr && r + n <= end && at + std::size_t{2} * n <= b.size()) {
      add_typed(out, b, at, *match);
    } else {  // outside the map, or a field only partly read
      add(out,
          std::string(holding ? "holding" : "input") + " register " + std::to_string(r),
          at,
          2,
          std::to_string(be(b, at, 2)));
      r += 1;
      at += 2;
      continue;
    }
    r += n;
    at += std::size_t{2} * n;
  }
}

void add_mbap(std::vector<FieldValue>& out, const std::vector<std::uint8_t>& b) {
  if (b.size() < 8) return;
  add(out, "transaction id", 0, 2, std::to_string(be(b, 0, 2)));
  add(out, "protocol id", 2, 2, std::to_string(be(b, 2, 2)));
  add(out, "MBAP length", 4, 2, std::to_string(be(b, 4, 2)));
  add(out, "unit id", 6, 1, std::to_string(b[6]));
  add(out, "function code", 7, 1, "0x" + format_hex(b[7], 2));
}

}  // namespace

std::vector<FieldValue> decode_modbus_request(const std::vector<std::uint8_t>& b) {
  std::vector<FieldValue> out;
  add_mbap(out, b);
  if (b.size() < 8) return out;
  const std::uint8_t fc = b[7];
  // Address and count of a read or write block starting at byte `at`; a write's byte count and
  // registers follow it.
  const auto add_read = [&](std::size_t at) {
    add(out, "read address", at, 2, std::to_string(be(b, at, 2)));
    add(out, "read count", at + 2, 2, std::to_string(be(b, at + 2, 2)));
  };
  const auto add_write = [&](std::size_t at) {
    add(out, "write address", at, 2, std::to_string(be(b, at, 2)));
    add(out, "write count", at + 2, 2, std::to_string(be(b, at + 2, 2)));
    add(out, "byte count", at + 4, 1, std::to_string(b[at + 4]));
    add_registers(out,
                  b,
                  at + 5,
                  static_cast<std::uint32_t>(be(b, at, 2)),
                  static_cast<std::uint32_t>(be(b, at + 2, 2)),
                  true);
  };
  if ((fc == 0x03 || fc == 0x04) && b.size() >= 12) {
    add_read(8);
  } else if (fc == 0x06 && b.size() >= 12) {
    add(out, "address", 8, 2, std::to_string(be(b, 8, 2)));
    add_registers(out, b, 10, static_cast<std::uint32_t>(be(b, 8, 2)), 1, true);
  } else if (fc == 0x10 && b.size() >= 13) {
    add_write(8);
  } else if (fc == 0x17 && b.size() >= 17) {
    add_read(8);
    add_write(12);
  }
  return out;
}

std::vector<FieldValue> decode_modbus_answer(const std::vector<std::uint8_t>& request,
                                             const std::vector<std::uint8_t>& b) {
  std::vector<FieldValue> out;
  add_mbap(out, b);
  if (b.size() < 9) return out;
  const std::uint8_t fc = b[7];
  if ((fc & 0x80) != 0) {
    add(out, "exception code", 8, 1, format_hex(b[8], 2) + " (" + exception_name(b[8]) + ")");
    return out;
  }
  const bool reads = fc == 0x03 || fc == 0x04 || fc == 0x17;
  if (reads) {
    add(out, "byte count", 8, 1, std::to_string(b[8]));
    // Where the read starts is in the request (FC03/04/23: bytes 8-9 of the ADU).
    const std::uint32_t first =
        request.size() >= 10 ? static_cast<std::uint32_t>(be(request, 8, 2)) : 0;
    add_registers(out, b, 9, first, b[8] / 2u, fc != 0x04);
  } else if ((fc == 0x06 || fc == 0x10) && b.size() >= 12) {
    add(out, "address", 8, 2, std::to_string(be(b, 8, 2)));
    add(out, fc == 0x06 ? "value" : "count", 10, 2, std::to_string(be(b, 10, 2)));
  }
  return out;
}

std::string summarize_modbus_request(const std::vector<std::uint8_t>& adu) {
  const std::vector<FieldValue> f = decode_modbus_request(adu);
  if (adu.size() < 8) return "short ADU";
  std::string s = "FC" + format_hex(adu[7], 2);
  const FieldValue* seq = field_named(f, "sequence");
  if (seq != nullptr) s += " seq " + seq->value;
  if (field_named(f, "PV") != nullptr) {
    s += " axis " + number_of(field_named(f, "axis")) + " dir (" +
         number_of(field_named(f, "direction x")) + ", " +
         number_of(field_named(f, "direction y")) + ", " +
         number_of(field_named(f, "direction z")) + ") PV " + number_of(field_named(f, "PV")) +
         " PD " + number_of(field_named(f, "PD")) + " AV " + number_of(field_named(f, "AV")) +
         " AD " + number_of(field_named(f, "AD")) + " Y " + number_of(field_named(f, "Y"));
  } else if (const FieldValue* ra = field_named(f, "read address")) {
    s += " read " + ra->value + "+" + number_of(field_named(f, "read count"));
  }
  return s;
}

std::string summarize_modbus_answer(const std::vector<std::uint8_t>& request,
                                    const std::vector<std::uint8_t>& adu) {
  const std::vector<FieldValue> f = decode_modbus_answer(request, adu);
  if (const FieldValue* e = field_named(f, "exception code")) return "exception " + e->value;
  std::string s;
  if (const FieldValue* st = field_named(f, "status")) s += "status " + st->value;
  if (const FieldValue* rae = field_named(f, "RAE"))
    s += (s.empty() ? "" : " ") + ("RAE " + rae->value);
  if (field_named(f, "correction x") != nullptr) {
    s += " corr (" + number_of(field_named(f, "correction x")) + ", " +
         number_of(field_named(f, "correction y")) + ", " +
         number_of(field_named(f, "correction z")) + ") µm";
  }
  if (const FieldValue* id = field_named(f, "model id")) s += " model " + id->value;
  if (s.empty()) s = "FC" + (adu.size() > 7 ? format_hex(adu[7], 2) : std::string("?")) + " ok";
  return s;
}

}  // namespace cmmcomp::replay

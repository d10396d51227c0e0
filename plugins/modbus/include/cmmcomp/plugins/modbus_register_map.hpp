// SPDX-License-Identifier: MIT
/// @file The Modbus register map of the compensation server: addresses, word order, encode and
/// decode of the request (holding registers) and the result (input registers).
///
/// docs/protocol-modbus.md is the single source of truth; a test checks that every register it
/// lists is in `kHoldingFields` / `kInputFields` below with the same address and size, and the
/// other way round. Pure functions on register arrays: no sockets, no libmodbus, RT-safe.
///
/// Encoding: 32-bit values (IEEE 754 binary32 floats, unsigned integers) take two registers,
/// 64-bit integers four; the most significant word comes first (lowest address), and each
/// register is big-endian on the wire as Modbus requires — the byte order "ABCD", `mbpoll -B`.
#pragma once

#include <array>
#include <cmath>
#include <cmmcomp/compensation/move_request.hpp>
#include <cmmcomp/status.hpp>
#include <cstdint>
#include <cstring>
#include <limits>

namespace cmmcomp::plugins::modbus {

/// Version of the register map in input register kProtocolVersionReg; bumped on any change that
/// a client can observe. Version 2 appended the interval block (input 52–61, its copy holding
/// 48–57); every register of version 1 keeps its address, type and meaning.
inline constexpr std::uint16_t kProtocolVersion = 2;

// ---- holding registers (FC03 read, FC06/FC16/FC23 write): the request
inline constexpr std::uint16_t kAxis = 0;           ///< u16, 0 .. kMaxAxes−1
inline constexpr std::uint16_t kReserved = 1;       ///< u16, must be 0
inline constexpr std::uint16_t kDirectionX = 2;     ///< f32, unit vector component
inline constexpr std::uint16_t kDirectionY = 4;     ///< f32
inline constexpr std::uint16_t kDirectionZ = 6;     ///< f32
inline constexpr std::uint16_t kPv = 8;             ///< f32 [mm/s]
inline constexpr std::uint16_t kPa = 10;            ///< f32 [mm/s²]
inline constexpr std::uint16_t kPd = 12;            ///< f32 [mm]
inline constexpr std::uint16_t kAv = 14;            ///< f32 [mm/s]
inline constexpr std::uint16_t kAa = 16;            ///< f32 [mm/s²]
inline constexpr std::uint16_t kAd = 18;            ///< f32 [mm]
inline constexpr std::uint16_t kY = 20;             ///< f32 [mm]
inline constexpr std::uint16_t kZ = 22;             ///< f32 [mm]
inline constexpr std::uint16_t kSequence = 24;      ///< u16; a write to it triggers the computation
inline constexpr std::uint16_t kRequestCount = 25;  ///< writable holding registers 0 .. 24
/// Read-only copy of the result block (input registers kResultSequence .. kResultEnd−1) so that
/// one FC23 transaction can write a request and read its result.
inline constexpr std::uint16_t kResultCopy = 25;

// ---- input registers (FC04 read): result and status
inline constexpr std::uint16_t kProtocolVersionReg = 0;  ///< u16, kProtocolVersion
inline constexpr std::uint16_t kResultSequence = 1;      ///< u16, echo of the request's sequence
inline constexpr std::uint16_t kResultStatus = 2;        ///< i16, cmmcomp::Status value
inline constexpr std::uint16_t kResultFlags = 3;         ///< u16, CorrectionFlag bits
inline constexpr std::uint16_t kResultAxis = 4;          ///< u16, echo of the request's axis
inline constexpr std::uint16_t kResultReserved = 5;      ///< u16, 0
inline constexpr std::uint16_t kMpe = 6;                 ///< f32 [µm]
inline constexpr std::uint16_t kRpe = 8;                 ///< f32 [µm]
inline constexpr std::uint16_t kMae = 10;                ///< f32 [µm]
inline constexpr std::uint16_t kRae = 12;                ///< f32 [µm]
inline constexpr std::uint16_t kCorrectionX = 14;        ///< f32 [µm]
inline constexpr std::uint16_t kCorrectionY = 16;        ///< f32 [µm]
inline constexpr std::uint16_t kCorrectionZ = 18;        ///< f32 [µm]
inline constexpr std::uint16_t kResultModelId = 20;      ///< u64, model that computed the result
inline constexpr std::uint16_t kResultEnd = 24;          ///< first register after the result
inline constexpr std::uint16_t kRequests = 24;           ///< u32 counter
inline constexpr std::uint16_t kAnswered = 26;           ///< u32 counter
inline constexpr std::uint16_t kRejected = 28;           ///< u32 counter
inline constexpr std::uint16_t kExceptions = 30;         ///< u32 counter
inline constexpr std::uint16_t kComputations = 32;       ///< u32 counter
inline constexpr std::uint16_t kClientsConnected = 34;   ///< u32 counter
inline constexpr std::uint16_t kModelIdAxis0 = 36;       ///< u64 ×4, current model id per axis
// protocol version 2: the result's 95 % prediction interval (docs/uncertainty.md)
inline constexpr std::uint16_t kIntervalFlags = 52;     ///< u16, every CorrectionFlag bit
inline constexpr std::uint16_t kIntervalReserved = 53;  ///< u16, 0
inline constexpr std::uint16_t kU95Mpe = 54;            ///< f32 [µm], U95 of MPE
inline constexpr std::uint16_t kU95Rpe = 56;            ///< f32 [µm]
inline constexpr std::uint16_t kU95Mae = 58;            ///< f32 [µm]
inline constexpr std::uint16_t kU95Rae = 60;            ///< f32 [µm]
inline constexpr std::uint16_t kIntervalEnd = 62;       ///< first register after the interval
inline constexpr std::uint16_t kInputCount = 62;
inline constexpr std::uint16_t kResultWords = kResultEnd - kResultSequence;
inline constexpr std::uint16_t kIntervalWords = kIntervalEnd - kIntervalFlags;
/// Read-only copy of the interval block, right after the result copy, so that one FC23 can write
/// a request and read its result and interval (holding 25–57).
inline constexpr std::uint16_t kIntervalCopy = kResultCopy + kResultWords;      ///< 48
inline constexpr std::uint16_t kHoldingCount = kIntervalCopy + kIntervalWords;  ///< 58

static_assert(kSequence == kRequestCount - 1, "the trigger is the last request register");
static_assert(kModelIdAxis0 + 4 * compensation::kMaxAxes == kIntervalFlags,
              "the interval block follows the model ids");
static_assert(kIntervalEnd == kInputCount, "input map size");

using HoldingRegisters = std::array<std::uint16_t, kHoldingCount>;
using InputRegisters = std::array<std::uint16_t, kInputCount>;

/// Value types of the map, as the document names them.
enum class FieldType : std::uint8_t { kU16, kI16, kU32, kU64, kF32 };

/// Registers a value of `type` occupies.
constexpr std::uint16_t words(FieldType type) noexcept {
  switch (type) {
    case FieldType::kU32:
    case FieldType::kF32:
      return 2;
    case FieldType::kU64:
      return 4;
    default:
      return 1;
  }
}

/// One named register (or register group) of the map, as listed in docs/protocol-modbus.md.
struct Field {
  const char* name;         ///< name used in the document's tables
  std::uint16_t address;    ///< 0-based PDU address (mbpoll: -0, or address + 1 without it)
  FieldType type;           ///< value type (of each element when `count` > 1)
  const char* label;        ///< short label for people (decoders, logs): "PV", "status"
  const char* unit;         ///< unit of the value, "" when it has none
  std::uint16_t count = 1;  ///< elements (the result copy is kResultWords u16)

  /// Registers the field occupies.
  constexpr std::uint16_t registers() const noexcept {
    return static_cast<std::uint16_t>(words(type) * count);
  }
};

inline constexpr std::array<Field, 16> kHoldingFields{{
    {"axis", kAxis, FieldType::kU16, "axis", ""},
    {"reserved", kReserved, FieldType::kU16, "reserved", ""},
    {"direction_x", kDirectionX, FieldType::kF32, "direction x", ""},
    {"direction_y", kDirectionY, FieldType::kF32, "direction y", ""},
    {"direction_z", kDirectionZ, FieldType::kF32, "direction z", ""},
    {"pv_mm_s", kPv, FieldType::kF32, "PV", "mm/s"},
    {"pa_mm_s2", kPa, FieldType::kF32, "PA", "mm/s²"},
    {"pd_mm", kPd, FieldType::kF32, "PD", "mm"},
    {"av_mm_s", kAv, FieldType::kF32, "AV", "mm/s"},
    {"aa_mm_s2", kAa, FieldType::kF32, "AA", "mm/s²"},
    {"ad_mm", kAd, FieldType::kF32, "AD", "mm"},
    {"y_mm", kY, FieldType::kF32, "Y", "mm"},
    {"z_mm", kZ, FieldType::kF32, "Z", "mm"},
    {"sequence", kSequence, FieldType::kU16, "sequence", ""},
    {"result_copy", kResultCopy, FieldType::kU16, "result copy", "", kResultWords},
    {"interval_copy", kIntervalCopy, FieldType::kU16, "interval copy", "", kIntervalWords},
}};

inline constexpr std::array<Field, 30> kInputFields{{
    {"protocol_version", kProtocolVersionReg, FieldType::kU16, "protocol version", ""},
    {"result_sequence", kResultSequence, FieldType::kU16, "sequence", ""},
    {"result_status", kResultStatus, FieldType::kI16, "status", ""},
    {"result_flags", kResultFlags, FieldType::kU16, "flags", ""},
    {"result_axis", kResultAxis, FieldType::kU16, "axis", ""},
    {"result_reserved", kResultReserved, FieldType::kU16, "reserved", ""},
    {"mpe_um", kMpe, FieldType::kF32, "MPE", "µm"},
    {"rpe_um", kRpe, FieldType::kF32, "RPE", "µm"},
    {"mae_um", kMae, FieldType::kF32, "MAE", "µm"},
    {"rae_um", kRae, FieldType::kF32, "RAE", "µm"},
    {"correction_x_um", kCorrectionX, FieldType::kF32, "correction x", "µm"},
    {"correction_y_um", kCorrectionY, FieldType::kF32, "correction y", "µm"},
    {"correction_z_um", kCorrectionZ, FieldType::kF32, "correction z", "µm"},
    {"result_model_id", kResultModelId, FieldType::kU64, "model id", ""},
    {"requests", kRequests, FieldType::kU32, "requests counter", ""},
    {"answered", kAnswered, FieldType::kU32, "answered counter", ""},
    {"rejected", kRejected, FieldType::kU32, "rejected counter", ""},
    {"exceptions", kExceptions, FieldType::kU32, "exceptions counter", ""},
    {"computations", kComputations, FieldType::kU32, "computations counter", ""},
    {"clients_connected", kClientsConnected, FieldType::kU32, "clients counter", ""},
    {"model_id_axis0", kModelIdAxis0, FieldType::kU64, "model id axis 0", ""},
    {"model_id_axis1", kModelIdAxis0 + 4, FieldType::kU64, "model id axis 1", ""},
    {"model_id_axis2", kModelIdAxis0 + 8, FieldType::kU64, "model id axis 2", ""},
    {"model_id_axis3", kModelIdAxis0 + 12, FieldType::kU64, "model id axis 3", ""},
    {"interval_flags", kIntervalFlags, FieldType::kU16, "interval flags", ""},
    {"interval_reserved", kIntervalReserved, FieldType::kU16, "interval reserved", ""},
    {"u95_mpe_um", kU95Mpe, FieldType::kF32, "U95 MPE", "µm"},
    {"u95_rpe_um", kU95Rpe, FieldType::kF32, "U95 RPE", "µm"},
    {"u95_mae_um", kU95Mae, FieldType::kF32, "U95 MAE", "µm"},
    {"u95_rae_um", kU95Rae, FieldType::kF32, "U95 RAE", "µm"},
}};

// ---- word codecs (most significant word first)

/// Writes `v` into regs[0..1], high word first. RT-safe.
inline void put_u32(std::uint16_t* regs, std::uint32_t v) noexcept {
  regs[0] = static_cast<std::uint16_t>(v >> 16);
  regs[1] = static_cast<std::uint16_t>(v & 0xFFFFu);
}

/// Reads the u32 at regs[0..1], high word first. RT-safe.
inline std::uint32_t get_u32(const std::uint16_t* regs) noexcept {
  return (static_cast<std::uint32_t>(regs[0]) << 16) | regs[1];
}

/// Writes `v` into regs[0..3], most significant word first. RT-safe.
inline void put_u64(std::uint16_t* regs, std::uint64_t v) noexcept {
  for (int i = 0; i < 4; ++i) {
    regs[i] = static_cast<std::uint16_t>(v >> (48 - 16 * i));
  }
}

/// Reads the u64 at regs[0..3], most significant word first. RT-safe.
inline std::uint64_t get_u64(const std::uint16_t* regs) noexcept {
  std::uint64_t v = 0;
  for (int i = 0; i < 4; ++i) v = (v << 16) | regs[i];
  return v;
}

/// Writes the binary32 `v` into regs[0..1] (sign and exponent in regs[0]). RT-safe.
inline void put_f32(std::uint16_t* regs, float v) noexcept {
  std::uint32_t bits = 0;
  static_assert(sizeof bits == sizeof v, "binary32");
  std::memcpy(&bits, &v, sizeof bits);
  put_u32(regs, bits);
}

/// Reads the binary32 at regs[0..1]. RT-safe.
inline float get_f32(const std::uint16_t* regs) noexcept {
  const std::uint32_t bits = get_u32(regs);
  float v = 0.0f;
  std::memcpy(&v, &bits, sizeof v);
  return v;
}

// ---- the request

/// One binary32 request field: its first holding register and its place in MoveRequest. The one
/// list of the request's float fields: encode_request and decode_request go through it.
struct FloatBinding {
  std::uint16_t reg;
  double (*get)(const compensation::MoveRequest&) noexcept;
  void (*set)(compensation::MoveRequest&, double) noexcept;
};

// clang-format off
inline constexpr FloatBinding kFloatBindings[] = {
    {kDirectionX, [](const compensation::MoveRequest& m) noexcept { return m.direction[0]; },
                  [](compensation::MoveRequest& m, double v) noexcept { m.direction[0] = v; }},
    {kDirectionY, [](const compensation::MoveRequest& m) noexcept { return m.direction[1]; },
                  [](compensation::MoveRequest& m, double v) noexcept { m.direction[1] = v; }},
    {kDirectionZ, [](const compensation::MoveRequest& m) noexcept { return m.direction[2]; },
                  [](compensation::MoveRequest& m, double v) noexcept { m.direction[2] = v; }},
    {kPv, [](const compensation::MoveRequest& m) noexcept { return m.pv_mm_s; },
          [](compensation::MoveRequest& m, double v) noexcept { m.pv_mm_s = v; }},
    {kPa, [](const compensation::MoveRequest& m) noexcept { return m.pa_mm_s2; },
          [](compensation::MoveRequest& m, double v) noexcept { m.pa_mm_s2 = v; }},
    {kPd, [](const compensation::MoveRequest& m) noexcept { return m.pd_mm; },
          [](compensation::MoveRequest& m, double v) noexcept { m.pd_mm = v; }},
    {kAv, [](const compensation::MoveRequest& m) noexcept { return m.av_mm_s; },
          [](compensation::MoveRequest& m, double v) noexcept { m.av_mm_s = v; }},
    {kAa, [](const compensation::MoveRequest& m) noexcept { return m.aa_mm_s2; },
          [](compensation::MoveRequest& m, double v) noexcept { m.aa_mm_s2 = v; }},
    {kAd, [](const compensation::MoveRequest& m) noexcept { return m.ad_mm; },
          [](compensation::MoveRequest& m, double v) noexcept { m.ad_mm = v; }},
    {kY, [](const compensation::MoveRequest& m) noexcept { return m.y_mm; },
         [](compensation::MoveRequest& m, double v) noexcept { m.y_mm = v; }},
    {kZ, [](const compensation::MoveRequest& m) noexcept { return m.z_mm; },
         [](compensation::MoveRequest& m, double v) noexcept { m.z_mm = v; }},
};
// clang-format on

/// Writes `m` into the holding-register image (direction and values rounded to binary32; the
/// sequence keeps its low 16 bits). RT-safe.
inline void encode_request(const compensation::MoveRequest& m, HoldingRegisters& h) noexcept {
  h[kAxis] = m.axis;
  h[kReserved] = 0;
  for (const FloatBinding& b : kFloatBindings) put_f32(&h[b.reg], static_cast<float>(b.get(m)));
  h[kSequence] = static_cast<std::uint16_t>(m.sequence & 0xFFFFu);
}

/// Reads the request from the holding-register image into `m` (floats widened exactly to
/// double). Returns kOk, or kInvalidInput when the axis is ≥ kMaxAxes or the reserved register
/// is not 0 (`m` untouched then). Values are checked by `check_field` / `validate_move`. RT-safe.
[[nodiscard]] inline Status decode_request(const HoldingRegisters& h,
                                           compensation::MoveRequest& m) noexcept {
  if (h[kAxis] >= compensation::kMaxAxes || h[kReserved] != 0) return Status::kInvalidInput;
  m.sequence = h[kSequence];
  m.axis = static_cast<std::uint8_t>(h[kAxis]);
  for (const FloatBinding& b : kFloatBindings) b.set(m, static_cast<double>(get_f32(&h[b.reg])));
  return Status::kOk;
}

/// Checks the value of the holding field that register `address` belongs to, as it stands in
/// `h` (a write is checked on the merged image, so a float written one register at a time is
/// checked with its other half). Rules: axis < kMaxAxes; reserved = 0; direction components
/// finite with |c| ≤ 1 + kDirectionTolerance; PV, PA, PD, AV, AA, AD finite and > 0; Y, Z finite;
/// sequence any value. Returns kOk or kInvalidInput. RT-safe.
[[nodiscard]] inline Status check_field(const HoldingRegisters& h, std::uint16_t address) noexcept {
  if (address >= kRequestCount) return Status::kInvalidInput;
  if (address == kAxis) {
    return h[kAxis] < compensation::kMaxAxes ? Status::kOk : Status::kInvalidInput;
  }
  if (address == kReserved) return h[kReserved] == 0 ? Status::kOk : Status::kInvalidInput;
  if (address == kSequence) return Status::kOk;
  const std::uint16_t first = static_cast<std::uint16_t>(address & ~1u);  // floats start even
  const float v = get_f32(&h[first]);
  if (!std::isfinite(v)) return Status::kInvalidInput;
  if (first <= kDirectionZ) {
    return std::fabs(static_cast<double>(v)) <= 1.0 + compensation::kDirectionTolerance
               ? Status::kOk
               : Status::kInvalidInput;
  }
  if (first <= kAd) return v > 0.0f ? Status::kOk : Status::kInvalidInput;
  return Status::kOk;  // y, z: finite is enough
}

// ---- the result

/// A result as a client reads it from the input registers (floats widened to double).
struct Result {
  std::uint16_t sequence = 0;  ///< echo of the request's sequence register
  std::int16_t status = 0;     ///< cmmcomp::Status value
  std::uint16_t flags = 0;     ///< CorrectionFlag bits; kFlagOk set ⇔ the correction may be used
  std::uint16_t axis = 0;      ///< echo of the request's axis
  double mpe_um = 0.0;         ///< predicted MPE [µm]
  double rpe_um = 0.0;         ///< predicted RPE [µm]
  double mae_um = 0.0;         ///< predicted MAE [µm]
  double rae_um = 0.0;         ///< predicted RAE [µm]
  std::array<double, 3> correction_um{0.0, 0.0, 0.0};  ///< +RAE·d [µm]
  std::uint64_t model_id = 0;                          ///< model that computed it
  /// Protocol version 2: every CorrectionFlag bit (kFlagNoUncertainty too), and the 95 %
  /// interval half-widths of MPE, RPE, MAE, RAE [µm] (0: unknown or no result).
  std::uint16_t interval_flags = 0;
  std::array<double, 4> u95_um{0.0, 0.0, 0.0, 0.0};
};

/// The seven values of `c` in result-block order (MPE, RPE, MAE, RAE, correction x, y, z).
/// RT-safe.
inline std::array<double, 7> result_values(const compensation::Correction& c) noexcept {
  return {c.mpe_um,
          c.rpe_um,
          c.mae_um,
          c.rae_um,
          c.correction_um[0],
          c.correction_um[1],
          c.correction_um[2]};
}

/// True when every value of `c` (the interval's half-widths too) fits a finite binary32.
/// RT-safe.
inline bool fits_f32(const compensation::Correction& c) noexcept {
  constexpr double kMax = static_cast<double>(std::numeric_limits<float>::max());
  bool good = true;
  for (double v : result_values(c)) good = good && std::isfinite(v) && std::fabs(v) <= kMax;
  for (double v : c.u95_um) good = good && std::isfinite(v) && std::fabs(v) <= kMax;
  return good;
}

/// Writes the result of one request into the result block [kResultSequence, kResultEnd) and the
/// interval block [kIntervalFlags, kIntervalEnd) of `in`: when ok(status) and `c` fits binary32,
/// the correction and its interval; otherwise zeros, flags_for(status) (kInvalidInput when the
/// values do not fit) and model id 0. `result_flags` keeps the version-1 bits (a version-1
/// client sees the same bytes); `interval_flags` has every bit. Never writes NaN or inf. RT-safe.
inline void encode_result(std::uint16_t sequence,
                          std::uint16_t axis,
                          Status status,
                          const compensation::Correction& c,
                          InputRegisters& in) noexcept {
  const bool usable = ok(status) && fits_f32(c);
  if (ok(status) && !usable) status = Status::kInvalidInput;
  in[kResultSequence] = sequence;
  in[kResultStatus] = static_cast<std::uint16_t>(static_cast<std::int16_t>(status));
  // result_flags carries only the flags a version-1 client knows (docs/protocol-modbus.md).
  in[kResultFlags] = static_cast<std::uint16_t>(
      (usable ? c.flags : compensation::flags_for(status)) & compensation::kFlagsVersion1);
  in[kResultAxis] = axis;
  in[kResultReserved] = 0;
  const std::array<double, 7> values = result_values(c);
  for (std::uint16_t i = 0; i < 7; ++i) {
    put_f32(&in[static_cast<std::size_t>(kMpe + 2 * i)],
            usable ? static_cast<float>(values[i]) : 0.0f);
  }
  put_u64(&in[kResultModelId], usable ? c.model_id : 0);
  in[kIntervalFlags] =
      static_cast<std::uint16_t>(usable ? c.flags : compensation::flags_for(status));
  in[kIntervalReserved] = 0;
  for (std::uint16_t i = 0; i < 4; ++i) {
    put_f32(&in[static_cast<std::size_t>(kU95Mpe + 2 * i)],
            usable ? static_cast<float>(c.u95_um[i]) : 0.0f);
  }
}

/// Reads the result block of `in`. RT-safe.
inline Result decode_result(const InputRegisters& in) noexcept {
  Result r;
  r.sequence = in[kResultSequence];
  r.status = static_cast<std::int16_t>(in[kResultStatus]);
  r.flags = in[kResultFlags];
  r.axis = in[kResultAxis];
  r.mpe_um = static_cast<double>(get_f32(&in[kMpe]));
  r.rpe_um = static_cast<double>(get_f32(&in[kRpe]));
  r.mae_um = static_cast<double>(get_f32(&in[kMae]));
  r.rae_um = static_cast<double>(get_f32(&in[kRae]));
  r.correction_um = {static_cast<double>(get_f32(&in[kCorrectionX])),
                     static_cast<double>(get_f32(&in[kCorrectionY])),
                     static_cast<double>(get_f32(&in[kCorrectionZ]))};
  r.model_id = get_u64(&in[kResultModelId]);
  r.interval_flags = in[kIntervalFlags];
  for (std::uint16_t i = 0; i < 4; ++i) {
    r.u95_um[i] = static_cast<double>(get_f32(&in[static_cast<std::size_t>(kU95Mpe + 2 * i)]));
  }
  return r;
}

}  // namespace cmmcomp::plugins::modbus

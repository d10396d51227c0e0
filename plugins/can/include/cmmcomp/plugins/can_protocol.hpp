// SPDX-License-Identifier: MIT
/// @file The cmmcomp CAN protocol (docs/protocol-can.md, plugins/can/cmmcomp.dbc): every frame
/// and signal as constexpr tables, and encode/decode of every frame. Pure: no socket, no kernel
/// header, so it is testable anywhere and usable by a controller written in C++.
///
/// All signals are Intel (little-endian) byte order: bit `start` of a signal is bit (start % 8)
/// of data byte (start / 8), and the signal occupies the `length` bits above it in the 64-bit
/// little-endian word made of the 8 data bytes — the DBC's `start|length@1`.
/// A physical value v is sent as raw = round((v − offset)/factor); a value whose raw would fall
/// outside [min, max]/factor is rejected (Status::kInvalidInput), never wrapped or clamped.
/// The one exception is a U95 of the interval part (response part 3): it saturates at its
/// largest raw value, flagged (docs/protocol-can.md, "Interval").
///
/// Protocol version 2 (kProtocolVersion): version 1 plus the request bit WantInterval, the
/// response's part 3 (the 95 % prediction interval) and the heartbeat's ProtocolVersion. A
/// request with WantInterval 0 gets exactly the frames of version 1.
#pragma once

#include <array>
#include <cmath>
#include <cmmcomp/compensation/move_request.hpp>
#include <cmmcomp/status.hpp>
#include <cstddef>
#include <cstdint>
#include <iterator>

namespace cmmcomp::plugins::can {

/// One classic CAN frame (11-bit identifier, up to 8 data bytes), independent of linux/can.h.
struct Frame {
  std::uint32_t id = 0;                ///< 11-bit standard identifier
  std::uint8_t dlc = 0;                ///< data length code, 0..8
  std::array<std::uint8_t, 8> data{};  ///< data bytes; those past `dlc` are 0
};

/// Data length of every cmmcomp frame: classic CAN, 8 bytes.
inline constexpr std::uint8_t kFrameDlc = 8;
/// Default base identifier; the four messages use base + their offset.
inline constexpr std::uint32_t kDefaultBaseId = 0x300;
/// Largest 11-bit identifier.
inline constexpr std::uint32_t kMaxStandardId = 0x7FF;

/// Version of the protocol this codec speaks, sent in every heartbeat (page 0, ProtocolVersion).
/// Version 1 servers sent 0 in those bits.
inline constexpr std::uint8_t kProtocolVersion = 2;

/// Identifier offsets from the base id.
inline constexpr std::uint32_t kRequestOffset = 0;    ///< controller → server, 3 parts
inline constexpr std::uint32_t kResponseOffset = 1;   ///< server → controller, 3 or 4 parts
inline constexpr std::uint32_t kRejectOffset = 2;     ///< server → controller, 1 frame
inline constexpr std::uint32_t kHeartbeatOffset = 3;  ///< server → controller, 5 pages
inline constexpr std::uint32_t kMessageCount = 4;

/// Parts of a request and of a response; pages of a heartbeat.
inline constexpr std::uint8_t kRequestParts = 3;
/// Parts 0–2 of a response: the result, what every version-1 client reads.
inline constexpr std::uint8_t kResponseParts = 3;
/// Part 3 of a response, the prediction interval: sent after parts 0–2 when the request asked
/// for it (WantInterval).
inline constexpr std::uint8_t kIntervalPart = 3;
inline constexpr std::uint8_t kHeartbeatPages = 5;
/// The sequence number is 6 bits: 0..63, incremented (mod 64) by the controller per request.
inline constexpr std::uint8_t kSequenceMask = 0x3F;
/// Sequence or part value in a reject frame when the frame was too short to carry it.
inline constexpr std::uint8_t kUnknown = 0xFF;

/// How a signal takes part in multiplexing (DBC: none, `M`, `mN`).
inline constexpr std::int8_t kNotMultiplexed = -1;
inline constexpr std::int8_t kMultiplexor = -2;

/// One signal, exactly as its DBC `SG_` line states it (the DBC test compares them).
struct SignalSpec {
  const char* name;     ///< DBC signal name
  std::uint8_t start;   ///< start bit (Intel: least significant bit)
  std::uint8_t length;  ///< bits
  bool is_signed;       ///< two's complement
  double factor;        ///< physical = raw·factor + offset
  double offset;
  double min;        ///< smallest accepted physical value
  double max;        ///< largest accepted physical value
  const char* unit;  ///< DBC unit (ASCII: "um" is µm, "mm/s2" is mm/s²)
  std::int8_t mux;   ///< kNotMultiplexed, kMultiplexor or the multiplexer value it belongs to

  /// Raw limits that correspond to min and max.
  constexpr std::int64_t raw_min() const noexcept {
    return round_half_away((min - offset) / factor);
  }
  constexpr std::int64_t raw_max() const noexcept {
    return round_half_away((max - offset) / factor);
  }

  static constexpr std::int64_t round_half_away(double v) noexcept {
    return static_cast<std::int64_t>(v < 0.0 ? v - 0.5 : v + 0.5);
  }
};

/// One message, as its DBC `BO_` line states it.
struct MessageSpec {
  const char* name;           ///< DBC message name
  std::uint32_t offset;       ///< identifier = base id + offset
  const char* sender;         ///< DBC transmitter node
  const SignalSpec* signals;  ///< its signals
  std::size_t signal_count;
};

// ---- Request (base + 0): the move, in three parts --------------------------------------------
namespace request {
inline constexpr SignalSpec kPart{"ReqPart", 0, 2, false, 1, 0, 0, 2, "", kMultiplexor};
inline constexpr SignalSpec kSequence{"ReqSequence", 2, 6, false, 1, 0, 0, 63, "", kNotMultiplexed};
// Part 0: the model's inputs PV, PD, AV and the axis.
inline constexpr SignalSpec kPv{"PV", 8, 16, false, 0.1, 0, 0.1, 6000, "mm/s", 0};
inline constexpr SignalSpec kPd{"PD", 24, 16, false, 0.01, 0, 0.01, 600, "mm", 0};
inline constexpr SignalSpec kAv{"AV", 40, 16, false, 0.01, 0, 0.01, 600, "mm/s", 0};
inline constexpr SignalSpec kAxis{"Axis", 56, 4, false, 1, 0, 0, 3, "", 0};
/// Version 2: 1 asks for the prediction interval (response part 3). Version-1 clients send 0.
inline constexpr SignalSpec kWantInterval{"WantInterval", 60, 1, false, 1, 0, 0, 1, "", 0};
// Part 1: AD (a model input), the accelerations and the carriage position.
inline constexpr SignalSpec kAd{"AD", 8, 16, false, 0.001, 0, 0.001, 60, "mm", 1};
inline constexpr SignalSpec kPa{"PA", 24, 12, false, 5, 0, 5, 20000, "mm/s2", 1};
inline constexpr SignalSpec kAa{"AA", 36, 12, false, 1, 0, 1, 4000, "mm/s2", 1};
inline constexpr SignalSpec kY{"Y", 48, 16, true, 0.1, 0, -3000, 3000, "mm", 1};
// Part 2: the ram position and the approach direction.
inline constexpr SignalSpec kZ{"Z", 8, 16, true, 0.1, 0, -3000, 3000, "mm", 2};
inline constexpr SignalSpec kDirX{"DirX", 24, 12, true, 0.0005, 0, -1, 1, "", 2};
inline constexpr SignalSpec kDirY{"DirY", 36, 12, true, 0.0005, 0, -1, 1, "", 2};
inline constexpr SignalSpec kDirZ{"DirZ", 48, 12, true, 0.0005, 0, -1, 1, "", 2};
inline constexpr std::array<SignalSpec, 15> kSignals{kPart,
                                                     kSequence,
                                                     kPv,
                                                     kPd,
                                                     kAv,
                                                     kAxis,
                                                     kWantInterval,
                                                     kAd,
                                                     kPa,
                                                     kAa,
                                                     kY,
                                                     kZ,
                                                     kDirX,
                                                     kDirY,
                                                     kDirZ};
/// Bits that must be 0 in each part (reserved for later versions of the protocol).
inline constexpr std::array<std::uint64_t, kRequestParts> kReservedMask{
    0xE000000000000000ull, 0, 0xF000000000000000ull};
/// |decoded direction| must be within 1 ± this before the server normalises it.
inline constexpr double kDirectionNormTolerance = 0.01;
}  // namespace request

// ---- Response (base + 1): the correction in three parts, and the interval in a fourth -------
namespace response {
inline constexpr SignalSpec kPart{"RespPart", 0, 2, false, 1, 0, 0, 3, "", kMultiplexor};
inline constexpr SignalSpec kSequence{
    "RespSequence", 2, 6, false, 1, 0, 0, 63, "", kNotMultiplexed};
inline constexpr SignalSpec kFlags{"Flags", 8, 4, false, 1, 0, 0, 15, "", 0};
inline constexpr SignalSpec kAxis{"RespAxis", 12, 4, false, 1, 0, 0, 3, "", 0};
inline constexpr SignalSpec kMpe{"MPE", 16, 16, true, 0.01, 0, -327.67, 327.67, "um", 0};
inline constexpr SignalSpec kRpe{"RPE", 32, 16, true, 0.01, 0, -327.67, 327.67, "um", 0};
inline constexpr SignalSpec kMae{"MAE", 48, 16, true, 0.01, 0, -327.67, 327.67, "um", 0};
inline constexpr SignalSpec kRae{"RAE", 8, 16, true, 0.01, 0, -327.67, 327.67, "um", 1};
inline constexpr SignalSpec kCorrX{"CorrX", 24, 16, true, 0.01, 0, -327.67, 327.67, "um", 1};
inline constexpr SignalSpec kCorrY{"CorrY", 40, 16, true, 0.01, 0, -327.67, 327.67, "um", 1};
inline constexpr SignalSpec kCorrZ{"CorrZ", 8, 16, true, 0.01, 0, -327.67, 327.67, "um", 2};
inline constexpr SignalSpec kModelId{"ModelId", 24, 32, false, 1, 0, 0, 4294967295.0, "", 2};
// Part 3 (version 2, only when the request set WantInterval): the 95 % prediction interval's
// half-widths. Raw 4095 (81.9 µm) means "81.89 µm or more" and comes with kIntervalSaturated.
inline constexpr SignalSpec kIntervalFlags{"IntervalFlags", 8, 8, false, 1, 0, 0, 255, "", 3};
inline constexpr SignalSpec kU95Mpe{"U95MPE", 16, 12, false, 0.02, 0, 0, 81.9, "um", 3};
inline constexpr SignalSpec kU95Rpe{"U95RPE", 28, 12, false, 0.02, 0, 0, 81.9, "um", 3};
inline constexpr SignalSpec kU95Mae{"U95MAE", 40, 12, false, 0.02, 0, 0, 81.9, "um", 3};
inline constexpr SignalSpec kU95Rae{"U95RAE", 52, 12, false, 0.02, 0, 0, 81.9, "um", 3};
inline constexpr std::array<SignalSpec, 17> kSignals{kPart,
                                                     kSequence,
                                                     kFlags,
                                                     kAxis,
                                                     kMpe,
                                                     kRpe,
                                                     kMae,
                                                     kRae,
                                                     kCorrX,
                                                     kCorrY,
                                                     kCorrZ,
                                                     kModelId,
                                                     kIntervalFlags,
                                                     kU95Mpe,
                                                     kU95Rpe,
                                                     kU95Mae,
                                                     kU95Rae};
/// The U95 signals in Correction::u95_um's order (MPE, RPE, MAE, RAE).
inline constexpr std::array<SignalSpec, 4> kU95{kU95Mpe, kU95Rpe, kU95Mae, kU95Rae};
/// Bits of IntervalFlags.
inline constexpr std::uint8_t kIntervalNoUncertainty = 1u << 0;  ///< no calibration: U95 unknown
inline constexpr std::uint8_t kIntervalSaturated = 1u << 1;      ///< a U95 sent as raw 4095
}  // namespace response

// ---- Reject (base + 2): one frame per rejected request or frame ------------------------------
namespace reject {
inline constexpr SignalSpec kReason{"Reason", 0, 8, false, 1, 0, 1, 12, "", kNotMultiplexed};
inline constexpr SignalSpec kSequence{
    "RejSequence", 8, 8, false, 1, 0, 0, 255, "", kNotMultiplexed};
inline constexpr SignalSpec kPart{"RejPart", 16, 8, false, 1, 0, 0, 255, "", kNotMultiplexed};
inline constexpr SignalSpec kDetail{"Detail", 24, 8, false, 1, 0, 0, 255, "", kNotMultiplexed};
inline constexpr SignalSpec kStatus{
    "Status", 32, 16, true, 1, 0, -32768, 32767, "", kNotMultiplexed};
inline constexpr SignalSpec kRejected{
    "RejectCount", 48, 16, false, 1, 0, 0, 65535, "", kNotMultiplexed};
inline constexpr std::array<SignalSpec, 6> kSignals{
    kReason, kSequence, kPart, kDetail, kStatus, kRejected};
}  // namespace reject

// ---- Heartbeat (base + 3): counters (page 0) and the model id of each axis (pages 1–4) -------
namespace heartbeat {
inline constexpr SignalSpec kPage{"HbPage", 0, 3, false, 1, 0, 0, 4, "", kMultiplexor};
inline constexpr SignalSpec kTick{"HbTick", 3, 5, false, 1, 0, 0, 31, "", kNotMultiplexed};
inline constexpr SignalSpec kRequests{"Requests", 8, 16, false, 1, 0, 0, 65535, "", 0};
inline constexpr SignalSpec kAnswered{"Answered", 24, 16, false, 1, 0, 0, 65535, "", 0};
inline constexpr SignalSpec kRejected{"Rejected", 40, 16, false, 1, 0, 0, 65535, "", 0};
inline constexpr SignalSpec kModelMask{"ModelMask", 56, 4, false, 1, 0, 0, 15, "", 0};
/// Version 2: kProtocolVersion. Version-1 servers sent 0 here (the bits were reserved).
inline constexpr SignalSpec kVersion{"ProtocolVersion", 60, 4, false, 1, 0, 0, 15, "", 0};
inline constexpr SignalSpec kModelId0{
    "ModelIdAxis0", 16, 48, false, 1, 0, 0, 281474976710655.0, "", 1};
inline constexpr SignalSpec kModelId1{
    "ModelIdAxis1", 16, 48, false, 1, 0, 0, 281474976710655.0, "", 2};
inline constexpr SignalSpec kModelId2{
    "ModelIdAxis2", 16, 48, false, 1, 0, 0, 281474976710655.0, "", 3};
inline constexpr SignalSpec kModelId3{
    "ModelIdAxis3", 16, 48, false, 1, 0, 0, 281474976710655.0, "", 4};
inline constexpr std::array<SignalSpec, 11> kSignals{kPage,
                                                     kTick,
                                                     kRequests,
                                                     kAnswered,
                                                     kRejected,
                                                     kModelMask,
                                                     kVersion,
                                                     kModelId0,
                                                     kModelId1,
                                                     kModelId2,
                                                     kModelId3};
inline constexpr std::array<SignalSpec, 4> kModelIds{kModelId0, kModelId1, kModelId2, kModelId3};
}  // namespace heartbeat

/// Every message of the protocol, in identifier order (the DBC lists the same).
inline constexpr std::array<MessageSpec, kMessageCount> kMessages{
    MessageSpec{"MoveRequest",
                kRequestOffset,
                "Controller",
                request::kSignals.data(),
                request::kSignals.size()},
    MessageSpec{"MoveResponse",
                kResponseOffset,
                "Compensator",
                response::kSignals.data(),
                response::kSignals.size()},
    MessageSpec{
        "Reject", kRejectOffset, "Compensator", reject::kSignals.data(), reject::kSignals.size()},
    MessageSpec{"Heartbeat",
                kHeartbeatOffset,
                "Compensator",
                heartbeat::kSignals.data(),
                heartbeat::kSignals.size()},
};

/// Why a request (or one of its frames) was rejected: the Reason signal of the reject frame.
enum class RejectReason : std::uint8_t {
  kNone = 0,              ///< not a rejection (never sent)
  kWrongDlc = 1,          ///< a request frame with DLC ≠ 8
  kUnknownPart = 2,       ///< part index 3 (the multiplexer has values 0..2)
  kSequenceMismatch = 3,  ///< a part 1/2 whose sequence differs from the request being assembled
  kMissingPart = 4,       ///< a part 1/2 without its predecessor (stale, duplicate or out of order)
  kTimeout = 5,           ///< the next part did not come within the part timeout
  kIncomplete = 6,        ///< a new part 0 came before the request being assembled was complete
  kFieldOutOfRange = 7,   ///< a field outside its range; Detail = RequestField
  kReservedBits = 8,      ///< a reserved bit was set (request part 0 bits 61–63, part 2 60–63)
  kInvalidMove = 9,       ///< the compensator refused the move (kInvalidInput); Status set
  kNoModel = 10,          ///< no model published for the axis
  kOutsideDomain = 11,    ///< outside the training domain and the policy rejects it
  kResultOutOfRange = 12,  ///< a result does not fit its signal; Detail = ResponseField
};

/// Static name of a reason (for logs and tests). RT-safe.
constexpr const char* to_string(RejectReason r) noexcept {
  switch (r) {
    case RejectReason::kNone:
      return "none";
    case RejectReason::kWrongDlc:
      return "wrong DLC";
    case RejectReason::kUnknownPart:
      return "unknown part";
    case RejectReason::kSequenceMismatch:
      return "sequence mismatch";
    case RejectReason::kMissingPart:
      return "missing part";
    case RejectReason::kTimeout:
      return "timeout between parts";
    case RejectReason::kIncomplete:
      return "incomplete (superseded by a new request)";
    case RejectReason::kFieldOutOfRange:
      return "field out of range";
    case RejectReason::kReservedBits:
      return "reserved bits set";
    case RejectReason::kInvalidMove:
      return "invalid move";
    case RejectReason::kNoModel:
      return "no model";
    case RejectReason::kOutsideDomain:
      return "outside the training domain";
    case RejectReason::kResultOutOfRange:
      return "result out of range";
  }
  return "unknown reason";
}

/// Detail of a kFieldOutOfRange reject: which request field.
enum class RequestField : std::uint8_t {
  kNone = 0,
  kPv = 1,
  kPd = 2,
  kAv = 3,
  kAxis = 4,
  kAd = 5,
  kPa = 6,
  kAa = 7,
  kY = 8,
  kZ = 9,
  kDirX = 10,
  kDirY = 11,
  kDirZ = 12,
  kDirection = 13,
  kSequence = 14,
};
/// The reject reason of a request the compensator refused with `s` (not ok).
constexpr RejectReason reject_reason(Status s) noexcept {
  switch (s) {
    case Status::kNoModel:
      return RejectReason::kNoModel;
    case Status::kOutsideDomainRejected:
      return RejectReason::kOutsideDomain;
    default:
      return RejectReason::kInvalidMove;
  }
}

/// One request field on the wire: its signal, the detail a reject names it by, and its place in
/// MoveRequest. The one list of the request's fields: encode_request, decode_request and the
/// DBC and document tests go through it.
struct RequestBinding {
  const SignalSpec* spec;
  RequestField field;
  double (*get)(const compensation::MoveRequest&) noexcept;
  void (*set)(compensation::MoveRequest&, double) noexcept;
};

// clang-format off
inline constexpr RequestBinding kRequestBindings[] = {
    {&request::kPv, RequestField::kPv,
     [](const compensation::MoveRequest& m) noexcept { return m.pv_mm_s; },
     [](compensation::MoveRequest& m, double v) noexcept { m.pv_mm_s = v; }},
    {&request::kPd, RequestField::kPd,
     [](const compensation::MoveRequest& m) noexcept { return m.pd_mm; },
     [](compensation::MoveRequest& m, double v) noexcept { m.pd_mm = v; }},
    {&request::kAv, RequestField::kAv,
     [](const compensation::MoveRequest& m) noexcept { return m.av_mm_s; },
     [](compensation::MoveRequest& m, double v) noexcept { m.av_mm_s = v; }},
    {&request::kAxis, RequestField::kAxis,
     [](const compensation::MoveRequest& m) noexcept { return static_cast<double>(m.axis); },
     [](compensation::MoveRequest& m, double v) noexcept { m.axis = static_cast<std::uint8_t>(v); }},
    {&request::kAd, RequestField::kAd,
     [](const compensation::MoveRequest& m) noexcept { return m.ad_mm; },
     [](compensation::MoveRequest& m, double v) noexcept { m.ad_mm = v; }},
    {&request::kPa, RequestField::kPa,
     [](const compensation::MoveRequest& m) noexcept { return m.pa_mm_s2; },
     [](compensation::MoveRequest& m, double v) noexcept { m.pa_mm_s2 = v; }},
    {&request::kAa, RequestField::kAa,
     [](const compensation::MoveRequest& m) noexcept { return m.aa_mm_s2; },
     [](compensation::MoveRequest& m, double v) noexcept { m.aa_mm_s2 = v; }},
    {&request::kY, RequestField::kY,
     [](const compensation::MoveRequest& m) noexcept { return m.y_mm; },
     [](compensation::MoveRequest& m, double v) noexcept { m.y_mm = v; }},
    {&request::kZ, RequestField::kZ,
     [](const compensation::MoveRequest& m) noexcept { return m.z_mm; },
     [](compensation::MoveRequest& m, double v) noexcept { m.z_mm = v; }},
    {&request::kDirX, RequestField::kDirX,
     [](const compensation::MoveRequest& m) noexcept { return m.direction[0]; },
     [](compensation::MoveRequest& m, double v) noexcept { m.direction[0] = v; }},
    {&request::kDirY, RequestField::kDirY,
     [](const compensation::MoveRequest& m) noexcept { return m.direction[1]; },
     [](compensation::MoveRequest& m, double v) noexcept { m.direction[1] = v; }},
    {&request::kDirZ, RequestField::kDirZ,
     [](const compensation::MoveRequest& m) noexcept { return m.direction[2]; },
     [](compensation::MoveRequest& m, double v) noexcept { m.direction[2] = v; }},
};
// clang-format on

/// Detail of a kResultOutOfRange reject: which response field.
enum class ResponseField : std::uint8_t {
  kNone = 0,
  kMpe = 1,
  kRpe = 2,
  kMae = 3,
  kRae = 4,
  kCorrX = 5,
  kCorrY = 6,
  kCorrZ = 7,
  kU95Mpe = 8,  ///< a U95 that is negative or NaN (a large one saturates instead)
  kU95Rpe = 9,
  kU95Mae = 10,
  kU95Rae = 11,
};

// ---- Bit packing ------------------------------------------------------------------------------

/// The 8 data bytes as one little-endian 64-bit word. RT-safe.
constexpr std::uint64_t load_word(const Frame& f) noexcept {
  std::uint64_t w = 0;
  for (std::size_t i = 0; i < 8; ++i) w |= std::uint64_t{f.data[i]} << (8 * i);
  return w;
}

/// Writes `w` into the 8 data bytes, little-endian. RT-safe.
constexpr void store_word(std::uint64_t w, Frame& f) noexcept {
  for (std::size_t i = 0; i < 8; ++i) f.data[i] = static_cast<std::uint8_t>(w >> (8 * i));
}

/// A data frame (DLC 8) with id `id` carrying `w`. RT-safe.
constexpr Frame frame_of(std::uint64_t w, std::uint32_t id) noexcept {
  Frame f;
  f.id = id;
  f.dlc = kFrameDlc;
  store_word(w, f);
  return f;
}

constexpr std::uint64_t field_mask(const SignalSpec& s) noexcept {
  return s.length >= 64 ? ~std::uint64_t{0} : ((std::uint64_t{1} << s.length) - 1);
}

/// The raw value of `s` in `w` (sign-extended when signed). RT-safe.
constexpr std::int64_t get_raw(std::uint64_t w, const SignalSpec& s) noexcept {
  const std::uint64_t bits = (w >> s.start) & field_mask(s);
  if (s.is_signed && s.length < 64 && ((bits >> (s.length - 1)) & 1u) != 0) {
    return static_cast<std::int64_t>(bits | ~field_mask(s));
  }
  return static_cast<std::int64_t>(bits);
}

/// Puts `raw` (already range-checked) into the bits of `s` in `w`. RT-safe.
constexpr void put_raw(std::uint64_t& w, const SignalSpec& s, std::int64_t raw) noexcept {
  const std::uint64_t m = field_mask(s);
  w = (w & ~(m << s.start)) | ((static_cast<std::uint64_t>(raw) & m) << s.start);
}

/// True when `raw` is inside the signal's range. RT-safe.
constexpr bool raw_in_range(const SignalSpec& s, std::int64_t raw) noexcept {
  return raw >= s.raw_min() && raw <= s.raw_max();
}

/// Physical value of `raw`. RT-safe.
constexpr double to_physical(const SignalSpec& s, std::int64_t raw) noexcept {
  return static_cast<double>(raw) * s.factor + s.offset;
}

/// Raw value of physical `v`: kOk, or kInvalidInput (and `raw` untouched) when `v` is NaN, inf
/// or would round outside [raw_min, raw_max]. Never wraps or clamps. RT-safe.
inline Status to_raw(const SignalSpec& s, double v, std::int64_t& raw) noexcept {
  const double q = (v - s.offset) / s.factor;
  // NaN fails both comparisons; the half-step bounds make "rounds to a raw value in range".
  if (!(q >= static_cast<double>(s.raw_min()) - 0.5 &&
        q < static_cast<double>(s.raw_max()) + 0.5)) {
    return Status::kInvalidInput;
  }
  raw = std::llround(q);
  if (!raw_in_range(s, raw)) return Status::kInvalidInput;  // q exactly at raw_max + 0.5 − ε
  return Status::kOk;
}

// ---- Multi-part messages (request, response) ------------------------------------------------

/// One physical value to encode: its signal, the value, and the field to name when it does not
/// fit.
template <typename Field>
struct EncodedValue {
  const SignalSpec* spec;
  double value;
  Field field;
};

/// Words of a `kParts`-part message with each part's multiplexor and the shared sequence set.
template <std::size_t kParts>
constexpr std::array<std::uint64_t, kParts> part_words(const SignalSpec& part,
                                                       const SignalSpec& sequence,
                                                       std::int64_t seq) noexcept {
  std::array<std::uint64_t, kParts> words{};
  for (std::size_t p = 0; p < kParts; ++p) {
    put_raw(words[p], part, static_cast<std::int64_t>(p));
    put_raw(words[p], sequence, seq);
  }
  return words;
}

/// Puts every value into the word of its part (the signal's multiplexor value). Returns kOk, or
/// kInvalidInput with `*bad` (if given) naming the first value that is NaN, inf or out of range.
template <typename Field, std::size_t kValues, std::size_t kParts>
Status put_values(const EncodedValue<Field> (&values)[kValues],
                  std::array<std::uint64_t, kParts>& words,
                  Field* bad) noexcept {
  for (const EncodedValue<Field>& v : values) {
    std::int64_t raw = 0;
    if (to_raw(*v.spec, v.value, raw) != Status::kOk) {
      if (bad != nullptr) *bad = v.field;
      return Status::kInvalidInput;
    }
    put_raw(words[static_cast<std::size_t>(static_cast<unsigned char>(v.spec->mux))], *v.spec, raw);
  }
  return Status::kOk;
}

/// The frames of a message: id `id`, DLC 8, one word each.
template <std::size_t kParts>
constexpr void store_frames(const std::array<std::uint64_t, kParts>& words,
                            std::uint32_t id,
                            std::array<Frame, kParts>& out) noexcept {
  for (std::size_t p = 0; p < kParts; ++p) out[p] = frame_of(words[p], id);
}

// ---- Request ----------------------------------------------------------------------------------

/// The three frames of one request.
using RequestFrames = std::array<Frame, kRequestParts>;

/// Encodes `move` (its sequence must be ≤ 63: the caller counts modulo 64) as three request frames
/// for `base_id`; `want_interval` sets WantInterval (version 2: the answer gets part 3, the
/// prediction interval). Returns kOk, or kInvalidInput with `*bad` (if given) naming the first
/// field that is NaN, inf or outside its range; `out` is then unspecified. RT-safe.
inline Status encode_request(const compensation::MoveRequest& move,
                             std::uint32_t base_id,
                             RequestFrames& out,
                             RequestField* bad = nullptr,
                             bool want_interval = false) noexcept {
  EncodedValue<RequestField> items[std::size(kRequestBindings)] = {};
  for (std::size_t i = 0; i < std::size(kRequestBindings); ++i) {
    const RequestBinding& b = kRequestBindings[i];
    items[i] = {b.spec, b.get(move), b.field};
  }
  if (move.sequence > kSequenceMask) {
    if (bad != nullptr) *bad = RequestField::kSequence;
    return Status::kInvalidInput;
  }
  auto words = part_words<kRequestParts>(request::kPart, request::kSequence, move.sequence);
  if (put_values(items, words, bad) != Status::kOk) return Status::kInvalidInput;
  put_raw(words[0], request::kWantInterval, want_interval ? 1 : 0);
  store_frames(words, base_id + kRequestOffset, out);
  return Status::kOk;
}

/// Result of decoding the payload of a complete request.
struct RequestCheck {
  RejectReason reason = RejectReason::kNone;  ///< kNone when `move` was written
  RequestField field = RequestField::kNone;   ///< the offending field
  std::uint8_t part = 0;                      ///< the part it is in
  bool want_interval = false;                 ///< WantInterval (version 2): answer with part 3 too
};

/// Decodes the three payload words (part 0, 1, 2; already checked for part index, sequence and
/// DLC) of request `sequence` into `move`. Every field is range-checked; reserved bits must be
/// 0; the direction must have |d| = 1 ± request::kDirectionNormTolerance and is then normalised
/// (the compensator wants |d| = 1 ± 1e-6, finer than the signal's resolution). `move` is
/// written only when the result's reason is kNone. RT-safe.
inline RequestCheck decode_request(const std::array<std::uint64_t, kRequestParts>& words,
                                   std::uint8_t sequence,
                                   compensation::MoveRequest& move) noexcept {
  for (std::uint8_t p = 0; p < kRequestParts; ++p) {
    if ((words[p] & request::kReservedMask[p]) != 0) {
      return {RejectReason::kReservedBits, RequestField::kNone, p};
    }
  }
  compensation::MoveRequest m;
  for (const RequestBinding& b : kRequestBindings) {
    const auto part = static_cast<std::uint8_t>(b.spec->mux);
    const std::int64_t raw = get_raw(words[part], *b.spec);
    if (!raw_in_range(*b.spec, raw)) return {RejectReason::kFieldOutOfRange, b.field, part};
    b.set(m, to_physical(*b.spec, raw));
  }
  const auto& d = m.direction;
  const double norm = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (!(std::fabs(norm - 1.0) <= request::kDirectionNormTolerance)) {
    return {RejectReason::kFieldOutOfRange, RequestField::kDirection, 2};
  }
  m.direction = {d[0] / norm, d[1] / norm, d[2] / norm};
  m.sequence = sequence;
  move = m;
  RequestCheck check;
  check.want_interval = get_raw(words[0], request::kWantInterval) != 0;
  return check;
}

// ---- Response ---------------------------------------------------------------------------------

/// The three frames of one response.
using ResponseFrames = std::array<Frame, kResponseParts>;

/// Encodes correction `c` for a request on `axis` (sequence: c.sequence, ≤ 63; model id: its low
/// 32 bits) as three response frames. Returns kOk, or kInvalidInput with `*bad` (if given)
/// naming the first value that does not fit (|value| > 327.67 µm); `out` is then unspecified.
/// RT-safe.
inline Status encode_response(const compensation::Correction& c,
                              std::uint8_t axis,
                              std::uint32_t base_id,
                              ResponseFrames& out,
                              ResponseField* bad = nullptr) noexcept {
  const EncodedValue<ResponseField> items[] = {
      {&response::kMpe, c.mpe_um, ResponseField::kMpe},
      {&response::kRpe, c.rpe_um, ResponseField::kRpe},
      {&response::kMae, c.mae_um, ResponseField::kMae},
      {&response::kRae, c.rae_um, ResponseField::kRae},
      {&response::kCorrX, c.correction_um[0], ResponseField::kCorrX},
      {&response::kCorrY, c.correction_um[1], ResponseField::kCorrY},
      {&response::kCorrZ, c.correction_um[2], ResponseField::kCorrZ},
  };
  if (c.sequence > kSequenceMask || axis >= compensation::kMaxAxes) return Status::kInvalidInput;
  auto words = part_words<kResponseParts>(response::kPart, response::kSequence, c.sequence);
  put_raw(words[0], response::kFlags, c.flags & compensation::kFlagsVersion1);
  put_raw(words[0], response::kAxis, axis);
  put_raw(words[2], response::kModelId, static_cast<std::int64_t>(c.model_id & 0xFFFFFFFFu));
  if (put_values(items, words, bad) != Status::kOk) return Status::kInvalidInput;
  store_frames(words, base_id + kResponseOffset, out);
  return Status::kOk;
}

/// Encodes part 3 of the response to a request with WantInterval (version 2): c.u95_um and
/// whether the model has a calibration (kFlagNoUncertainty in c.flags: IntervalFlags bit 0 and
/// every U95 sent as 0, "unknown"). A U95 that does not fit (≥ 81.89 µm, inf included) is sent
/// as raw 4095 with IntervalFlags bit 1 (saturated): beyond that width the controller only
/// needs to know not to trust the point. Returns kOk, or kInvalidInput with `*bad` (if given)
/// naming the first U95 that is negative or NaN (never produced by a compensator), or for a
/// sequence > 63; `out` is then unspecified. RT-safe.
inline Status encode_interval(const compensation::Correction& c,
                              std::uint32_t base_id,
                              Frame& out,
                              ResponseField* bad = nullptr) noexcept {
  if (c.sequence > kSequenceMask) return Status::kInvalidInput;
  std::uint64_t w = 0;
  put_raw(w, response::kPart, kIntervalPart);
  put_raw(w, response::kSequence, c.sequence);
  std::uint8_t flags = 0;
  if ((c.flags & compensation::kFlagNoUncertainty) != 0) {
    flags = response::kIntervalNoUncertainty;  // the U95 fields stay 0
  } else {
    for (std::size_t k = 0; k < response::kU95.size(); ++k) {
      const SignalSpec& s = response::kU95[k];
      const double u = c.u95_um[k];
      if (!(u >= 0.0)) {  // negative or NaN
        if (bad != nullptr) {
          *bad = static_cast<ResponseField>(static_cast<std::uint8_t>(ResponseField::kU95Mpe) + k);
        }
        return Status::kInvalidInput;
      }
      const double q = (u - s.offset) / s.factor;
      std::int64_t raw = s.raw_max();  // saturated: "at least (raw_max − ½)·factor"
      if (q < static_cast<double>(s.raw_max()) - 0.5) {
        raw = std::llround(q);
      } else {
        flags = static_cast<std::uint8_t>(flags | response::kIntervalSaturated);
      }
      put_raw(w, s, raw);
    }
  }
  put_raw(w, response::kIntervalFlags, flags);
  out = frame_of(w, base_id + kResponseOffset);
  return Status::kOk;
}

/// A decoded response (what a controller gets).
struct DecodedResponse {
  compensation::Correction correction;  ///< model_id holds the low 32 bits only
  std::uint8_t axis = 0;
  /// Part 3 was decoded (decode_interval): correction.u95_um, interval_flags and
  /// kFlagNoUncertainty in correction.flags come from it.
  bool has_interval = false;
  std::uint8_t interval_flags = 0;  ///< IntervalFlags as received (kIntervalNoUncertainty, …)
};

/// Decodes three response frames (in part order 0, 1, 2, same sequence, DLC 8, id base + 1).
/// Returns false when they are not such a response. For controllers and tests. RT-safe.
inline bool decode_response(const ResponseFrames& frames,
                            std::uint32_t base_id,
                            DecodedResponse& out) noexcept {
  std::array<std::uint64_t, kResponseParts> w{};
  for (std::size_t p = 0; p < kResponseParts; ++p) {
    if (frames[p].id != base_id + kResponseOffset || frames[p].dlc != kFrameDlc) return false;
    w[p] = load_word(frames[p]);
    if (get_raw(w[p], response::kPart) != static_cast<std::int64_t>(p)) return false;
    if (get_raw(w[p], response::kSequence) != get_raw(w[0], response::kSequence)) return false;
  }
  compensation::Correction& c = out.correction;
  c.sequence = static_cast<std::uint32_t>(get_raw(w[0], response::kSequence));
  c.flags = static_cast<std::uint32_t>(get_raw(w[0], response::kFlags));
  out.axis = static_cast<std::uint8_t>(get_raw(w[0], response::kAxis));
  c.mpe_um = to_physical(response::kMpe, get_raw(w[0], response::kMpe));
  c.rpe_um = to_physical(response::kRpe, get_raw(w[0], response::kRpe));
  c.mae_um = to_physical(response::kMae, get_raw(w[0], response::kMae));
  c.rae_um = to_physical(response::kRae, get_raw(w[1], response::kRae));
  c.correction_um[0] = to_physical(response::kCorrX, get_raw(w[1], response::kCorrX));
  c.correction_um[1] = to_physical(response::kCorrY, get_raw(w[1], response::kCorrY));
  c.correction_um[2] = to_physical(response::kCorrZ, get_raw(w[2], response::kCorrZ));
  c.model_id = static_cast<std::uint64_t>(get_raw(w[2], response::kModelId));
  c.u95_um = {0.0, 0.0, 0.0, 0.0};
  out.has_interval = false;
  out.interval_flags = 0;
  return true;
}

/// Decodes response part 3 (the interval) into `out`, after decode_response decoded parts 0–2
/// of the same response: `f` must be part 3 with out.correction.sequence, DLC 8, id base + 1.
/// Sets correction.u95_um (a saturated one reads 81.9 µm: "at least"), interval_flags,
/// kFlagNoUncertainty in correction.flags when IntervalFlags bit 0 is set, and has_interval.
/// Returns false (and leaves `out` alone) when `f` is not such a frame. RT-safe.
inline bool decode_interval(const Frame& f, std::uint32_t base_id, DecodedResponse& out) noexcept {
  if (f.id != base_id + kResponseOffset || f.dlc != kFrameDlc) return false;
  const std::uint64_t w = load_word(f);
  if (get_raw(w, response::kPart) != kIntervalPart) return false;
  if (get_raw(w, response::kSequence) != static_cast<std::int64_t>(out.correction.sequence)) {
    return false;
  }
  out.interval_flags = static_cast<std::uint8_t>(get_raw(w, response::kIntervalFlags));
  for (std::size_t k = 0; k < response::kU95.size(); ++k) {
    out.correction.u95_um[k] = to_physical(response::kU95[k], get_raw(w, response::kU95[k]));
  }
  if ((out.interval_flags & response::kIntervalNoUncertainty) != 0) {
    out.correction.flags |= compensation::kFlagNoUncertainty;
  }
  out.has_interval = true;
  return true;
}

// ---- Reject -----------------------------------------------------------------------------------

/// The content of a reject frame.
struct RejectInfo {
  RejectReason reason = RejectReason::kNone;
  std::uint8_t sequence = kUnknown;  ///< the request's sequence, kUnknown if unreadable
  std::uint8_t part = kUnknown;      ///< the part index of the frame, kUnknown if unreadable
  std::uint8_t detail = 0;           ///< RequestField / ResponseField, else 0
  std::int16_t status = 0;           ///< cmmcomp::Status of the compensator, else 0
  std::uint16_t rejected = 0;        ///< rejects sent so far including this one (mod 65536)
};

/// The reject frame for `r`. RT-safe.
constexpr Frame encode_reject(const RejectInfo& r, std::uint32_t base_id) noexcept {
  std::uint64_t w = 0;
  put_raw(w, reject::kReason, static_cast<std::int64_t>(r.reason));
  put_raw(w, reject::kSequence, r.sequence);
  put_raw(w, reject::kPart, r.part);
  put_raw(w, reject::kDetail, r.detail);
  put_raw(w, reject::kStatus, r.status);
  put_raw(w, reject::kRejected, r.rejected);
  return frame_of(w, base_id + kRejectOffset);
}

/// Decodes a reject frame; false when `f` is not one. RT-safe.
constexpr bool decode_reject(const Frame& f, std::uint32_t base_id, RejectInfo& out) noexcept {
  if (f.id != base_id + kRejectOffset || f.dlc != kFrameDlc) return false;
  const std::uint64_t w = load_word(f);
  out.reason = static_cast<RejectReason>(get_raw(w, reject::kReason));
  out.sequence = static_cast<std::uint8_t>(get_raw(w, reject::kSequence));
  out.part = static_cast<std::uint8_t>(get_raw(w, reject::kPart));
  out.detail = static_cast<std::uint8_t>(get_raw(w, reject::kDetail));
  out.status = static_cast<std::int16_t>(get_raw(w, reject::kStatus));
  out.rejected = static_cast<std::uint16_t>(get_raw(w, reject::kRejected));
  return true;
}

// ---- Heartbeat --------------------------------------------------------------------------------

/// What one heartbeat reports (counters modulo 65536, model ids modulo 2^48).
struct HeartbeatInfo {
  std::uint8_t tick = 0;  ///< heartbeat number modulo 32
  std::uint16_t requests = 0;
  std::uint16_t answered = 0;
  std::uint16_t rejected = 0;
  std::uint8_t model_mask = 0;               ///< bit a: axis a has a model
  std::array<std::uint64_t, 4> model_ids{};  ///< model id of each axis (0 = none)
  /// ProtocolVersion: kProtocolVersion when encoded; decoded, 0 from a version-1 server.
  std::uint8_t protocol_version = kProtocolVersion;
};

/// Page `page` (0..4) of heartbeat `h`. RT-safe.
constexpr Frame encode_heartbeat(const HeartbeatInfo& h,
                                 std::uint8_t page,
                                 std::uint32_t base_id) noexcept {
  std::uint64_t w = 0;
  put_raw(w, heartbeat::kPage, page);
  put_raw(w, heartbeat::kTick, h.tick & 0x1F);
  if (page == 0) {
    put_raw(w, heartbeat::kRequests, h.requests);
    put_raw(w, heartbeat::kAnswered, h.answered);
    put_raw(w, heartbeat::kRejected, h.rejected);
    put_raw(w, heartbeat::kModelMask, h.model_mask & 0xF);
    put_raw(w, heartbeat::kVersion, h.protocol_version & 0xF);
  } else if (page <= 4) {
    const std::size_t axis = page - 1u;
    put_raw(w,
            heartbeat::kModelIds[axis],
            static_cast<std::int64_t>(h.model_ids[axis] & 0xFFFFFFFFFFFFull));
  }
  return frame_of(w, base_id + kHeartbeatOffset);
}

/// Merges one heartbeat page into `out`; returns the page, or −1 when `f` is not a heartbeat.
/// RT-safe.
constexpr int decode_heartbeat(const Frame& f, std::uint32_t base_id, HeartbeatInfo& out) noexcept {
  if (f.id != base_id + kHeartbeatOffset || f.dlc != kFrameDlc) return -1;
  const std::uint64_t w = load_word(f);
  const auto page = static_cast<int>(get_raw(w, heartbeat::kPage));
  out.tick = static_cast<std::uint8_t>(get_raw(w, heartbeat::kTick));
  if (page == 0) {
    out.requests = static_cast<std::uint16_t>(get_raw(w, heartbeat::kRequests));
    out.answered = static_cast<std::uint16_t>(get_raw(w, heartbeat::kAnswered));
    out.rejected = static_cast<std::uint16_t>(get_raw(w, heartbeat::kRejected));
    out.model_mask = static_cast<std::uint8_t>(get_raw(w, heartbeat::kModelMask));
    out.protocol_version = static_cast<std::uint8_t>(get_raw(w, heartbeat::kVersion));
  } else if (page <= 4) {
    const auto axis = static_cast<std::size_t>(page - 1);
    out.model_ids[axis] = static_cast<std::uint64_t>(get_raw(w, heartbeat::kModelIds[axis]));
  } else {
    return -1;
  }
  return page;
}

}  // namespace cmmcomp::plugins::can

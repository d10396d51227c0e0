// SPDX-License-Identifier: MIT
/// @file Where a compensation model is valid: its inputs' training box, and the accelerations it
/// was trained at, which are not inputs (docs/compensator.md, "Domain").
///
/// Contract, for every compensator (MoveCompensator, StaticMoveCompensator, the C ABIs and the
/// protocols over them):
///  - a move whose PA or AA lies outside the model's training conditions (beyond the trained
///    range by more than kConditionTolerance of its value) is outside the domain: with
///    DomainPolicy kClamp or kExtrapolate it is answered with kOutsideDomain (kFlagOutsideDomain),
///    with kReject it is refused (kOutsideDomainRejected). The network cannot clamp a condition
///    that is not one of its inputs, so the policy only decides between flagging and refusing;
///  - a move FAR outside (an input, PA or AA beyond its range by more than kFarOutsideShare of
///    the range's width, or of its value for a single trained value) is refused under every
///    policy: a clamped answer 10⁶ mm/s away is not an answer.
/// A condition the model does not record (a format-3 file, Conditions{}) is not checked.
/// Everything here is RT-safe: noexcept, no allocation, fixed loops.
#pragma once

#include <cmath>
#include <cmmcomp/compensation/move_request.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cstddef>

namespace cmmcomp::compensation {

/// A move beyond an input's or a condition's range by more than this share of the range's
/// width (of the trained value, for a condition trained at one value) is refused under every
/// domain policy.
inline constexpr double kFarOutsideShare = 0.10;
/// A PA or AA within this share of its value beyond the trained range counts as inside: a
/// controller rounds the accelerations it is given (0.1 % would do for most; 1 % leaves room for
/// a unit converted by hand, and is far below what changes the errors, docs/compensator.md).
inline constexpr double kConditionTolerance = 0.01;

/// A range of a training condition [lo, hi], lo <= hi; lo = hi = 0: unknown (not checked).
struct ConditionRange {
  double lo = 0.0;
  double hi = 0.0;
  constexpr bool known() const noexcept { return hi > 0.0; }
};

/// The training conditions of a model that the compensator checks (the model file's
/// `conditions`, io::compensation_conditions). Conditions{} checks nothing. The layout is the
/// firmware C ABI's cmmcomp_fw_conditions.
struct Conditions {
  ConditionRange pa_mm_s2{};  ///< positioning accelerations trained at [mm/s²]
  ConditionRange aa_mm_s2{};  ///< approach accelerations trained at [mm/s²]
};

/// True when every range is unknown (0, 0) or finite with 0 < lo <= hi. RT-safe.
constexpr bool conditions_are_valid(const Conditions& c) noexcept {
  const auto ok = [](const ConditionRange& r) {
    if (r.lo == 0.0 && r.hi == 0.0) return true;
    // (x - x) == 0 is false for inf and NaN without <cmath>'s non-constexpr isfinite.
    return (r.lo - r.lo) == 0.0 && (r.hi - r.hi) == 0.0 && r.lo > 0.0 && r.lo <= r.hi;
  };
  return ok(c.pa_mm_s2) && ok(c.aa_mm_s2);
}

/// Where a move lies against a model's domain.
enum class Domain {
  kInside,      ///< every input and known condition within its range
  kOutside,     ///< an input or condition outside, none far outside
  kFarOutside,  ///< an input or condition beyond its range by more than kFarOutsideShare
};

/// How far `x` lies beyond [lo, hi] against `allowance` (the far-outside limit) and `slack`
/// (what still counts as inside). RT-safe; `x` finite.
constexpr Domain domain_of(
    double x, double lo, double hi, double slack, double allowance) noexcept {
  const double beyond = x < lo ? lo - x : (x > hi ? x - hi : 0.0);
  if (beyond > allowance) return Domain::kFarOutside;
  return beyond > slack ? Domain::kOutside : Domain::kInside;
}

/// The worse of two domains.
constexpr Domain worse(Domain a, Domain b) noexcept { return a > b ? a : b; }

/// Where `move`'s PA and AA lie against the known conditions. RT-safe; `move` validated.
constexpr Domain condition_domain(const Conditions& c, const MoveRequest& move) noexcept {
  const auto one = [](const ConditionRange& r, double x) {
    if (!r.known()) return Domain::kInside;
    const double span = r.hi > r.lo ? r.hi - r.lo : r.hi;
    return domain_of(x, r.lo, r.hi, kConditionTolerance * x, kFarOutsideShare * span);
  };
  return worse(one(c.pa_mm_s2, move.pa_mm_s2), one(c.aa_mm_s2, move.aa_mm_s2));
}

/// Where `move`'s network inputs lie against the model's training ranges (inside: within
/// [lo, hi], as fuzzy::evaluate decides; far: beyond by more than kFarOutsideShare·(hi − lo)).
/// RT-safe; `move` validated.
template <typename M>
constexpr Domain input_domain(const M& model, const MoveRequest& move) noexcept {
  const auto x = M::input(move);
  Domain d = Domain::kInside;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double lo = model.ranges[i].lo;
    const double hi = model.ranges[i].hi;
    d = worse(d, domain_of(static_cast<double>(x[i]), lo, hi, 0.0, kFarOutsideShare * (hi - lo)));
  }
  return d;
}

/// The status of a move evaluated with status `s` (what fuzzy::evaluate returned) whose
/// domain, inputs and conditions together, is `d`, under `policy`: the contract in the file
/// comment. RT-safe.
constexpr Status domain_status(Status s, Domain d, fuzzy::DomainPolicy policy) noexcept {
  if (d == Domain::kFarOutside) return Status::kOutsideDomainRejected;
  if (!ok(s) || d == Domain::kInside) return s;
  if (policy == fuzzy::DomainPolicy::kReject) return Status::kOutsideDomainRejected;
  return Status::kOutsideDomain;
}

}  // namespace cmmcomp::compensation

// SPDX-License-Identifier: MIT
/// @file Status codes returned by every real-time (RT) function of cmmcomp.
#pragma once

#include <cstdint>

namespace cmmcomp {

/// Result of an RT-path call. Non-negative values mean the output is valid.
enum class [[nodiscard]] Status : std::int32_t{
    kOk = 0,                        ///< computed; output valid
    kOutsideDomain = 1,             ///< computed under the domain policy; flagged to the controller
    kInvalidInput = -100,           ///< NaN, inf, non-positive or out-of-range parameter
    kNoModel = -101,                ///< no model published for this axis
    kTraceTooShort = -102,          ///< a trace does not cover the instants asked for
    kOutsideDomainRejected = -103,  ///< outside the training domain; the policy rejects it
    kBusy = -104,  ///< publish only: a reader still uses the buffer it needs; nothing changed
    kIntegratorFailed = -200,  ///< the ODE integrator reported a failure (offline twin)
};

/// True when `s` means the output is valid. RT-safe.
constexpr bool ok(Status s) noexcept { return static_cast<std::int32_t>(s) >= 0; }

/// Static description of `s` (never allocates). RT-safe.
constexpr const char* to_string(Status s) noexcept {
  switch (s) {
    case Status::kOk:
      return "ok";
    case Status::kOutsideDomain:
      return "outside the training domain (policy applied)";
    case Status::kInvalidInput:
      return "invalid input (NaN, inf, non-positive or out of range)";
    case Status::kNoModel:
      return "no model published";
    case Status::kTraceTooShort:
      return "trace does not cover the move's phase instants";
    case Status::kOutsideDomainRejected:
      return "outside the training domain (rejected by policy)";
    case Status::kBusy:
      return "busy: a reader still uses the model buffer (nothing published)";
    case Status::kIntegratorFailed:
      return "ODE integrator failed";
  }
  return "unknown status";
}

}  // namespace cmmcomp

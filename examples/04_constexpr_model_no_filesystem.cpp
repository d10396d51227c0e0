// SPDX-License-Identifier: MIT
/// @file Example 4 (core only): a model compiled into the program, for firmware without files.
///
/// `cmmcomp-train export MODEL.json --header OUT.hpp --symbol NAME` writes a self-contained
/// C++17 header defining `inline constexpr cmmcomp::fuzzy::TskModel<double, 4, 3, 4> NAME`,
/// plus NAME_model_id and NAME_checksum. examples/CMakeLists.txt runs it at build time on the
/// installed default model (symbol `default_model`); nothing generated is committed.
/// The program needs only the header-only core: no JSON, no file system, no heap.
/// Self-check: the network evaluates, and its prediction is finite and plausible.
#include <array>
#include <cmath>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "default_model.hpp"  // generated in the build tree

// The model is a compile-time constant, so it can be checked at compile time too.
static_assert(default_model.ranges[0].lo < default_model.ranges[0].hi, "PV range");
static_assert(sizeof(default_model_model_id) == 17, "16 hex digits and the terminating 0");

int main() {
  using namespace cmmcomp;
  std::printf("compiled-in model %s (%d rules, %d parameters)\n",
              default_model_model_id,
              decltype(default_model)::kRules,
              decltype(default_model)::kParamCount);

  // The baseline move: PV 40 mm/s, PD 40 mm, AV 12 mm/s, AD 10 mm.
  const std::array<double, 4> x{40.0, 40.0, 12.0, 10.0};
  std::array<double, 4> y{};  // MPE, RPE, MAE, RAE [um]
  std::uint32_t outside = 0;  // bit i set: input i outside its training range
  const Status s = fuzzy::evaluate(default_model, x, y, fuzzy::DomainPolicy::kClamp, &outside);
  std::printf("status %s, outside mask 0x%x\n", to_string(s), outside);
  std::printf("MPE %.3f um  RPE %.3f um  MAE %.3f um  RAE %.3f um\n", y[0], y[1], y[2], y[3]);

  // A move beyond the trained PV range: kClamp evaluates at the range's edge and says so.
  std::array<double, 4> fast{};
  const Status s2 = fuzzy::evaluate(
      default_model, {250.0, 40.0, 12.0, 10.0}, fast, fuzzy::DomainPolicy::kClamp, &outside);
  std::printf(
      "PV 250 mm/s: status %s, outside mask 0x%x, MPE %.3f um\n", to_string(s2), outside, fast[0]);

  const bool good = s == Status::kOk && s2 == Status::kOutsideDomain && outside == 0x1u &&
                    std::isfinite(y[1]) && std::isfinite(y[3]) && y[0] > 0.0 &&
                    y[0] >= std::fabs(y[1]) && y[2] >= std::fabs(y[3]) &&
                    std::strlen(default_model_checksum) == 64;
  std::printf("%s\n", good ? "OK" : "WRONG");
  return good ? 0 : 1;
}

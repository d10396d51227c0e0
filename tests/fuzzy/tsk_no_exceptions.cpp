// SPDX-License-Identifier: MIT
/// @file Compiled with -fno-exceptions -fno-rtti: the RT evaluator needs neither. Exits 0 when
/// a small model evaluates as expected.
#include <array>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cstdio>

int main() {
  namespace fz = cmmcomp::fuzzy;
  fz::TskModel<double, 4, 3, 4> model;
  for (auto& r : model.ranges) r = fz::InputRange{0.0, 2.0};
  for (int i = 0; i < 4; ++i) {
    for (int s = 0; s < 3; ++s) {
      model.params.centre(i, s) = 0.5 * s;
      model.params.width(i, s) = 0.4;
    }
  }
  // Every rule's consequent is y_o = o + 1: the output is o + 1 wherever it is evaluated.
  for (int o = 0; o < 4; ++o) {
    for (int j = 0; j < fz::TskModel<double, 4, 3, 4>::kRules; ++j) {
      model.params.consequent(o, j, 0) = o + 1.0;
    }
  }
  if (!fz::validate(model)) return 1;
  std::array<double, 4> y{};
  std::uint32_t mask = 0;
  if (fz::evaluate(model, {0.3, 1.0, 1.7, 2.5}, y, fz::DomainPolicy::kClamp, &mask) !=
      cmmcomp::Status::kOutsideDomain) {
    return 2;
  }
  if (mask != 0b1000u) return 3;
  for (int o = 0; o < 4; ++o) {
    const double err = y[static_cast<unsigned>(o)] - (o + 1.0);
    if (err > 1e-12 || err < -1e-12) return 4;
  }
  if (fz::evaluate(model, {0.3, 1.0, 1.7, 2.5}, y, fz::DomainPolicy::kReject) !=
      cmmcomp::Status::kOutsideDomainRejected) {
    return 5;
  }
  std::puts("tsk_no_exceptions: ok");
  return 0;
}

// SPDX-License-Identifier: MIT
/// @file Uses the installed header-only core: plans the baseline move and evaluates a tiny T-S
/// network (one input, two sets, constant consequents 1 and 3: the output lies between them).
#include <array>
#include <cmath>
#include <cmmcomp/cmmcomp.hpp>
#include <cstdio>

int main() {
  cmmcomp::motion::MoveProfile p;
  if (!cmmcomp::ok(cmmcomp::motion::MoveProfile::plan(cmmcomp::motion::baseline_move(), p))) {
    return 1;
  }
  std::printf("cmmcomp %s: touch at %.6f s\n", CMMCOMP_VERSION_STRING, p.instants().touch);
  if (std::fabs(p.instants().touch - 32.0 / 15.0) >= 1e-12) return 1;

  cmmcomp::fuzzy::TskModel<double, 1, 2, 1> model;
  model.ranges[0] = {0.0, 10.0};
  model.params.centre(0, 0) = 0.0;
  model.params.centre(0, 1) = 1.0;
  model.params.width(0, 0) = 0.5;
  model.params.width(0, 1) = 0.5;
  model.params.consequent(0, 0, 0) = 1.0;
  model.params.consequent(0, 1, 0) = 3.0;
  std::array<double, 1> y{};
  const cmmcomp::Status s =
      cmmcomp::fuzzy::evaluate(model, {5.0}, y, cmmcomp::fuzzy::DomainPolicy::kReject);
  std::printf("network at the middle of its range: %.17g\n", y[0]);
  return cmmcomp::ok(s) && std::fabs(y[0] - 2.0) < 1e-12 ? 0 : 1;
}

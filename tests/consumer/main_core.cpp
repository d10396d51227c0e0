// SPDX-License-Identifier: MIT
/// @file Uses the installed header-only core: plans the baseline move.
#include <cmath>
#include <cmmcomp/cmmcomp.hpp>
#include <cstdio>

int main() {
  cmmcomp::motion::MoveProfile p;
  if (!cmmcomp::ok(cmmcomp::motion::MoveProfile::plan(cmmcomp::motion::baseline_move(), p))) {
    return 1;
  }
  std::printf("cmmcomp %s: touch at %.6f s\n", CMMCOMP_VERSION_STRING, p.instants().touch);
  return std::fabs(p.instants().touch - 32.0 / 15.0) < 1e-12 ? 0 : 1;
}

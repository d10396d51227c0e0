// SPDX-License-Identifier: MIT
/// @file Example 5: simulate the baseline move on the digital twin and read its dynamic errors.
///
/// The twin is a lumped model of the bridge, carriage and probe integrated with SUNDIALS CVODE;
/// dynamics::default_machine() is the machine identified against the paper's tables. It stands
/// in for the laser tracker of the paper: it reports the error trace e(t) = (tip - scale) * d.
/// Self-check: the simulator's MPE/RPE/MAE/RAE equal those example 1's extract_dynamic_errors
/// reads off the recorded trace, and they are plausible.
#include <cmath>
#include <cmmcomp/dynamics/bridge_model.hpp>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/errors/dynamic_errors.hpp>
#include <cstdio>
#include <vector>

int main() {
  using namespace cmmcomp;
  dynamics::SimulationOptions options;
  options.record_trace = true;  // keep the sampled trace (1 kHz plus every extremum and kink)
  dynamics::BridgeSimulator sim(dynamics::default_machine(), options);

  // The carriage at Y = 0.25 m along the beam (the paper's position; SI units here).
  const dynamics::SimulationResult r = sim.simulate(motion::baseline_move(), 0.25);
  const errors::DynamicErrors& e = r.errors_um;
  std::printf("MPE %.4f um  RPE %.4f um  MAE %.4f um  RAE %.4f um\n", e.mpe, e.rpe, e.mae, e.rae);
  std::printf("CVODE: %ld steps, %ld right-hand-side evaluations; %zu trace samples\n",
              r.stats.steps,
              r.stats.rhs_evals,
              r.trace.size());
  std::printf("touch at %.4f s (the controller's dwell and smoothing included)\n",
              r.instants.touch);

  // Re-extract the errors from the trace with the core function of example 1.
  std::vector<double> t, err;
  for (const dynamics::TraceSample& s : r.trace) {
    t.push_back(s.t_s);
    err.push_back(s.error_um);  // already (tip - scale) * d, so direction +1 below
  }
  errors::DynamicErrors again;
  const Status s =
      errors::extract_dynamic_errors({t.data(), err.data(), t.size()}, r.instants, +1, again);
  std::printf("from the trace: MPE %.4f  RPE %.4f  MAE %.4f  RAE %.4f um (%s)\n",
              again.mpe,
              again.rpe,
              again.mae,
              again.rae,
              to_string(s));

  const double tol = 1e-6;  // um
  const bool good = ok(s) && r.stats.steps > 0 && e.mpe > 0.0 && e.mpe >= std::fabs(e.rpe) &&
                    e.mae >= std::fabs(e.rae) && std::fabs(again.mpe - e.mpe) < tol &&
                    std::fabs(again.rpe - e.rpe) < tol && std::fabs(again.mae - e.mae) < tol &&
                    std::fabs(again.rae - e.rae) < tol;
  std::printf("%s\n", good ? "OK" : "WRONG");
  return good ? 0 : 1;
}

// SPDX-License-Identifier: MIT
/// @file Example 1 (core only): plan a probing move and extract its four dynamic errors.
///
/// A probing move is a fast *positioning* move to the pre-hit point, then a slow *approach*
/// that ends when the probe touches. MoveProfile::plan turns the move's speeds, accelerations
/// and distances into a time profile with named phase instants. Given an error trace
/// e(t) = tip - scale (here a synthetic one; example 5 gets a real one from the digital twin),
/// extract_dynamic_errors reads MPE, RPE, MAE and RAE off it at those instants.
/// Self-check: the extracted values equal those computed straight from the formula.
#include <cmath>
#include <cmmcomp/cmmcomp.hpp>  // the real-time core: motion, errors, fuzzy, status
#include <cstdio>
#include <vector>

namespace {
constexpr double kPi = 3.14159265358979323846;

// Synthetic error [um] at time t [s]: a static lag of 0.05 um per mm/s of speed (the tip trails
// the scale while moving) plus a decaying 6 Hz bridge vibration started by the first push.
double synthetic_error_um(const cmmcomp::motion::MoveProfile& p, double t) {
  const double v_mm_s = p.sample(t).velocity * 1e3;
  return -0.05 * v_mm_s + 5.0 * std::exp(-t / 0.6) * std::sin(2.0 * kPi * 6.0 * t);
}
}  // namespace

int main() {
  using namespace cmmcomp;
  // The paper's baseline move: PV 40 mm/s, PA 200 mm/s^2, PD 40 mm, AV 12 mm/s, AA 60 mm/s^2,
  // AD 10 mm (ProbingMove is in SI units; motion::probing_move_mm takes mm-based ones).
  motion::MoveProfile profile;
  const Status s = motion::MoveProfile::plan(motion::baseline_move(), profile);
  if (!ok(s)) {
    std::fprintf(stderr, "plan failed: %s\n", to_string(s));
    return 1;
  }
  const motion::PhaseInstants& in = profile.instants();
  std::printf(
      "phase instants [s]: accel end %.4f, decel start %.4f, positioning end %.4f,\n"
      "                    approach start %.4f, approach accel end %.4f, touch %.4f\n",
      in.positioning_accel_end,
      in.positioning_decel_start,
      in.positioning_end,
      in.approach_start,
      in.approach_accel_end,
      in.touch);

  // Sample the trace at 10 kHz from t = 0 to just past the touch (it must cover [0, touch]).
  std::vector<double> time, error;
  for (int i = 0; i * 1e-4 <= in.touch + 1e-4; ++i) {
    time.push_back(i * 1e-4);
    error.push_back(synthetic_error_um(profile, time.back()));
  }
  const errors::TraceView trace{time.data(), error.data(), time.size()};

  errors::DynamicErrors e;  // moving in +X: direction +1
  if (!ok(errors::extract_dynamic_errors(trace, in, +1, e))) return 1;
  std::printf("MPE %.4f um  RPE %.4f um  MAE %.4f um  RAE %.4f um\n", e.mpe, e.rpe, e.mae, e.rae);

  // Self-check against the definitions, evaluated directly on a 100x finer grid.
  double mpe = 0.0, mae = 0.0;
  for (double t = 0.0; t <= in.touch; t += 1e-6) {
    const double v = std::fabs(synthetic_error_um(profile, t));
    if (t <= in.positioning_end && v > mpe) mpe = v;
    if (t >= in.approach_start && v > mae) mae = v;
  }
  const double rpe = synthetic_error_um(profile, in.positioning_decel_start);
  const double rae = synthetic_error_um(profile, in.touch);
  const double tol = 1e-3;  // um; linear interpolation of a 10 kHz trace
  const bool good = std::fabs(e.mpe - mpe) < tol && std::fabs(e.rpe - rpe) < tol &&
                    std::fabs(e.mae - mae) < tol && std::fabs(e.rae - rae) < tol &&
                    std::fabs(in.touch - 32.0 / 15.0) < 1e-12;
  std::printf("%s\n", good ? "OK: matches the definitions" : "WRONG: differs from definitions");
  return good ? 0 : 1;
}

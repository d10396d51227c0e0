// SPDX-License-Identifier: MIT
/// @file A small ODE integrator facade over SUNDIALS CVODE (no SUNDIALS types cross it).
///
/// The handles (context, vector, dense matrix and linear solver) are created once; every move
/// re-initialises them with reset(), so simulating many moves allocates nothing per move inside
/// CVODE beyond what CVodeReInit does (nothing).
#pragma once

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/status.hpp>
#include <memory>
#include <string>

namespace cmmcomp::dynamics {

/// Integration settings. Defaults suit the bridge model (states in m, m/s, rad, rad/s).
struct IntegratorOptions {
  double relative_tolerance = 1e-8;   ///< CVODE rtol (dimensionless)
  double absolute_tolerance = 1e-13;  ///< CVODE atol, same for every state [state units]
  long max_steps = 200000;            ///< internal steps allowed per advance_to() call
  double max_step = 0.0;              ///< largest internal step [s]; 0 = no limit
  bool bdf = true;                    ///< BDF (stiff) when true, Adams–Moulton otherwise

  /// True when every field is usable; otherwise false with the reason in `why`.
  bool is_valid(std::string* why) const;
};

/// Work counters since the last reset() (CVODE restarts them on re-initialisation).
struct IntegratorStats {
  long steps = 0;       ///< internal steps
  long rhs_evals = 0;   ///< right-hand-side evaluations (incl. those for Jacobians)
  long root_evals = 0;  ///< root-function evaluations
  long error_test_fails = 0;
  long matrix_exponentials = 0;  ///< the exponential integrator's transition matrices
};

/// CVODE behind a plain function-pointer interface.
class Integrator {
 public:
  /// dy/dt = f(t, y). Return 0 on success, > 0 for a recoverable failure, < 0 to abort.
  using Rhs = int (*)(double t, const double* y, double* ydot, void* user) noexcept;
  /// Root functions g_i(t, y); the integrator stops where one changes sign.
  using Roots = int (*)(double t, const double* y, double* g, void* user) noexcept;

  /// Setup only: creates the CVODE handles. Throws ConfigError for invalid options,
  /// state_size < 1 or root_count < 0, Error when SUNDIALS fails to allocate.
  Integrator(const IntegratorOptions& options,
             Rhs rhs,
             void* user,
             int state_size,
             Roots roots = nullptr,
             int root_count = 0);
  ~Integrator();
  Integrator(const Integrator&) = delete;
  Integrator& operator=(const Integrator&) = delete;

  /// Restarts the integration at (t0, y0), discarding the step history: call it at every kink
  /// of the forcing. Returns kOk or kIntegratorFailed.
  [[nodiscard]] Status reset(double t0, const double* y0) noexcept;
  /// Replaces the scalar absolute tolerance by one per state (`state_size` values, each > 0),
  /// keeping the relative tolerance. Returns kOk, kInvalidInput for a non-positive or non-finite
  /// value (nothing changed), or kIntegratorFailed.
  [[nodiscard]] Status set_absolute_tolerances(const double* atol) noexcept;
  /// The integrator never steps past `t_stop` (set it to the next kink). kOk/kIntegratorFailed.
  [[nodiscard]] Status set_stop_time(double t_stop) noexcept;
  /// Advances towards `t_out`, writing the state to `y` and the time reached to `t_reached`.
  /// Stops early where a root function changes sign (then `*root_found` is true and the state is
  /// at the root). Returns kOk, or kIntegratorFailed with `last_flag()` holding CVODE's flag.
  [[nodiscard]] Status advance_to(double t_out,
                                  double* y,
                                  double* t_reached,
                                  bool* root_found) noexcept;

  IntegratorStats stats() const noexcept;
  /// The last CVODE return flag (negative after a failure).
  int last_flag() const noexcept;
  /// CVODE's name for `last_flag()` (static string).
  const char* last_flag_name() const noexcept;
  int state_size() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cmmcomp::dynamics

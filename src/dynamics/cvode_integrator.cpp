// SPDX-License-Identifier: MIT
/// @file The only translation unit that includes SUNDIALS.
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <cmath>
#include <cmmcomp/dynamics/integrator.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cstring>
#include <stdexcept>
#include <string>

namespace cmmcomp::dynamics {

bool IntegratorOptions::is_valid(std::string* why) const {
  auto fail = [why](const char* msg) {
    if (why != nullptr) *why = msg;
    return false;
  };
  if (!(relative_tolerance > 0.0 && relative_tolerance < 1.0)) {
    return fail("relative_tolerance must be in (0, 1)");
  }
  if (!(absolute_tolerance > 0.0 && std::isfinite(absolute_tolerance))) {
    return fail("absolute_tolerance must be positive and finite");
  }
  if (max_steps < 1) return fail("max_steps must be at least 1");
  if (!(max_step >= 0.0 && std::isfinite(max_step))) {
    return fail("max_step must be >= 0 (0 = no limit)");
  }
  return true;
}

struct Integrator::Impl {
  SUNContext context = nullptr;
  N_Vector y = nullptr;
  N_Vector atol = nullptr;
  double rtol = 0.0;
  SUNMatrix matrix = nullptr;
  SUNLinearSolver solver = nullptr;
  SUNNonlinearSolver fixed_point = nullptr;
  void* cvode = nullptr;
  Rhs rhs = nullptr;
  Roots roots = nullptr;
  void* user = nullptr;
  int size = 0;
  int root_count = 0;
  int last_flag = 0;
  bool initialised = false;

  ~Impl() {
    if (cvode != nullptr) CVodeFree(&cvode);
    if (fixed_point != nullptr) SUNNonlinSolFree(fixed_point);
    if (solver != nullptr) SUNLinSolFree(solver);
    if (matrix != nullptr) SUNMatDestroy(matrix);
    if (y != nullptr) N_VDestroy(y);
    if (atol != nullptr) N_VDestroy(atol);
    if (context != nullptr) SUNContext_Free(&context);
  }

  static int rhs_trampoline(realtype t, N_Vector y, N_Vector ydot, void* self) {
    const Impl* impl = static_cast<const Impl*>(self);
    return impl->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot), impl->user);
  }
  // CVODE would print its own messages to stderr; the caller reports failures with context.
  static void silent(int, const char*, const char*, char*, void*) {}

  static int root_trampoline(realtype t, N_Vector y, realtype* g, void* self) {
    const Impl* impl = static_cast<const Impl*>(self);
    return impl->roots(t, N_VGetArrayPointer(y), g, impl->user);
  }
};

Integrator::Integrator(const IntegratorOptions& options,
                       Rhs rhs,
                       void* user,
                       int state_size,
                       Roots roots,
                       int root_count)
    : impl_(std::make_unique<Impl>()) {
  std::string why;
  if (!options.is_valid(&why)) throw ConfigError("IntegratorOptions: " + why);
  if (rhs == nullptr) throw ConfigError("Integrator: no right-hand side");
  if (state_size < 1) throw ConfigError("Integrator: state_size must be >= 1");
  if (root_count < 0 || (root_count > 0 && roots == nullptr)) {
    throw ConfigError("Integrator: root_count needs a root function");
  }
  Impl& m = *impl_;
  m.rhs = rhs;
  m.roots = roots;
  m.user = user;
  m.size = state_size;
  m.root_count = root_count;
  auto check = [](bool good, const char* what) {
    if (!good) throw Error(std::string("SUNDIALS: ") + what + " failed");
  };
  check(SUNContext_Create(nullptr, &m.context) == 0, "SUNContext_Create");
  m.y = N_VNew_Serial(state_size, m.context);
  check(m.y != nullptr, "N_VNew_Serial");
  N_VConst(0.0, m.y);
  m.atol = N_VNew_Serial(state_size, m.context);
  check(m.atol != nullptr, "N_VNew_Serial");
  m.rtol = options.relative_tolerance;
  m.cvode = CVodeCreate(options.bdf ? CV_BDF : CV_ADAMS, m.context);
  check(m.cvode != nullptr, "CVodeCreate");
  check(CVodeInit(m.cvode, &Impl::rhs_trampoline, 0.0, m.y) == CV_SUCCESS, "CVodeInit");
  check(CVodeSetUserData(m.cvode, &m) == CV_SUCCESS, "CVodeSetUserData");
  check(CVodeSetErrHandlerFn(m.cvode, &Impl::silent, nullptr) == CV_SUCCESS,
        "CVodeSetErrHandlerFn");
  check(CVodeSStolerances(m.cvode, options.relative_tolerance, options.absolute_tolerance) ==
            CV_SUCCESS,
        "CVodeSStolerances");
  check(CVodeSetMaxNumSteps(m.cvode, options.max_steps) == CV_SUCCESS, "CVodeSetMaxNumSteps");
  if (options.max_step > 0.0) {
    check(CVodeSetMaxStep(m.cvode, options.max_step) == CV_SUCCESS, "CVodeSetMaxStep");
  }
  if (options.bdf) {
    // Stiff problems: Newton iteration with a dense direct linear solver.
    m.matrix = SUNDenseMatrix(state_size, state_size, m.context);
    check(m.matrix != nullptr, "SUNDenseMatrix");
    m.solver = SUNLinSol_Dense(m.y, m.matrix, m.context);
    check(m.solver != nullptr, "SUNLinSol_Dense");
    check(CVodeSetLinearSolver(m.cvode, m.solver, m.matrix) == CV_SUCCESS, "CVodeSetLinearSolver");
  } else {
    // Non-stiff problems (Adams–Moulton): fixed-point iteration needs no Jacobian and no
    // linear solve, the cheaper step for a lightly damped oscillator.
    m.fixed_point = SUNNonlinSol_FixedPoint(m.y, 0, m.context);
    check(m.fixed_point != nullptr, "SUNNonlinSol_FixedPoint");
    check(CVodeSetNonlinearSolver(m.cvode, m.fixed_point) == CV_SUCCESS, "CVodeSetNonlinearSolver");
  }
  if (root_count > 0) {
    check(CVodeRootInit(m.cvode, root_count, &Impl::root_trampoline) == CV_SUCCESS,
          "CVodeRootInit");
  }
  // Root functions that are exactly zero at a restart are expected (kinks happen at rest);
  // CVODE then looks for the sign change just after, which is what we want.
  check(CVodeSetNoInactiveRootWarn(m.cvode) == CV_SUCCESS, "CVodeSetNoInactiveRootWarn");
}

Integrator::~Integrator() = default;

Status Integrator::reset(double t0, const double* y0) noexcept {
  Impl& m = *impl_;
  std::memcpy(N_VGetArrayPointer(m.y), y0, sizeof(double) * static_cast<std::size_t>(m.size));
  m.last_flag = CVodeReInit(m.cvode, t0, m.y);
  return m.last_flag == CV_SUCCESS ? Status::kOk : Status::kIntegratorFailed;
}

Status Integrator::set_absolute_tolerances(const double* atol) noexcept {
  Impl& m = *impl_;
  double* dst = N_VGetArrayPointer(m.atol);
  for (int i = 0; i < m.size; ++i) {
    if (!(atol[i] > 0.0 && std::isfinite(atol[i]))) {
      m.last_flag = CV_ILL_INPUT;
      return Status::kInvalidInput;
    }
    dst[i] = atol[i];
  }
  m.last_flag = CVodeSVtolerances(m.cvode, m.rtol, m.atol);
  return m.last_flag == CV_SUCCESS ? Status::kOk : Status::kIntegratorFailed;
}

Status Integrator::set_stop_time(double t_stop) noexcept {
  Impl& m = *impl_;
  m.last_flag = CVodeSetStopTime(m.cvode, t_stop);
  return m.last_flag == CV_SUCCESS ? Status::kOk : Status::kIntegratorFailed;
}

Status Integrator::advance_to(double t_out,
                              double* y,
                              double* t_reached,
                              bool* root_found) noexcept {
  Impl& m = *impl_;
  realtype t = 0.0;
  m.last_flag = CVode(m.cvode, t_out, m.y, &t, CV_NORMAL);
  if (m.last_flag < 0) return Status::kIntegratorFailed;
  std::memcpy(y, N_VGetArrayPointer(m.y), sizeof(double) * static_cast<std::size_t>(m.size));
  *t_reached = t;
  *root_found = m.last_flag == CV_ROOT_RETURN;
  return Status::kOk;
}

IntegratorStats Integrator::stats() const noexcept {
  IntegratorStats s;
  const Impl& m = *impl_;
  long v = 0;
  if (CVodeGetNumSteps(m.cvode, &v) == CV_SUCCESS) s.steps = v;
  long rhs = 0;
  if (CVodeGetNumRhsEvals(m.cvode, &rhs) == CV_SUCCESS) s.rhs_evals = rhs;
  long ls_rhs = 0;
  if (CVodeGetNumLinRhsEvals(m.cvode, &ls_rhs) == CV_SUCCESS) s.rhs_evals += ls_rhs;
  if (m.root_count > 0 && CVodeGetNumGEvals(m.cvode, &v) == CV_SUCCESS) s.root_evals = v;
  if (CVodeGetNumErrTestFails(m.cvode, &v) == CV_SUCCESS) s.error_test_fails = v;
  return s;
}

int Integrator::last_flag() const noexcept { return impl_->last_flag; }

const char* Integrator::last_flag_name() const noexcept {
  // CVodeGetReturnFlagName allocates; keep a static table of the flags we can meet instead.
  switch (impl_->last_flag) {
    case CV_SUCCESS:
      return "CV_SUCCESS";
    case CV_TSTOP_RETURN:
      return "CV_TSTOP_RETURN";
    case CV_ROOT_RETURN:
      return "CV_ROOT_RETURN";
    case CV_TOO_MUCH_WORK:
      return "CV_TOO_MUCH_WORK (max_steps reached)";
    case CV_TOO_MUCH_ACC:
      return "CV_TOO_MUCH_ACC (tolerances too tight)";
    case CV_ERR_FAILURE:
      return "CV_ERR_FAILURE (error test failed repeatedly)";
    case CV_CONV_FAILURE:
      return "CV_CONV_FAILURE (nonlinear solver failed)";
    case CV_RHSFUNC_FAIL:
      return "CV_RHSFUNC_FAIL (right-hand side failed)";
    case CV_FIRST_RHSFUNC_ERR:
      return "CV_FIRST_RHSFUNC_ERR";
    case CV_UNREC_RHSFUNC_ERR:
      return "CV_UNREC_RHSFUNC_ERR";
    case CV_RTFUNC_FAIL:
      return "CV_RTFUNC_FAIL";
    case CV_ILL_INPUT:
      return "CV_ILL_INPUT";
    case CV_TOO_CLOSE:
      return "CV_TOO_CLOSE";
    default:
      return "CVODE flag (see cvode.h)";
  }
}

int Integrator::state_size() const noexcept { return impl_->size; }

}  // namespace cmmcomp::dynamics

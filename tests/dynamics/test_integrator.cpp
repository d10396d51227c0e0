// SPDX-License-Identifier: MIT
/// @file The CVODE facade on a harmonic oscillator: accuracy, roots, restarts, stop time, failures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/dynamics/integrator.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/status.hpp>
#include <limits>
#include <stdexcept>
#include <string>

namespace cmmcomp::dynamics {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// y'' = −ω² y as the first-order system (y, y'). Records the latest time the RHS was asked for.
struct Oscillator {
  double omega = 2.0 * kPi;  // period 1 s
  double latest_rhs_time = -kInf;
};

int oscillator_rhs(double t, const double* y, double* ydot, void* user) noexcept {
  Oscillator& o = *static_cast<Oscillator*>(user);
  o.latest_rhs_time = std::max(o.latest_rhs_time, t);
  ydot[0] = y[1];
  ydot[1] = -o.omega * o.omega * y[0];
  return 0;
}

// g = y': zero at every extremum of y.
int velocity_root(double /*t*/, const double* y, double* g, void* /*user*/) noexcept {
  g[0] = y[1];
  return 0;
}

int failing_rhs(double, const double*, double*, void*) noexcept { return -1; }

IntegratorOptions tight() {
  IntegratorOptions o;
  o.relative_tolerance = 1e-9;
  o.absolute_tolerance = 1e-12;
  return o;
}

TEST(Integrator, HarmonicOscillatorMatchesCosine) {
  Oscillator osc;
  Integrator integ(tight(), &oscillator_rhs, &osc, 2);
  EXPECT_EQ(integ.state_size(), 2);
  const double y0[2] = {1.0, 0.0};
  ASSERT_EQ(integ.reset(0.0, y0), Status::kOk);
  const double w = osc.omega;
  // rtol 1e-9 over 2.5 periods: the state stays within 1e-6 of the amplitude (1 and ω).
  for (int k = 1; k <= 25; ++k) {
    const double t_out = 0.1 * k;
    double y[2] = {kNaN, kNaN};
    double reached = kNaN;
    bool root = true;
    ASSERT_EQ(integ.advance_to(t_out, y, &reached, &root), Status::kOk) << "t=" << t_out;
    EXPECT_EQ(reached, t_out);
    EXPECT_FALSE(root);
    EXPECT_NEAR(y[0], std::cos(w * t_out), 1e-6) << "t=" << t_out;
    EXPECT_NEAR(y[1], -w * std::sin(w * t_out), 1e-6 * w) << "t=" << t_out;
  }
  const IntegratorStats s = integ.stats();
  EXPECT_GT(s.steps, 0);
  EXPECT_GE(s.rhs_evals, s.steps);
  EXPECT_EQ(s.root_evals, 0);  // no root function
}

TEST(Integrator, AdamsMethodIsAccurateToo) {
  Oscillator osc;
  IntegratorOptions o = tight();
  o.bdf = false;
  Integrator integ(o, &oscillator_rhs, &osc, 2);
  const double y0[2] = {1.0, 0.0};
  ASSERT_EQ(integ.reset(0.0, y0), Status::kOk);
  double y[2];
  double reached = 0;
  bool root = false;
  ASSERT_EQ(integ.advance_to(1.3, y, &reached, &root), Status::kOk);
  EXPECT_NEAR(y[0], std::cos(osc.omega * 1.3), 1e-6);
}

TEST(Integrator, RootOnVelocityFindsTheExtremumAtPiOverOmega) {
  Oscillator osc;
  IntegratorOptions o = tight();
  o.relative_tolerance = 1e-10;
  Integrator integ(o, &oscillator_rhs, &osc, 2, &velocity_root, 1);
  const double y0[2] = {1.0, 0.0};  // g = 0 at t0: CVODE must look for the next sign change
  ASSERT_EQ(integ.reset(0.0, y0), Status::kOk);
  const double t_root = kPi / osc.omega;  // the minimum y = −1
  double y[2];
  double reached = 0;
  bool root = false;
  ASSERT_EQ(integ.advance_to(0.9, y, &reached, &root), Status::kOk);
  EXPECT_TRUE(root);
  EXPECT_NEAR(reached, t_root, 1e-8);
  EXPECT_NEAR(y[0], -1.0, 1e-6);
  EXPECT_NEAR(y[1], 0.0, 1e-6 * osc.omega);

  // Continuing finds the next extremum (the maximum at 2π/ω), then reaches t_out.
  ASSERT_EQ(integ.advance_to(1.2, y, &reached, &root), Status::kOk);
  EXPECT_TRUE(root);
  EXPECT_NEAR(reached, 2.0 * t_root, 1e-8);
  EXPECT_NEAR(y[0], 1.0, 1e-6);
  ASSERT_EQ(integ.advance_to(1.2, y, &reached, &root), Status::kOk);
  EXPECT_FALSE(root);
  EXPECT_EQ(reached, 1.2);
  EXPECT_GT(integ.stats().root_evals, 0);
}

TEST(Integrator, ResetRestartsTheHistory) {
  Oscillator osc;
  Integrator integ(tight(), &oscillator_rhs, &osc, 2);
  const double y0[2] = {1.0, 0.0};
  double first[2];
  double again[2];
  double reached = 0;
  bool root = false;
  ASSERT_EQ(integ.reset(0.0, y0), Status::kOk);
  ASSERT_EQ(integ.advance_to(0.77, first, &reached, &root), Status::kOk);
  // Keep going, then restart at the same point: the run is repeated bit for bit.
  double later[2];
  ASSERT_EQ(integ.advance_to(2.0, later, &reached, &root), Status::kOk);
  ASSERT_EQ(integ.reset(0.0, y0), Status::kOk);
  ASSERT_EQ(integ.advance_to(0.77, again, &reached, &root), Status::kOk);
  EXPECT_EQ(reached, 0.77);
  EXPECT_EQ(first[0], again[0]);
  EXPECT_EQ(first[1], again[1]);

  // A restart at another time from another state follows the new solution y = sin(ω(t − 0.25)).
  const double w = osc.omega;
  const double s0[2] = {0.0, w};  // y = sin(ωt)
  ASSERT_EQ(integ.reset(0.25, s0), Status::kOk);
  double y[2];
  ASSERT_EQ(integ.advance_to(0.6, y, &reached, &root), Status::kOk);
  EXPECT_EQ(reached, 0.6);
  EXPECT_NEAR(y[0], std::sin(w * (0.6 - 0.25)), 1e-6);
  EXPECT_NEAR(y[1], w * std::cos(w * (0.6 - 0.25)), 1e-6 * w);
}

TEST(Integrator, NeverStepsPastTheStopTime) {
  Oscillator osc;
  Integrator integ(tight(), &oscillator_rhs, &osc, 2);
  const double y0[2] = {1.0, 0.0};
  ASSERT_EQ(integ.reset(0.0, y0), Status::kOk);
  const double t_stop = 0.3;
  ASSERT_EQ(integ.set_stop_time(t_stop), Status::kOk);
  double y[2];
  double reached = 0;
  bool root = false;
  ASSERT_EQ(integ.advance_to(5.0, y, &reached, &root), Status::kOk);
  EXPECT_EQ(reached, t_stop);
  EXPECT_FALSE(root);
  EXPECT_LE(osc.latest_rhs_time, t_stop);  // not even a trial evaluation beyond it
  EXPECT_NEAR(y[0], std::cos(osc.omega * t_stop), 1e-6);
}

TEST(Integrator, StopTimeBeforeTheCurrentTimeFails) {
  Oscillator osc;
  Integrator integ(tight(), &oscillator_rhs, &osc, 2);
  const double y0[2] = {1.0, 0.0};
  ASSERT_EQ(integ.reset(1.0, y0), Status::kOk);
  double y[2];
  double reached = 0;
  bool root = false;
  ASSERT_EQ(integ.advance_to(1.5, y, &reached, &root), Status::kOk);
  EXPECT_EQ(integ.set_stop_time(1.2), Status::kIntegratorFailed);
  EXPECT_LT(integ.last_flag(), 0);
}

TEST(Integrator, InvalidOptionsAreReportedAndRejected) {
  Oscillator osc;
  auto expect_invalid = [&osc](IntegratorOptions o, const char* what) {
    std::string why;
    EXPECT_FALSE(o.is_valid(&why)) << what;
    EXPECT_FALSE(why.empty()) << what;
    EXPECT_FALSE(o.is_valid(nullptr)) << what;
    EXPECT_THROW(Integrator(o, &oscillator_rhs, &osc, 2), cmmcomp::ConfigError) << what;
  };
  std::string why;
  EXPECT_TRUE(IntegratorOptions{}.is_valid(&why)) << why;

  IntegratorOptions o;
  o.relative_tolerance = 0.0;
  expect_invalid(o, "rtol 0");
  o.relative_tolerance = 1.0;
  expect_invalid(o, "rtol 1");
  o.relative_tolerance = kNaN;
  expect_invalid(o, "rtol NaN");
  o = IntegratorOptions{};
  o.absolute_tolerance = 0.0;
  expect_invalid(o, "atol 0");
  o.absolute_tolerance = kInf;
  expect_invalid(o, "atol inf");
  o = IntegratorOptions{};
  o.max_steps = 0;
  expect_invalid(o, "max_steps 0");
  o = IntegratorOptions{};
  o.max_step = -1.0;
  expect_invalid(o, "max_step -1");
  o.max_step = kNaN;
  expect_invalid(o, "max_step NaN");
}

TEST(Integrator, ConstructorRejectsBadSizesAndMissingFunctions) {
  Oscillator osc;
  const IntegratorOptions o;
  EXPECT_THROW(Integrator(o, &oscillator_rhs, &osc, 0), cmmcomp::ConfigError);
  EXPECT_THROW(Integrator(o, &oscillator_rhs, &osc, -3), cmmcomp::ConfigError);
  EXPECT_THROW(Integrator(o, nullptr, &osc, 2), cmmcomp::ConfigError);
  EXPECT_THROW(Integrator(o, &oscillator_rhs, &osc, 2, nullptr, 1), cmmcomp::ConfigError);
  EXPECT_THROW(Integrator(o, &oscillator_rhs, &osc, 2, &velocity_root, -1), cmmcomp::ConfigError);
  EXPECT_NO_THROW(Integrator(o, &oscillator_rhs, &osc, 2, nullptr, 0));
}

TEST(Integrator, FailingRhsReportsTheFlagAndLeavesOutputsUntouched) {
  Integrator integ(IntegratorOptions{}, &failing_rhs, nullptr, 3);
  const double y0[3] = {1.0, 2.0, 3.0};
  ASSERT_EQ(integ.reset(0.0, y0), Status::kOk);
  double y[3] = {-7.0, -7.0, -7.0};
  double reached = -7.0;
  bool root = true;
  EXPECT_EQ(integ.advance_to(1.0, y, &reached, &root), Status::kIntegratorFailed);
  EXPECT_LT(integ.last_flag(), 0);
  ASSERT_NE(integ.last_flag_name(), nullptr);
  EXPECT_GT(std::string(integ.last_flag_name()).size(), 0u);
  EXPECT_NE(std::string(integ.last_flag_name()).find("RHSFUNC"), std::string::npos)
      << integ.last_flag_name();
  EXPECT_EQ(y[0], -7.0);
  EXPECT_EQ(y[2], -7.0);
  EXPECT_EQ(reached, -7.0);
  EXPECT_TRUE(root);
}

TEST(Integrator, TooManyStepsIsCvTooMuchWork) {
  Oscillator osc;
  IntegratorOptions o = tight();
  o.max_steps = 1;
  Integrator integ(o, &oscillator_rhs, &osc, 2);
  const double y0[2] = {1.0, 0.0};
  ASSERT_EQ(integ.reset(0.0, y0), Status::kOk);
  double y[2];
  double reached = 0;
  bool root = false;
  EXPECT_EQ(integ.advance_to(10.0, y, &reached, &root), Status::kIntegratorFailed);
  EXPECT_LT(integ.last_flag(), 0);
  EXPECT_NE(std::string(integ.last_flag_name()).find("CV_TOO_MUCH_WORK"), std::string::npos)
      << integ.last_flag_name();

  // A restart clears the failure.
  ASSERT_EQ(integ.reset(0.0, y0), Status::kOk);
  EXPECT_EQ(integ.last_flag(), 0);
  EXPECT_STREQ(integ.last_flag_name(), "CV_SUCCESS");
}

}  // namespace
}  // namespace cmmcomp::dynamics

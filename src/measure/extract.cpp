// SPDX-License-Identifier: MIT
/// @file Recordings to the four parameters (docs/measurement.md, "Extraction").
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/dynamics/dataset.hpp>
#include <cmmcomp/errors/dynamic_errors.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/measure/extract.hpp>
#include <cmmcomp/measure/twin_recording.hpp>
#include <cmmcomp/motion/move_profile.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>

#include "csv_reader.hpp"

namespace cmmcomp::measure {
namespace {

constexpr std::uintmax_t kMaxRecordingBytes = 512u << 20;

/// A recording's columns: the times (strictly increasing, no jump over kMaxTimeJump_s), the
/// values of `names`, and the times of its sync marker rows.
struct Columns {
  std::vector<std::vector<double>> values;  ///< t first, then the other names
  std::vector<double> sync_t_s;
};

constexpr double kMaxTimeJump_s = 3600.0;

Columns read_columns(const std::string& path, const std::vector<std::string>& names) {
  detail::NumericColumns t = detail::read_numeric(
      io::read_file_bounded(path, "recording", kMaxRecordingBytes), path, names, {"sync"});
  Columns out;
  const std::vector<double>& time = t.columns[0];
  for (std::size_t r = 1; r < t.rows; ++r) {
    if (!(time[r] > time[r - 1])) {
      throw ConfigError(path + ":" + std::to_string(t.lines[r]) + ": column '" + names[0] +
                        "': time does not increase");
    }
    if (time[r] - time[r - 1] > kMaxTimeJump_s) {
      throw ConfigError(fmt::format(
          "{}:{}: column '{}': the time jumps by {:.6g} s from the row before (a stray row, or "
          "another clock's time stamp): remove the row or fix its time",
          path,
          t.lines[r],
          names[0],
          time[r] - time[r - 1]));
    }
  }
  if (t.rows < 2) throw ConfigError(path + ": fewer than two samples");
  if (t.present.back()) {
    const std::vector<double>& sync = t.columns.back();
    for (std::size_t r = 0; r < t.rows; ++r) {
      if (sync[r] != 0.0 && sync[r] != 1.0) {
        throw ConfigError(path + ":" + std::to_string(t.lines[r]) +
                          ": column 'sync': not 0 or 1 (1 marks the row taken at the trigger)");
      }
      if (sync[r] == 1.0) out.sync_t_s.push_back(time[r]);
    }
  }
  t.columns.pop_back();
  out.values = std::move(t.columns);
  return out;
}

/// Linear interpolation of (t, x) at `at`, clamped at the ends.
double interpolate(const std::vector<double>& t, const std::vector<double>& x, double at) {
  if (at <= t.front()) return x.front();
  if (at >= t.back()) return x.back();
  const auto it = std::upper_bound(t.begin(), t.end(), at);
  const std::size_t i = static_cast<std::size_t>(it - t.begin()) - 1;
  const double w = (at - t[i]) / (t[i + 1] - t[i]);
  return x[i] + w * (x[i + 1] - x[i]);
}

/// The first time the trace crosses `level` upwards, interpolated; NaN if never.
double crossing(const std::vector<double>& t, const std::vector<double>& s, double level) {
  for (std::size_t i = 1; i < t.size(); ++i) {
    if (s[i - 1] < level && s[i] >= level) {
      return t[i - 1] + (level - s[i - 1]) / (s[i] - s[i - 1]) * (t[i] - t[i - 1]);
    }
  }
  return std::nan("");
}

/// The commanded time at which the profile reaches `level` [mm], by bisection in [lo, hi]
/// (the positioning by default), where the position is monotone.
double profile_time_at(const motion::MoveProfile& p,
                       double level_mm,
                       double lo = 0.0,
                       double hi = -1.0) {
  if (hi < 0) hi = p.instants().positioning_end;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (p.sample(mid).position * 1e3 < level_mm ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double median_step(const std::vector<double>& t) {
  std::vector<double> d;
  for (std::size_t i = 1; i < t.size(); ++i) d.push_back(t[i] - t[i - 1]);
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

/// Solves the 2×2 system [a b; b c] x = (u, v); false when singular.
bool solve2(double a, double b, double c, double u, double v, double& x, double& y) {
  const double det = a * c - b * b;
  if (!(std::fabs(det) > 1e-300)) return false;
  x = (c * u - b * v) / det;
  y = (a * v - b * u) / det;
  return true;
}

/// One move, given the tracker→controller clock (offset + drift · t).
struct MoveFit {
  motion::MoveProfile profile;
  std::vector<double> ts, ss;  ///< scale: controller time, position along the motion [mm]
  double t0 = 0, c = 0;        ///< fitted start and position offset
  double rms_um = 0;
};

/// A fit of the commanded profile's start t0 and offset c to a scale trace.
struct PhaseFit {
  enum class Failure { kNone, kNoHalfCrossing, kSingular } failure = Failure::kNone;
  double t0 = 0, c = 0, rms_um = 0;
  int samples = 0;  ///< in [0, until], where the RMS is taken
};

/// Fits t0 and c so that s(t) ≈ c + p(t − t0) over τ ∈ [−0.05, until] (Gauss–Newton, started at
/// the half-PD crossing); the RMS is over τ ∈ [0, until].
PhaseFit fit_start_and_offset(const motion::MoveProfile& p,
                              const std::vector<double>& ts,
                              const std::vector<double>& ss,
                              double until) {
  PhaseFit f;
  const motion::PhaseInstants& in = p.instants();
  const double half = 0.5 * p.sample(in.positioning_end).position * 1e3;
  const double tc = crossing(ts, ss, ss.front() + half);
  if (std::isnan(tc)) {
    f.failure = PhaseFit::Failure::kNoHalfCrossing;
    return f;
  }
  f.t0 = tc - profile_time_at(p, half);
  f.c = ss.front();
  for (int iter = 0; iter < 20; ++iter) {
    double a = 0, b = 0, cc = 0, u = 0, v = 0;
    for (std::size_t i = 0; i < ts.size(); ++i) {
      const double tau = ts[i] - f.t0;
      if (tau < -0.05 || tau > until) continue;
      const motion::MotionState m = p.sample(tau);
      const double r = ss[i] - f.c - m.position * 1e3;
      const double jt = -m.velocity * 1e3;  // ∂model/∂t0; ∂model/∂c = 1
      a += 1;
      b += jt;
      cc += jt * jt;
      u += r;
      v += jt * r;
    }
    double dc = 0, dt = 0;
    if (!solve2(a, b, cc, u, v, dc, dt)) {
      f.failure = PhaseFit::Failure::kSingular;
      return f;
    }
    f.c += dc;
    f.t0 += dt;
    if (std::fabs(dt) < 1e-12 && std::fabs(dc) < 1e-9) break;
  }
  double sum = 0;
  for (std::size_t i = 0; i < ts.size(); ++i) {
    const double tau = ts[i] - f.t0;
    if (tau < 0 || tau > until) continue;
    const double r = ss[i] - f.c - p.sample(tau).position * 1e3;
    sum += r * r;
    ++f.samples;
  }
  f.rms_um = f.samples > 0 ? std::sqrt(sum / f.samples) * 1e3 : 0.0;
  return f;
}

/// Fits the move's profile to its scale trace up to the touch; the reason it is not this move,
/// or an empty string.
std::string fit_profile(MoveFit& f, double max_rms_um) {
  const motion::PhaseInstants& in = f.profile.instants();
  const PhaseFit fit = fit_start_and_offset(f.profile, f.ts, f.ss, in.touch);
  if (fit.failure == PhaseFit::Failure::kNoHalfCrossing) {
    return "the scale never moves half the planned PD: not this move";
  }
  if (fit.failure == PhaseFit::Failure::kSingular) return "the scale trace does not cover the move";
  f.t0 = fit.t0;
  f.c = fit.c;
  f.rms_um = fit.rms_um;
  if (!(f.rms_um <= max_rms_um)) {
    return fmt::format("the scale does not follow the planned profile: {:.1f} µm RMS > {:g}",
                       f.rms_um,
                       max_rms_um);
  }
  if (f.ts.front() > f.t0 + 1e-9) return "the scale recording starts after the move";
  if (f.ts.back() < f.t0 + in.touch) return "the scale recording ends before the touch";
  return {};
}

/// The tracker→controller offset [s] of one move, from the motion: the time shift δ that makes
/// tip − scale least correlated with the speed while the axis moves in the positioning, with a
/// free constant α (Gauss–Newton on r_i = tip − rest − S(t_i + δ) ≈ α, ∂r/∂δ = −v). A clock
/// offset shows as v·δ. What else is in tip − scale does not bias δ when it is uncorrelated with
/// v over the phase: a constant while moving (Coulomb drag) is α, and an inertial error ∝ a has
/// ∫ v·a dt = 0 over a rest-to-rest phase. A tip error ∝ v (viscous drag) is a lag, which no
/// motion can tell from a clock offset (docs/measurement.md, "Clock alignment").
double own_offset(const MoveFit& f,
                  const std::vector<double>& tt,
                  const std::vector<double>& st,
                  double rest) {
  const motion::PhaseInstants& in = f.profile.instants();
  const double half = 0.5 * f.profile.sample(in.positioning_end).position * 1e3;
  const double tc = crossing(tt, st, rest + f.c + half);
  if (std::isnan(tc)) return std::nan("");
  const double peak = f.profile.positioning_peak_speed() * 1e3;
  double delta = (f.t0 + profile_time_at(f.profile, half)) - tc;
  double alpha = 0;
  for (int iter = 0; iter < 30; ++iter) {
    double a = 0, b = 0, c = 0, u = 0, v = 0;
    for (std::size_t i = 0; i < tt.size(); ++i) {
      const double tau = tt[i] + delta - f.t0;
      if (tau < 0 || tau > in.positioning_end) continue;
      const double vel = f.profile.sample(tau).velocity * 1e3;
      if (vel < 0.02 * peak) continue;  // moving samples only: α is the moving constant
      const double r = st[i] - rest - interpolate(f.ts, f.ss, tt[i] + delta) - alpha;
      // r(α + dα, δ + dδ) ≈ r − dα − v·dδ = 0: the normal equations of [1 v]·(dα, dδ) = r.
      a += 1;
      b += vel;
      c += vel * vel;
      u += r;
      v += vel * r;
    }
    double d_alpha = 0, d_delta = 0;
    if (!solve2(a, b, c, u, v, d_alpha, d_delta)) return std::nan("");
    alpha += d_alpha;
    delta += d_delta;
    if (std::fabs(d_delta) < 1e-12) break;
  }
  return delta;
}

/// The profile of the planned move at the given controller timing; false when it is not valid.
bool plan_profile(const DatasetRow& settings,
                  double dwell,
                  double smoothing,
                  motion::MoveProfile& out) {
  motion::ProbingMove move = dynamics::move_of(settings);
  move.dwell = dwell;
  move.smoothing = smoothing;
  return motion::MoveProfile::plan(move, out) == Status::kOk;
}

/// The positioning alone, τ ≤ positioning_end: what the dwell and the approach cannot change.
/// Usable when the fit converged on at least 4 samples.
bool fit_positioning(const motion::MoveProfile& p,
                     const std::vector<double>& ts,
                     const std::vector<double>& ss,
                     PhaseFit& out) {
  out = fit_start_and_offset(p, ts, ss, p.instants().positioning_end);
  return out.failure == PhaseFit::Failure::kNone && out.samples >= 4;
}

/// The controller timing one move ran with, measured from its scale trace (docs/measurement.md,
/// "Controller timing"): the smoothing is the one whose positioning S-curve fits the scale best
/// (a grid of 20 ms, then golden section); the dwell is the time shift that puts the planned
/// approach (at that smoothing, no dwell) on the scale's approach.
struct MeasuredTiming {
  double dwell = std::nan(""), smoothing = std::nan("");
  double rms_um = std::nan("");  ///< the positioning's fit at the smoothing found
};

MeasuredTiming measure_timing(const DatasetRow& settings,
                              const std::vector<double>& ts,
                              const std::vector<double>& ss) {
  MeasuredTiming out;
  const auto cost = [&](double s) {
    motion::MoveProfile p;
    if (!plan_profile(settings, 0.0, s, p)) return std::numeric_limits<double>::infinity();
    PhaseFit f;
    return fit_positioning(p, ts, ss, f) ? f.rms_um : std::numeric_limits<double>::infinity();
  };
  constexpr double kStep = 0.02, kMax = 0.5;
  double best = 0, best_cost = cost(0.0);
  for (double s = kStep; s <= kMax + 1e-9; s += kStep) {
    const double c = cost(s);
    if (c < best_cost) {
      best_cost = c;
      best = s;
    }
  }
  if (!std::isfinite(best_cost)) return out;
  // Golden section on [best − step, best + step] (the cost is smooth and unimodal there).
  double lo = std::max(0.0, best - kStep), hi = best + kStep;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double f1 = cost(x1), f2 = cost(x2);
  for (int i = 0; i < 18; ++i) {
    if (f1 < f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = cost(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = cost(x2);
    }
  }
  const double s = 0.5 * (lo + hi);
  const double smoothing = cost(s) <= best_cost ? s : best;
  motion::MoveProfile p;
  if (!plan_profile(settings, 0.0, smoothing, p)) return out;
  PhaseFit f;
  if (!fit_positioning(p, ts, ss, f)) return out;
  out.smoothing = smoothing;
  out.rms_um = f.rms_um;
  // The dwell: the approach of the no-dwell profile shifted by ta onto the scale's approach.
  const motion::PhaseInstants& in = p.instants();
  const double pd = p.sample(in.positioning_end).position * 1e3;
  const double ad = p.sample(in.touch).position * 1e3 - pd;
  const double tc = crossing(ts, ss, f.c + pd + 0.5 * ad);
  if (std::isnan(tc)) return out;
  double ta = tc - (f.t0 + profile_time_at(p, pd + 0.5 * ad, in.approach_start, in.touch));
  for (int iter = 0; iter < 12; ++iter) {
    double num = 0, den = 0;
    for (std::size_t i = 0; i < ts.size(); ++i) {
      const double tau = ts[i] - f.t0 - ta;
      if (tau < in.approach_start || tau > in.touch) continue;
      const motion::MotionState m = p.sample(tau);
      const double r = ss[i] - f.c - m.position * 1e3;
      const double v = m.velocity * 1e3;
      num += v * r;
      den += v * v;
    }
    if (!(den > 0)) return out;
    const double d = -num / den;
    ta += d;
    if (std::fabs(d) < 1e-9) break;
  }
  out.dwell = ta;
  return out;
}

double median_of(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return std::isnan(x); }), v.end());
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Sample standard deviation of x about its least-squares line over t (a rest's drift is not
/// noise); NaN with fewer than 3 samples.
double detrended_sd(const std::vector<double>& t, const std::vector<double>& x) {
  const std::size_t n = x.size();
  if (n < 3) return std::nan("");
  double st = 0, sx = 0, stt = 0, stx = 0;
  for (std::size_t i = 0; i < n; ++i) {
    st += t[i];
    sx += x[i];
    stt += t[i] * t[i];
    stx += t[i] * x[i];
  }
  const double dn = static_cast<double>(n);
  const double det = dn * stt - st * st;
  const double b = det > 0 ? (dn * stx - st * sx) / det : 0.0;
  const double a = (sx - b * st) / dn;
  double ss = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = x[i] - a - b * t[i];
    ss += r * r;
  }
  return std::sqrt(ss / (dn - 2));
}

}  // namespace

MoveRecording read_planned_recording(const std::string& dir, const PlannedMove& move) {
  const std::string base = dir.empty() || dir.back() == '/' ? dir : dir + "/";
  const std::string one = base + one_clock_file(move.move_id);
  const std::string ctl = base + controller_file(move.move_id);
  const std::string trk = base + tracker_file(move.move_id);
  MoveRecording r;
  r.move_id = move.move_id;
  try {
    if (std::filesystem::exists(one)) return read_move_recording(one, "", move.axis, move.move_id);
    if (std::filesystem::exists(ctl) && std::filesystem::exists(trk)) {
      return read_move_recording(ctl, trk, move.axis, move.move_id);
    }
    r.problem = "a stream is missing: no " + one_clock_file(move.move_id) + ", or not both " +
                controller_file(move.move_id) + " and " + tracker_file(move.move_id);
  } catch (const ConfigError& e) {
    r.problem = std::string("unreadable recording: ") + e.what();
  }
  return r;
}

MoveRecording read_move_recording(const std::string& controller_path,
                                  const std::string& tracker_path,
                                  char axis,
                                  int move_id) {
  const std::string a(1, axis);
  MoveRecording r;
  r.move_id = move_id;
  if (tracker_path.empty()) {
    Columns cols = read_columns(controller_path, {"t_s", a + "_scale_mm", a + "_tip_mm"});
    r.scale_t_s = cols.values[0];
    r.scale_mm = std::move(cols.values[1]);
    r.tip_t_s = std::move(cols.values[0]);
    r.tip_mm = std::move(cols.values[2]);
    r.one_clock = true;
    r.source = controller_path;
  } else {
    Columns c = read_columns(controller_path, {"t_s", a + "_scale_mm"});
    Columns t = read_columns(tracker_path, {"t_s", a + "_tip_mm"});
    r.scale_t_s = std::move(c.values[0]);
    r.scale_mm = std::move(c.values[1]);
    r.tip_t_s = std::move(t.values[0]);
    r.tip_mm = std::move(t.values[1]);
    r.scale_sync_t_s = std::move(c.sync_t_s);
    r.tip_sync_t_s = std::move(t.sync_t_s);
    r.one_clock = false;
    r.source = controller_path + " + " + tracker_path;
  }
  return r;
}

std::vector<DatasetRow> Extraction::rows() const {
  std::vector<DatasetRow> out;
  if (!refusal.empty()) return out;
  for (const MoveExtraction& m : moves) {
    if (m.ok) out.push_back(m.row);
  }
  return out;
}

namespace {

void check_options(const ExtractOptions& o) {
  const auto bad = [](const char* what, double v, const char* range) {
    throw ConfigError(fmt::format("{} {} is out of range: {}", what, v, range));
  };
  const auto timing = [&](const char* what, double v, double max) {
    if (!std::isnan(v) && !(v >= 0.0 && v <= max)) bad(what, v, "0 .. the profile's limit");
  };
  timing("the dwell [s]", o.dwell_s, motion::MoveLimits::kMaxDwell);
  timing("the smoothing [s]", o.smoothing_s, motion::MoveLimits::kMaxSmoothing);
  if (!(o.timing_tolerance_s > 0 && o.timing_tolerance_s <= 1))
    bad("the timing tolerance [s]", o.timing_tolerance_s, "(0, 1]");
  if (!(o.max_profile_rms_um > 0 && o.max_profile_rms_um <= 1e4))
    bad("the profile RMS limit [µm]", o.max_profile_rms_um, "(0, 10000]");
  if (!(o.max_alignment_residual_ms > 0 && o.max_alignment_residual_ms <= 1e3))
    bad("the alignment residual limit [ms]", o.max_alignment_residual_ms, "(0, 1000]");
  if (!(o.max_gap_ms > 0 && o.max_gap_ms <= 1e4))
    bad("the dropout limit [ms]", o.max_gap_ms, "(0, 10000]");
  if (!(o.max_touch_speed_error > 0 && o.max_touch_speed_error < 1))
    bad("the touch speed limit", o.max_touch_speed_error, "(0, 1)");
  if (!(o.max_travel_ratio_error > 0 && o.max_travel_ratio_error < 0.5))
    bad("the travel ratio limit", o.max_travel_ratio_error, "(0, 0.5)");
  if (!(o.max_scale_factor_ppm > 0 && o.max_scale_factor_ppm <= 1e5))
    bad("the scale factor limit [ppm]", o.max_scale_factor_ppm, "(0, 100000]");
  if (!std::isfinite(o.clock_offset_s) || !(std::fabs(o.clock_offset_s) <= 1e6))
    bad("the clock offset [s]", o.clock_offset_s, "|offset| <= 1e6 s");
  if (!(std::fabs(o.clock_drift) < 0.01))
    bad("the clock drift", o.clock_drift, "|drift| < 1 % (10000 ppm)");
  if (!(o.motion_alignment_bias_ms >= 0 && o.motion_alignment_bias_ms <= 100))
    bad("the motion alignment bias [ms]", o.motion_alignment_bias_ms, "[0, 100]");
  if (!(o.clock_budget_share > 0 && o.clock_budget_share <= 100))
    bad("the clock budget share", o.clock_budget_share, "(0, 100]");
  if (!(o.max_plan_mismatch_share > 0 && o.max_plan_mismatch_share <= 1))
    bad("the plan mismatch share", o.max_plan_mismatch_share, "(0, 1]");
}

/// Runs of digits (a number) in a reason replaced by '#', to count reasons by kind.
std::string reason_kind(const std::string& reason) {
  std::string out;
  bool in_number = false;
  for (std::size_t i = 0; i < reason.size(); ++i) {
    const char ch = reason[i];
    const bool digit = (ch >= '0' && ch <= '9') || (in_number && (ch == '.' || ch == 'e')) ||
                       ((ch == '-' || ch == '+') && i + 1 < reason.size() && reason[i + 1] >= '0' &&
                        reason[i + 1] <= '9');
    if (digit) {
      if (!in_number) out += '#';
      in_number = true;
    } else {
      in_number = false;
      out += ch;
    }
  }
  return out;
}

/// The error trace of one move on the controller clock, and its four parameters. Returns the
/// reason it cannot be had, or an empty string.
struct TraceResult {
  errors::DynamicErrors e{};
  int dropouts = 0;
  double longest_gap_ms = 0;
  double plateau_um = std::nan("");  ///< mean e over the dwell's second half (dwell ≥ 0.1 s)
};

/// `scale_factor` is the static share k by which the tip's travel exceeds the scale's (a
/// tracker at an angle to the axis, its wavelength): k·s(t) is removed from e, a static error.
template <typename ToController>
std::string error_parameters(const MoveFit& fit,
                             const MoveRecording& rec,
                             const std::vector<double>& st,
                             double rest,
                             double tip_rate_hz,
                             double max_gap_ms,
                             double scale_factor,
                             ToController to_controller,
                             TraceResult& out) {
  const motion::PhaseInstants& in = fit.profile.instants();
  std::vector<double> time, error;
  for (std::size_t i = 0; i < rec.tip_t_s.size(); ++i) {
    const double t = to_controller(rec.tip_t_s[i]);
    const double tau = t - fit.t0;
    if (tau < -0.5 || tau > in.touch + 0.5) continue;
    if (t < fit.ts.front() || t > fit.ts.back()) continue;
    time.push_back(tau);
    const double scale = interpolate(fit.ts, fit.ss, t);
    error.push_back((st[i] - rest - (1.0 + scale_factor) * scale) * 1e3);
  }
  // Dropouts: gaps longer than 1.5 sample steps are bridged by interpolation and counted;
  // one longer than the limit inside [0, touch] skips the move (it may hide a maximum).
  const double step = 1.0 / tip_rate_hz;
  const double limit = std::max(max_gap_ms * 1e-3, 3.0 * step);
  std::string reason;
  for (std::size_t i = 1; i < time.size(); ++i) {
    const double gap = time[i] - time[i - 1];
    if (gap > 1.5 * step) {
      ++out.dropouts;
      out.longest_gap_ms = std::max(out.longest_gap_ms, gap * 1e3);
      if (gap > limit && time[i] > 0 && time[i - 1] < in.touch) {
        reason = fmt::format("a tracker dropout of {:.1f} ms at {:.3f}–{:.3f} s of the move",
                             gap * 1e3,
                             time[i - 1],
                             time[i]);
      }
    }
  }
  if (!reason.empty()) return reason;
  const double dwell = in.approach_start - in.positioning_end;
  if (dwell >= 0.1) {
    double sum = 0;
    int n = 0;
    for (std::size_t i = 0; i < time.size(); ++i) {
      if (time[i] >= in.positioning_end + 0.5 * dwell && time[i] <= in.approach_start) {
        sum += error[i];
        ++n;
      }
    }
    if (n > 0) out.plateau_um = sum / n;
  }
  const errors::TraceView view{time.data(), error.data(), time.size()};
  const Status s = errors::extract_dynamic_errors(view, in, 1, out.e);
  if (s == Status::kTraceTooShort) {
    return "the tip recording does not cover the move from its start to the touch";
  }
  if (s != Status::kOk) return "the error trace is not valid";
  return {};
}

constexpr std::array<const char*, 4> kParameterLabels = {"MPE", "RPE", "MAE", "RAE"};

std::array<double, 4> as_array(const errors::DynamicErrors& e) {
  return {e.mpe, e.rpe, e.mae, e.rae};
}

/// The parameter the clock's uncertainty moves furthest past its allowance (median over the
/// extracted moves against `clock_budget_share` × Table 1's σ), described, or an empty string.
std::string clock_budget_excess(const Extraction& ex, const ExtractOptions& o) {
  std::string worst;
  double worst_excess = 0;
  for (std::size_t p = 0; p < 4; ++p) {
    std::vector<double> shifts;
    double largest = 0;
    for (const MoveExtraction& m : ex.moves) {
      if (!m.ok) continue;
      shifts.push_back(m.clock_sensitivity_um[p]);
      largest = std::max(largest, m.clock_sensitivity_um[p]);
    }
    const double median = median_of(shifts);
    const double allowed = o.clock_budget_share * paper::kTable1Std[p];
    if (median > allowed && median / allowed > worst_excess) {
      worst_excess = median / allowed;
      worst = fmt::format(
          "{} by {:.2f} µm (median over {} moves; up to {:.2f} µm) against an allowance of "
          "{:.2f} µm ({:g} × Table 1's σ)",
          kParameterLabels[p],
          median,
          shifts.size(),
          largest,
          allowed,
          o.clock_budget_share);
    }
  }
  return worst;
}

/// The campaign's noise: the median rest σ of the extracted moves, and each parameter's pooled
/// σ over the repeats of each run (`run_of_move`, per move), with warnings where a model's
/// residual floor (mean |noise| = √(2/π)·σ) would exceed 1.5 × the paper's, i.e. σ above 1.5 ×
/// Table 1's σ.
void estimate_noise(Extraction& ex, const std::vector<int>& run_of_move) {
  std::vector<double> rest;
  std::map<int, std::vector<std::array<double, 4>>> by_run;
  for (std::size_t k = 0; k < ex.moves.size(); ++k) {
    const MoveExtraction& m = ex.moves[k];
    if (!m.ok) continue;
    rest.push_back(m.rest_noise_um);
    by_run[run_of_move[k]].push_back({m.row.mpe_um, m.row.rpe_um, m.row.mae_um, m.row.rae_um});
  }
  ex.noise.rest_um = median_of(rest);
  std::array<double, 4> ss{};
  int dof = 0;
  for (const auto& [run, values] : by_run) {
    if (values.size() < 2) continue;
    dof += static_cast<int>(values.size()) - 1;
    for (std::size_t p = 0; p < 4; ++p) {
      double mean = 0;
      for (const auto& v : values) mean += v[p];
      mean /= static_cast<double>(values.size());
      for (const auto& v : values) ss[p] += (v[p] - mean) * (v[p] - mean);
    }
  }
  ex.noise.repeat_dof = dof;
  for (std::size_t p = 0; p < 4; ++p) {
    ex.noise.repeat_sd_um[p] = dof > 0 ? std::sqrt(ss[p] / dof) : std::nan("");
  }
  constexpr double kNoiseLimit = 1.5;
  if (dof >= 5) {
    for (std::size_t p = 0; p < 4; ++p) {
      const double sd = ex.noise.repeat_sd_um[p], table = paper::kTable1Std[p];
      if (!(sd > kNoiseLimit * table)) continue;
      ex.warnings.push_back(fmt::format(
          "the repeats scatter {} by σ {:.3f} µm ({} degrees of freedom), {:.1f}× Table 1's "
          "{:.3f} µm: a model's residual floor (√(2/π)·σ = {:.3f} µm) exceeds {:g} × the "
          "paper's ({:.3f} µm). The tracker's noise at rest is {:.3f} µm; check its noise, "
          "its mounting and the machine's repeatability",
          kParameterLabels[p],
          sd,
          dof,
          sd / table,
          table,
          std::sqrt(2.0 / M_PI) * sd,
          kNoiseLimit,
          kNoiseLimit * std::sqrt(2.0 / M_PI) * table,
          ex.noise.rest_um));
    }
  }
  const double point_sigma = std::min(paper::kTable1Std[1], paper::kTable1Std[3]);
  if (ex.noise.rest_um > kNoiseLimit * point_sigma) {
    ex.warnings.push_back(fmt::format(
        "the tip sensor's noise at rest is σ {:.3f} µm (median over {} moves), above {:g} × "
        "Table 1's σ of RAE ({:.3f} µm): RPE and RAE, read at one instant, carry it whole. "
        "Use a quieter sensor, a higher rate or a filter that keeps the phase",
        ex.noise.rest_um,
        rest.size(),
        kNoiseLimit,
        point_sigma));
  }
}

}  // namespace

void check_extract_options(const ExtractOptions& options) { check_options(options); }

ClockFit sync_clock(const std::vector<double>& scale_markers,
                    const std::vector<double>& tip_markers,
                    const std::string& source) {
  ClockFit c;
  if (scale_markers.empty() || tip_markers.empty()) return c;
  if (scale_markers.size() != tip_markers.size()) {
    throw ConfigError(fmt::format(
        "{}: {} sync markers in the controller's recording, {} in the tracker's: each trigger "
        "must mark one row of both streams (docs/measurement.md, \"Sync\")",
        source,
        scale_markers.size(),
        tip_markers.size()));
  }
  const std::size_t n = scale_markers.size();
  // t_c = a + b·t_t, about the means for conditioning.
  double mt = 0, mc = 0;
  for (std::size_t i = 0; i < n; ++i) {
    mt += tip_markers[i];
    mc += scale_markers[i];
  }
  mt /= static_cast<double>(n);
  mc /= static_cast<double>(n);
  double stt = 0, stc = 0;
  for (std::size_t i = 0; i < n; ++i) {
    stt += (tip_markers[i] - mt) * (tip_markers[i] - mt);
    stc += (tip_markers[i] - mt) * (scale_markers[i] - mc);
  }
  const double b = n >= 2 && stt > 1e-6 ? stc / stt : 1.0;
  const double a = mc - b * mt;
  double worst = 0;
  for (std::size_t i = 0; i < n; ++i) {
    worst = std::max(worst, std::fabs(scale_markers[i] - (a + b * tip_markers[i])));
  }
  if (worst > 0.05e-3) {
    throw ConfigError(fmt::format(
        "{}: the sync markers are not the same triggers: one is {:.3f} ms off the clock fit "
        "over {} pairs (limit 0.05 ms)",
        source,
        worst * 1e3,
        n));
  }
  // t_c = (t_t + offset)/(1 − drift): b = 1/(1 − drift), a = offset/(1 − drift).
  c.fitted = true;
  c.drift = 1.0 - 1.0 / b;
  c.offset_s = a / b;
  c.source = "sync markers";
  c.sync_markers = static_cast<int>(n);
  c.sync_residual_ms = worst * 1e3;
  return c;
}

std::string Extraction::most_frequent_reason() const {
  std::map<std::string, std::pair<int, std::string>> kinds;
  for (const MoveExtraction& m : moves) {
    if (m.ok) continue;
    auto& k = kinds[reason_kind(m.reason)];
    if (k.first++ == 0) k.second = m.reason;
  }
  int best = 0;
  std::string text;
  for (const auto& [kind, k] : kinds) {
    if (k.first > best) {
      best = k.first;
      text = k.second;
    }
  }
  if (best == 0) return {};
  return fmt::format("{} of {} moves: {}", best, moves.size(), text);
}

Extraction extract_moves(const std::vector<PlannedMove>& plan,
                         const std::vector<MoveRecording>& recordings,
                         const ExtractOptions& o) {
  check_options(o);
  std::map<int, const PlannedMove*> by_id;
  for (const PlannedMove& m : plan) {
    if (!by_id.emplace(m.move_id, &m).second) {
      throw ConfigError(fmt::format("the plan has move {} twice", m.move_id));
    }
  }

  struct Work {
    MoveFit fit;
    const PlannedMove* planned = nullptr;
    const MoveRecording* rec = nullptr;
    std::vector<double> ss0;  ///< scale along the motion [mm], before the fit
    std::vector<double> st;   ///< tip along the motion [mm]
    double rest = 0;          ///< tip − scale at rest before the move [mm]
    double own_delta = std::nan("");
  };
  // A move's own offset is measured over its positioning: it belongs to the middle of it.
  const auto mid_time = [](const Work& w) {
    return w.fit.t0 + 0.5 * w.fit.profile.instants().positioning_end;
  };
  Extraction ex;
  std::vector<Work> work(recordings.size());
  ex.moves.resize(recordings.size());
  if (!plan.empty() && std::all_of(plan.begin(), plan.end(), [&](const PlannedMove& m) {
        return m.axis == plan.front().axis;
      })) {
    ex.axis = std::string(1, plan.front().axis);
  }
  // Two clocks when any readable recording has them (a missing one says nothing).
  const bool two_clocks =
      std::any_of(recordings.begin(), recordings.end(), [](const MoveRecording& r) {
        return r.problem.empty() && !r.one_clock;
      });

  // 0. The tracker's clock: given, or from sync markers that both streams carry.
  bool known_clock = o.known_clock;
  if (!two_clocks) {
    ex.clock.source = "one clock";
  } else if (o.known_clock) {
    ex.clock.fitted = true;
    ex.clock.offset_s = o.clock_offset_s;
    ex.clock.drift = o.clock_drift;
    ex.clock.source = o.known_clock_source;
  } else {
    std::vector<double> scale_markers, tip_markers;
    int with_markers = 0;
    for (const MoveRecording& r : recordings) {
      if (r.scale_sync_t_s.empty() && r.tip_sync_t_s.empty()) continue;
      ++with_markers;
      if (r.scale_sync_t_s.size() != r.tip_sync_t_s.size()) {
        throw ConfigError(fmt::format(
            "move {}: {} sync markers in the controller's recording, {} in the tracker's "
            "({}): each trigger must mark one row of both streams",
            r.move_id,
            r.scale_sync_t_s.size(),
            r.tip_sync_t_s.size(),
            r.source));
      }
      scale_markers.insert(scale_markers.end(), r.scale_sync_t_s.begin(), r.scale_sync_t_s.end());
      tip_markers.insert(tip_markers.end(), r.tip_sync_t_s.begin(), r.tip_sync_t_s.end());
    }
    if (!scale_markers.empty()) {
      ex.clock = sync_clock(scale_markers, tip_markers, "the recordings");
      known_clock = true;
    }
  }
  const double clock_offset = known_clock ? ex.clock.offset_s : 0.0;
  const double clock_drift = known_clock ? ex.clock.drift : 0.0;

  // 1. Each recording against its plan row: is it this move, at which controller timing, and
  // does the tracker read the same travel as the scale?
  for (std::size_t k = 0; k < recordings.size(); ++k) {
    const MoveRecording& rec = recordings[k];
    MoveExtraction& out = ex.moves[k];
    Work& w = work[k];
    out.move_id = rec.move_id;
    w.rec = &rec;
    const auto it = by_id.find(rec.move_id);
    if (it == by_id.end()) {
      out.reason = "move " + std::to_string(rec.move_id) + " is not in the plan";
      continue;
    }
    w.planned = it->second;
    out.row = w.planned->settings;
    if (!rec.problem.empty()) {
      out.reason = rec.problem;
      continue;
    }
    if (rec.scale_t_s.size() < 2 || rec.tip_t_s.size() < 2) {
      out.reason = "a stream is missing or has fewer than two samples";
      continue;
    }
    const double d = w.planned->direction;
    const double start = axis_value(w.planned->start, w.planned->axis);
    for (double x : rec.scale_mm) w.ss0.push_back((x - start) * d);
    for (double x : rec.tip_mm) w.st.push_back((x - start) * d);
    out.tip_rate_hz = 1.0 / median_step(rec.tip_t_s);
    // The travels: the furthest each stream gets from where it starts (its sign kept), so
    // samples after the touch (a retract, the next move) do not count.
    const auto travel = [](const std::vector<double>& v) {
      double best = 0;
      for (double x : v) {
        if (std::fabs(x - v.front()) > std::fabs(best)) best = x - v.front();
      }
      return best;
    };
    const double scale_travel = travel(w.ss0);
    const double tip_travel = travel(w.st);
    if (!(scale_travel > 0.5 * w.planned->settings.pd_mm)) {
      out.reason = fmt::format(
          "the scale travels {:.3f} mm along the planned direction, not the planned {:g} mm: not "
          "this move",
          scale_travel,
          w.planned->settings.pd_mm + w.planned->settings.ad_mm);
      out.plan_mismatch = true;
      continue;
    }
    const double planned_travel = w.planned->settings.pd_mm + w.planned->settings.ad_mm;
    if (scale_travel < planned_travel - std::max(0.05, 0.002 * planned_travel)) {
      out.reason = fmt::format(
          "the scale travels {:.3f} mm of the planned {:g} mm: the recording ends before the "
          "touch, or the probe triggered early (hit something before the planned point)",
          scale_travel,
          planned_travel);
      out.plan_mismatch = scale_travel < w.planned->settings.pd_mm;
      continue;
    }
    out.travel_ratio = tip_travel / scale_travel;
    const MeasuredTiming timing = measure_timing(w.planned->settings, rec.scale_t_s, w.ss0);
    out.dwell_s = timing.dwell;
    out.smoothing_s = timing.smoothing;
    if (std::isnan(timing.smoothing) || std::isnan(timing.dwell)) {
      out.reason =
          "the scale does not follow the planned move at any controller timing: not this move";
      out.plan_mismatch = true;
      continue;
    }
    if (!(timing.rms_um <= o.max_profile_rms_um)) {
      out.reason = fmt::format(
          "the scale does not follow the planned positioning at any smoothing (best {:.1f} µm "
          "RMS > {:g}): not this move",
          timing.rms_um,
          o.max_profile_rms_um);
      out.plan_mismatch = true;
      continue;
    }
    if (std::fabs(out.travel_ratio - 1.0) > o.max_travel_ratio_error) {
      out.reason = fmt::format(
          "the tip travels {:.4g}× the scale's travel: a tracker axis pointing the other way "
          "(−1), another unit (25.4: inches; 1000: µm) or a scale factor error",
          out.travel_ratio);
    }
  }

  // A run whose recordings do not match the plan is refused whole.
  {
    int recorded = 0, mismatched = 0;
    for (std::size_t k = 0; k < work.size(); ++k) {
      if (work[k].planned == nullptr || !recordings[k].problem.empty()) continue;
      ++recorded;
      mismatched += ex.moves[k].plan_mismatch;
    }
    if (recorded > 0 && mismatched > o.max_plan_mismatch_share * recorded) {
      ex.refusal = fmt::format(
          "recordings of another plan? {} of {} recorded moves do not match their plan rows "
          "({}): check that plan.csv is the plan the machine ran, in its run order",
          mismatched,
          recorded,
          ex.most_frequent_reason());
      return ex;
    }
  }
  // A tracker of another unit or sign on most moves refuses the run.
  {
    std::vector<double> ratios;
    for (const MoveExtraction& m : ex.moves) ratios.push_back(m.travel_ratio);
    ex.travel_ratio = median_of(ratios);
    if (!std::isnan(ex.travel_ratio) &&
        std::fabs(ex.travel_ratio - 1.0) > o.max_travel_ratio_error) {
      ex.refusal = fmt::format(
          "the tip travels {:.5g}× the scale's travel (median over the moves): the tracker's "
          "axis points the other way (−1), reads another unit (25.4: inches; 1000: µm; 0.001: "
          "m) or has a scale factor error; fix its set-up or its export",
          ex.travel_ratio);
      return ex;
    }
  }

  // 1b. The controller timing of the run: the medians of the moves' measurements, against the
  // values given.
  {
    std::vector<double> dwells, smoothings;
    for (const MoveExtraction& m : ex.moves) {
      if (!m.plan_mismatch && !std::isnan(m.dwell_s)) {
        dwells.push_back(m.dwell_s);
        smoothings.push_back(m.smoothing_s);
      }
    }
    ControllerTiming& t = ex.timing;
    t.measured_moves = static_cast<int>(dwells.size());
    t.measured_dwell_s = median_of(dwells);
    t.measured_smoothing_s = median_of(smoothings);
    const auto decide = [&](const char* what,
                            const char* option,
                            const char* key,
                            double given,
                            double measured,
                            const std::vector<double>& per_move,
                            double& used,
                            bool& given_used) {
      if (std::isnan(measured)) {
        if (std::isnan(given)) {
          ex.refusal = fmt::format(
              "the controller's {} could not be measured on any move and none was given: "
              "pass {} (the machine file's [controller] {})",
              what,
              option,
              key);
          return false;
        }
        used = given;
        given_used = true;
        return true;
      }
      if (!std::isnan(given) && std::fabs(given - measured) > o.timing_tolerance_s) {
        int agreeing = 0;
        for (double v : per_move) agreeing += std::fabs(v - measured) <= o.timing_tolerance_s;
        ex.refusal = fmt::format(
            "the scale traces say the controller's {} is {:.3f} s ({} of {} moves within "
            "{:g} ms of it), the given {} is {:.3f} s: pass {} {:.3f} (or set [controller] {} "
            "in the machine file), or leave it out to use the measured value",
            what,
            measured,
            agreeing,
            per_move.size(),
            o.timing_tolerance_s * 1e3,
            what,
            given,
            option,
            measured,
            key);
        return false;
      }
      given_used = !std::isnan(given);
      used = given_used ? given : std::max(0.0, measured);
      return true;
    };
    if (!decide("dwell",
                "--dwell",
                "dwell_s",
                o.dwell_s,
                t.measured_dwell_s,
                dwells,
                t.dwell_s,
                t.dwell_given) ||
        !decide("smoothing",
                "--smoothing",
                "smoothing_s",
                o.smoothing_s,
                t.measured_smoothing_s,
                smoothings,
                t.smoothing_s,
                t.smoothing_given)) {
      return ex;
    }
  }

  // 1c. Each move at the run's timing: the commanded profile fitted to its scale trace, the
  // touch where it was planned, the rest offset and (two clocks from the motion) its own offset.
  for (std::size_t k = 0; k < recordings.size(); ++k) {
    const MoveRecording& rec = recordings[k];
    MoveExtraction& out = ex.moves[k];
    Work& w = work[k];
    if (!out.reason.empty()) continue;
    if (std::fabs(out.dwell_s - ex.timing.dwell_s) > o.timing_tolerance_s ||
        std::fabs(out.smoothing_s - ex.timing.smoothing_s) > o.timing_tolerance_s) {
      out.reason = fmt::format(
          "the scale shows a dwell of {:.3f} s and a smoothing of {:.3f} s, the run's are "
          "{:.3f} s and {:.3f} s: a pause, a touch out of place or another plan's move",
          out.dwell_s,
          out.smoothing_s,
          ex.timing.dwell_s,
          ex.timing.smoothing_s);
      continue;
    }
    if (!plan_profile(
            w.planned->settings, ex.timing.dwell_s, ex.timing.smoothing_s, w.fit.profile)) {
      out.reason = "the planned move is not a valid profile";
      continue;
    }
    w.fit.ts = rec.scale_t_s;
    w.fit.ss = w.ss0;
    out.reason = fit_profile(w.fit, o.max_profile_rms_um);
    out.profile_rms_um = w.fit.rms_um;
    out.start_s = w.fit.t0;
    if (!out.reason.empty()) continue;
    const motion::PhaseInstants& in = w.fit.profile.instants();
    {
      // The approach must still run at its planned speed when the touch is planned.
      const double window = std::min(0.01, in.touch - in.approach_start);
      const double te = w.fit.t0 + in.touch;
      const double v =
          (interpolate(w.fit.ts, w.fit.ss, te) - interpolate(w.fit.ts, w.fit.ss, te - window)) /
          window;
      const double planned = (w.fit.profile.sample(in.touch).position -
                              w.fit.profile.sample(in.touch - window).position) *
                             1e3 / window;
      if (!(std::fabs(v / planned - 1.0) <= o.max_touch_speed_error)) {
        out.reason = fmt::format(
            "the scale moves at {:.2f} mm/s in the {:.0f} ms before the planned touch, not the "
            "planned {:.2f} mm/s: the probe triggered early (or late) or the move hit something",
            v,
            window * 1e3,
            planned);
        continue;
      }
    }
    // The tip's rest offset, tip − scale over the samples at rest before the move (a tracker's
    // frame and the scale's zero differ; the twin and the paper count e from the machine at rest).
    double sum = 0;
    int n = 0;
    std::vector<double> rest_t, rest_x;
    if (rec.one_clock) {
      for (std::size_t i = 0; i < rec.tip_t_s.size() && rec.tip_t_s[i] <= w.fit.t0 + 1e-9; ++i) {
        const double x = w.st[i] - interpolate(w.fit.ts, w.fit.ss, rec.tip_t_s[i]);
        sum += x;
        ++n;
        rest_t.push_back(rec.tip_t_s[i]);
        rest_x.push_back(x);
      }
    } else {
      // Both streams at rest: up to 50 ms before the fitted start, the tracker's samples placed
      // on the controller clock by the known clock, or by the half-PD crossings (good to a
      // millisecond).
      const double half = 0.5 * w.fit.profile.sample(in.positioning_end).position * 1e3;
      const double tip_half = crossing(rec.tip_t_s, w.st, w.st.front() + half);
      const double coarse = w.fit.t0 + profile_time_at(w.fit.profile, half) - tip_half;
      const double rest_end = w.fit.t0 - 0.05;
      for (std::size_t i = 0; i < rec.tip_t_s.size() && rec.tip_t_s[i] + coarse <= rest_end; ++i) {
        sum += w.st[i];
        ++n;
        rest_t.push_back(rec.tip_t_s[i]);
        rest_x.push_back(w.st[i]);
      }
      double scale_sum = 0;
      int scale_n = 0;
      for (std::size_t i = 0; i < w.fit.ts.size() && w.fit.ts[i] <= rest_end; ++i) {
        scale_sum += w.fit.ss[i];
        ++scale_n;
      }
      if (std::isnan(coarse) || scale_n == 0) n = 0;
      if (n > 0) sum -= n * (scale_sum / scale_n);
    }
    if (n == 0) {
      out.reason = "no samples at rest before the move (record from 50 ms before it)";
      continue;
    }
    w.rest = sum / n;
    out.rest_noise_um = detrended_sd(rest_t, rest_x) * 1e3;
    if (two_clocks && !known_clock) {
      w.own_delta = own_offset(w.fit, rec.tip_t_s, w.st, w.rest);
      if (std::isnan(w.own_delta)) out.reason = "the tip trace cannot be aligned to the scale";
    }
  }

  // 2. Two clocks without a sync: offset + drift over every aligned move (two passes, the second
  // without moves whose offset is off the first fit by more than the limit), and how uncertain
  // that leaves each move's clock.
  if (two_clocks && !known_clock) {
    ex.clock.source = "motion";
    std::vector<bool> use(work.size());
    for (std::size_t k = 0; k < work.size(); ++k) use[k] = ex.moves[k].reason.empty();
    double residual_sd = std::nan("");
    int used = 0;
    for (int pass = 0; pass < 2; ++pass) {
      double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
      for (std::size_t k = 0; k < work.size(); ++k) {
        if (!use[k]) continue;
        const double x = mid_time(work[k]), y = work[k].own_delta;
        n += 1;
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
      }
      if (n >= 3 && sxx * n - sx * sx > 1e-12) {
        ex.clock.fitted = true;
        ex.clock.drift = (n * sxy - sx * sy) / (n * sxx - sx * sx);
        ex.clock.offset_s = (sy - ex.clock.drift * sx) / n;
      }
      if (!ex.clock.fitted) break;
      double ss = 0;
      used = 0;
      for (std::size_t k = 0; k < work.size(); ++k) {
        if (!use[k]) continue;
        const double r =
            work[k].own_delta - (ex.clock.offset_s + ex.clock.drift * mid_time(work[k]));
        ss += r * r;
        ++used;
        if (std::fabs(r) * 1e3 > o.max_alignment_residual_ms) use[k] = false;
      }
      residual_sd = used > 2 ? std::sqrt(ss / (used - 2)) : std::nan("");
    }
    // Statistical: 2σ of the fit at a typical move; bias: what the method cannot see.
    const double statistical_ms = ex.clock.fitted && used > 2
                                      ? 2.0 * residual_sd / std::sqrt(used) * 1e3
                                      : o.max_alignment_residual_ms;
    ex.clock.uncertainty_ms = std::hypot(statistical_ms, o.motion_alignment_bias_ms);
  }

  // 3. The error trace on the controller clock, then the four parameters; twice when the
  // first pass finds a static scale factor between tip and scale (removed in the second).
  std::vector<TraceResult> results(work.size());
  const std::vector<MoveExtraction> before_traces = ex.moves;
  const auto trace_pass = [&](double scale_factor, bool with_sensitivity) {
    ex.moves = before_traces;
    results.assign(work.size(), TraceResult{});
    for (std::size_t k = 0; k < work.size(); ++k) {
      MoveExtraction& out = ex.moves[k];
      if (!out.reason.empty()) continue;
      Work& w = work[k];
      const MoveRecording& rec = *w.rec;
      // tracker → controller: with the session fit δ = a + b·t_controller, so
      // t_controller = (t_tracker + a) / (1 − b); without it this move's own constant offset.
      double delta = 0;
      if (two_clocks && !known_clock) {
        delta = ex.clock.fitted ? ex.clock.offset_s + ex.clock.drift * mid_time(w) : w.own_delta;
        out.alignment_residual_ms = (w.own_delta - delta) * 1e3;
        if (std::fabs(out.alignment_residual_ms) > o.max_alignment_residual_ms) {
          out.reason = fmt::format("clock alignment residual {:.3f} ms > {:g} ms",
                                   out.alignment_residual_ms,
                                   o.max_alignment_residual_ms);
          continue;
        }
      }
      if (known_clock) delta = clock_offset + clock_drift * mid_time(w);
      const auto to_controller = [&](double shift) {
        return [&, shift](double t_tracker) {
          if (rec.one_clock) return t_tracker;
          if (known_clock) return (t_tracker + clock_offset) / (1.0 - clock_drift);
          if (!ex.clock.fitted) return t_tracker + w.own_delta + shift;
          return (t_tracker + ex.clock.offset_s) / (1.0 - ex.clock.drift) + shift;
        };
      };
      out.clock_offset_ms = delta * 1e3;
      // The move's parameters with its clock shifted by `shift` [s].
      const auto trace = [&](double shift, TraceResult& result) {
        return error_parameters(w.fit,
                                rec,
                                w.st,
                                w.rest,
                                out.tip_rate_hz,
                                o.max_gap_ms,
                                scale_factor,
                                to_controller(shift),
                                result);
      };
      TraceResult& r = results[k];
      out.reason = trace(0.0, r);
      out.dropouts = r.dropouts;
      out.longest_gap_ms = r.longest_gap_ms;
      if (!out.reason.empty()) continue;
      out.row.mpe_um = r.e.mpe;
      out.row.rpe_um = r.e.rpe;
      out.row.mae_um = r.e.mae;
      out.row.rae_um = r.e.rae;
      out.ok = true;
      // How far the clock's uncertainty moves each parameter: the move extracted again with its
      // clock shifted by ± the uncertainty.
      if (with_sensitivity && two_clocks && !known_clock) {
        const std::array<double, 4> base = as_array(r.e);
        for (double sign : {-1.0, 1.0}) {
          TraceResult shifted;
          if (!trace(sign * ex.clock.uncertainty_ms * 1e-3, shifted).empty()) continue;
          const std::array<double, 4> moved = as_array(shifted.e);
          for (std::size_t p = 0; p < 4; ++p) {
            out.clock_sensitivity_um[p] =
                std::max(out.clock_sensitivity_um[p], std::fabs(moved[p] - base[p]));
          }
        }
      }
    }
  };
  // Pass 1 gives the plateaus for the static scale factor: tip − scale at rest in the dwell
  // against at rest before the move, per mm of the positioning (a tracker at an angle to the
  // axis reads cos θ of the travel). Pass 2 extracts with it removed.
  trace_pass(0.0, false);
  {
    // plateau = b + k·PD over the moves: b is what the stop leaves at rest whatever the
    // distance (friction, a hose's set), k the scale factor; PD must vary for k to be seen.
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, lo = 1e300, hi = -1e300;
    for (std::size_t k = 0; k < work.size(); ++k) {
      if (!ex.moves[k].ok || std::isnan(results[k].plateau_um)) continue;
      const double x = work[k].planned->settings.pd_mm * 1e3;  // µm
      const double y = results[k].plateau_um;
      n += 1;
      sx += x;
      sy += y;
      sxx += x * x;
      sxy += x * y;
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    const double det = n * sxx - sx * sx;
    if (n >= 3 && hi - lo >= 0.2 * (sx / n) && det > 0) {
      ex.scale_factor = (n * sxy - sx * sy) / det;
      ex.scale_factor_moves = static_cast<int>(n);
    }
    const bool removed = !std::isnan(ex.scale_factor) && std::fabs(ex.scale_factor) > 1e-6;
    trace_pass(removed ? ex.scale_factor : 0.0, true);
  }

  // 4. The campaign's checks: the clock's uncertainty against the budget, the scale factor, the
  // noise at rest and over the repeats.
  if (two_clocks && !known_clock) {
    const std::string worst = clock_budget_excess(ex, o);
    if (!worst.empty()) {
      const std::string message = fmt::format(
          "two clocks aligned from the motion alone: the alignment is uncertain by ±{:.3f} ms "
          "(a lag of the tip cannot be told from a clock offset), which moves {}: record a sync "
          "marker in both streams (docs/measurement.md, \"Sync\"), or pass the clock known from "
          "a sync event with --clock-offset-ms and --drift-ppm",
          ex.clock.uncertainty_ms,
          worst);
      if (!o.accept_clock_uncertainty) {
        ex.refusal = message + " (or --accept-clock-uncertainty to extract anyway)";
        return ex;
      }
      ex.warnings.push_back(message);
    }
  }
  if (!std::isnan(ex.scale_factor) && std::fabs(ex.scale_factor) * 1e6 > o.max_scale_factor_ppm) {
    ex.warnings.push_back(fmt::format(
        "the tip and the scale disagree on the positioning's length by {:.0f} ppm (the slope over "
        "PD of tip − scale at rest in the dwell, {} moves; limit {:g} ppm): a tracker not parallel "
        "to the axis (cosine error: {:.2f}°), its wavelength or unit, or the scale's own error. It "
        "was removed as a static error; align the tracker to the axis",
        ex.scale_factor * 1e6,
        ex.scale_factor_moves,
        o.max_scale_factor_ppm,
        std::acos(std::min(1.0, 1.0 + std::min(0.0, ex.scale_factor))) * 180 / M_PI));
  }
  std::vector<int> runs;
  runs.reserve(work.size());
  for (const Work& w : work) runs.push_back(w.planned != nullptr ? w.planned->run : 0);
  estimate_noise(ex, runs);
  return ex;
}

SessionRecording read_session_recording(const std::string& controller_path,
                                        const std::string& tracker_path,
                                        char axis) {
  const MoveRecording r = read_move_recording(controller_path, tracker_path, axis, 0);
  SessionRecording s;
  s.source = r.source;
  s.scale_t_s = r.scale_t_s;
  s.scale_mm = r.scale_mm;
  s.tip_t_s = r.tip_t_s;
  s.tip_mm = r.tip_mm;
  s.scale_sync_t_s = r.scale_sync_t_s;
  s.tip_sync_t_s = r.tip_sync_t_s;
  s.one_clock = r.one_clock;
  return s;
}

namespace {

/// The speeds of (t, x) on the grid t0 + k·dt, k < n (finite differences of the interpolated
/// positions).
std::vector<double> speeds_on_grid(const std::vector<double>& t,
                                   const std::vector<double>& x,
                                   double t0,
                                   double dt,
                                   std::size_t n) {
  std::vector<double> v(n, 0.0);
  double previous = interpolate(t, x, t0);
  for (std::size_t k = 1; k < n; ++k) {
    const double now = interpolate(t, x, t0 + static_cast<double>(k) * dt);
    v[k] = (now - previous) / dt;
    previous = now;
  }
  return v;
}

/// The lag L (tracker → controller) in [lo, hi] that maximises Σ v_scale(t) · v_tip(t − L),
/// searched on the grid step `dt`.
double best_lag(const SessionRecording& s, double lo, double hi, double dt) {
  // The first kCorrelationSpan_s of the log: enough moves to lock on, and a grid whose size
  // does not grow with the session (a long log costs no more than a short one).
  constexpr double kCorrelationSpan_s = 120.0;
  const double t0 = s.scale_t_s.front();
  const double span = std::min(s.scale_t_s.back() - t0, kCorrelationSpan_s);
  const auto n = static_cast<std::size_t>(span / dt);
  if (n < 4) return 0.0;
  const std::vector<double> vs = speeds_on_grid(s.scale_t_s, s.scale_mm, t0, dt, n);
  double best = lo, best_score = -1.0;
  for (double lag = lo; lag <= hi; lag += dt) {
    const std::vector<double> vt = speeds_on_grid(s.tip_t_s, s.tip_mm, t0 - lag, dt, n);
    double score = 0;
    for (std::size_t k = 0; k < n; ++k) score += vs[k] * vt[k];
    if (score > best_score) {
      best_score = score;
      best = lag;
    }
  }
  return best;
}

}  // namespace

SessionSplit split_session(const std::vector<PlannedMove>& plan,
                           const SessionRecording& session,
                           const ExtractOptions& o) {
  SessionSplit out;
  if (session.scale_t_s.size() < 2 || session.tip_t_s.size() < 2) {
    throw ConfigError(session.source + ": a session needs both streams");
  }
  if (!session.one_clock) {
    if (!o.known_clock)
      out.sync = sync_clock(session.scale_sync_t_s, session.tip_sync_t_s, session.source);
    if (o.known_clock) {
      out.coarse_offset_s = o.clock_offset_s;
    } else if (out.sync.fitted) {
      out.coarse_offset_s = out.sync.offset_s;
    } else {
      // Coarse on a 10 ms grid over ±5 s, then 1 ms around it.
      const double coarse = best_lag(session, -5.0, 5.0, 0.01);
      out.coarse_offset_s = best_lag(session, coarse - 0.02, coarse + 0.02, 0.001);
    }
  }
  const std::vector<double>& t = session.scale_t_s;
  const std::vector<double>& x = session.scale_mm;
  std::size_t cursor = 0;
  for (const PlannedMove& m : plan) {
    MoveRecording rec;
    rec.move_id = m.move_id;
    rec.one_clock = session.one_clock;
    rec.source = session.source;
    const double start = axis_value(m.start, m.axis);
    const double d = m.direction;
    const double tol = std::max(0.2, 0.01 * m.settings.pd_mm);
    // The timing checks below compare durations within one phase, which the dwell does not
    // change and the smoothing hardly does: an unknown timing is taken as none, and the
    // approach is looked for up to the longest dwell a controller may have.
    const bool dwell_known = !std::isnan(o.dwell_s);
    motion::ProbingMove move = dynamics::move_of(m.settings);
    move.dwell = dwell_known ? o.dwell_s : 0.0;
    move.smoothing = std::isnan(o.smoothing_s) ? 0.0 : o.smoothing_s;
    const double approach_search_s = dwell_known ? 1.0 : motion::MoveLimits::kMaxDwell;
    motion::MoveProfile profile;
    if (motion::MoveProfile::plan(move, profile) != Status::kOk) {
      rec.problem = "the planned move is not a valid profile";
      out.moves.push_back(rec);
      continue;
    }
    // At rest at the start (within tol for 20 ms), then half of PD towards the point.
    std::size_t i = cursor, found = t.size();
    while (i < t.size()) {
      if (std::fabs(x[i] - start) > tol) {
        ++i;
        continue;
      }
      std::size_t j = i;
      while (j < t.size() && std::fabs(x[j] - start) <= tol) ++j;
      if (j < t.size() && t[j - 1] - t[i] >= 0.02 && (x[j] - start) * d > 0) {
        std::size_t k = j;
        while (k < t.size() && (x[k] - start) * d < 0.5 * m.settings.pd_mm &&
               (x[k] - start) * d > -tol) {
          ++k;
        }
        if (k < t.size() && (x[k] - start) * d >= 0.5 * m.settings.pd_mm) {
          // It must be this move: the scale comes to rest at the pre-hit point (PD from the
          // start) in about the planned positioning time, not at another move's.
          const double prehit = start + d * m.settings.pd_mm;
          std::size_t e = k;
          while (e < t.size() && std::fabs(x[e] - prehit) > tol && (x[e] - start) * d > -tol &&
                 t[e] - t[j - 1] < 3.0 * profile.instants().positioning_end + 1.0) {
            ++e;
          }
          // The time from a quarter to three quarters of PD, against the profile's: servo lag
          // and the tolerance windows shift both ends alike.
          bool timing = false;
          if (e < t.size() && std::fabs(x[e] - prehit) <= tol) {
            const auto crossing_at = [&](double level, std::size_t from, std::size_t until) {
              for (std::size_t q = std::max<std::size_t>(from, 1); q <= until && q < t.size();
                   ++q) {
                const double a = (x[q - 1] - start) * d, b = (x[q] - start) * d;
                if (a < level && b >= level) {
                  return t[q - 1] + (level - a) / (b - a) * (t[q] - t[q - 1]);
                }
              }
              return std::nan("");
            };
            const double pd = m.settings.pd_mm, ad = m.settings.ad_mm;
            const motion::PhaseInstants& pi = profile.instants();
            const double took = crossing_at(0.75 * pd, j, e) - crossing_at(0.25 * pd, j, e);
            const double planned =
                profile_time_at(profile, 0.75 * pd) - profile_time_at(profile, 0.25 * pd);
            // And the approach: from a quarter to three quarters of AD after the pre-hit point.
            std::size_t until = e;
            while (until + 1 < t.size() &&
                   t[until] - t[e] < pi.touch - pi.positioning_end + approach_search_s) {
              ++until;
            }
            const double took_approach =
                crossing_at(pd + 0.75 * ad, e, until) - crossing_at(pd + 0.25 * ad, e, until);
            const double planned_approach =
                profile_time_at(profile, pd + 0.75 * ad, pi.approach_start, pi.touch) -
                profile_time_at(profile, pd + 0.25 * ad, pi.approach_start, pi.touch);
            timing = std::fabs(took - planned) <= 0.1 * planned + 0.02 &&
                     std::fabs(took_approach - planned_approach) <= 0.1 * planned_approach + 0.02;
          }
          if (timing) {
            found = j;
            break;
          }
        }
      }
      i = j;
    }
    if (found == t.size()) {
      rec.problem = fmt::format(
          "not found in the session's scale log after {:.3f} s (at rest at {} = {} mm, then {} "
          "mm towards the point)",
          cursor < t.size() ? t[cursor] : t.back(),
          m.axis,
          start,
          m.settings.pd_mm);
      out.moves.push_back(rec);
      continue;
    }
    // The rest before the move: back to where the scale came within tol of the start.
    std::size_t rest = found;
    while (rest > cursor && std::fabs(x[rest - 1] - start) <= tol) --rest;
    const double moves_at = t[found - 1];
    const double from = std::max(t[rest], moves_at - 0.25);
    // Up to 50 ms after the touch: found from the log when the dwell is unknown.
    double to = moves_at + profile.instants().touch + 0.05;
    if (!dwell_known) {
      std::size_t q = found;
      const double past = start + m.direction * (m.settings.pd_mm + m.settings.ad_mm);
      while (q < t.size() && (x[q] - past) * m.direction < 0) ++q;
      to = (q < t.size() ? t[q] : t.back()) + 0.05;
    }
    // …and no further than the furthest point along the motion: after it the machine retracts
    // (or, in a twin's session, the next move begins).
    {
      std::size_t furthest = found;
      for (std::size_t q = found; q < t.size() && t[q] <= to; ++q) {
        if ((x[q] - start) * m.direction > (x[furthest] - start) * m.direction) furthest = q;
      }
      to = std::min(to, t[furthest]);
    }
    for (std::size_t k = rest; k < t.size() && t[k] <= to; ++k) {
      if (t[k] < from) continue;
      rec.scale_t_s.push_back(t[k]);
      rec.scale_mm.push_back(x[k]);
      cursor = k;
    }
    for (std::size_t k = 0; k < session.tip_t_s.size(); ++k) {
      const double tc =
          out.sync.fitted ? (session.tip_t_s[k] + out.sync.offset_s) / (1.0 - out.sync.drift)
          : o.known_clock ? (session.tip_t_s[k] + o.clock_offset_s) / (1.0 - o.clock_drift)
                          : session.tip_t_s[k] + out.coarse_offset_s;
      if (tc < from || tc > to) continue;
      rec.tip_t_s.push_back(session.tip_t_s[k]);
      rec.tip_mm.push_back(session.tip_mm[k]);
    }
    out.moves.push_back(rec);
  }
  return out;
}

std::string format_extraction_report(const Extraction& ex) {
  std::string s =
      "move_id,status,mpe_um,rpe_um,mae_um,rae_um,start_s,profile_rms_um,clock_offset_ms,"
      "alignment_residual_ms,dropouts,longest_gap_ms,tip_rate_hz,dwell_s,smoothing_s,"
      "travel_ratio,rest_noise_um,clock_mpe_um,clock_rpe_um,clock_mae_um,clock_rae_um,reason\n";
  for (const MoveExtraction& m : ex.moves) {
    std::string reason = m.reason;
    std::replace(reason.begin(), reason.end(), ',', ';');
    std::replace(reason.begin(), reason.end(), '\n', ' ');
    s += fmt::format(
        "{},{},{:.4f},{:.4f},{:.4f},{:.4f},{:.6f},{:.3f},{:.4f},{:.4f},{},{:.2f},{:.0f},{:.4f},"
        "{:.4f},{:.6f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{}\n",
        m.move_id,
        m.ok ? "ok" : "skipped",
        m.row.mpe_um,
        m.row.rpe_um,
        m.row.mae_um,
        m.row.rae_um,
        m.start_s,
        m.profile_rms_um,
        m.clock_offset_ms,
        m.alignment_residual_ms,
        m.dropouts,
        m.longest_gap_ms,
        m.tip_rate_hz,
        m.dwell_s,
        m.smoothing_s,
        m.travel_ratio,
        m.rest_noise_um,
        m.clock_sensitivity_um[0],
        m.clock_sensitivity_um[1],
        m.clock_sensitivity_um[2],
        m.clock_sensitivity_um[3],
        reason);
  }
  return s;
}

std::string format_extraction_summary(const Extraction& ex) {
  using nlohmann::ordered_json;
  const auto number = [](double v) { return std::isfinite(v) ? ordered_json(v) : ordered_json(); };
  ordered_json j;
  int ok = 0;
  std::map<std::string, std::pair<int, std::string>> kinds;
  for (const MoveExtraction& m : ex.moves) {
    if (m.ok) {
      ++ok;
      continue;
    }
    auto& k = kinds[reason_kind(m.reason)];
    if (k.first++ == 0) k.second = m.reason;
  }
  j["format"] = kSummaryFormat;
  j["axis"] = ex.axis.empty() ? ordered_json() : ordered_json(ex.axis);
  j["moves"] = ex.moves.size();
  j["extracted"] = ok;
  ordered_json skipped = ordered_json::array();
  for (const auto& [kind, k] : kinds) {
    skipped.push_back({{"count", k.first}, {"reason", kind}, {"example", k.second}});
  }
  j["skipped"] = skipped;
  j["controller_timing"] = {{"dwell_s", number(ex.timing.dwell_s)},
                            {"dwell_from", ex.timing.dwell_given ? "given" : "measured"},
                            {"smoothing_s", number(ex.timing.smoothing_s)},
                            {"smoothing_from", ex.timing.smoothing_given ? "given" : "measured"},
                            {"measured_dwell_s", number(ex.timing.measured_dwell_s)},
                            {"measured_smoothing_s", number(ex.timing.measured_smoothing_s)},
                            {"measured_moves", ex.timing.measured_moves}};
  j["clock"] = {{"source", ex.clock.source},
                {"fitted", ex.clock.fitted},
                {"offset_ms", ex.clock.offset_s * 1e3},
                {"drift_ppm", ex.clock.drift * 1e6},
                {"sync_markers", ex.clock.sync_markers},
                {"sync_residual_ms", ex.clock.sync_residual_ms},
                {"uncertainty_ms", ex.clock.uncertainty_ms}};
  j["travel_ratio"] = number(ex.travel_ratio);
  j["scale_factor_ppm"] = number(ex.scale_factor * 1e6);
  j["scale_factor_moves"] = ex.scale_factor_moves;
  ordered_json noise;
  noise["rest_um"] = number(ex.noise.rest_um);
  noise["repeat_dof"] = ex.noise.repeat_dof;
  for (std::size_t p = 0; p < 4; ++p) {
    noise[std::string(kParameterLabels[p])] = {{"repeat_sd_um", number(ex.noise.repeat_sd_um[p])},
                                               {"table1_sd_um", paper::kTable1Std[p]}};
  }
  j["noise"] = noise;
  j["refusal"] = ex.refusal;
  j["warnings"] = ex.warnings;
  return j.dump(2) + "\n";
}

CampaignSummary parse_extraction_summary(const std::string& text, const std::string& source) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw ConfigError(source + ": not JSON (" + e.what() + ")");
  }
  const auto fail = [&source](const std::string& what) {
    throw ConfigError(source + ": " + what + " (expected the OUTPUT.summary.json that " +
                      "cmmcomp-measure extract writes)");
  };
  if (!j.is_object() || j.value("format", std::string()) != kSummaryFormat) {
    fail("no \"format\": \"" + std::string(kSummaryFormat) + "\"");
  }
  const auto number = [&](const nlohmann::json& obj, const char* key, const std::string& at) {
    const auto it = obj.find(key);
    if (it == obj.end()) fail("no key '" + at + key + "'");
    if (it->is_null()) return std::nan("");
    if (!it->is_number()) fail("'" + at + key + "' is not a number");
    const double v = it->get<double>();
    if (!std::isfinite(v)) fail("'" + at + key + "' is not finite");
    return v;
  };
  CampaignSummary s;
  s.source = source;
  if (j.contains("axis") && j["axis"].is_string()) s.axis = j["axis"].get<std::string>();
  if (!j.contains("refusal") || !j["refusal"].is_string()) fail("no key 'refusal'");
  s.refusal = j["refusal"].get<std::string>();
  if (!j.contains("extracted") || !j["extracted"].is_number_integer()) fail("no key 'extracted'");
  s.extracted = j["extracted"].get<int>();
  if (!j.contains("controller_timing") || !j["controller_timing"].is_object()) {
    fail("no object 'controller_timing'");
  }
  s.dwell_s = number(j["controller_timing"], "dwell_s", "controller_timing.");
  s.smoothing_s = number(j["controller_timing"], "smoothing_s", "controller_timing.");
  if (!j.contains("noise") || !j["noise"].is_object()) fail("no object 'noise'");
  for (std::size_t p = 0; p < 4; ++p) {
    const std::string label = kParameterLabels[p];
    if (!j["noise"].contains(label) || !j["noise"][label].is_object()) {
      fail("no object 'noise." + label + "'");
    }
    s.repeat_sd_um[p] = number(j["noise"][label], "repeat_sd_um", "noise." + label + ".");
  }
  return s;
}

CampaignSummary read_extraction_summary(const std::string& path) {
  return parse_extraction_summary(io::read_file_bounded(path, "campaign summary", 1 << 20), path);
}

io::TrainingConditions campaign_conditions(const std::vector<CampaignSummary>& campaigns,
                                           double timing_tolerance_s) {
  io::TrainingConditions c;
  if (campaigns.empty()) return c;
  const CampaignSummary& first = campaigns.front();
  std::array<double, 4> pooled{};
  bool noise_known = true;
  for (const CampaignSummary& s : campaigns) {
    if (!s.refusal.empty()) {
      throw ConfigError(s.source + ": the campaign was refused (" + s.refusal +
                        "): a model must not be trained on it");
    }
    const auto agree = [&](double a, double b, const char* what) {
      if (std::isfinite(a) != std::isfinite(b) ||
          (std::isfinite(a) && std::abs(a - b) > timing_tolerance_s)) {
        throw ConfigError(fmt::format(
            "{}: controller {} {} s, but {} says {} s: one model is trained at one controller "
            "setting (train one model per setting)",
            s.source,
            what,
            b,
            first.source,
            a));
      }
    };
    agree(first.dwell_s, s.dwell_s, "dwell");
    agree(first.smoothing_s, s.smoothing_s, "smoothing");
    if (s.axis != first.axis) {
      throw ConfigError(s.source + ": axis '" + s.axis + "', but " + first.source + " says '" +
                        first.axis + "': one model serves one axis");
    }
    for (std::size_t p = 0; p < 4; ++p) {
      noise_known = noise_known && std::isfinite(s.repeat_sd_um[p]);
      if (noise_known) pooled[p] += s.repeat_sd_um[p] * s.repeat_sd_um[p];
    }
  }
  if (std::isfinite(first.dwell_s)) c.dwell_s = first.dwell_s;
  if (std::isfinite(first.smoothing_s)) c.smoothing_s = first.smoothing_s;
  c.axis = first.axis;
  if (noise_known) {
    for (double v : pooled) {
      c.noise_floor.push_back(std::sqrt(v / static_cast<double>(campaigns.size())));
    }
  }
  return c;
}

std::string campaign_plot_script(const Extraction& ex, const std::string& png_path) {
  int ok = 0;
  std::map<std::string, int> kinds;
  for (const MoveExtraction& m : ex.moves) {
    if (m.ok) {
      ++ok;
    } else {
      ++kinds[reason_kind(m.reason).substr(0, 60)];
    }
  }
  const auto quoted = [](std::string text) {
    for (char& c : text) {
      if (c == '"' || c == '\\') c = '\'';
    }
    return "\"" + text + "\"";
  };
  std::string g = "set terminal pngcairo size 1400,1000 noenhanced font ',10'\nset output " +
                  quoted(png_path) + "\n";
  g += "$moves << EOD\n";
  for (std::size_t k = 0; k < ex.moves.size(); ++k) {
    const MoveExtraction& m = ex.moves[k];
    g += fmt::format(
        "{} {} {} {}\n",
        k + 1,
        std::isnan(m.dwell_s) ? std::string("NaN") : fmt::format("{:.6f}", m.dwell_s),
        std::isnan(m.smoothing_s) ? std::string("NaN") : fmt::format("{:.6f}", m.smoothing_s),
        m.ok ? 1 : 0);
  }
  g += "EOD\n$noise << EOD\n";
  for (std::size_t p = 0; p < 4; ++p) {
    const double sd = ex.noise.repeat_sd_um[p];
    g += fmt::format("{} {} {} {}\n",
                     p,
                     kParameterLabels[p],
                     std::isnan(sd) ? std::string("NaN") : fmt::format("{:.4f}", sd),
                     paper::kTable1Std[p]);
  }
  g += "EOD\n$skips << EOD\n";
  g += fmt::format("0 {} {}\n", quoted("extracted"), ok);
  int i = 1;
  for (const auto& [kind, n] : kinds) g += fmt::format("{} {} {}\n", i++, quoted(kind), n);
  g += "EOD\n";
  const std::string verdict = !ex.refusal.empty() ? "REFUSED: " + ex.refusal.substr(0, 110)
                              : !ex.warnings.empty()
                                  ? fmt::format("{} warning(s)", ex.warnings.size())
                                  : std::string("clean");
  g += "set multiplot layout 2,2 title " +
       quoted(fmt::format("campaign: {} of {} moves extracted; clock: {}; {}",
                          ok,
                          ex.moves.size(),
                          ex.clock.source.empty() ? "-" : ex.clock.source,
                          verdict)) +
       "\nset grid\nset key outside bottom center horizontal\n";
  const auto timing = [&](const char* what, int column, double used) {
    return fmt::format(
        "set title '{} measured per move [s]'\nset xlabel 'move (plan order)'\nset ylabel 's'\n"
        "plot $moves using 1:{} with points pt 7 ps 0.6 title 'measured', {} with lines lw 2 "
        "title 'used by the run ({:.4f} s)'\n",
        what,
        column,
        std::isnan(used) ? 0.0 : used,
        std::isnan(used) ? 0.0 : used);
  };
  g += timing("controller dwell", 2, ex.timing.dwell_s);
  g += timing("controller smoothing", 3, ex.timing.smoothing_s);
  g += fmt::format(
      "set title 'noise: repeat sigma per parameter [µm] ({} degrees of freedom)'\n"
      "set xlabel ''\nset ylabel 'µm'\nset style data histograms\nset style fill solid 0.6\n"
      "set boxwidth 0.35\nset yrange [0:*]\n"
      "plot $noise using ($1-0.2):3:xtic(2) with boxes title 'this campaign', "
      "$noise using ($1+0.2):4 with boxes title 'paper Table 1', "
      "$noise using 1:(1.5*$4) with points pt 2 ps 2 title 'warning limit (1.5 x Table 1)'\n",
      ex.noise.repeat_dof);
  g += fmt::format(
      "set title 'moves by outcome'\nset ylabel 'moves'\nset xtics rotate by -20\n"
      "set xrange [-0.8:{}]\nset boxwidth 0.6\nplot $skips using 1:3:xtic(2) with boxes notitle\n",
      static_cast<double>(kinds.size()) + 0.8);
  g += "unset multiplot\n";
  return g;
}

}  // namespace cmmcomp::measure

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
#include <cmmcomp/motion/move_profile.hpp>
#include <map>

#include "csv_reader.hpp"

namespace cmmcomp::measure {
namespace {

constexpr std::uintmax_t kMaxRecordingBytes = 512u << 20;

/// Reads the columns `names` of a recording; times strictly increasing.
std::vector<std::vector<double>> read_columns(const std::string& path,
                                              const std::vector<std::string>& names) {
  const detail::CsvTable t =
      detail::parse_csv(io::read_file_bounded(path, "recording", kMaxRecordingBytes), path);
  std::vector<std::size_t> idx;
  for (const std::string& n : names) idx.push_back(t.require(n));
  std::vector<std::vector<double>> cols(names.size());
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    for (std::size_t c = 0; c < idx.size(); ++c) cols[c].push_back(t.number(r, idx[c]));
    if (r > 0 && !(cols[0][r] > cols[0][r - 1])) {
      throw ConfigError(t.where(r) + ": column '" + names[0] + "': time does not increase");
    }
  }
  if (t.rows.size() < 2) throw ConfigError(path + ": fewer than two samples");
  return cols;
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

/// Fits start time t0 and offset c so that s(t) ≈ c + p(t − t0), over the move.
std::string fit_profile(MoveFit& f, double max_rms_um) {
  const motion::PhaseInstants& in = f.profile.instants();
  const double half = 0.5 * f.profile.sample(in.positioning_end).position * 1e3;
  const double s0 = f.ss.front();
  const double tc = crossing(f.ts, f.ss, s0 + half);
  if (std::isnan(tc)) return "the scale never moves half the planned PD: not this move";
  f.t0 = tc - profile_time_at(f.profile, half);
  f.c = s0;
  for (int iter = 0; iter < 20; ++iter) {
    double a = 0, b = 0, cc = 0, u = 0, v = 0;
    for (std::size_t i = 0; i < f.ts.size(); ++i) {
      const double tau = f.ts[i] - f.t0;
      if (tau < -0.05 || tau > in.touch) continue;
      const motion::MotionState m = f.profile.sample(tau);
      const double r = f.ss[i] - f.c - m.position * 1e3;
      const double jc = 1.0, jt = -m.velocity * 1e3;  // ∂model/∂c, ∂model/∂t0
      a += jc * jc;
      b += jc * jt;
      cc += jt * jt;
      u += jc * r;
      v += jt * r;
    }
    double dc = 0, dt = 0;
    if (!solve2(a, b, cc, u, v, dc, dt)) return "the scale trace does not cover the move";
    f.c += dc;
    f.t0 += dt;
    if (std::fabs(dt) < 1e-12 && std::fabs(dc) < 1e-9) break;
  }
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < f.ts.size(); ++i) {
    const double tau = f.ts[i] - f.t0;
    if (tau < 0 || tau > in.touch) continue;
    const double r = f.ss[i] - f.c - f.profile.sample(tau).position * 1e3;
    sum += r * r;
    ++n;
  }
  f.rms_um = n > 0 ? std::sqrt(sum / n) * 1e3 : 0.0;
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

}  // namespace

MoveRecording read_move_recording(const std::string& controller_path,
                                  const std::string& tracker_path,
                                  char axis,
                                  int move_id) {
  const std::string a(1, axis);
  MoveRecording r;
  r.move_id = move_id;
  if (tracker_path.empty()) {
    auto cols = read_columns(controller_path, {"t_s", a + "_scale_mm", a + "_tip_mm"});
    r.scale_t_s = cols[0];
    r.scale_mm = std::move(cols[1]);
    r.tip_t_s = std::move(cols[0]);
    r.tip_mm = std::move(cols[2]);
    r.one_clock = true;
    r.source = controller_path;
  } else {
    auto c = read_columns(controller_path, {"t_s", a + "_scale_mm"});
    auto t = read_columns(tracker_path, {"t_s", a + "_tip_mm"});
    r.scale_t_s = std::move(c[0]);
    r.scale_mm = std::move(c[1]);
    r.tip_t_s = std::move(t[0]);
    r.tip_mm = std::move(t[1]);
    r.one_clock = false;
    r.source = controller_path + " + " + tracker_path;
  }
  return r;
}

std::vector<DatasetRow> Extraction::rows() const {
  std::vector<DatasetRow> out;
  for (const MoveExtraction& m : moves) {
    if (m.ok) out.push_back(m.row);
  }
  return out;
}

Extraction extract_moves(const std::vector<PlannedMove>& plan,
                         const std::vector<MoveRecording>& recordings,
                         const ExtractOptions& o) {
  std::map<int, const PlannedMove*> by_id;
  for (const PlannedMove& m : plan) by_id[m.move_id] = &m;

  struct Work {
    MoveFit fit;
    const PlannedMove* planned = nullptr;
    const MoveRecording* rec = nullptr;
    std::vector<double> st;  ///< tip along the motion [mm]
    double rest = 0;         ///< tip − scale at rest before the move [mm]
    double own_delta = std::nan("");
  };
  // A move's own offset is measured over its positioning: it belongs to the middle of it.
  const auto mid_time = [](const Work& w) {
    return w.fit.t0 + 0.5 * w.fit.profile.instants().positioning_end;
  };
  Extraction ex;
  std::vector<Work> work(recordings.size());
  ex.moves.resize(recordings.size());

  // 1. The commanded profile of each move, fitted to its scale trace.
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
    motion::ProbingMove move = dynamics::move_of(w.planned->settings);
    move.dwell = o.dwell_s;
    move.smoothing = o.smoothing_s;
    if (motion::MoveProfile::plan(move, w.fit.profile) != Status::kOk) {
      out.reason = "the planned move is not a valid profile";
      continue;
    }
    const double d = w.planned->direction;
    const double start = axis_value(w.planned->start, w.planned->axis);
    w.fit.ts = rec.scale_t_s;
    for (double x : rec.scale_mm) w.fit.ss.push_back((x - start) * d);
    for (double x : rec.tip_mm) w.st.push_back((x - start) * d);
    out.reason = fit_profile(w.fit, o.max_profile_rms_um);
    out.profile_rms_um = w.fit.rms_um;
    out.start_s = w.fit.t0;
    out.tip_rate_hz = 1.0 / median_step(rec.tip_t_s);
    if (!out.reason.empty()) continue;
    // The tip's rest offset: its mean over the samples at rest before the move (tracker frame
    // and scale zero differ; the twin and the paper count e from the machine at rest).
    // The tip's rest offset, tip − scale over the samples at rest before the move (a tracker's
    // frame and the scale's zero differ; the twin and the paper count e from the machine at rest).
    double sum = 0;
    int n = 0;
    if (rec.one_clock) {
      for (std::size_t i = 0; i < rec.tip_t_s.size() && rec.tip_t_s[i] <= w.fit.t0 + 1e-9; ++i) {
        sum += w.st[i] - interpolate(w.fit.ts, w.fit.ss, rec.tip_t_s[i]);
        ++n;
      }
    } else {
      // Both streams at rest: up to 50 ms before the fitted start, the tracker's samples placed
      // on the controller clock by the half-PD crossings (good to a millisecond).
      const double half =
          0.5 * w.fit.profile.sample(w.fit.profile.instants().positioning_end).position * 1e3;
      const double tip_half = crossing(rec.tip_t_s, w.st, w.st.front() + half);
      const double coarse = w.fit.t0 + profile_time_at(w.fit.profile, half) - tip_half;
      const double rest_end = w.fit.t0 - 0.05;
      for (std::size_t i = 0; i < rec.tip_t_s.size() && rec.tip_t_s[i] + coarse <= rest_end; ++i) {
        sum += w.st[i];
        ++n;
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
    if (!rec.one_clock && !o.known_clock) {
      w.own_delta = own_offset(w.fit, rec.tip_t_s, w.st, w.rest);
      if (std::isnan(w.own_delta)) out.reason = "the tip trace cannot be aligned to the scale";
    }
  }

  // 2. The session's clock: offset + drift over every aligned move (two passes, the second
  // without moves whose offset is off the first fit by more than the limit).
  if (o.known_clock) {
    ex.clock.fitted = true;
    ex.clock.offset_s = o.clock_offset_s;
    ex.clock.drift = o.clock_drift;
  } else if (!recordings.empty() && !recordings.front().one_clock) {
    std::vector<bool> use(work.size());
    for (std::size_t k = 0; k < work.size(); ++k) use[k] = ex.moves[k].reason.empty();
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
      for (std::size_t k = 0; k < work.size(); ++k) {
        if (!use[k]) continue;
        const double r =
            work[k].own_delta - (ex.clock.offset_s + ex.clock.drift * mid_time(work[k]));
        if (std::fabs(r) * 1e3 > o.max_alignment_residual_ms) use[k] = false;
      }
    }
  }

  // 3. The error trace on the controller clock, then the four parameters.
  for (std::size_t k = 0; k < work.size(); ++k) {
    MoveExtraction& out = ex.moves[k];
    if (!out.reason.empty()) continue;
    Work& w = work[k];
    const MoveRecording& rec = *w.rec;
    const motion::PhaseInstants& in = w.fit.profile.instants();
    // tracker → controller: with the session fit δ = a + b·t_controller, so
    // t_controller = (t_tracker + a) / (1 − b); without it this move's own constant offset.
    double delta = 0;
    if (!rec.one_clock && !o.known_clock) {
      delta = ex.clock.fitted ? ex.clock.offset_s + ex.clock.drift * mid_time(w) : w.own_delta;
      out.alignment_residual_ms = (w.own_delta - delta) * 1e3;
      if (std::fabs(out.alignment_residual_ms) > o.max_alignment_residual_ms) {
        out.reason = fmt::format("clock alignment residual {:.3f} ms > {:g} ms",
                                 out.alignment_residual_ms,
                                 o.max_alignment_residual_ms);
        continue;
      }
    }
    if (o.known_clock) delta = o.clock_offset_s + o.clock_drift * mid_time(w);
    const auto to_controller = [&](double t_tracker) {
      if (rec.one_clock) return t_tracker;
      if (!ex.clock.fitted) return t_tracker + w.own_delta;
      return (t_tracker + ex.clock.offset_s) / (1.0 - ex.clock.drift);
    };
    out.clock_offset_ms = delta * 1e3;
    std::vector<double> time, error;
    for (std::size_t i = 0; i < rec.tip_t_s.size(); ++i) {
      const double t = to_controller(rec.tip_t_s[i]);
      const double tau = t - w.fit.t0;
      if (tau < -0.5 || tau > in.touch + 0.5) continue;
      if (t < w.fit.ts.front() || t > w.fit.ts.back()) continue;
      time.push_back(tau);
      error.push_back((w.st[i] - w.rest - interpolate(w.fit.ts, w.fit.ss, t)) * 1e3);
    }
    // Dropouts: gaps longer than 1.5 sample steps are bridged by interpolation and counted;
    // one longer than the limit inside [0, touch] skips the move (it may hide a maximum).
    const double step = 1.0 / out.tip_rate_hz;
    const double limit = std::max(o.max_gap_ms * 1e-3, 3.0 * step);
    for (std::size_t i = 1; i < time.size(); ++i) {
      const double gap = time[i] - time[i - 1];
      if (gap > 1.5 * step) {
        ++out.dropouts;
        out.longest_gap_ms = std::max(out.longest_gap_ms, gap * 1e3);
        if (gap > limit && time[i] > 0 && time[i - 1] < in.touch) {
          out.reason = fmt::format("a tracker dropout of {:.1f} ms at {:.3f}–{:.3f} s of the move",
                                   gap * 1e3,
                                   time[i - 1],
                                   time[i]);
        }
      }
    }
    if (!out.reason.empty()) continue;
    errors::DynamicErrors e;
    const errors::TraceView view{time.data(), error.data(), time.size()};
    const Status s = errors::extract_dynamic_errors(view, in, 1, e);
    if (s == Status::kTraceTooShort) {
      out.reason = "the tip recording does not cover the move from its start to the touch";
      continue;
    }
    if (s != Status::kOk) {
      out.reason = "the error trace is not valid";
      continue;
    }
    out.row.mpe_um = e.mpe;
    out.row.rpe_um = e.rpe;
    out.row.mae_um = e.mae;
    out.row.rae_um = e.rae;
    out.ok = true;
  }
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
  const double t0 = s.scale_t_s.front();
  const auto n = static_cast<std::size_t>((s.scale_t_s.back() - t0) / dt);
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
    if (o.known_clock) {
      out.coarse_offset_s = o.clock_offset_s;
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
    motion::ProbingMove move = dynamics::move_of(m.settings);
    move.dwell = o.dwell_s;
    move.smoothing = o.smoothing_s;
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
            while (until + 1 < t.size() && t[until] - t[e] < pi.touch - pi.positioning_end + 1.0) {
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
    const double to = moves_at + profile.instants().touch + 0.05;
    for (std::size_t k = rest; k < t.size() && t[k] <= to; ++k) {
      if (t[k] < from) continue;
      rec.scale_t_s.push_back(t[k]);
      rec.scale_mm.push_back(x[k]);
      cursor = k;
    }
    for (std::size_t k = 0; k < session.tip_t_s.size(); ++k) {
      const double tc = session.tip_t_s[k] + out.coarse_offset_s;
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
      "alignment_residual_ms,dropouts,longest_gap_ms,tip_rate_hz,reason\n";
  for (const MoveExtraction& m : ex.moves) {
    std::string reason = m.reason;
    std::replace(reason.begin(), reason.end(), ',', ';');
    s += fmt::format(
        "{},{},{:.4f},{:.4f},{:.4f},{:.4f},{:.6f},{:.3f},{:.4f},{:.4f},{},{:.2f},{:.0f},{}\n",
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
        reason);
  }
  return s;
}

}  // namespace cmmcomp::measure

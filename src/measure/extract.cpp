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

double axis_value(const Vec3& p, char axis) { return axis == 'x' ? p.x : axis == 'y' ? p.y : p.z; }

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

/// The commanded time at which the profile reaches `level` [mm] (bisection on the monotone
/// positioning phase).
double profile_time_at(const motion::MoveProfile& p, double level_mm) {
  double lo = 0.0, hi = p.instants().positioning_end;
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

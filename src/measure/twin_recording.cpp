// SPDX-License-Identifier: MIT
/// @file A measurement campaign on the twin (docs/measurement.md, "Recordings from the twin").
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cmmcomp/detail/splitmix64.hpp>
#include <cmmcomp/dynamics/dataset.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/measure/twin_recording.hpp>
#include <utility>

namespace cmmcomp::measure {
namespace {

/// A twin recording goes on past the touch by max(kPastTouchMin, kPastTouchShare · AV) of
/// approach [m, s].
constexpr double kPastTouchMin = 1e-3;
constexpr double kPastTouchShare = 0.05;

/// Linear interpolation in the twin's trace (sampled at 20 kHz plus its kinks and extrema, so
/// the interpolation error is ~1e-5 of the signal). Before the move: at rest at 0.
struct Trace {
  std::vector<double> t, scale, tip;  // [s], [mm] along the motion
  void at(double time, double& s, double& p) const {
    if (time <= t.front()) {
      s = scale.front();
      p = tip.front();
      return;
    }
    const auto it = std::upper_bound(t.begin(), t.end(), time);
    if (it == t.end()) {
      s = scale.back();
      p = tip.back();
      return;
    }
    const std::size_t i = static_cast<std::size_t>(it - t.begin()) - 1;
    const double w = (time - t[i]) / (t[i + 1] - t[i]);
    s = scale[i] + w * (scale[i + 1] - scale[i]);
    p = tip[i] + w * (tip[i + 1] - tip[i]);
  }
};

/// 1/f noise: six first-order low-passed white noises one decade apart (0.01 Hz … 1 kHz
/// corners), equal variance each, so the sum has a ~1/f spectrum over the band of a move.
struct PinkNoise {
  std::array<double, 6> state{};
  double sigma = 0;
  double draw(cmmcomp::detail::SplitMix64& rng, double dt) {
    double sum = 0;
    for (std::size_t k = 0; k < state.size(); ++k) {
      const double corner_hz = 0.01 * std::pow(10.0, static_cast<double>(k));
      const double a = std::exp(-2.0 * M_PI * corner_hz * dt);
      // Stationary variance σ²/6 for each: innovation σ_k² = σ²/6 · (1 − a²).
      state[k] = a * state[k] + std::sqrt((1 - a * a) / 6.0) * sigma * rng.normal();
      sum += state[k];
    }
    return sum;
  }
};

/// Marks the sample of (t, x) at time `at` as a sync marker and returns its time: a sample
/// within 1 µs of it is that sample (times are written to 0.1 µs); otherwise a row with
/// `value()` is inserted in time order.
template <typename Value>
double mark_sync(std::vector<double>& t, std::vector<double>& x, double at, Value value) {
  const auto near = std::lower_bound(t.begin(), t.end(), at - 1e-6);
  if (near != t.end() && std::fabs(*near - at) <= 1e-6) return *near;
  const auto it = std::lower_bound(t.begin(), t.end(), at);
  x.insert(x.begin() + (it - t.begin()), value());
  t.insert(it, at);
  return at;
}

}  // namespace

std::string one_clock_file(int move_id) { return fmt::format("move-{:04d}.csv", move_id); }
std::string controller_file(int move_id) {
  return fmt::format("move-{:04d}.controller.csv", move_id);
}
std::string tracker_file(int move_id) { return fmt::format("move-{:04d}.tracker.csv", move_id); }

std::vector<TwinMove> record_on_twin(const dynamics::Machine& machine,
                                     const std::vector<PlannedMove>& plan,
                                     const RecordingSetup& setup) {
  if (!(setup.controller_rate_hz >= 10 && setup.controller_rate_hz <= 1e5) ||
      !(setup.tracker_rate_hz >= 10 && setup.tracker_rate_hz <= 1e5)) {
    throw ConfigError("recording rates must be 10 Hz .. 100 kHz");
  }
  if (!(setup.rest_s >= 0.01 && setup.rest_s <= 60) || !(std::fabs(setup.drift) < 0.01) ||
      !(setup.white_noise_um >= 0) || !(setup.pink_noise_um >= 0) ||
      !(setup.dropout_fraction >= 0 && setup.dropout_fraction < 0.5) ||
      !(setup.tracker_jitter >= 0 && setup.tracker_jitter <= 0.45)) {
    throw ConfigError(
        "recording setup out of range (rest 0.01–60 s, |drift| < 1 %, noise ≥ 0, "
        "dropouts < 50 %, tracker jitter 0–0.45 of a period)");
  }
  if (setup.sync && !setup.two_clocks) {
    throw ConfigError("sync markers need two clocks (one clock needs no sync)");
  }
  if (setup.tracker_jitter > 0 && !setup.two_clocks) {
    throw ConfigError("tracker jitter needs two clocks (one clock samples the tip with the scale)");
  }
  dynamics::SimulationOptions exact_options;
  dynamics::SimulationOptions trace_options;
  trace_options.record_trace = true;
  trace_options.trace_rate_hz = 20000.0;
  dynamics::BridgeSimulator exact_sim(machine, exact_options);
  // The trace runs on past the touch (below): its controller takes the longer approach, which is
  // the recording's, not a setting anybody chose; exact_sim checks the planned move.
  dynamics::Machine trace_machine = machine;
  motion::SettingRange& ad = trace_machine.capabilities[motion::Setting::kApproachDistance];
  ad.max = std::min(
      motion::MoveLimits::kMaxDistance,
      ad.max + std::max(kPastTouchMin,
                        kPastTouchShare *
                            trace_machine.capabilities[motion::Setting::kApproachSpeed].max));
  dynamics::BridgeSimulator trace_sim(trace_machine, trace_options);
  cmmcomp::detail::SplitMix64 rng{setup.seed ^ 0x7472616365725f6eULL};
  PinkNoise pink;
  pink.sigma = setup.pink_noise_um * 1e-3;

  std::vector<TwinMove> out;
  double session = 0.0;  // controller time of this move's recording start
  for (const PlannedMove& m : plan) {
    const motion::ProbingMove move = dynamics::move_of(m.settings);
    const double y_m = m.settings.y_mm * 1e-3;
    TwinMove tm;
    const dynamics::SimulationResult exact = exact_sim.simulate(move, y_m);
    tm.exact_um = exact.errors_um;
    // The recording goes on past the touch, as a real one does: the same move with a longer
    // approach has the same motion up to the touch (the approach never decelerates).
    motion::ProbingMove longer = move;
    longer.approach_distance += std::max(kPastTouchMin, kPastTouchShare * move.approach_speed);
    const dynamics::SimulationResult run = trace_sim.simulate(longer, y_m);
    Trace tr;
    for (const dynamics::TraceSample& s : run.trace) {
      tr.t.push_back(s.t_s);
      tr.scale.push_back(s.scale_mm);
      tr.tip.push_back(s.tip_mm);
    }
    const double touch = exact.instants.touch;
    const double start = session + setup.rest_s;  // the move starts after the rest
    const double end = start + touch + 0.02;
    const double x0 = axis_value(m.start, m.axis);
    const double d = m.direction;

    MoveRecording& rec = tm.recording;
    rec.move_id = m.move_id;
    rec.one_clock = !setup.two_clocks;
    rec.source = "twin";
    const double dtc = 1.0 / setup.controller_rate_hz;
    for (double t = std::ceil(session / dtc) * dtc; t <= end; t += dtc) {
      double s = 0, p = 0;
      tr.at(t - start, s, p);
      rec.scale_t_s.push_back(t);
      rec.scale_mm.push_back(x0 + d * s);
      if (rec.one_clock) rec.tip_mm.push_back(x0 + d * p);
    }
    if (rec.one_clock) rec.tip_t_s = rec.scale_t_s;
    double trigger = session + std::min(0.1, 0.5 * setup.rest_s);  // controller clock
    const auto twin_at_trigger = [&] {
      double s = 0, p = 0;
      tr.at(trigger - start, s, p);
      return std::pair{x0 + d * s, x0 + d * p};
    };
    if (setup.sync && !rec.one_clock) {
      // The controller's marker row, at the trigger's instant.
      trigger =
          mark_sync(rec.scale_t_s, rec.scale_mm, trigger, [&] { return twin_at_trigger().first; });
      rec.scale_sync_t_s.push_back(trigger);
    }
    if (!rec.one_clock) {
      // The tracker's clock: t_t = t_c·(1 − drift) − offset, sampled evenly on its own clock.
      const double dtt = 1.0 / setup.tracker_rate_hz;
      const auto tracker_time = [&](double tc) {
        return tc * (1.0 - setup.drift) - setup.clock_offset_s;
      };
      for (double nominal = std::ceil(tracker_time(session) / dtt) * dtt;
           nominal <= tracker_time(end);
           nominal += dtt) {
        // Uneven sampling: the sample is taken when its time stamp says, off the even grid
        // (no draw without jitter, so the other recordings keep their noise).
        const double tt = setup.tracker_jitter > 0
                              ? nominal + (2.0 * rng.uniform() - 1.0) * setup.tracker_jitter * dtt
                              : nominal;
        const double tc = (tt + setup.clock_offset_s) / (1.0 - setup.drift);
        double s = 0, p = 0;
        tr.at(tc - start, s, p);
        rec.tip_t_s.push_back(tt);
        rec.tip_mm.push_back(x0 + d * p);
      }
    }
    // Tracker noise and dropouts.
    const double dtt = rec.tip_t_s.size() > 1 ? rec.tip_t_s[1] - rec.tip_t_s[0] : 1e-3;
    std::vector<double> t_kept, x_kept;
    int lost = 0;
    for (std::size_t i = 0; i < rec.tip_t_s.size(); ++i) {
      double x = rec.tip_mm[i] + setup.white_noise_um * 1e-3 * rng.normal();
      if (setup.pink_noise_um > 0) x += pink.draw(rng, dtt);
      if (lost == 0 && setup.dropout_fraction > 0 && i > 0 &&
          rng.uniform() < setup.dropout_fraction / 3.0) {
        lost = 1 + static_cast<int>(rng.below(5));  // bursts of 1–5 samples, 3 on average
      }
      if (lost > 0) {
        --lost;
        continue;
      }
      t_kept.push_back(rec.tip_t_s[i]);
      x_kept.push_back(x);
    }
    rec.tip_t_s = std::move(t_kept);
    rec.tip_mm = std::move(x_kept);
    if (setup.sync && !rec.one_clock) {
      // The tracker's marker row: the same trigger on its own clock, never lost.
      const double tt = mark_sync(
          rec.tip_t_s, rec.tip_mm, trigger * (1.0 - setup.drift) - setup.clock_offset_s, [&] {
            return twin_at_trigger().second + setup.white_noise_um * 1e-3 * rng.normal();
          });
      rec.tip_sync_t_s.push_back(tt);
    }
    if (rec.one_clock && rec.tip_t_s.size() != rec.scale_t_s.size()) {
      // One file, one clock: a lost tracker sample loses its row.
      std::vector<double> ts, xs;
      std::size_t j = 0;
      for (std::size_t i = 0; i < rec.scale_t_s.size() && j < rec.tip_t_s.size(); ++i) {
        if (rec.scale_t_s[i] == rec.tip_t_s[j]) {
          ts.push_back(rec.scale_t_s[i]);
          xs.push_back(rec.scale_mm[i]);
          ++j;
        }
      }
      rec.scale_t_s = std::move(ts);
      rec.scale_mm = std::move(xs);
    }
    out.push_back(std::move(tm));
    session = end;
  }
  return out;
}

SessionRecording as_session(const std::vector<TwinMove>& moves) {
  SessionRecording s;
  s.source = "twin session";
  for (const TwinMove& m : moves) {
    const MoveRecording& r = m.recording;
    s.one_clock = r.one_clock;
    for (std::size_t i = 0; i < r.scale_t_s.size(); ++i) {
      if (!s.scale_t_s.empty() && !(r.scale_t_s[i] > s.scale_t_s.back())) continue;
      s.scale_t_s.push_back(r.scale_t_s[i]);
      s.scale_mm.push_back(r.scale_mm[i]);
    }
    for (std::size_t i = 0; i < r.tip_t_s.size(); ++i) {
      if (!s.tip_t_s.empty() && !(r.tip_t_s[i] > s.tip_t_s.back())) continue;
      s.tip_t_s.push_back(r.tip_t_s[i]);
      s.tip_mm.push_back(r.tip_mm[i]);
    }
    s.scale_sync_t_s.insert(
        s.scale_sync_t_s.end(), r.scale_sync_t_s.begin(), r.scale_sync_t_s.end());
    s.tip_sync_t_s.insert(s.tip_sync_t_s.end(), r.tip_sync_t_s.begin(), r.tip_sync_t_s.end());
  }
  return s;
}

namespace {

/// Writes `r` to `one` (one clock) or to `controller` and `tracker`.
void write_streams(const MoveRecording& r,
                   char axis,
                   const std::string& one,
                   const std::string& controller,
                   const std::string& tracker) {
  const std::string a(1, axis);
  if (r.one_clock) {
    std::string s = "t_s," + a + "_scale_mm," + a + "_tip_mm\n";
    for (std::size_t i = 0; i < r.scale_t_s.size(); ++i) {
      s += fmt::format("{:.7f},{:.7f},{:.7f}\n", r.scale_t_s[i], r.scale_mm[i], r.tip_mm[i]);
    }
    io::write_file_atomically(one, s);
    return;
  }
  // With sync markers a `sync` column: 1 on the rows taken at a trigger.
  const auto stream = [](const std::string& header,
                         const std::vector<double>& t,
                         const std::vector<double>& x,
                         const std::vector<double>& markers) {
    std::string s = header + (markers.empty() ? "\n" : ",sync\n");
    std::size_t next = 0;
    for (std::size_t i = 0; i < t.size(); ++i) {
      s += fmt::format("{:.7f},{:.7f}", t[i], x[i]);
      if (!markers.empty()) {
        const bool marker = next < markers.size() && t[i] == markers[next];
        next += marker;
        s += marker ? ",1" : ",0";
      }
      s += '\n';
    }
    return s;
  };
  const std::string c = stream("t_s," + a + "_scale_mm", r.scale_t_s, r.scale_mm, r.scale_sync_t_s);
  const std::string t = stream("t_s," + a + "_tip_mm", r.tip_t_s, r.tip_mm, r.tip_sync_t_s);
  io::write_file_atomically(controller, c);
  io::write_file_atomically(tracker, t);
}

}  // namespace

void write_move_recording(const std::string& dir, const MoveRecording& r, char axis) {
  write_streams(r,
                axis,
                dir + "/" + one_clock_file(r.move_id),
                dir + "/" + controller_file(r.move_id),
                dir + "/" + tracker_file(r.move_id));
}

void write_session_recording(const std::string& dir, const SessionRecording& session, char axis) {
  MoveRecording r;
  r.scale_t_s = session.scale_t_s;
  r.scale_mm = session.scale_mm;
  r.tip_t_s = session.tip_t_s;
  r.tip_mm = session.tip_mm;
  r.scale_sync_t_s = session.scale_sync_t_s;
  r.tip_sync_t_s = session.tip_sync_t_s;
  r.one_clock = session.one_clock;
  write_streams(r,
                axis,
                dir + "/" + kSessionFile,
                dir + "/" + kSessionControllerFile,
                dir + "/" + kSessionTrackerFile);
}

}  // namespace cmmcomp::measure

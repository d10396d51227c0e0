// SPDX-License-Identifier: MIT
/// @file Reports of a planned move profile.
#include <fmt/format.h>

#include <algorithm>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/profile_report.hpp>
#include <stdexcept>
#include <vector>

namespace cmmcomp::io {
namespace {
constexpr double kMm = 1e3;  // m -> mm
}  // namespace

std::string describe_profile(const motion::MoveProfile& profile) {
  const motion::ProbingMove& m = profile.move();
  const motion::PhaseInstants& t = profile.instants();
  std::string s;
  fmt::format_to(std::back_inserter(s),
                 "move: PV {:g} mm/s, PA {:g} mm/s^2, PD {:g} mm, AV {:g} mm/s, AA {:g} mm/s^2, "
                 "AD {:g} mm, jerk {}, dwell {:g} s, smoothing {:g} s\n",
                 m.positioning_speed * kMm,
                 m.positioning_accel * kMm,
                 m.positioning_distance * kMm,
                 m.approach_speed * kMm,
                 m.approach_accel * kMm,
                 m.approach_distance * kMm,
                 m.jerk > 0.0 ? fmt::format("{:g} mm/s^3", m.jerk * kMm) : "unlimited",
                 m.dwell,
                 m.smoothing);
  fmt::format_to(std::back_inserter(s),
                 "positioning: {} (peak {:.3f} mm/s); approach: {}\n",
                 profile.positioning_reaches_speed() ? "cruises at PV" : "too short to reach PV",
                 profile.positioning_peak_speed() * kMm,
                 profile.approach_reaches_speed() ? "reaches AV before the touch"
                                                  : "touches while still accelerating");
  fmt::format_to(std::back_inserter(s), "phase instants [s]:\n");
  const struct {
    const char* name;
    double t;
  } rows[] = {{"positioning acceleration end", t.positioning_accel_end},
              {"positioning deceleration start (RPE)", t.positioning_decel_start},
              {"positioning end (pre-hit point)", t.positioning_end},
              {"approach start (after the dwell)", t.approach_start},
              {"approach acceleration end", t.approach_accel_end},
              {"touch (RAE)", t.touch}};
  for (const auto& r : rows)
    fmt::format_to(std::back_inserter(s), "  {:<38} {:.6f}\n", r.name, r.t);
  fmt::format_to(std::back_inserter(s),
                 "segments:\n  {:>3} {:>10} {:>10} {:>11} {:>12} {:>14} {:>14}\n",
                 "#",
                 "start s",
                 "length s",
                 "start mm",
                 "start mm/s",
                 "start mm/s^2",
                 "jerk mm/s^3");
  for (int i = 0; i < profile.segment_count(); ++i) {
    const motion::Segment& g = profile.segment(i);
    fmt::format_to(std::back_inserter(s),
                   "  {:>3} {:>10.6f} {:>10.6f} {:>11.6f} {:>12.6f} {:>14.6f} {:>14.3f}\n",
                   i,
                   g.start_time,
                   g.duration,
                   g.p0 * kMm,
                   g.v0 * kMm,
                   g.a0 * kMm,
                   g.jerk * kMm);
  }
  const motion::MotionState end = profile.sample(t.touch);
  fmt::format_to(std::back_inserter(s),
                 "touch at {:.6f} mm moving at {:.6f} mm/s\n",
                 end.position * kMm,
                 end.velocity * kMm);
  return s;
}

std::string profile_csv(const motion::MoveProfile& profile, int samples) {
  if (samples < 2) throw ConfigError("profile_csv: samples must be at least 2");
  const motion::PhaseInstants& in = profile.instants();
  std::vector<double> times;
  times.reserve(static_cast<std::size_t>(samples) + 4);
  for (int i = 0; i < samples; ++i) {
    times.push_back(in.touch * i / (samples - 1));
  }
  times.insert(times.end(),
               {in.positioning_accel_end,
                in.positioning_decel_start,
                in.positioning_end,
                in.approach_start,
                in.approach_accel_end,
                in.touch});
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  std::string s = "t_s,position_mm,velocity_mm_s,acceleration_mm_s2,jerk_mm_s3\n";
  for (double t : times) {
    const motion::MotionState st = profile.sample(t);
    fmt::format_to(std::back_inserter(s),
                   "{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n",
                   t,
                   st.position * kMm,
                   st.velocity * kMm,
                   st.acceleration * kMm,
                   st.jerk * kMm);
  }
  return s;
}

}  // namespace cmmcomp::io

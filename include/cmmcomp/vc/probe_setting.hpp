// SPDX-License-Identifier: MIT
/// @file A probing speed setting (PV, PA, PD, AV, AA, AD) and the time one point takes with it.
#pragma once

#include <cmmcomp/motion/move_profile.hpp>
#include <string>

namespace cmmcomp::vc {

/// The commanded parameters of every point probed with one setting, in the units of the model
/// and the protocols (mm, mm/s, mm/s²).
struct ProbeSetting {
  std::string name;         ///< "fast", "slow", …: the label in every report
  double pv_mm_s = 0;       ///< positioning speed PV
  double pa_mm_s2 = 200;    ///< positioning acceleration PA (the paper's fixed value)
  double pd_mm = 0;         ///< positioning distance PD (to the pre-hit point)
  double av_mm_s = 0;       ///< approach speed AV
  double aa_mm_s2 = 60;     ///< approach acceleration AA (the paper's fixed value)
  double ad_mm = 0;         ///< approach distance AD (pre-hit point to the touch)
  bool compensated = true;  ///< ask the agents for corrections (false: the slow reference)
};

/// Fast default: the top of the model's training ranges (PV 40–100, AV 8–16 mm/s), PD 60 and
/// AD 10 mm in the middle of theirs (PD 40–80, AD 5–15 mm).
ProbeSetting default_fast_setting();

/// Slow reference: how such a machine probes without compensation to meet its MPE_E: PV 20 mm/s,
/// then 2 mm of approach at 1 mm/s (on the twin the touch then lags by only 0.2–0.4 µm; at
/// AV 2 mm/s over 2 mm it is 0.9–1.7 µm, which with the probing scatter already fails MPE_E).
ProbeSetting default_slow_setting();

/// Parses "pv=100,pd=60,av=16,ad=10[,pa=200][,aa=60]" over `base` (keys not given keep their
/// value). Throws ConfigError naming the bad key or value.
ProbeSetting parse_setting(const std::string& text, ProbeSetting base);

/// The move of a point in SI units (no jerk limit, as the twin's training data).
motion::ProbingMove move_of(const ProbeSetting& s) noexcept;

/// Time from the start of the positioning move to the touch [s], from the planned profiles
/// (positioning from rest to rest over PD, then the approach over AD). Throws Error when the
/// setting cannot be planned.
double time_per_point_s(const ProbeSetting& s, double dwell_s = 0.0, double smoothing_s = 0.0);

}  // namespace cmmcomp::vc

// SPDX-License-Identifier: MIT
/// @file What a machine's controller lets a measuring program or its configuration set for one
/// probing cycle, and the range of each setting (docs/machine-file.md, "Capabilities").
///
/// Seven settings shape a probing cycle: the positioning speed and acceleration (PV, PA), the
/// approach speed, acceleration and distance (AV, AA, AD), the settling dwell at the pre-hit
/// point and the command smoothing. PD is not among them: it is the geometry (where the
/// positioning starts). Five have an I++ DME property a program sets with `SetProp`; the dwell and
/// the smoothing have none in I++ DME (ISO 22093): they belong to the controller's configuration.
///
/// The table `kSettings` is the one source of every setting's name, symbol, unit, I++ property
/// and accepted range; the machine file, its documentation and the messages iterate it.
/// Core (header-only, constexpr, no allocation): usable on the real-time path and in firmware.
#pragma once

#include <cmmcomp/motion/move_profile.hpp>

namespace cmmcomp::motion {

/// One setting of a probing cycle (index into kSettings and ControllerCapabilities::range).
enum class Setting : int {
  kPositioningSpeed = 0,
  kPositioningAccel,
  kApproachSpeed,
  kApproachAccel,
  kApproachDistance,
  kDwell,
  kSmoothing,
};
inline constexpr int kSettingCount = 7;

/// A closed interval [min, max] in SI units.
struct SettingRange {
  double min = 0.0;
  double max = 0.0;
  /// False for NaN.
  constexpr bool contains(double v) const noexcept { return v >= min && v <= max; }
};

/// How a setting is named, where it is set, and what a file may hold at all.
struct SettingInfo {
  Setting setting;
  const char* key;   ///< machine-file key stem: `<key>_min_<unit>`, `<key>_max_<unit>`
  const char* unit;  ///< unit of the file's keys, as written in them: "mm_s", "mm_s2", "mm", "s"
  const char* unit_text;     ///< the same unit in messages: "mm/s", "mm/s^2", "mm", "s"
  double to_si;              ///< file unit to SI: 1e-3 for mm, 1 for s
  const char* symbol;        ///< "PV", "PA", "AV", "AA", "AD", "dwell", "smoothing"
  const char* description;   ///< one phrase for the docs and messages
  const char* ipp_property;  ///< the I++ DME property that sets it, or nullptr when there is none
  SettingRange limits;       ///< what a capability range may span at all [SI] (MoveLimits)
};

inline constexpr SettingInfo kSettings[kSettingCount] = {
    {Setting::kPositioningSpeed,
     "positioning_speed",
     "mm_s",
     "mm/s",
     1e-3,
     "PV",
     "positioning speed",
     "Tool.GoToPar.Speed",
     {MoveLimits::kMinSpeed, MoveLimits::kMaxSpeed}},
    {Setting::kPositioningAccel,
     "positioning_accel",
     "mm_s2",
     "mm/s^2",
     1e-3,
     "PA",
     "positioning acceleration",
     "Tool.GoToPar.Accel",
     {MoveLimits::kMinAccel, MoveLimits::kMaxAccel}},
    {Setting::kApproachSpeed,
     "approach_speed",
     "mm_s",
     "mm/s",
     1e-3,
     "AV",
     "approach (probing) speed",
     "Tool.PtMeasPar.Speed",
     {MoveLimits::kMinSpeed, MoveLimits::kMaxSpeed}},
    {Setting::kApproachAccel,
     "approach_accel",
     "mm_s2",
     "mm/s^2",
     1e-3,
     "AA",
     "approach acceleration",
     "Tool.PtMeasPar.Accel",
     {MoveLimits::kMinAccel, MoveLimits::kMaxAccel}},
    {Setting::kApproachDistance,
     "approach_distance",
     "mm",
     "mm",
     1e-3,
     "AD",
     "approach distance from the pre-hit point to the nominal point",
     "Tool.PtMeasPar.Approach",
     {MoveLimits::kMinDistance, MoveLimits::kMaxDistance}},
    {Setting::kDwell,
     "dwell",
     "s",
     "s",
     1.0,
     "dwell",
     "settling dwell at rest at the pre-hit point before the approach",
     nullptr,
     {0.0, MoveLimits::kMaxDwell}},
    {Setting::kSmoothing,
     "smoothing",
     "s",
     "s",
     1.0,
     "smoothing",
     "command smoothing (moving average of the commanded acceleration)",
     nullptr,
     {0.0, MoveLimits::kMaxSmoothing}},
};

/// The setting's row of kSettings.
constexpr const SettingInfo& setting_info(Setting s) noexcept {
  return kSettings[static_cast<int>(s)];
}

/// The value a probing cycle gives a setting [SI]. The cycle's dwell and smoothing are those of
/// the move (a ProbingMove carries them).
constexpr double setting_value(const ProbingMove& cycle, Setting s) noexcept {
  switch (s) {
    case Setting::kPositioningSpeed:
      return cycle.positioning_speed;
    case Setting::kPositioningAccel:
      return cycle.positioning_accel;
    case Setting::kApproachSpeed:
      return cycle.approach_speed;
    case Setting::kApproachAccel:
      return cycle.approach_accel;
    case Setting::kApproachDistance:
      return cycle.approach_distance;
    case Setting::kDwell:
      return cycle.dwell;
    case Setting::kSmoothing:
      return cycle.smoothing;
  }
  return 0.0;
}

/// The range of every setting a controller accepts [SI]. A setting the controller does not let
/// anyone change has min == max.
struct ControllerCapabilities {
  SettingRange range[kSettingCount] = {};

  constexpr const SettingRange& operator[](Setting s) const noexcept {
    return range[static_cast<int>(s)];
  }
  constexpr SettingRange& operator[](Setting s) noexcept { return range[static_cast<int>(s)]; }
};

/// What a machine file without a capabilities section means (format 2): the motion settings
/// anywhere MoveLimits accepts, the dwell and the smoothing fixed at the given values.
constexpr ControllerCapabilities fixed_timing_capabilities(double dwell_s,
                                                           double smoothing_s) noexcept {
  ControllerCapabilities c;
  for (const SettingInfo& info : kSettings) c[info.setting] = info.limits;
  c[Setting::kDwell] = {dwell_s, dwell_s};
  c[Setting::kSmoothing] = {smoothing_s, smoothing_s};
  return c;
}

/// The first setting of `cycle` outside `caps` (NaN included); `outside` is false when every
/// setting is accepted.
struct SettingViolation {
  bool outside = false;
  Setting setting = Setting::kPositioningSpeed;
  double value = 0.0;
  SettingRange range;
};
constexpr SettingViolation first_violation(const ControllerCapabilities& caps,
                                           const ProbingMove& cycle) noexcept {
  for (const SettingInfo& info : kSettings) {
    const double v = setting_value(cycle, info.setting);
    if (!caps[info.setting].contains(v)) return {true, info.setting, v, caps[info.setting]};
  }
  return {};
}

}  // namespace cmmcomp::motion

// SPDX-License-Identifier: MIT
/// @file The probing-move reconstruction rule: from what an I++ DME session commanded (the
/// properties set, the positions reached), the paper's probing move (PV, PA, PD, AV, AA, AD, Y,
/// direction) of each `PtMeas`. One rule, used by the server on the twin and by a proxy that only
/// sees the client's commands and the server's answers (docs/protocol-ippdme.md, "The probing
/// move"; the same mapping as measure's plan.ipp, docs/measurement.md).
///
/// The rule (all in mm, mm/s, mm/s²):
///  - n = IJK / |IJK| (the surface normal); the approach runs along d = −n;
///  - pre-hit point P = nominal + Approach · n;
///  - PV, PA = Tool.GoToPar.Speed, .Accel; AV, AA, AD = Tool.PtMeasPar.Speed, .Accel, .Approach;
///  - PD = the length of the positioning: the last motion that ends at P. When the last motion
///    was a GoTo ending at P (within kSamePointMm), its length; otherwise the PtMeas moves there
///    itself from the current position, and PD = |P − position|. A PD under 1 µm
///    (motion::MoveLimits::kMinDistance) is taken as 1 µm: the approach starts at rest at P;
///  - Y = the nominal point's Y (the carriage position along the beam, as plan.ipp writes it).
/// After a PtMeas the probe stands at nominal + Retract · n, and no GoTo is the last motion.
/// Setup-level code (no allocation in the rule itself; no exceptions).
#pragma once

#include <cmath>
#include <cmmcomp/motion/controller_capabilities.hpp>
#include <cmmcomp/motion/move_profile.hpp>

namespace cmmcomp::ipp {

/// A point or a vector in machine coordinates [mm].
struct Point3 {
  double x = 0, y = 0, z = 0;
};
inline Point3 operator+(Point3 a, Point3 b) noexcept { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Point3 operator-(Point3 a, Point3 b) noexcept { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Point3 operator*(double k, Point3 a) noexcept { return {k * a.x, k * a.y, k * a.z}; }
inline double norm(Point3 a) noexcept { return std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z); }

/// Two points closer than this are the same point [mm] (numbers travel at 1e-6 mm).
inline constexpr double kSamePointMm = 1e-4;

/// The I++ DME properties of a probing cycle the subset knows.
enum class Property : int {
  kGoToSpeed = 0,
  kGoToAccel,
  kPtMeasSpeed,
  kPtMeasAccel,
  kPtMeasApproach,
  kPtMeasSearch,
  kPtMeasRetract,
};
inline constexpr int kPropertyCount = 7;

/// How a property is named and what it sets.
struct PropertyInfo {
  Property property;
  const char* name;         ///< `Tool.GoToPar.Speed`
  const char* unit;         ///< "mm/s", "mm/s^2", "mm"
  bool has_setting;         ///< false: no controller setting (Search, Retract)
  motion::Setting setting;  ///< the controller setting it sets (motion::kSettings) when it has one
};

inline constexpr PropertyInfo kProperties[kPropertyCount] = {
    {Property::kGoToSpeed, "Tool.GoToPar.Speed", "mm/s", true, motion::Setting::kPositioningSpeed},
    {Property::kGoToAccel,
     "Tool.GoToPar.Accel",
     "mm/s^2",
     true,
     motion::Setting::kPositioningAccel},
    {Property::kPtMeasSpeed, "Tool.PtMeasPar.Speed", "mm/s", true, motion::Setting::kApproachSpeed},
    {Property::kPtMeasAccel,
     "Tool.PtMeasPar.Accel",
     "mm/s^2",
     true,
     motion::Setting::kApproachAccel},
    {Property::kPtMeasApproach,
     "Tool.PtMeasPar.Approach",
     "mm",
     true,
     motion::Setting::kApproachDistance},
    {Property::kPtMeasSearch, "Tool.PtMeasPar.Search", "mm", false, motion::Setting::kDwell},
    {Property::kPtMeasRetract, "Tool.PtMeasPar.Retract", "mm", false, motion::Setting::kDwell},
};

constexpr const PropertyInfo& property_info(Property p) noexcept {
  return kProperties[static_cast<int>(p)];
}

/// The property named `name` (`Tool.GoToPar.Speed`); false when there is none.
bool find_property(const char* name, std::size_t length, Property& out) noexcept;

/// One probing move as the rule rebuilds it.
struct ReconstructedMove {
  bool ok = false;
  const char* problem = "";  ///< why not, when !ok (a static string)
  double pv_mm_s = 0, pa_mm_s2 = 0, pd_mm = 0, av_mm_s = 0, aa_mm_s2 = 0, ad_mm = 0;
  double y_mm = 0;               ///< the carriage position along the beam
  Point3 direction;              ///< d = −IJK/|IJK|: the approach's direction of motion
  Point3 nominal;                ///< the nominal contact point
  Point3 prehit;                 ///< nominal + AD · n
  bool own_positioning = false;  ///< the PtMeas positioned itself (the last GoTo did not end at P)

  /// The move for the twin and the compensator (SI; dwell and smoothing are the controller's).
  motion::ProbingMove move() const noexcept {
    return motion::probing_move_mm(pv_mm_s, pa_mm_s2, pd_mm, av_mm_s, aa_mm_s2, ad_mm);
  }
};

/// The rule's state over one session: feed it what the session commanded and what the answers
/// said, in order; ask it for the move of each PtMeas before telling it the PtMeas was done.
class ProbingMoveTracker {
 public:
  /// A property's value took effect (SetProp done, or read back from a GetProp answer).
  void set_property(Property p, double value) noexcept;
  /// The property's value; NaN while unknown.
  double property(Property p) const noexcept { return values_[static_cast<int>(p)]; }

  /// A GoTo finished at `target` (from the current position, when known).
  void moved_to(const Point3& target) noexcept;
  /// The position is known without a motion (a Get answer, a Home): no GoTo is the last motion.
  void position_is(const Point3& p) noexcept;
  /// The position is no longer known (a proxy after a Home or an aborted move of a server it
  /// does not see into): the next PtMeas cannot be rebuilt until a GoTo or a Get.
  void position_unknown() noexcept;
  /// The current position, when known.
  bool position(Point3& out) const noexcept;

  /// The probing move of `PtMeas(nominal, IJK)` under the rule (not ok: an IJK of no length, a
  /// property or the position unknown).
  ReconstructedMove probing_move(const Point3& nominal, const Point3& ijk) const noexcept;
  /// The PtMeas finished: the probe retracted to nominal + Retract · n.
  void probed(const ReconstructedMove& move) noexcept;

 private:
  double values_[kPropertyCount] = {NAN, NAN, NAN, NAN, NAN, NAN, NAN};
  bool known_ = false;
  Point3 position_;
  bool last_is_goto_ = false;
  Point3 goto_start_;
  bool goto_start_known_ = false;
};

}  // namespace cmmcomp::ipp

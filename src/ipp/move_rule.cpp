// SPDX-License-Identifier: MIT
/// @file The probing-move reconstruction rule (move_rule.hpp).
#include <cmmcomp/ipp/move_rule.hpp>
#include <cstring>

namespace cmmcomp::ipp {

bool find_property(const char* name, std::size_t length, Property& out) noexcept {
  for (const PropertyInfo& info : kProperties) {
    if (std::strlen(info.name) == length && std::strncmp(info.name, name, length) == 0) {
      out = info.property;
      return true;
    }
  }
  return false;
}

void ProbingMoveTracker::set_property(Property p, double value) noexcept {
  values_[static_cast<int>(p)] = value;
}

void ProbingMoveTracker::moved_to(const Point3& target) noexcept {
  goto_start_known_ = known_;
  goto_start_ = position_;
  position_ = target;
  known_ = true;
  last_is_goto_ = true;
}

void ProbingMoveTracker::position_is(const Point3& p) noexcept {
  position_ = p;
  known_ = true;
  last_is_goto_ = false;
}

void ProbingMoveTracker::position_unknown() noexcept {
  known_ = false;
  last_is_goto_ = false;
}

bool ProbingMoveTracker::position(Point3& out) const noexcept {
  if (known_) out = position_;
  return known_;
}

ReconstructedMove ProbingMoveTracker::probing_move(const Point3& nominal,
                                                   const Point3& ijk) const noexcept {
  ReconstructedMove m;
  const double length = norm(ijk);
  if (!(length > 1e-9) || !std::isfinite(length)) {
    m.problem = "IJK has no length";
    return m;
  }
  const Point3 n = (1.0 / length) * ijk;
  m.nominal = nominal;
  m.direction = -1.0 * n;
  m.pv_mm_s = property(Property::kGoToSpeed);
  m.pa_mm_s2 = property(Property::kGoToAccel);
  m.av_mm_s = property(Property::kPtMeasSpeed);
  m.aa_mm_s2 = property(Property::kPtMeasAccel);
  m.ad_mm = property(Property::kPtMeasApproach);
  m.y_mm = nominal.y;
  for (double v : {m.pv_mm_s, m.pa_mm_s2, m.av_mm_s, m.aa_mm_s2, m.ad_mm}) {
    if (std::isnan(v)) {
      m.problem = "a GoToPar or PtMeasPar property is not known";
      return m;
    }
  }
  m.prehit = nominal + m.ad_mm * n;
  if (!known_) {
    m.problem = "the position before the probing move is not known";
    return m;
  }
  if (last_is_goto_ && norm(position_ - m.prehit) <= kSamePointMm) {
    if (!goto_start_known_) {
      m.problem = "the start of the GoTo to the pre-hit point is not known";
      return m;
    }
    m.pd_mm = norm(position_ - goto_start_);
  } else {
    m.own_positioning = true;
    m.pd_mm = norm(m.prehit - position_);
  }
  const double min_pd_mm = motion::MoveLimits::kMinDistance * 1e3;
  if (m.pd_mm < min_pd_mm) m.pd_mm = min_pd_mm;
  m.ok = true;
  return m;
}

void ProbingMoveTracker::probed(const ReconstructedMove& move) noexcept {
  const double retract = property(Property::kPtMeasRetract);
  const Point3 n = -1.0 * move.direction;
  position_ = move.nominal + (std::isnan(retract) ? 0.0 : retract) * n;
  known_ = !std::isnan(retract);
  last_is_goto_ = false;
}

}  // namespace cmmcomp::ipp

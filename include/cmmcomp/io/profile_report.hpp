// SPDX-License-Identifier: MIT
/// @file Human-readable and CSV reports of a planned move profile (offline, cmmcomp::cmmcomp).
#pragma once

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/motion/move_profile.hpp>
#include <string>

namespace cmmcomp::io {

/// A table of the move's parameters, its phase instants and its segments, in mm and s.
/// Setup only (allocates).
std::string describe_profile(const motion::MoveProfile& profile);

/// CSV of the commanded motion sampled at `samples` (>= 2) evenly spaced instants from 0 to the
/// touch, columns `t_s,position_mm,velocity_mm_s,acceleration_mm_s2,jerk_mm_s3`, the phase
/// instants included as extra rows. Setup only; throws ConfigError for samples < 2.
std::string profile_csv(const motion::MoveProfile& profile, int samples);

}  // namespace cmmcomp::io

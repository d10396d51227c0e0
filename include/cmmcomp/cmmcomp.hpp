// SPDX-License-Identifier: MIT
/// @file Umbrella header for the real-time core (cmmcomp::core). Never includes offline code.
#pragma once

#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/errors/dynamic_errors.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/motion/move_profile.hpp>
#include <cmmcomp/status.hpp>
#include <cmmcomp/version.hpp>

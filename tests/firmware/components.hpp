// SPDX-License-Identifier: MIT
/// @file The component functions of components.cpp (Cortex-M7 figures).
#pragma once

#include <cmmcomp/compensation/move_request.hpp>
#include <cstddef>

extern "C" {
/// fuzzy::evaluate of the shipped 4-input model, double and float; returns the Status.
int cmmcomp_fw_evaluate_double(const double x[4], double y[4]);
int cmmcomp_fw_evaluate_float(const double x[4], double y[4]);
/// StaticMoveCompensator::publish of the shipped model on `axis` (model id 1 double, 2 float).
int cmmcomp_fw_publish_double(int axis);
int cmmcomp_fw_publish_float(int axis);
/// StaticMoveCompensator::before_approach, double and float model.
int cmmcomp_fw_before_approach_double(const cmmcomp::compensation::MoveRequest* move,
                                      cmmcomp::compensation::Correction* out);
int cmmcomp_fw_before_approach_float(const cmmcomp::compensation::MoveRequest* move,
                                     cmmcomp::compensation::Correction* out);
/// MoveProfile::plan of the baseline move and extract_dynamic_errors of a trace.
int cmmcomp_fw_profile_and_extract(const double* time,
                                   const double* error,
                                   std::size_t count,
                                   double errors_um[4]);
/// Duration of the planned baseline move [s], or −1.
double cmmcomp_fw_profile_duration();
}

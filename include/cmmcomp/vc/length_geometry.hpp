// SPDX-License-Identifier: MIT
/// @file Geometry and acceptance of the ISO 10360-2 style bidirectional length test.
///
/// A step gauge lies along X. Each nominal length L is the distance between two opposed faces:
///  - face B at x0, facing +X, approached moving −X (d = −1);
///  - face A at x0 + L, facing −X, approached moving +X (d = +1).
/// The measured length is x_A − x_B. Probing the two ends from opposite directions is what makes
/// the test bidirectional: a unidirectional length (both faces from the same side) would cancel
/// any error that is the same at both touches; here the dynamic errors add.
///
/// Signs (docs/compensator.md): the scale reports s = p − RAE·d [RAE in µm, + = tip ahead], the
/// controller adds the correction +RAE_pred·d. Hence with the same RAE at both faces
/// E = (s_A − s_B) − L = −(RAE_A + RAE_B) = −2·RAE uncompensated, and 0 when RAE_pred = RAE.
#pragma once

namespace cmmcomp::vc {

/// The two faces of a length.
enum class Face { kA, kB };

/// Approach direction along X of a face: A +1, B −1.
constexpr int direction_of(Face f) noexcept { return f == Face::kA ? +1 : -1; }

/// "A" or "B".
constexpr const char* to_string(Face f) noexcept { return f == Face::kA ? "A" : "B"; }

/// True position of a face [mm] for a gauge starting at `x0_mm`.
constexpr double face_position_mm(Face f, double x0_mm, double length_mm) noexcept {
  return f == Face::kA ? x0_mm + length_mm : x0_mm;
}

/// The point the X scale reports [mm] when the tip touches `true_mm` moving along `direction`
/// with residual approach error `rae_um` (tip ahead of the scale by RAE along d).
constexpr double scale_point_mm(double true_mm, int direction, double rae_um) noexcept {
  return true_mm - rae_um * 1e-3 * direction;
}

/// The point after the controller adds the agent's X correction [µm].
constexpr double corrected_point_mm(double scale_mm, double correction_x_um) noexcept {
  return scale_mm + correction_x_um * 1e-3;
}

/// Length error [µm] of a measured length: (x_A − x_B) − L.
constexpr double length_error_um(double a_mm, double b_mm, double nominal_mm) noexcept {
  return ((a_mm - b_mm) - nominal_mm) * 1e3;
}

/// Maximum permissible length error of a typical machine, MPE_E = (1.9 + L/300) µm, L in mm.
constexpr double mpe_e_um(double length_mm) noexcept { return 1.9 + length_mm / 300.0; }

}  // namespace cmmcomp::vc

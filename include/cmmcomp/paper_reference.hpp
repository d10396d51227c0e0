// SPDX-License-Identifier: MIT
/// @file The published figures of Wei, Zhang & Feng (2019) that cmmcomp is checked against.
///
/// Values as printed (µm, %); RPE and RAE are magnitudes. data/paper/*.csv carry the same
/// numbers for the identification script; a test keeps the two in step.
#pragma once

#include <array>
#include <cmmcomp/schema.hpp>

namespace cmmcomp::paper {

/// Order of the four parameters in every array here: schema.hpp's kErrors order.
inline constexpr std::array<const char*, 4> kParameters = {
    kErrors[0].label, kErrors[1].label, kErrors[2].label, kErrors[3].label};

/// The baseline move of Tables 1 and 2, in file units (mm, mm/s, mm/s²), and the carriage
/// position of Table 1 (Table 2's middle row repeats it).
struct BaselineMove {
  double pv_mm_s, pa_mm_s2, pd_mm, av_mm_s, aa_mm_s2, ad_mm, y_mm;
};
inline constexpr BaselineMove kBaseline = {40.0, 200.0, 40.0, 12.0, 60.0, 10.0, 250.0};

/// Table 3: the three levels of each factor, in PaperInputs order (PV, PD, AV, AD) and file
/// units. PD's third level, 80 mm, is the project's choice: the paper prints only two.
inline constexpr std::array<std::array<double, 3>, 4> kTable3Levels = {{
    {40.0, 70.0, 100.0},  // PV [mm/s]
    {40.0, 60.0, 80.0},   // PD [mm]
    {8.0, 12.0, 16.0},    // AV [mm/s]
    {5.0, 10.0, 15.0},    // AD [mm]
}};

/// Table 1: repeatability at the baseline move, mean and standard deviation of 5 runs [µm].
inline constexpr std::array<double, 4> kTable1Mean = {13.622, 5.861, 7.545, 3.919};
inline constexpr std::array<double, 4> kTable1Std = {1.321, 0.461, 0.612, 0.304};

/// Table 2: the baseline move with the carriage at Y = 0, 250, 500 mm [µm]; [y][parameter].
inline constexpr std::array<double, 3> kTable2Y_mm = {0.0, 250.0, 500.0};
inline constexpr std::array<std::array<double, 4>, 3> kTable2 = {{{11.957, 5.137, 7.473, 4.272},
                                                                  {13.622, 5.861, 7.544, 3.928},
                                                                  {22.619, 10.291, 12.196, 7.543}}};

/// Table 4: ANOVA weights [%] on the L18 × 3 experiment; [parameter][PV, PD, AV, AD, error].
/// The sources are PaperInputs' labels and the error term.
inline constexpr std::array<const char*, 5> kAnovaSources = {PaperInputs::labels()[0],
                                                             PaperInputs::labels()[1],
                                                             PaperInputs::labels()[2],
                                                             PaperInputs::labels()[3],
                                                             "error"};
inline constexpr std::array<std::array<double, 5>, 4> kTable4Weight = {{
    {91.6, 0.28, 1.77, 1.15, 5.19},  // MPE
    {79.1, 13.6, 2.4, 0.01, 4.89},   // RPE
    {2.32, 0.49, 82.1, 3.25, 11.8},  // MAE
    {0.70, 0.80, 61.8, 29.1, 7.6},   // RAE
}};

/// Table 5: on the test data, mean |error| before and mean |residual| after compensation [µm],
/// reduction [%], variance after [µm²].
inline constexpr std::array<double, 4> kTable5MeanBefore = {20.748, 8.211, 8.839, 5.333};
inline constexpr std::array<double, 4> kTable5MeanAfter = {2.315, 0.758, 1.750, 1.533};
inline constexpr std::array<double, 4> kTable5Reduction = {88.8, 90.8, 80.2, 71.3};
inline constexpr std::array<double, 4> kTable5VarianceAfter = {1.572, 1.453, 1.239, 0.986};

}  // namespace cmmcomp::paper

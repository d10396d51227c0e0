// SPDX-License-Identifier: MIT
/// @file The factor levels of a probing experiment as the tools take them, and the design they
/// make: "pv=40,70,100;pd=40,60,80;av=8,12,16;ad=5,10,15[;y=0,250,500]" in mm, mm/s
/// (`cmmcomp-sim dataset --levels`, `cmmcomp-measure plan --levels`). Offline; throws ConfigError.
#pragma once

#include <cctype>
#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <cmmcomp/schema.hpp>
#include <cstdint>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace cmmcomp::doe {

/// The paper's Table 3 levels in the --levels form (the tools' default).
std::string table3_levels_text();

/// Parses the --levels text into the factors PV, PD, AV, AD (and Y when given), in SI units.
std::vector<Factor> parse_levels(const std::string& text);

/// design_by_name over parse_levels(levels), with the library's "design NAME ..." errors
/// reworded for the option the user wrote (--design).
Design design_from_text(const std::string& name,
                        const std::string& levels,
                        int lhs_samples,
                        std::uint64_t seed);

}  // namespace cmmcomp::doe

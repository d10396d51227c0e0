// SPDX-License-Identifier: MIT
/// @file Probing settings: defaults, parsing, and time per point.
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/vc/probe_setting.hpp>
#include <sstream>

namespace cmmcomp::vc {

ProbeSetting default_fast_setting() {
  ProbeSetting s;
  s.name = "fast";
  s.pv_mm_s = 100;
  s.pd_mm = 60;
  s.av_mm_s = 16;
  s.ad_mm = 10;
  return s;
}

ProbeSetting default_slow_setting() {
  ProbeSetting s;
  s.name = "slow";
  s.pv_mm_s = 20;
  s.pd_mm = 60;
  s.av_mm_s = 1;
  s.ad_mm = 2;
  s.compensated = false;
  return s;
}

ProbeSetting parse_setting(const std::string& text, ProbeSetting base) {
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) {
      throw ConfigError("setting '" + text + "': '" + item + "' is not KEY=VALUE");
    }
    const std::string key = item.substr(0, eq);
    const std::string value = item.substr(eq + 1);
    double v = 0;
    std::size_t used = 0;
    try {
      v = std::stod(value, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != value.size() || value.empty() || !std::isfinite(v) || v <= 0) {
      throw ConfigError("setting '" + text + "': " + key + " must be a positive number, not '" +
                        value + "'");
    }
    if (key == "pv") {
      base.pv_mm_s = v;
    } else if (key == "pa") {
      base.pa_mm_s2 = v;
    } else if (key == "pd") {
      base.pd_mm = v;
    } else if (key == "av") {
      base.av_mm_s = v;
    } else if (key == "aa") {
      base.aa_mm_s2 = v;
    } else if (key == "ad") {
      base.ad_mm = v;
    } else {
      throw ConfigError("setting '" + text + "': unknown key '" + key +
                        "' (pv, pa, pd, av, aa, ad)");
    }
  }
  return base;
}

motion::ProbingMove move_of(const ProbeSetting& s) noexcept {
  return motion::probing_move_mm(s.pv_mm_s, s.pa_mm_s2, s.pd_mm, s.av_mm_s, s.aa_mm_s2, s.ad_mm);
}

double time_per_point_s(const ProbeSetting& s, double dwell_s, double smoothing_s) {
  motion::ProbingMove move = move_of(s);
  move.dwell = dwell_s;
  move.smoothing = smoothing_s;
  motion::MoveProfile profile;
  if (!ok(motion::MoveProfile::plan(move, profile))) {
    throw Error("setting '" + s.name + "' cannot be planned (a value out of range)");
  }
  return profile.instants().touch;
}

}  // namespace cmmcomp::vc

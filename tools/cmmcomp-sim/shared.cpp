// SPDX-License-Identifier: MIT
/// @file The move flags and the machine file of cmmcomp-sim's commands.
#include "shared.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace cmmcomp::tools::sim {

CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& text) {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        return std::isfinite(v) ? std::string() : "'" + text + "' is not a finite number";
      },
      "FINITE");
}

void MoveFlags::add_to(CLI::App& app) {
  using L = cmmcomp::motion::MoveLimits;
  const CLI::Validator finite = finite_number();
  const auto range = [&finite](double lo_si, double hi_si) {
    return finite & CLI::Range(lo_si / kMm, hi_si / kMm);
  };
  const struct {
    const char* name;
    double* value;
    const char* what;
    double lo_si, hi_si;
  } flags[] = {
      {"--pv", &pv, "positioning speed PV [mm/s]", L::kMinSpeed, L::kMaxSpeed},
      {"--pa", &pa, "positioning acceleration PA [mm/s^2]", L::kMinAccel, L::kMaxAccel},
      {"--pd", &pd, "positioning distance PD [mm]", L::kMinDistance, L::kMaxDistance},
      {"--av", &av, "approach speed AV [mm/s]", L::kMinSpeed, L::kMaxSpeed},
      {"--aa", &aa, "approach acceleration AA [mm/s^2]", L::kMinAccel, L::kMaxAccel},
      {"--ad", &ad, "approach distance AD [mm]", L::kMinDistance, L::kMaxDistance},
  };
  for (const auto& f : flags) {
    app.add_option(f.name, *f.value, f.what)->check(range(f.lo_si, f.hi_si))->capture_default_str();
  }
  app.add_option("--jerk", jerk, "jerk limit [mm/s^3]; 0 = trapezoidal")
      ->check(finite & (CLI::Range(0.0, 0.0) | range(L::kMinJerk, L::kMaxJerk)))
      ->capture_default_str();
}

cmmcomp::dynamics::Machine machine_from(const std::string& path) {
  if (path.empty()) return cmmcomp::dynamics::default_machine();
  cmmcomp::dynamics::Machine m = cmmcomp::dynamics::load_machine(path);
  for (const std::string& w : cmmcomp::dynamics::implausible_parameters(m.parameters)) {
    std::fprintf(stderr, "warning: %s: %s\n", path.c_str(), w.c_str());
  }
  return m;
}

}  // namespace cmmcomp::tools::sim

// SPDX-License-Identifier: MIT
/// @file The calibration verdict over noise seeds (calibration.hpp).
#include <fmt/format.h>

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/study/calibration.hpp>

namespace cmmcomp::study {

CalibrationResult paper_calibration(const dynamics::Machine& machine,
                                    std::uint64_t seed,
                                    int seeds,
                                    const RunOptions& options) {
  if (seeds < 1) throw ConfigError(fmt::format("--seeds {}: must be at least 1", seeds));
  CalibrationResult out;
  out.machine = machine.name;
  out.seed = seed;
  out.seeds = seeds;
  out.needed = seeds - seeds / 50;  // all but one in 50
  // The noiseless simulations are shared by every seed; only the noise differs.
  const dynamics::PaperSimulations sims =
      dynamics::simulate_paper_experiments(machine, options.threads);
  std::vector<int> held;
  for (int k = 0; k < seeds; ++k) {
    const dynamics::PaperComparison c =
        dynamics::compare_with_paper(sims, seed + static_cast<std::uint64_t>(k));
    if (k == 0) {
      out.first = c;
      held.assign(c.checks.size(), 0);
    }
    for (std::size_t i = 0; i < c.checks.size() && i < held.size(); ++i) {
      held[i] += c.checks[i].passed ? 1 : 0;
    }
    if (options.progress && (k + 1) % 10 == 0) {
      options.progress(fmt::format("{} of {} noise seeds", k + 1, seeds));
    }
  }
  for (std::size_t i = 0; i < held.size(); ++i) {
    out.targets.push_back({out.first.checks[i].requirement,
                           static_cast<double>(held[i]),
                           static_cast<double>(out.needed),
                           Target::Kind::kAtLeast,
                           "seeds"});
  }
  return out;
}

}  // namespace cmmcomp::study

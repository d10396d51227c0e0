// SPDX-License-Identifier: MIT
/// @file Identification from many starts (identify_multistart.hpp).
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cmmcomp/detail/splitmix64.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/study/calibration.hpp>
#include <cmmcomp/study/identify_multistart.hpp>

namespace cmmcomp::study {

PaperIdentification paper_identification(const std::string& paper_dir) {
  PaperIdentification p;
  p.targets.moves = io::read_dataset_csv(paper_dir + "/table1_table2_targets.csv");
  p.targets.compare_magnitudes = true;
  p.targets.anova = training::read_anova_targets(paper_dir + "/table4_anova.csv");
  p.targets.grid_mean = training::read_grid_mean_targets(paper_dir + "/table5_compensation.csv");
  p.targets.anova.sigma_pct = 5;
  p.targets.grid_mean.relative_sigma = 0.05;
  p.options.relative_move_sigma = 0.04;
  p.options.fixed_parameters.clear();
  return p;
}

MultistartResult identify_multistart(const dynamics::Machine& start,
                                     const training::IdentificationTargets& targets,
                                     const training::IdentificationOptions& options,
                                     const MultistartPlan& plan,
                                     const RunOptions& run) {
  if (plan.starts < 1) throw ConfigError("identify-multistart: --starts must be at least 1");
  if (!(plan.spread >= 0 && plan.spread <= 4)) {
    throw ConfigError("identify-multistart: --spread must be 0 .. 4 (a factor of up to 16)");
  }
  if (options.free_parameters.empty()) {
    throw ConfigError("identify-multistart: name the free parameters (--free)");
  }
  if (plan.calibration_seeds < 1) {
    throw ConfigError("identify-multistart: --calibration-seeds must be at least 1");
  }
  // Options every start would refuse: refused once, before minutes of fitting.
  std::string why;
  if (!options.is_valid(&why)) throw ConfigError("identify-multistart: " + why);
  const auto& table = dynamics::machine_parameter_table();
  std::vector<const dynamics::ParameterInfo<dynamics::MachineParameters>*> free;
  for (const std::string& name : options.free_parameters) {
    const dynamics::ParameterInfo<dynamics::MachineParameters>* found = nullptr;
    for (const auto& info : table) {
      if (name == std::string(info.section) + "." + info.key) found = &info;
    }
    if (found == nullptr)
      throw ConfigError("identify-multistart: unknown parameter '" + name + "'");
    free.push_back(found);
  }
  MultistartResult out;
  out.free_parameters = options.free_parameters;
  for (int i = 0; i < plan.starts; ++i) {
    MultistartRow row;
    row.start = i;
    dynamics::Machine m = start;
    if (i > 0) {
      detail::SplitMix64 rng{plan.seed * 1000 + static_cast<std::uint64_t>(i)};
      for (const auto* info : free) {
        info->set(m.parameters,
                  info->get(m.parameters) * std::exp2(plan.spread * (2 * rng.uniform() - 1)));
      }
    }
    for (const auto* info : free) row.start_values.push_back(info->get(m.parameters));
    try {
      const auto t0 = std::chrono::steady_clock::now();
      const training::IdentificationReport r = training::identify_machine(m, targets, options);
      row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      row.initial_cost = r.initial_cost;
      row.final_cost = r.final_cost;
      row.fitted_values = r.fitted_values;
      row.at_bound = r.at_bound;
      if (!r.usable) {
        row.failure = "the fit is not usable: " + r.termination;
      } else {
        const CalibrationResult c =
            paper_calibration(r.fitted, plan.calibration_seed, plan.calibration_seeds, run);
        row.requirements = static_cast<int>(c.targets.size());
        for (const Target& t : c.targets) row.held += t.met() ? 1 : 0;
      }
    } catch (const Error& e) {
      row.failure = e.what();
    }
    if (run.progress) {
      run.progress(row.failure.empty()
                       ? fmt::format("start {}: cost {:.4g} -> {:.4g}, {} of {} requirements held",
                                     i,
                                     row.initial_cost,
                                     row.final_cost,
                                     row.held,
                                     row.requirements)
                       : fmt::format("start {}: {}", i, row.failure));
    }
    out.rows.push_back(std::move(row));
  }
  return out;
}

}  // namespace cmmcomp::study

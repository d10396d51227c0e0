// SPDX-License-Identifier: MIT
/// @file The qualified sweep (qualified_sweep.hpp).
#include <fmt/format.h>

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/study/qualified_sweep.hpp>
#include <cmmcomp/vc/length_test.hpp>
#include <cmmcomp/vc/local_source.hpp>
#include <cmmcomp/vc/twin_probe.hpp>
#include <memory>

namespace cmmcomp::study {

namespace {

/// Whether every Y met MPE_E: {qualified uncompensated, compensated}.
std::pair<bool, bool> passes(const vc::LengthTestResult& r) {
  bool unc = !r.per_y.empty(), comp = !r.per_y.empty();
  for (const vc::YSummary& y : r.per_y) {
    unc = unc && y.fast_uncompensated_pass;
    comp = comp && !y.fast_compensated_pass.empty() && y.fast_compensated_pass[0];
  }
  return {unc, comp};
}

/// The fastest setting whose `passes` is every seed; grid order breaks ties.
std::optional<std::size_t> fastest(const std::vector<SweepSetting>& s,
                                   int SweepSetting::*passes,
                                   int seeds) {
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i].*passes != seeds) continue;
    if (!best || s[i].time_per_point_s < s[*best].time_per_point_s) best = i;
  }
  return best;
}

}  // namespace

SweepResult qualified_sweep(const io::CompensationModelFile& model,
                            const dynamics::Machine& machine,
                            const std::vector<std::uint64_t>& seeds,
                            const SweepGrid& grid,
                            const RunOptions& options) {
  if (seeds.empty()) throw ConfigError("qualified sweep: no noise seed");
  if (grid.pv_mm_s.empty() || grid.pd_mm.empty() || grid.av_mm_s.empty() || grid.ad_mm.empty()) {
    throw ConfigError("qualified sweep: every input of the grid needs at least one value");
  }
  SweepResult out;
  out.model_id = io::model_id(model);
  out.seeds = seeds;
  vc::LocalSource source("model", model, "model " + out.model_id);
  std::vector<vc::CorrectionSource*> agents{&source};
  // One twin per seed serves every setting: a touch's noise depends only on (seed, index).
  std::vector<std::unique_ptr<vc::TwinProbe>> twins;
  for (std::uint64_t seed : seeds) {
    dynamics::MeasurementNoise noise;
    noise.enabled = true;
    noise.seed = seed;
    twins.push_back(std::make_unique<vc::TwinProbe>(machine, noise));
  }
  vc::LengthProgram program;
  program.qualify = true;
  program.qualification.map_setting.name = "map";
  program.dwell_s = machine.parameters.controller_dwell_s;
  program.smoothing_s = machine.parameters.controller_smoothing_s;
  for (double pv : grid.pv_mm_s) {
    for (double pd : grid.pd_mm) {
      for (double av : grid.av_mm_s) {
        for (double ad : grid.ad_mm) {
          program.fast.pv_mm_s = pv;
          program.fast.pd_mm = pd;
          program.fast.av_mm_s = av;
          program.fast.ad_mm = ad;
          program.validate();
          SweepSetting s{pv, pd, av, ad};
          for (auto& twin : twins) {
            const vc::LengthTestResult r = vc::run_length_test(program, *twin, agents);
            s.time_per_point_s = r.fast_time_per_point_s;
            const auto [unc, comp] = passes(r);
            s.uncompensated_passes += unc ? 1 : 0;
            s.compensated_passes += comp ? 1 : 0;
          }
          out.settings.push_back(s);
          if (options.progress) {
            options.progress(fmt::format("PV {} PD {} AV {} AD {}: {:.3f} s per point, {}/{} {}/{}",
                                         pv,
                                         pd,
                                         av,
                                         ad,
                                         s.time_per_point_s,
                                         s.uncompensated_passes,
                                         seeds.size(),
                                         s.compensated_passes,
                                         seeds.size()));
          }
        }
      }
    }
  }
  const int n = static_cast<int>(seeds.size());
  out.fastest_uncompensated = fastest(out.settings, &SweepSetting::uncompensated_passes, n);
  out.fastest_compensated = fastest(out.settings, &SweepSetting::compensated_passes, n);
  if (out.fastest_uncompensated && out.fastest_compensated) {
    out.speedup = out.settings[*out.fastest_uncompensated].time_per_point_s /
                  out.settings[*out.fastest_compensated].time_per_point_s;
  }
  const auto count = [&](int SweepSetting::*passes) {
    double c = 0;
    for (const SweepSetting& s : out.settings) c += s.*passes == n ? 1 : 0;
    return c;
  };
  out.targets = {
      {"a qualified uncompensated setting passes",
       count(&SweepSetting::uncompensated_passes),
       1,
       Target::Kind::kAtLeast,
       "settings"},
      {"a compensated setting passes",
       count(&SweepSetting::compensated_passes),
       1,
       Target::Kind::kAtLeast,
       "settings"},
      {"compensation is not slower", out.speedup, 1, Target::Kind::kAtLeast, "x"},
  };
  return out;
}

}  // namespace cmmcomp::study

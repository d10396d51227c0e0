// SPDX-License-Identifier: MIT
/// @file The whole probing cycle's speed-up (cycle_speedup.hpp).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/dynamics/bridge_model.hpp>
#include <cmmcomp/dynamics/dataset.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <cmmcomp/planning/qualified_reference.hpp>
#include <cmmcomp/study/cycle_speedup.hpp>
#include <cmmcomp/training/machine_identification.hpp>
#include <cmmcomp/vc/length_geometry.hpp>
#include <cmmcomp/vc/length_test.hpp>
#include <cmmcomp/vc/twin_probe.hpp>
#include <cmmcomp/vc/twin_source.hpp>
#include <map>
#include <memory>
#include <numeric>
#include <thread>

namespace cmmcomp::study {
namespace {

using dynamics::BridgeSimulator;
using dynamics::Machine;

/// The reference the project started from (docs/planner.md, "The qualified reference"): the
/// fastest qualified uncompensated setting of the Table 3 box with the shipped controller.
constexpr double kTodaysQualifiedReferenceS = 2.777;

/// A candidate cycle and its time.
struct Candidate {
  motion::ProbingMove cycle;
  double time_s = 0.0;
};

/// Every plannable grid cycle at `pd_mm` whose touch comes at constant speed, fastest first
/// (grid order breaks ties).
std::vector<Candidate> candidates(const CycleGrid& g, double pd_mm) {
  for (const auto* levels :
       {&g.pv_mm_s, &g.pa_mm_s2, &g.av_mm_s, &g.aa_mm_s2, &g.ad_mm, &g.dwell_s, &g.smoothing_s}) {
    if (levels->empty()) throw ConfigError("the cycle grid has a setting without levels");
  }
  std::vector<Candidate> out;
  motion::MoveProfile profile;
  for (const double pv : g.pv_mm_s) {
    for (const double pa : g.pa_mm_s2) {
      for (const double av : g.av_mm_s) {
        for (const double aa : g.aa_mm_s2) {
          for (const double ad : g.ad_mm) {
            for (const double dwell : g.dwell_s) {
              for (const double smoothing : g.smoothing_s) {
                motion::ProbingMove m{
                    pv * 1e-3, pa * 1e-3, pd_mm * 1e-3, av * 1e-3, aa * 1e-3, ad * 1e-3, 0.0};
                m.dwell = dwell;
                m.smoothing = smoothing;
                if (!ok(motion::MoveProfile::plan(m, profile))) continue;
                const motion::PhaseInstants& t = profile.instants();
                if (!(t.approach_accel_end < t.touch)) continue;  // no constant-speed touch
                out.push_back({m, t.touch});
              }
            }
          }
        }
      }
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const Candidate& a, const Candidate& b) {
    return a.time_s < b.time_s;
  });
  return out;
}

/// A machine the judge simulates, with its reversal map when the judge qualifies.
struct Judged {
  Machine machine;
  planning::QualifiedReference reference;
};

/// What one worker thread simulates with: a simulator per machine.
struct Worker {
  std::vector<std::unique_ptr<BridgeSimulator>> sims;  // the truth's variants, then the model
};

/// Judges candidates in time order, `threads` at a time, and returns the first that passes.
/// `judge(worker, candidate, check)` fills the check; it must only use its worker's simulators.
template <typename Judge>
CycleChoice first_passing(const std::vector<Candidate>& all,
                          const std::vector<const Machine*>& machines,
                          const Judge& judge) {
  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<Worker> workers(threads);
  for (Worker& w : workers) {
    for (const Machine* m : machines) w.sims.push_back(std::make_unique<BridgeSimulator>(*m));
  }
  CycleChoice choice;
  constexpr std::size_t kChunk = 64;
  for (std::size_t begin = 0; begin < all.size(); begin += kChunk) {
    const std::size_t end = std::min(all.size(), begin + kChunk);
    std::vector<CycleCheck> checks(end - begin);
    std::atomic<std::size_t> next{begin};
    auto run = [&](Worker& w) {
      for (std::size_t i = next++; i < end; i = next++) judge(w, all[i], checks[i - begin]);
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(run, std::ref(workers[t]));
    run(workers[0]);
    for (std::thread& t : pool) t.join();
    for (std::size_t i = begin; i < end; ++i) {
      if (!checks[i - begin].passes) continue;
      choice.found = true;
      choice.cycle = all[i].cycle;
      choice.time_s = all[i].time_s;
      choice.check = checks[i - begin];
      choice.judged = static_cast<long>(i + 1);
      return choice;
    }
  }
  choice.judged = static_cast<long>(all.size());
  return choice;
}

/// RAE and MAE [µm] of `cycle` at `y_mm`.
errors::DynamicErrors touch(BridgeSimulator& sim, const motion::ProbingMove& cycle, double y_mm) {
  return sim.simulate_cycle(cycle, y_mm * 1e-3).errors_um;
}

/// Y positions, the largest first (where the residuals and MAE are largest: fail fast).
std::vector<double> largest_first(std::vector<double> y) {
  std::sort(y.begin(), y.end(), std::greater<>());
  return y;
}

/// The reversal map of `machine` at the program's Y and the sphere: RAE at the map setting.
planning::QualifiedReference reversal_map(const Machine& machine, const CycleRules& r) {
  BridgeSimulator sim(machine);
  std::vector<double> ys = r.y_mm;
  ys.push_back(r.sphere_y_mm);
  std::sort(ys.begin(), ys.end());
  ys.erase(std::unique(ys.begin(), ys.end()), ys.end());
  planning::QualifiedReference q;
  q.sphere_y_mm = r.sphere_y_mm;
  for (const double y : ys) {
    q.map_y_mm.push_back(y);
    q.map_um.push_back(sim.simulate(vc::move_of(r.map_setting), y * 1e-3).errors_um.rae);
  }
  q.validate();
  return q;
}

std::string at_row(const std::string& machine, double pd) {
  return fmt::format("{} PD {:g}", machine, pd);
}

}  // namespace

double CycleRules::allowance_um() const {
  return budget_um - k95 * sigma_um * std::sqrt(1.0 + scatter_share);
}

CycleRules CycleRules::resolved() const {
  CycleRules r = *this;
  if (r.budget_um == 0.0) r.budget_um = 0.5 * vc::mpe_e_um(20.0);
  if (r.sigma_um == 0.0) r.sigma_um = paper::kTable1Std[3];
  for (const double v : {r.budget_um, r.sigma_um, r.k95, r.scatter_share, r.mae_limit_um}) {
    if (!(std::isfinite(v) && v >= 0.0)) throw ConfigError("cycle rules: a value is not finite");
  }
  if (r.y_mm.empty()) throw ConfigError("cycle rules: no carriage position");
  if (!(r.allowance_um() > 0.0)) {
    throw ConfigError(fmt::format(
        "cycle rules: the budget {:g} um leaves nothing beyond the repeatability's {:g} um",
        r.budget_um,
        r.k95 * r.sigma_um * std::sqrt(1.0 + r.scatter_share)));
  }
  return r;
}

CycleGrid default_cycle_grid(const Machine& machine) {
  const motion::ControllerCapabilities& caps = machine.capabilities;
  // Levels in the file's units, kept inside the capability range of their setting.
  auto within = [&caps](motion::Setting s, const std::vector<double>& levels, double to_si) {
    const motion::SettingRange r = caps[s];
    std::vector<double> out;
    for (const double v : levels) {
      if (r.contains(v * to_si)) out.push_back(v);
    }
    if (out.empty()) out.push_back(r.max / to_si);
    return out;
  };
  using motion::Setting;
  CycleGrid g;
  g.pv_mm_s = within(Setting::kPositioningSpeed, {50, 100, 200, 350, 500}, 1e-3);
  g.pa_mm_s2 = within(Setting::kPositioningAccel, {200, 600, 1200}, 1e-3);
  g.av_mm_s = within(Setting::kApproachSpeed, {1, 2, 4, 6, 8, 10, 12, 14, 16, 20}, 1e-3);
  g.aa_mm_s2 = within(Setting::kApproachAccel, {60, 300, 1200}, 1e-3);
  g.ad_mm = within(Setting::kApproachDistance, {0.5, 1, 2, 3, 5, 7, 10, 15}, 1e-3);
  const double own_dwell = machine.parameters.controller_dwell_s;
  g.dwell_s =
      within(Setting::kDwell, {0, 0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.6, 0.8, own_dwell}, 1.0);
  const double period = 1.0 / machine.parameters.mode_frequency_hz;
  g.smoothing_s =
      within(Setting::kSmoothing, {0, period, machine.parameters.controller_smoothing_s}, 1.0);
  for (auto* levels : {&g.dwell_s, &g.smoothing_s}) {
    std::sort(levels->begin(), levels->end());
    levels->erase(std::unique(levels->begin(), levels->end()), levels->end());
  }
  return g;
}

std::vector<Machine> robustness_variants(const Machine& truth) {
  struct Change {
    const char* label;
    double dynamics::MachineParameters::*member;
    double factor;
  };
  using P = dynamics::MachineParameters;
  const Change changes[] = {{"f1 -2 %", &P::mode_frequency_hz, 0.98},
                            {"f1 +2 %", &P::mode_frequency_hz, 1.02},
                            {"zeta1 -20 %", &P::mode_damping_ratio, 0.8},
                            {"zeta1 +20 %", &P::mode_damping_ratio, 1.2},
                            {"tau -10 %", &P::hose_time_constant_s, 0.9},
                            {"tau +10 %", &P::hose_time_constant_s, 1.1},
                            {"lambda -20 %", &P::hose_accel_lag_s2, 0.8},
                            {"lambda +20 %", &P::hose_accel_lag_s2, 1.2}};
  std::vector<Machine> out;
  for (const Change& c : changes) {
    Machine m = truth;
    m.name = truth.name + " " + c.label;
    m.parameters.*(c.member) *= c.factor;
    out.push_back(m);
  }
  return out;
}

double todays_qualified_reference_s() { return kTodaysQualifiedReferenceS; }

CycleChoice fastest_qualified_cycle(const Machine& truth,
                                    const std::vector<Machine>& variants,
                                    double pd_mm,
                                    const CycleGrid& grid,
                                    const CycleRules& rules) {
  const CycleRules r = rules.resolved();
  std::vector<Judged> judged{{truth, reversal_map(truth, r)}};
  judged.reserve(variants.size() + 1);
  for (const Machine& v : variants) judged.push_back({v, reversal_map(v, r)});
  std::vector<const Machine*> machines;
  machines.reserve(judged.size());
  for (const Judged& j : judged) machines.push_back(&j.machine);
  const std::vector<double> ys = largest_first(r.y_mm);
  const double allowance = r.allowance_um();
  auto judge = [&](Worker& w, const Candidate& c, CycleCheck& check) {
    check.constant_speed_touch = true;
    try {
      for (std::size_t k = 0; k < judged.size(); ++k) {
        BridgeSimulator& sim = *w.sims[k];
        const errors::DynamicErrors sphere = touch(sim, c.cycle, r.sphere_y_mm);
        const double at_sphere = sphere.rae;
        for (const double y : ys) {
          // The sphere's Y is usually one of the program's: simulated once.
          const errors::DynamicErrors e = y == r.sphere_y_mm ? sphere : touch(sim, c.cycle, y);
          const double res = judged[k].reference.residual_um(e.rae, y, at_sphere);
          if (std::abs(res) > check.residual_um) {
            check.residual_um = std::abs(res);
            check.worst_y_mm = y;
            check.worst_machine = judged[k].machine.name;
          }
          check.mae_um = std::max(check.mae_um, std::abs(e.mae));
          if (check.mae_um > r.mae_limit_um) {
            check.binding = "MAE";
            return;
          }
          if (check.residual_um > allowance) {
            check.binding = fmt::format("residual at Y {:g} on {}", y, judged[k].machine.name);
            return;
          }
        }
      }
    } catch (const Error& e) {
      check.binding = std::string("simulation: ") + e.what();
      return;
    }
    check.passes = true;
    check.binding =
        check.residual_um / allowance >= check.mae_um / r.mae_limit_um
            ? fmt::format("residual at Y {:g} on {}", check.worst_y_mm, check.worst_machine)
            : std::string("MAE");
  };
  return first_passing(candidates(grid, pd_mm), machines, judge);
}

CycleChoice fastest_compensated_cycle(const Machine& truth,
                                      const Machine& model,
                                      double pd_mm,
                                      const CycleGrid& grid,
                                      const CycleRules& rules) {
  const CycleRules r = rules.resolved();
  const std::vector<double> ys = largest_first(r.y_mm);
  const double allowance = r.allowance_um();
  const std::vector<const Machine*> machines{&truth, &model};
  auto judge = [&](Worker& w, const Candidate& c, CycleCheck& check) {
    check.constant_speed_touch = true;
    try {
      for (const double y : ys) {
        const errors::DynamicErrors e = touch(*w.sims[0], c.cycle, y);
        check.mae_um = std::max(check.mae_um, std::abs(e.mae));
        if (check.mae_um > r.mae_limit_um) {
          check.binding = "MAE";
          return;
        }
        const double predicted = touch(*w.sims[1], c.cycle, y).rae;
        const double res = e.rae - predicted;
        if (std::abs(res) > check.residual_um) {
          check.residual_um = std::abs(res);
          check.worst_y_mm = y;
          check.worst_machine = truth.name;
        }
        if (check.residual_um > allowance) {
          check.binding = fmt::format("residual at Y {:g}", y);
          return;
        }
      }
    } catch (const Error& e) {
      check.binding = std::string("simulation: ") + e.what();
      return;
    }
    check.passes = true;
    check.binding = check.residual_um / allowance >= check.mae_um / r.mae_limit_um
                        ? fmt::format("residual at Y {:g}", check.worst_y_mm)
                        : std::string("MAE");
  };
  return first_passing(candidates(grid, pd_mm), machines, judge);
}

int length_test_passes(const Machine& truth,
                       const Machine* model,
                       const motion::ProbingMove& cycle,
                       const std::vector<double>& y_mm,
                       int seeds) {
  // The machines run the cycle's own controller timing.
  auto timed = [&cycle](Machine m) {
    m.parameters.controller_dwell_s = cycle.dwell;
    m.parameters.controller_smoothing_s = cycle.smoothing;
    return m;
  };
  const Machine machine = timed(truth);
  vc::LengthProgram program;
  program.y_mm = y_mm;
  program.fast = vc::ProbeSetting{"cycle",
                                  cycle.positioning_speed * 1e3,
                                  cycle.positioning_accel * 1e3,
                                  cycle.positioning_distance * 1e3,
                                  cycle.approach_speed * 1e3,
                                  cycle.approach_accel * 1e3,
                                  cycle.approach_distance * 1e3,
                                  model != nullptr};
  program.dwell_s = cycle.dwell;
  program.smoothing_s = cycle.smoothing;
  program.qualify = model == nullptr;
  int passed = 0;
  for (int seed = 1; seed <= seeds; ++seed) {
    dynamics::MeasurementNoise noise;
    noise.enabled = true;
    noise.seed = static_cast<std::uint64_t>(seed);
    vc::TwinProbe probe(machine, noise);
    std::vector<vc::CorrectionSource*> agents;
    std::unique_ptr<vc::TwinSource> source;
    if (model != nullptr) {
      source = std::make_unique<vc::TwinSource>("identified", timed(*model));
      agents.push_back(source.get());
    }
    const vc::LengthTestResult r = vc::run_length_test(program, probe, agents);
    bool every_y = true;
    for (const vc::YSummary& y : r.per_y) {
      every_y =
          every_y && (model == nullptr ? y.fast_uncompensated_pass : y.fast_compensated_pass.at(0));
    }
    passed += every_y ? 1 : 0;
  }
  return passed;
}

IdentifiedModel identify_from_campaign(const Machine& truth, const CampaignIdentification& c) {
  if (c.moves < 10) throw ConfigError("a campaign needs at least 10 moves");
  const motion::ControllerCapabilities& caps = truth.capabilities;
  using motion::Setting;
  auto range = [&caps](Setting s, double lo, double hi) {
    const motion::SettingRange r = caps[s];
    return std::make_pair(std::max(lo, r.min * 1e3), std::min(hi, r.max * 1e3));
  };
  const auto pv = range(Setting::kPositioningSpeed, 5.0, 500.0);
  const auto pa = range(Setting::kPositioningAccel, 50.0, 1200.0);
  const auto av = range(Setting::kApproachSpeed, 1.0, 20.0);
  const auto aa = range(Setting::kApproachAccel, 50.0, 1200.0);
  const auto ad = range(Setting::kApproachDistance, 0.5, 15.0);
  const doe::Design d =
      doe::latin_hypercube({"PV", "PD", "AV", "AD", "PA", "AA", "Y"},
                           {pv.first, 5.0, av.first, ad.first, pa.first, aa.first, 0.0},
                           {pv.second, 300.0, av.second, ad.second, pa.second, aa.second, 500.0},
                           c.moves,
                           c.seed);
  std::vector<DatasetRow> rows;
  for (const std::vector<double>& v : d.values) {
    DatasetRow r;
    r.pv_mm_s = v[0];
    r.pd_mm = v[1];
    r.av_mm_s = v[2];
    r.ad_mm = v[3];
    r.pa_mm_s2 = v[4];
    r.aa_mm_s2 = v[5];
    r.y_mm = v[6];
    rows.push_back(r);
  }
  dynamics::DatasetOptions noisy;
  noisy.noise.enabled = true;
  noisy.noise.seed = c.seed;
  training::IdentificationTargets targets;
  targets.moves = dynamics::simulate_dataset(truth, rows, noisy);
  training::IdentificationOptions options;
  options.max_iterations = 100;
  options.free_parameters = c.free_parameters;
  // The controller's timing is what the recordings measure (cmmcomp-measure extract), not a fit.
  Machine start = c.start;
  start.capabilities = truth.capabilities;
  start.parameters.controller_dwell_s = truth.parameters.controller_dwell_s;
  start.parameters.controller_smoothing_s = truth.parameters.controller_smoothing_s;
  // The objective has a minimum per mode frequency the smoothing leaves unresolved (the
  // quasi-static lag trades the frequency against the participation): fit from several
  // frequencies and keep the lowest cost.
  training::IdentificationReport report;
  double out_truth_cost = 0.0;
  bool have = false;
  for (const double scale : c.frequency_starts) {
    Machine s = start;
    s.parameters.mode_frequency_hz *= scale;
    training::IdentificationReport r;
    try {
      r = training::identify_machine(s, targets, options);
    } catch (const ConfigError&) {
      continue;  // a start outside the plausible range
    }
    if (!r.usable) continue;
    if (!have || r.final_cost < report.final_cost) report = r;
    have = true;
  }
  if (!have) throw Error("no identification from the campaign's starts converged");
  // The cost the truth itself has on these moves: a fit above it stopped in a local minimum.
  {
    training::IdentificationOptions once = options;
    once.max_iterations = 1;
    Machine at_truth = truth;
    at_truth.name = start.name;
    out_truth_cost = training::identify_machine(at_truth, targets, once).initial_cost;
  }
  IdentifiedModel out;
  out.truth_cost = out_truth_cost;
  out.machine = report.fitted;
  out.machine.name = truth.name + " identified";
  out.parameters = report.free_parameters;
  out.fitted_values = report.fitted_values;
  out.relative_sigma = report.relative_sigma;
  out.final_cost = report.final_cost;
  out.residuals = static_cast<int>(report.residuals.size());
  for (const std::string& key : report.free_parameters) {
    for (const auto& info : dynamics::machine_parameter_table()) {
      if (key == std::string(info.section) + "." + info.key) {
        out.truth_values.push_back(info.get(truth.parameters));
      }
    }
  }
  return out;
}

CycleSpeedupResult cycle_speedup(const std::vector<CycleSubject>& subjects,
                                 const std::vector<double>& pd_mm,
                                 const CycleRules& rules,
                                 const CampaignIdentification* campaign,
                                 const std::function<void(const std::string&)>& progress,
                                 int length_test_seeds) {
  const CycleRules r = rules.resolved();
  CycleSpeedupResult result;
  result.rules = r;
  for (CycleSubject s : subjects) {
    if (!s.has_model && campaign != nullptr) {
      if (progress) progress(fmt::format("{}: identifying from its campaign", s.truth.name));
      result.identified.push_back(identify_from_campaign(s.truth, *campaign));
      s.model = result.identified.back().machine;
      s.has_model = true;
    }
    const CycleGrid grid = default_cycle_grid(s.truth);
    const std::vector<Machine> variants = robustness_variants(s.truth);
    for (const double pd : pd_mm) {
      CycleSpeedupRow row;
      row.machine = s.truth.name;
      row.pd_mm = pd;
      if (progress) progress(fmt::format("{} PD {:g}: qualified", s.truth.name, pd));
      row.qualified = fastest_qualified_cycle(s.truth, variants, pd, grid, r);
      if (progress) progress(fmt::format("{} PD {:g}: oracle", s.truth.name, pd));
      row.oracle = fastest_compensated_cycle(s.truth, s.truth, pd, grid, r);
      if (s.has_model) {
        if (progress) progress(fmt::format("{} PD {:g}: identified model", s.truth.name, pd));
        row.identified = fastest_compensated_cycle(s.truth, s.model, pd, grid, r);
        row.has_identified = true;
        if (length_test_seeds > 0) {
          if (progress) progress(fmt::format("{} PD {:g}: length tests", s.truth.name, pd));
          row.length_test_seeds = length_test_seeds;
          if (row.qualified.found) {
            row.qualified_seeds_passed = length_test_passes(
                s.truth, nullptr, row.qualified.cycle, r.y_mm, length_test_seeds);
          }
          if (row.identified.found) {
            row.identified_seeds_passed = length_test_passes(
                s.truth, &s.model, row.identified.cycle, r.y_mm, length_test_seeds);
          }
          result.targets.push_back({at_row(s.truth.name, pd) + " qualified length test seeds",
                                    static_cast<double>(row.qualified_seeds_passed),
                                    static_cast<double>(length_test_seeds),
                                    Target::Kind::kAtLeast,
                                    "seeds"});
          result.targets.push_back({at_row(s.truth.name, pd) + " compensated length test seeds",
                                    static_cast<double>(row.identified_seeds_passed),
                                    static_cast<double>(length_test_seeds),
                                    Target::Kind::kAtLeast,
                                    "seeds"});
        }
        const std::string at = at_row(s.truth.name, pd);
        const double comp = row.identified.found ? row.identified.time_s : 0.0;
        const double qual = row.qualified.found ? row.qualified.time_s : 0.0;
        result.targets.push_back({at + " compensated vs qualified, same freedom",
                                  comp > 0.0 ? qual / comp : 0.0,
                                  1.4,
                                  Target::Kind::kAtLeast,
                                  "x"});
        result.targets.push_back({at + " compensated vs today's reference",
                                  comp > 0.0 ? kTodaysQualifiedReferenceS / comp : 0.0,
                                  3.5,
                                  Target::Kind::kAtLeast,
                                  "x"});
      }
      result.rows.push_back(row);
    }
  }
  return result;
}

}  // namespace cmmcomp::study

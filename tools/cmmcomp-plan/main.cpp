// SPDX-License-Identifier: MIT
/// @file cmmcomp-plan: the feed planner (docs/planner.md). From a model with its U95, a point
/// error budget, the machine's limits and the feature's geometry, the fastest probing setting
/// with compensation and the fastest without, their times per point and the ratio.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/default_model.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/planning/feed_planner.hpp>
#include <cstdio>
#include <exception>
#include <nlohmann/json.hpp>
#include <string>
#include <variant>
#include <vector>

#include "../common/usage.hpp"

namespace {

namespace planning = cmmcomp::planning;

struct Options {
  std::string model;
  std::vector<std::string> model_at;  // Y=PATH, a model per Y
  double budget_um = 0.0;
  std::string mpe_e = "1.9,300";
  double length_mm = 20.0;
  double share = 0.5;
  double mae_limit_um = 25.0;
  std::string pv = "0:1e9";
  std::string av = "0:1e9";
  std::string pa = "0:1e9";
  std::string aa = "0:1e9";
  std::string pd = "0:1e9";
  std::string ad = "0:1e9";
  std::string y = "250";
  double z_mm = 0.0;
  std::string machine;
  int grid = 11;
  double edge_margin = 0.0;
  int brute_force = 0;
  double trained_pa = 200.0;
  double trained_aa = 60.0;
  bool trained_pa_given = false, trained_aa_given = false;
  double coverage = 0.95;
  std::string vc_settings;
  bool json = false;
  std::string reversal_map;  // Y=UM,…: the qualified reference's map (cmmcomp-vc --qualify)
  double sphere_y_mm = 250.0;
};

double parse_number(const std::string& text, const std::string& option) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v)) {
    throw cmmcomp::ConfigError(option + ": '" + text + "' is not a number");
  }
  return v;
}

/// "LO:HI" → an interval.
planning::Interval parse_interval(const std::string& text, const std::string& option) {
  const auto colon = text.find(':');
  if (colon == std::string::npos) {
    throw cmmcomp::ConfigError(option + ": '" + text + "' is not LO:HI");
  }
  const planning::Interval i{parse_number(text.substr(0, colon), option),
                             parse_number(text.substr(colon + 1), option)};
  if (i.lo < 0 || i.lo > i.hi) {
    throw cmmcomp::ConfigError(option + ": '" + text + "' needs 0 <= LO <= HI");
  }
  return i;
}

/// "a,b,c" → {"a", "b", "c"} (an empty text is one empty item).
std::vector<std::string> split_commas(const std::string& text) {
  std::vector<std::string> items;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t comma = std::min(text.find(',', pos), text.size());
    items.push_back(text.substr(pos, comma - pos));
    pos = comma + 1;
  }
  return items;
}

std::vector<double> parse_list(const std::string& text, const std::string& option) {
  std::vector<double> v;
  for (const std::string& item : split_commas(text)) v.push_back(parse_number(item, option));
  return v;
}

nlohmann::json setting_json(const planning::FeedSetting& s) {
  return {{"pv_mm_s", s.pv_mm_s},
          {"pa_mm_s2", s.pa_mm_s2},
          {"pd_mm", s.pd_mm},
          {"av_mm_s", s.av_mm_s},
          {"aa_mm_s2", s.aa_mm_s2},
          {"ad_mm", s.ad_mm}};
}

nlohmann::json result_json(const planning::PlanResult& r) {
  nlohmann::json j = {
      {"mode", planning::to_string(r.mode)}, {"found", r.found}, {"evaluations", r.evaluations}};
  if (r.found) {
    j["setting"] = setting_json(r.setting);
    j["vc_setting"] = fmt::format("pv={:.6g},pa={:.6g},pd={:.6g},av={:.6g},aa={:.6g},ad={:.6g}",
                                  r.setting.pv_mm_s,
                                  r.setting.pa_mm_s2,
                                  r.setting.pd_mm,
                                  r.setting.av_mm_s,
                                  r.setting.aa_mm_s2,
                                  r.setting.ad_mm);
    j["time_per_point_s"] = r.check.time_per_point_s;
    j["point_bound_um"] = r.check.point_bound_um;
    j["mae_bound_um"] = r.check.mae_bound_um;
    j["worst_y_mm"] = r.check.worst_y_mm;
    j["rae_um"] = r.check.rae_um;
    j["u95_rae_um"] = r.check.u95_rae_um;
  } else {
    j["best_point_bound_um"] = r.best_point_bound_um;
    j["best_point_setting"] = setting_json(r.best_point_setting);
  }
  return j;
}

/// The qualified reference the uncompensated bound used, or null.
nlohmann::json qualified_json(const planning::PlanProblem& p) {
  if (!p.qualified) return nullptr;
  nlohmann::json map = nlohmann::json::array();
  for (std::size_t i = 0; i < p.qualified->map_y_mm.size(); ++i) {
    map.push_back({{"y_mm", p.qualified->map_y_mm[i]}, {"rae_um", p.qualified->map_um[i]}});
  }
  return {{"sphere_y_mm", p.qualified->sphere_y_mm}, {"map", map}};
}

/// One table row; `qualified`: the uncompensated row is judged with the qualified reference.
std::string row(const planning::PlanResult& r, bool qualified) {
  const auto& s = r.setting;
  const std::string mode =
      std::string(planning::to_string(r.mode)) +
      (qualified && r.mode == planning::Mode::kUncompensated ? ", qualified" : "");
  if (!r.found) {
    return fmt::format(
        "| {} | none in the domain meets the budget: the smallest bound is {:.3f} µm "
        "(PV {:.4g}, PD {:.4g}, AV {:.4g}, AD {:.4g}) | | | | | | | |\n",
        mode,
        r.best_point_bound_um,
        r.best_point_setting.pv_mm_s,
        r.best_point_setting.pd_mm,
        r.best_point_setting.av_mm_s,
        r.best_point_setting.ad_mm);
  }
  return fmt::format(
      "| {} | {:.2f} | {:.0f} | {:.2f} | {:.3f} | {:.0f} | {:.3f} | {:.3f} | {:.3f} (Y {:.0f}) | "
      "{:.2f} |\n",
      mode,
      s.pv_mm_s,
      s.pa_mm_s2,
      s.pd_mm,
      s.av_mm_s,
      s.aa_mm_s2,
      s.ad_mm,
      r.check.time_per_point_s,
      r.check.point_bound_um,
      r.check.worst_y_mm,
      r.check.mae_bound_um);
}

/// "Y=UM,Y=UM,…" of --reversal-map (what cmmcomp-vc --qualify --map-only prints) → the
/// qualified reference with the sphere at `sphere_y_mm`. Throws ConfigError.
planning::QualifiedReference parse_reversal_map(const std::string& text, double sphere_y_mm) {
  planning::QualifiedReference q;
  q.sphere_y_mm = sphere_y_mm;
  for (const std::string& node : split_commas(text)) {
    const auto eq = node.find('=');
    if (eq == std::string::npos) {
      throw cmmcomp::ConfigError("--reversal-map: '" + node + "' is not Y=UM");
    }
    q.map_y_mm.push_back(parse_number(node.substr(0, eq), "--reversal-map"));
    q.map_um.push_back(parse_number(node.substr(eq + 1), "--reversal-map"));
  }
  q.validate();
  return q;
}

/// "Y=PATH" of --model-at → the model and its Y.
planning::ModelAtY parse_model_at(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq + 1 == text.size()) {
    throw cmmcomp::ConfigError("--model-at: '" + text + "' is not Y=PATH");
  }
  return planning::ModelAtY{parse_number(text.substr(0, eq), "--model-at"),
                            cmmcomp::io::load_compensation_model(text.substr(eq + 1))};
}

int run(const Options& opt, bool y_given) {
  std::vector<planning::ModelAtY> per_y;
  for (const std::string& m : opt.model_at) per_y.push_back(parse_model_at(m));
  const cmmcomp::io::CompensationModelFile model =
      opt.model.empty() ? cmmcomp::io::CompensationModelFile(cmmcomp::io::default_model_file())
                        : cmmcomp::io::load_compensation_model(opt.model);
  const cmmcomp::dynamics::Machine machine = opt.machine.empty()
                                                 ? cmmcomp::dynamics::default_machine()
                                                 : cmmcomp::dynamics::load_machine(opt.machine);
  for (const std::string& w : cmmcomp::dynamics::implausible_parameters(machine.parameters)) {
    std::fprintf(stderr, "warning: %s: %s\n", opt.machine.c_str(), w.c_str());
  }
  planning::PlanProblem p;
  std::string budget_source;
  if (opt.budget_um > 0) {
    p.budget_um = opt.budget_um;
    budget_source = "given";
  } else {
    const std::vector<double> ak = parse_list(opt.mpe_e, "--mpe-e");
    if (ak.size() != 2 || ak[0] < 0 || ak[1] <= 0) {
      throw cmmcomp::ConfigError("--mpe-e: give A,K of MPE_E = A + L/K µm, e.g. 1.9,300");
    }
    if (!(opt.share > 0 && opt.share <= 1) || !(opt.length_mm >= 0)) {
      throw cmmcomp::ConfigError("--share must be in (0, 1] and --length >= 0");
    }
    p.budget_um = opt.share * (ak[0] + opt.length_mm / ak[1]);
    budget_source = fmt::format(
        "{} × MPE_E({} mm), MPE_E = {} + L/{} µm", opt.share, opt.length_mm, ak[0], ak[1]);
  }
  p.mae_limit_um = opt.mae_limit_um;
  p.pv_mm_s = parse_interval(opt.pv, "--pv");
  p.av_mm_s = parse_interval(opt.av, "--av");
  p.pa_mm_s2 = parse_interval(opt.pa, "--pa");
  p.aa_mm_s2 = parse_interval(opt.aa, "--aa");
  p.pd_mm = parse_interval(opt.pd, "--pd");
  p.ad_mm = parse_interval(opt.ad, "--ad");
  p.y_mm = parse_list(opt.y, "--y");
  if (!per_y.empty() && !y_given) {  // the program's Y: where the models are
    p.y_mm.clear();
    for (const auto& m : per_y) p.y_mm.push_back(m.y_mm);
  }
  p.z_mm = opt.z_mm;
  std::vector<const cmmcomp::io::TrainingConditions*> trained;
  std::vector<std::string> trained_ids;
  for (const auto& m : per_y) {
    trained.push_back(&cmmcomp::io::training_conditions(m.model));
    trained_ids.push_back(cmmcomp::io::model_id(m.model));
  }
  if (per_y.empty()) {
    trained.push_back(&cmmcomp::io::training_conditions(model));
    trained_ids.push_back(cmmcomp::io::model_id(model));
  }
  planning::GivenConditions given;
  if (opt.trained_pa_given) given.pa_mm_s2 = opt.trained_pa;
  if (opt.trained_aa_given) given.aa_mm_s2 = opt.trained_aa;
  if (!opt.machine.empty()) {
    given.dwell_s = machine.parameters.controller_dwell_s;
    given.smoothing_s = machine.parameters.controller_smoothing_s;
    given.machine_label = "the controller of " + opt.machine;
  }
  const planning::PlanConditions conditions =
      planning::resolve_conditions(trained, trained_ids, given);
  p.dwell_s = conditions.dwell_s;
  p.smoothing_s = conditions.smoothing_s;
  p.grid_points = opt.grid;
  p.pa_mm_s2_model = conditions.pa_mm_s2;
  p.aa_mm_s2_model = conditions.aa_mm_s2;
  p.coverage = opt.coverage;
  p.edge_margin = opt.edge_margin;
  if (!opt.reversal_map.empty())
    p.qualified = parse_reversal_map(opt.reversal_map, opt.sphere_y_mm);
  const planning::FeedPlanner planner =
      per_y.empty() ? planning::FeedPlanner(model, p) : planning::FeedPlanner(per_y, p);

  const auto has_corner_gain = [](const cmmcomp::io::CompensationModelFile& file) {
    return std::visit(
        [](const auto& f) {
          for (double k : f.interval.corner_gain) {
            if (k > 0) return true;
          }
          return false;
        },
        file);
  };
  bool corner_aware = per_y.empty() ? has_corner_gain(model) : true;
  for (const auto& m : per_y) corner_aware = corner_aware && has_corner_gain(m.model);
  if (!corner_aware && p.edge_margin == 0) {
    std::fprintf(stderr,
                 "cmmcomp-plan: note: this model's interval has no corner gain (a format-2 file, "
                 "or a fit whose residuals did not grow towards the corners), so its U95 may be "
                 "too narrow in the corners where the fastest settings lie; --edge-margin 0.2 "
                 "keeps clear of them (docs/planner.md)\n");
  }
  const planning::PlanResult compensated = planner.plan(planning::Mode::kCompensated);
  const planning::PlanResult raw = planner.plan(planning::Mode::kUncompensated);
  const bool both = compensated.found && raw.found;
  const double ratio = both ? raw.check.time_per_point_s / compensated.check.time_per_point_s : 0;

  if (!opt.vc_settings.empty()) {
    std::string text;
    for (const auto* r : {&compensated, &raw}) {
      if (r->found) {
        text += std::string(planning::to_string(r->mode)) + "=" +
                result_json(*r)["vc_setting"].get<std::string>() + "\n";
      }
    }
    cmmcomp::io::write_file_atomically(opt.vc_settings, text);
  }

  std::vector<planning::PlanResult> brute;
  if (opt.brute_force > 0) {
    brute.push_back(planner.brute_force(planning::Mode::kCompensated, opt.brute_force));
    brute.push_back(planner.brute_force(planning::Mode::kUncompensated, opt.brute_force));
  }

  if (opt.json) {
    nlohmann::json models = nlohmann::json::array();
    for (std::size_t k = 0; k < p.y_mm.size(); ++k) {
      models.push_back({{"y_mm", p.y_mm[k]},
                        {"model_id", planner.model_ids()[k]},
                        {"model_inputs", planner.model_inputs()[k]}});
    }
    nlohmann::json j = {{"model_id", planner.model_ids().front()},
                        {"model_inputs", planner.model_inputs().front()},
                        {"models_per_y", planner.models_per_y()},
                        {"models", models},
                        {"budget_um", p.budget_um},
                        {"coverage", p.coverage},
                        {"budget_source", budget_source},
                        {"mae_limit_um", p.mae_limit_um},
                        {"y_mm", p.y_mm},
                        {"dwell_s", p.dwell_s},
                        {"smoothing_s", p.smoothing_s},
                        {"edge_margin", p.edge_margin},
                        {"box",
                         {{"pv_mm_s", {planner.pv_mm_s().lo, planner.pv_mm_s().hi}},
                          {"pd_mm", {planner.pd_mm().lo, planner.pd_mm().hi}},
                          {"av_mm_s", {planner.av_mm_s().lo, planner.av_mm_s().hi}},
                          {"ad_mm", {planner.ad_mm().lo, planner.ad_mm().hi}}}},
                        {"qualified", qualified_json(p)},
                        {"compensated", result_json(compensated)},
                        {"uncompensated", result_json(raw)},
                        {"speedup", both ? nlohmann::json(ratio) : nlohmann::json(nullptr)}};
    if (!brute.empty()) {
      j["brute_force"] = {{"points_per_input", opt.brute_force},
                          {"compensated", result_json(brute[0])},
                          {"uncompensated", result_json(brute[1])}};
    }
    std::printf("%s\n", j.dump(2).c_str());
    return compensated.found ? 0 : 1;
  }
  std::string models;
  if (planner.models_per_y()) {
    models = "models per Y:";
    for (std::size_t k = 0; k < p.y_mm.size(); ++k) {
      models += fmt::format("{} Y {:g} mm {} ({} inputs)",
                            k == 0 ? "" : ",",
                            p.y_mm[k],
                            planner.model_ids()[k],
                            planner.model_inputs()[k]);
    }
  } else {
    models = fmt::format(
        "model {} ({} inputs)", planner.model_ids().front(), planner.model_inputs().front());
  }
  std::string out = fmt::format(
      "cmmcomp-plan: {}; point budget {:.3f} µm at {:g} % ({}); "
      "|MAE| + U95 <= {} µm\n",
      models,
      p.budget_um,
      p.coverage * 100,
      budget_source,
      p.mae_limit_um);
  std::string ys;
  for (double y : p.y_mm) ys += (ys.empty() ? "" : ", ") + fmt::format("{:g}", y);
  out += fmt::format(
      "search box (limits within the model's ranges, edge margin {:g}): PV {:g}–{:g} mm/s, PD "
      "{:g}–{:g} mm, "
      "AV {:g}–{:g} mm/s, AD {:g}–{:g} mm; PA {:g}, AA {:g} mm/s² ({}); Y {} mm; "
      "dwell {:g} s, smoothing {:g} s ({})\n",
      p.edge_margin,
      planner.pv_mm_s().lo,
      planner.pv_mm_s().hi,
      planner.pd_mm().lo,
      planner.pd_mm().hi,
      planner.av_mm_s().lo,
      planner.av_mm_s().hi,
      planner.ad_mm().lo,
      planner.ad_mm().hi,
      p.pa_mm_s2_model,
      p.aa_mm_s2_model,
      conditions.acceleration_source,
      ys,
      p.dwell_s,
      p.smoothing_s,
      conditions.timing_source);
  if (p.qualified) {
    std::string nodes;
    for (std::size_t i = 0; i < p.qualified->map_y_mm.size(); ++i) {
      nodes += fmt::format(
          "{}Y {:g} {:+.3f}", i ? ", " : "", p.qualified->map_y_mm[i], p.qualified->map_um[i]);
    }
    out += fmt::format(
        "uncompensated: qualified on a sphere at Y {:g} mm with the reversal map {} µm; its "
        "bound is |residual| + √(U95(Y)² + U95(Y {:g})²) (docs/planner.md)\n",
        p.qualified->sphere_y_mm,
        nodes,
        p.qualified->sphere_y_mm);
  }
  out += "\n";
  out +=
      "| setting | PV mm/s | PA mm/s² | PD mm | AV mm/s | AA mm/s² | AD mm | time per point s | "
      "point bound µm (worst Y) | MAE bound µm |\n";
  out += "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  const bool qualified = p.qualified.has_value();
  out += row(compensated, qualified) + row(raw, qualified);
  if (both) {
    out += fmt::format(
        "\ncompensation: {:.2f}x less time per point than the fastest "
        "{}uncompensated setting that meets the same budget\n",
        ratio,
        qualified ? "qualified " : "");
  } else if (compensated.found) {
    out += fmt::format(
        "\nno {}uncompensated setting inside the model's domain meets the budget: compensation "
        "is what makes this budget reachable in the domain\n",
        qualified ? "qualified " : "");
  }
  for (const auto& b : brute) {
    out +=
        fmt::format("brute force ({}^4 grid, {}): ", opt.brute_force, planning::to_string(b.mode));
    out += b.found ? fmt::format("{:.4f} s per point\n", b.check.time_per_point_s)
                   : std::string("none feasible\n");
  }
  std::printf("%s", out.c_str());
  return compensated.found ? 0 : 1;
}

}  // namespace

static int run_tool(int argc, char** argv) {
  CLI::App app{
      "cmmcomp-plan: the fastest probing setting whose point error meets a budget at a coverage "
      "(95 %), with "
      "the model's correction and without it (docs/planner.md)."};
  Options opt;
  auto* one_model = app.add_option("--model",
                                   opt.model,
                                   "model file with an interval calibration (default: the "
                                   "shipped 4-input model)");
  app.add_option("--model-at",
                 opt.model_at,
                 "Y=PATH: a model per carriage position (repeat it: one trained at each Y); the "
                 "setting is judged at each Y by its model, and --y defaults to these Y")
      ->excludes(one_model);
  auto* budget =
      app.add_option("--budget-um", opt.budget_um, "point error budget [µm] (instead of --mpe-e)")
          ->check(CLI::PositiveNumber);
  app.add_option("--coverage",
                 opt.coverage,
                 "the coverage the budget is stated at; every model's interval must have been "
                 "calibrated at it (cmmcomp-train fit --interval-coverage)")
      ->check(CLI::Range(0.5, 0.999))
      ->capture_default_str();
  auto* mpe_e =
      app.add_option("--mpe-e", opt.mpe_e, "A,K of MPE_E = A + L/K µm")->capture_default_str();
  auto* length = app.add_option("--length", opt.length_mm, "length L of the MPE_E budget [mm]")
                     ->capture_default_str();
  auto* share =
      app.add_option("--share",
                     opt.share,
                     "share of MPE_E(L) one point may use (0.5: a bidirectional length's two "
                     "touches)")
          ->capture_default_str();
  budget->excludes(mpe_e)->excludes(length)->excludes(share);
  app.add_option("--mae-limit-um", opt.mae_limit_um, "bound on |MAE| + U95(MAE) [µm]")
      ->capture_default_str();
  app.add_option("--pv", opt.pv, "the machine's PV range LO:HI [mm/s]")->capture_default_str();
  app.add_option("--av", opt.av, "the machine's AV range LO:HI [mm/s]")->capture_default_str();
  app.add_option("--pa", opt.pa, "the machine's PA range LO:HI [mm/s²]")->capture_default_str();
  app.add_option("--aa", opt.aa, "the machine's AA range LO:HI [mm/s²]")->capture_default_str();
  app.add_option("--pd", opt.pd, "PD the feature allows LO:HI [mm] (LO: its minimum)")
      ->capture_default_str();
  app.add_option("--ad", opt.ad, "AD the feature allows LO:HI [mm] (LO: its minimum)")
      ->capture_default_str();
  auto* y_option = app.add_option("--y", opt.y, "carriage positions the setting must hold at [mm]")
                       ->capture_default_str();
  app.add_option("--z", opt.z_mm, "ram position [mm]")->capture_default_str();
  app.add_option("--machine",
                 opt.machine,
                 "machine file whose controller dwell and smoothing count in the time per point "
                 "(default: those the model was trained at; it must agree with them)");
  app.add_option("--edge-margin",
                 opt.edge_margin,
                 "share of each model input's range kept clear at both ends, in [0, 0.45) "
                 "(docs/planner.md)")
      ->capture_default_str();
  app.add_option("--grid", opt.grid, "points per input of the global grid")
      ->capture_default_str()
      ->check(CLI::Range(2, 41));
  app.add_option("--brute-force",
                 opt.brute_force,
                 "also search an N^4 grid exhaustively and print its best (a check; 0: none)")
      ->check(CLI::Range(0, 41) & !CLI::IsMember({1}));
  CLI::Option* trained_pa =
      app.add_option("--trained-pa",
                     opt.trained_pa,
                     "PA to plan at [mm/s²], within the model's training range (default: the "
                     "highest the model file records; needed for a model that records none)")
          ->check(CLI::PositiveNumber);
  CLI::Option* trained_aa =
      app.add_option("--trained-aa",
                     opt.trained_aa,
                     "AA to plan at [mm/s²], within the model's training range (default: the "
                     "highest the model file records; needed for a model that records none)")
          ->check(CLI::PositiveNumber);
  app.add_option("--vc-settings",
                 opt.vc_settings,
                 "also write the two settings as cmmcomp-vc --fast/--slow values to FILE: lines "
                 "'compensated=…' and 'uncompensated=…' (a line only for a setting found)");
  auto* map = app.add_option(
      "--reversal-map",
      opt.reversal_map,
      "Y=UM,…: judge the uncompensated setting as a CMM with this static reversal map and its "
      "probe qualified at the measuring setting (cmmcomp-vc --qualify --map-only prints it; "
      "needs a model that sees Y; docs/planner.md, \"The qualified reference\")");
  app.add_option(
         "--sphere-y", opt.sphere_y_mm, "with --reversal-map: the reference sphere's Y [mm]")
      ->capture_default_str()
      ->needs(map);
  app.add_flag("--json", opt.json, "print the result as JSON");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cmmcomp::tools::usage_exit(app, e);
  }
  opt.trained_pa_given = trained_pa->count() > 0;
  opt.trained_aa_given = trained_aa->count() > 0;
  try {
    return run(opt, y_option->count() > 0);
  } catch (const cmmcomp::ConfigError& e) {
    std::fprintf(stderr, "cmmcomp-plan: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cmmcomp-plan: %s\n", e.what());
    return 1;
  }
}

int main(int argc, char** argv) {
  return cmmcomp::tools::guarded_main("cmmcomp-plan", run_tool, argc, argv);
}

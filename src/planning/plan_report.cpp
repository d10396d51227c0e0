// SPDX-License-Identifier: MIT
/// @file cmmcomp-plan's question and report (include/cmmcomp/planning/plan_report.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/planning/plan_report.hpp>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <variant>
#include <vector>

namespace cmmcomp::planning {
namespace {

double parse_number(const std::string& text, const std::string& option) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v)) {
    throw ConfigError(option + ": '" + text + "' is not a number");
  }
  return v;
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

bool has_corner_gain(const io::CompensationModelFile& file) {
  return std::visit(
      [](const auto& f) {
        for (const double k : f.interval.corner_gain) {
          if (k > 0) return true;
        }
        return false;
      },
      file);
}

nlohmann::json setting_json(const FeedSetting& s) {
  return {{"pv_mm_s", s.pv_mm_s},
          {"pa_mm_s2", s.pa_mm_s2},
          {"pd_mm", s.pd_mm},
          {"av_mm_s", s.av_mm_s},
          {"aa_mm_s2", s.aa_mm_s2},
          {"ad_mm", s.ad_mm}};
}

/// The setting as cmmcomp-vc --fast/--slow takes it.
std::string vc_setting(const FeedSetting& s) {
  return fmt::format("pv={:.6g},pa={:.6g},pd={:.6g},av={:.6g},aa={:.6g},ad={:.6g}",
                     s.pv_mm_s,
                     s.pa_mm_s2,
                     s.pd_mm,
                     s.av_mm_s,
                     s.aa_mm_s2,
                     s.ad_mm);
}

nlohmann::json result_json(const PlanResult& r) {
  nlohmann::json j = {
      {"mode", to_string(r.mode)}, {"found", r.found}, {"evaluations", r.evaluations}};
  if (r.found) {
    j["setting"] = setting_json(r.setting);
    j["vc_setting"] = vc_setting(r.setting);
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
nlohmann::json qualified_json(const PlanProblem& p) {
  if (!p.qualified) return nullptr;
  nlohmann::json map = nlohmann::json::array();
  for (std::size_t i = 0; i < p.qualified->map_y_mm.size(); ++i) {
    map.push_back({{"y_mm", p.qualified->map_y_mm[i]}, {"rae_um", p.qualified->map_um[i]}});
  }
  return {{"sphere_y_mm", p.qualified->sphere_y_mm}, {"map", map}};
}

/// One table row; `qualified`: the uncompensated row is judged with the qualified reference.
std::string row(const PlanResult& r, bool qualified) {
  const auto& s = r.setting;
  const std::string mode = std::string(to_string(r.mode)) +
                           (qualified && r.mode == Mode::kUncompensated ? ", qualified" : "");
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

}  // namespace

double PlanReport::speedup() const {
  return compensated.found && uncompensated.found
             ? uncompensated.check.time_per_point_s / compensated.check.time_per_point_s
             : 0.0;
}

PlanReport plan_feeds(const io::CompensationModelFile& model,
                      const std::vector<ModelAtY>& per_y,
                      PlanRequest request) {
  PlanReport report;
  PlanProblem& p = request.problem;
  const BudgetSpec& b = request.budget;
  if (b.budget_um > 0) {
    p.budget_um = b.budget_um;
    report.budget_source = "given";
  } else {
    if (!(b.mpe_a_um >= 0) || !(b.mpe_k > 0)) {
      throw ConfigError("--mpe-e: give A,K of MPE_E = A + L/K µm, e.g. 1.9,300");
    }
    if (!(b.share > 0 && b.share <= 1) || !(b.length_mm >= 0)) {
      throw ConfigError("--share must be in (0, 1] and --length >= 0");
    }
    p.budget_um = b.share * (b.mpe_a_um + b.length_mm / b.mpe_k);
    report.budget_source = fmt::format(
        "{} × MPE_E({} mm), MPE_E = {} + L/{} µm", b.share, b.length_mm, b.mpe_a_um, b.mpe_k);
  }
  if (!per_y.empty() && !request.y_given) {  // the program's Y: where the models are
    p.y_mm.clear();
    for (const auto& m : per_y) p.y_mm.push_back(m.y_mm);
  }
  std::vector<const io::TrainingConditions*> trained;
  std::vector<std::string> trained_ids;
  for (const auto& m : per_y) {
    trained.push_back(&io::training_conditions(m.model));
    trained_ids.push_back(io::model_id(m.model));
  }
  if (per_y.empty()) {
    trained.push_back(&io::training_conditions(model));
    trained_ids.push_back(io::model_id(model));
  }
  report.conditions = resolve_conditions(trained, trained_ids, request.given);
  p.dwell_s = report.conditions.dwell_s;
  p.smoothing_s = report.conditions.smoothing_s;
  p.pa_mm_s2_model = report.conditions.pa_mm_s2;
  p.aa_mm_s2_model = report.conditions.aa_mm_s2;
  const FeedPlanner planner = per_y.empty() ? FeedPlanner(model, p) : FeedPlanner(per_y, p);

  report.corner_aware = per_y.empty() ? has_corner_gain(model) : true;
  for (const auto& m : per_y) report.corner_aware = report.corner_aware && has_corner_gain(m.model);
  report.compensated = planner.plan(Mode::kCompensated);
  report.uncompensated = planner.plan(Mode::kUncompensated);
  report.brute_force_points = request.brute_force_points;
  if (request.brute_force_points > 0) {
    report.brute_force.push_back(
        planner.brute_force(Mode::kCompensated, request.brute_force_points));
    report.brute_force.push_back(
        planner.brute_force(Mode::kUncompensated, request.brute_force_points));
  }
  report.model_ids = planner.model_ids();
  report.model_inputs = planner.model_inputs();
  report.models_per_y = planner.models_per_y();
  report.pv_mm_s = planner.pv_mm_s();
  report.pd_mm = planner.pd_mm();
  report.av_mm_s = planner.av_mm_s();
  report.ad_mm = planner.ad_mm();
  report.problem = p;
  return report;
}

std::string format_vc_settings(const PlanReport& report) {
  std::string text;
  for (const PlanResult* r : {&report.compensated, &report.uncompensated}) {
    if (r->found) text += std::string(to_string(r->mode)) + "=" + vc_setting(r->setting) + "\n";
  }
  return text;
}

std::string format_plan_json(const PlanReport& r) {
  const PlanProblem& p = r.problem;
  nlohmann::json models = nlohmann::json::array();
  for (std::size_t k = 0; k < p.y_mm.size(); ++k) {
    models.push_back(
        {{"y_mm", p.y_mm[k]}, {"model_id", r.model_ids[k]}, {"model_inputs", r.model_inputs[k]}});
  }
  const bool both = r.compensated.found && r.uncompensated.found;
  nlohmann::json j = {{"model_id", r.model_ids.front()},
                      {"model_inputs", r.model_inputs.front()},
                      {"models_per_y", r.models_per_y},
                      {"models", models},
                      {"budget_um", p.budget_um},
                      {"coverage", p.coverage},
                      {"budget_source", r.budget_source},
                      {"mae_limit_um", p.mae_limit_um},
                      {"y_mm", p.y_mm},
                      {"dwell_s", p.dwell_s},
                      {"smoothing_s", p.smoothing_s},
                      {"edge_margin", p.edge_margin},
                      {"box",
                       {{"pv_mm_s", {r.pv_mm_s.lo, r.pv_mm_s.hi}},
                        {"pd_mm", {r.pd_mm.lo, r.pd_mm.hi}},
                        {"av_mm_s", {r.av_mm_s.lo, r.av_mm_s.hi}},
                        {"ad_mm", {r.ad_mm.lo, r.ad_mm.hi}}}},
                      {"qualified", qualified_json(p)},
                      {"compensated", result_json(r.compensated)},
                      {"uncompensated", result_json(r.uncompensated)},
                      {"speedup", both ? nlohmann::json(r.speedup()) : nlohmann::json(nullptr)}};
  if (!r.brute_force.empty()) {
    j["brute_force"] = {{"points_per_input", r.brute_force_points},
                        {"compensated", result_json(r.brute_force[0])},
                        {"uncompensated", result_json(r.brute_force[1])}};
  }
  return j.dump(2);
}

std::string format_plan_table(const PlanReport& r) {
  const PlanProblem& p = r.problem;
  std::string models;
  if (r.models_per_y) {
    models = "models per Y:";
    for (std::size_t k = 0; k < p.y_mm.size(); ++k) {
      models += fmt::format("{} Y {:g} mm {} ({} inputs)",
                            k == 0 ? "" : ",",
                            p.y_mm[k],
                            r.model_ids[k],
                            r.model_inputs[k]);
    }
  } else {
    models = fmt::format("model {} ({} inputs)", r.model_ids.front(), r.model_inputs.front());
  }
  std::string out = fmt::format(
      "cmmcomp-plan: {}; point budget {:.3f} µm at {:g} % ({}); "
      "|MAE| + U95 <= {} µm\n",
      models,
      p.budget_um,
      p.coverage * 100,
      r.budget_source,
      p.mae_limit_um);
  std::string ys;
  for (const double y : p.y_mm) ys += (ys.empty() ? "" : ", ") + fmt::format("{:g}", y);
  out += fmt::format(
      "search box (limits within the model's ranges, edge margin {:g}): PV {:g}–{:g} mm/s, PD "
      "{:g}–{:g} mm, "
      "AV {:g}–{:g} mm/s, AD {:g}–{:g} mm; PA {:g}, AA {:g} mm/s² ({}); Y {} mm; "
      "dwell {:g} s, smoothing {:g} s ({})\n",
      p.edge_margin,
      r.pv_mm_s.lo,
      r.pv_mm_s.hi,
      r.pd_mm.lo,
      r.pd_mm.hi,
      r.av_mm_s.lo,
      r.av_mm_s.hi,
      r.ad_mm.lo,
      r.ad_mm.hi,
      p.pa_mm_s2_model,
      p.aa_mm_s2_model,
      r.conditions.acceleration_source,
      ys,
      p.dwell_s,
      p.smoothing_s,
      r.conditions.timing_source);
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
  out += row(r.compensated, qualified) + row(r.uncompensated, qualified);
  if (r.compensated.found && r.uncompensated.found) {
    out += fmt::format(
        "\ncompensation: {:.2f}x less time per point than the fastest "
        "{}uncompensated setting that meets the same budget\n",
        r.speedup(),
        qualified ? "qualified " : "");
  } else if (r.compensated.found) {
    out += fmt::format(
        "\nno {}uncompensated setting inside the model's domain meets the budget: compensation "
        "is what makes this budget reachable in the domain\n",
        qualified ? "qualified " : "");
  }
  for (const auto& b : r.brute_force) {
    out += fmt::format("brute force ({}^4 grid, {}): ", r.brute_force_points, to_string(b.mode));
    out += b.found ? fmt::format("{:.4f} s per point\n", b.check.time_per_point_s)
                   : std::string("none feasible\n");
  }
  return out;
}

void restrict_to_capabilities(PlanProblem& problem,
                              const motion::ControllerCapabilities& capabilities,
                              const std::string& machine) {
  const struct {
    motion::Setting setting;
    Interval* interval;
    const char* option;
  } limits[] = {
      {motion::Setting::kPositioningSpeed, &problem.pv_mm_s, "--pv"},
      {motion::Setting::kPositioningAccel, &problem.pa_mm_s2, "--pa"},
      {motion::Setting::kApproachSpeed, &problem.av_mm_s, "--av"},
      {motion::Setting::kApproachAccel, &problem.aa_mm_s2, "--aa"},
      {motion::Setting::kApproachDistance, &problem.ad_mm, "--ad"},
  };
  for (const auto& l : limits) {
    const motion::SettingInfo& info = motion::setting_info(l.setting);
    const motion::SettingRange r = capabilities[l.setting];
    const Interval cap{r.min / info.to_si, r.max / info.to_si};
    const Interval given = *l.interval;
    *l.interval = {std::max(given.lo, cap.lo), std::min(given.hi, cap.hi)};
    if (!(l.interval->lo <= l.interval->hi)) {
      throw ConfigError(fmt::format(
          "{} {:g}:{:g} and the capabilities of {} ({} {:g} .. {:g}) have nothing in common",
          l.option,
          given.lo,
          given.hi,
          machine,
          info.symbol,
          cap.lo,
          cap.hi));
    }
  }
}

Interval parse_interval(const std::string& text, const std::string& option) {
  const auto colon = text.find(':');
  if (colon == std::string::npos) throw ConfigError(option + ": '" + text + "' is not LO:HI");
  const Interval i{parse_number(text.substr(0, colon), option),
                   parse_number(text.substr(colon + 1), option)};
  if (i.lo < 0 || i.lo > i.hi) {
    throw ConfigError(option + ": '" + text + "' needs 0 <= LO <= HI");
  }
  return i;
}

std::vector<double> parse_number_list(const std::string& text, const std::string& option) {
  std::vector<double> v;
  for (const std::string& item : split_commas(text)) v.push_back(parse_number(item, option));
  return v;
}

void parse_mpe_e(const std::string& text, BudgetSpec& budget) {
  const std::vector<double> ak = parse_number_list(text, "--mpe-e");
  if (ak.size() != 2 || ak[0] < 0 || ak[1] <= 0) {
    throw ConfigError("--mpe-e: give A,K of MPE_E = A + L/K µm, e.g. 1.9,300");
  }
  budget.mpe_a_um = ak[0];
  budget.mpe_k = ak[1];
}

QualifiedReference parse_reversal_map(const std::string& text, double sphere_y_mm) {
  QualifiedReference q;
  q.sphere_y_mm = sphere_y_mm;
  for (const std::string& node : split_commas(text)) {
    const auto eq = node.find('=');
    if (eq == std::string::npos) throw ConfigError("--reversal-map: '" + node + "' is not Y=UM");
    q.map_y_mm.push_back(parse_number(node.substr(0, eq), "--reversal-map"));
    q.map_um.push_back(parse_number(node.substr(eq + 1), "--reversal-map"));
  }
  q.validate();
  return q;
}

ModelAtY parse_model_at(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq + 1 == text.size()) {
    throw ConfigError("--model-at: '" + text + "' is not Y=PATH");
  }
  return ModelAtY{parse_number(text.substr(0, eq), "--model-at"),
                  io::load_compensation_model(text.substr(eq + 1))};
}

}  // namespace cmmcomp::planning

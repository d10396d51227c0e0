// SPDX-License-Identifier: MIT
/// @file The feed planner (docs/planner.md): global grid, then a pattern search.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cmmcomp/compensation/conditions.hpp>
#include <cmmcomp/detail/splitmix64.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/motion/move_profile.hpp>
#include <cmmcomp/planning/feed_planner.hpp>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <variant>

namespace cmmcomp::planning {
namespace {

bool positive_finite(double v) { return std::isfinite(v) && v > 0.0; }

/// A length or position in mm as a person writes it: 250, 12.5.
std::string mm(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

void require_interval(const Interval& i, const char* what) {
  if (!(std::isfinite(i.lo) && std::isfinite(i.hi) && i.lo >= 0.0 && i.lo <= i.hi)) {
    throw ConfigError(std::string("planner: the range of ") + what +
                      " must be finite with 0 <= lo <= hi");
  }
}

/// The model's training range of input `column`, or none for an input the model does not have.
bool model_range(const io::CompensationModelFile& file, const char* column, Interval& out) {
  return std::visit(
      [&](const auto& f) {
        for (std::size_t i = 0; i < f.input_names.size(); ++i) {
          if (f.input_names[i] == column) {
            out = {f.model.ranges[i].lo, f.model.ranges[i].hi};
            return true;
          }
        }
        return false;
      },
      file);
}

/// `limit` is the problem's limit, or (`after_other_models`) that limit already narrowed to the
/// ranges of the models before this one: the error says which, so a user knows what to widen.
Interval intersect(const io::CompensationModelFile& file,
                   const char* column,
                   const char* label,
                   const Interval& limit,
                   double edge_margin,
                   bool after_other_models) {
  Interval model{};
  if (!model_range(file, column, model)) {
    throw ConfigError(std::string("planner: the model has no input ") + column);
  }
  const double clear = edge_margin * (model.hi - model.lo);
  model = {model.lo + clear, model.hi - clear};
  const Interval box{std::max(limit.lo, model.lo), std::min(limit.hi, model.hi)};
  if (box.lo > box.hi) {
    throw ConfigError(
        std::string("planner: ") + label +
        (after_other_models ? " limits within the other models' ranges [" : " limits [") +
        std::to_string(limit.lo) + ", " + std::to_string(limit.hi) +
        "] miss the model's training range [" + std::to_string(model.lo) + ", " +
        std::to_string(model.hi) + "]" +
        (edge_margin > 0 ? " (less the edge margin)" : std::string()) +
        ": the model cannot predict there");
  }
  return box;
}

/// The point at share u of `i`; exactly hi at u = 1, so a grid's last point is inside the
/// model's range (the compensator checks it strictly).
double lerp(const Interval& i, double u) { return u >= 1.0 ? i.hi : i.lo + (i.hi - i.lo) * u; }

/// Order of candidates: feasible before infeasible, then faster first.
bool better(const SettingCheck& a, const SettingCheck& b) {
  if (a.feasible != b.feasible) return a.feasible;
  return a.time_per_point_s < b.time_per_point_s;
}

}  // namespace

const char* to_string(Mode mode) {
  return mode == Mode::kCompensated ? "compensated" : "uncompensated";
}

FeedPlanner::FeedPlanner(const io::CompensationModelFile& model, PlanProblem problem)
    : FeedPlanner(std::vector<ModelAtY>{ModelAtY{0.0, model}}, std::move(problem), false) {}

FeedPlanner::FeedPlanner(const std::vector<ModelAtY>& models, PlanProblem problem)
    : FeedPlanner(models, std::move(problem), true) {}

FeedPlanner::FeedPlanner(const std::vector<ModelAtY>& models, PlanProblem problem, bool per_y)
    : problem_(std::move(problem)), per_y_(per_y) {
  if (models.empty()) throw ConfigError("planner: no model");
  // "the model" or "the model for Y 500 mm", in every message about one model.
  const auto which = [&](const ModelAtY& m) {
    return per_y_ ? "the model for Y " + mm(m.y_mm) + " mm" : std::string("the model");
  };
  for (const ModelAtY& m : models) {
    const bool calibrated =
        std::visit([](const auto& f) { return f.interval.available(); }, m.model);
    if (!calibrated) {
      throw ConfigError("planner: " + which(m) +
                        " has no interval calibration (a format-1 model file); retrain it with "
                        "cmmcomp-train to get U95, which every bound of the planner needs");
    }
    const double coverage = std::visit([](const auto& f) { return f.interval.coverage; }, m.model);
    if (!(problem_.coverage > 0 && problem_.coverage < 1)) {
      throw ConfigError("planner: the coverage must be in (0, 1)");
    }
    if (std::fabs(coverage - problem_.coverage) > 1e-9) {
      throw ConfigError(fmt::format(
          "planner: {}'s interval was calibrated at {:g} % coverage, the budget is at {:g} %: "
          "retrain it with cmmcomp-train fit --interval-coverage {:g}, or state the budget at "
          "the model's coverage (cmmcomp-plan --coverage {:g})",
          which(m),
          coverage * 100,
          problem_.coverage * 100,
          problem_.coverage,
          coverage));
    }
  }
  if (!positive_finite(problem_.budget_um)) {
    throw ConfigError("planner: the budget must be a positive number of µm");
  }
  if (!positive_finite(problem_.mae_limit_um)) {
    throw ConfigError("planner: the MAE limit must be a positive number of µm");
  }
  for (const auto& [i, what] : {std::pair{problem_.pv_mm_s, "PV"},
                                std::pair{problem_.av_mm_s, "AV"},
                                std::pair{problem_.pd_mm, "PD"},
                                std::pair{problem_.ad_mm, "AD"},
                                std::pair{problem_.pa_mm_s2, "PA"},
                                std::pair{problem_.aa_mm_s2, "AA"}}) {
    require_interval(i, what);
  }
  if (!positive_finite(problem_.pa_mm_s2_model) || !positive_finite(problem_.aa_mm_s2_model)) {
    throw ConfigError("planner: the model's PA and AA must be positive");
  }
  if (problem_.pa_mm_s2_model < problem_.pa_mm_s2.lo ||
      problem_.pa_mm_s2_model > problem_.pa_mm_s2.hi ||
      problem_.aa_mm_s2_model < problem_.aa_mm_s2.lo ||
      problem_.aa_mm_s2_model > problem_.aa_mm_s2.hi) {
    throw ConfigError(
        "planner: the machine's PA/AA ranges do not hold the accelerations the model was trained "
        "at (PA " +
        std::to_string(problem_.pa_mm_s2_model) + ", AA " +
        std::to_string(problem_.aa_mm_s2_model) + " mm/s²)");
  }
  if (problem_.y_mm.empty()) throw ConfigError("planner: no carriage position Y");
  for (double y : problem_.y_mm) {
    if (!std::isfinite(y)) throw ConfigError("planner: a carriage position Y is not finite");
  }
  if (!std::isfinite(problem_.z_mm) || !(problem_.dwell_s >= 0.0) ||
      !(problem_.smoothing_s >= 0.0) || !std::isfinite(problem_.dwell_s) ||
      !std::isfinite(problem_.smoothing_s)) {
    throw ConfigError(
        "planner: Z, the dwell and the smoothing must be finite (dwell, smoothing >= 0)");
  }
  if (!(problem_.edge_margin >= 0.0 && problem_.edge_margin < 0.45)) {
    throw ConfigError("planner: the edge margin must be in [0, 0.45)");
  }
  if (problem_.grid_points < 2 || problem_.grid_points > 201) {
    throw ConfigError("planner: grid points per input must be in [2, 201]");
  }
  if (!(problem_.tolerance > 0.0 && problem_.tolerance < 0.5)) {
    throw ConfigError("planner: the tolerance must be in (0, 0.5)");
  }

  // Which model judges each Y of the program.
  constexpr double kSameY = 1e-6;  // mm
  std::string given;               // "0, 250, 500": the models' Y, for messages
  // The model given for `y`, or models.size().
  const auto model_for = [&](double y) {
    std::size_t found = models.size();
    for (std::size_t a = 0; a < models.size(); ++a) {
      if (std::fabs(models[a].y_mm - y) <= kSameY) found = a;
    }
    return found;
  };
  if (per_y_) {
    for (std::size_t a = 0; a < models.size(); ++a) {
      if (!std::isfinite(models[a].y_mm)) {
        throw ConfigError("planner: a model's carriage position Y is not finite");
      }
      for (std::size_t b = 0; b < a; ++b) {
        if (std::fabs(models[a].y_mm - models[b].y_mm) <= kSameY) {
          throw ConfigError("planner: two models are given for Y " + mm(models[a].y_mm) + " mm");
        }
      }
      given += (given.empty() ? "" : ", ") + mm(models[a].y_mm);
    }
    for (double y : problem_.y_mm) {
      const std::size_t found = model_for(y);
      if (found == models.size()) {
        throw ConfigError("planner: no model for Y " + mm(y) + " mm (models for Y " + given +
                          " mm)");
      }
      compensator_of_y_.push_back(found);
    }
  } else {
    compensator_of_y_.assign(problem_.y_mm.size(), 0);
  }

  // The qualified reference: the model that judges the sphere's Y must see Y, or the planner
  // would take the static lag's growth with Y for the setting's (a 4-input model predicts the
  // same lag at every Y, and the residual would be the map's difference alone).
  if (problem_.qualified) {
    problem_.qualified->validate();
    const double sphere = problem_.qualified->sphere_y_mm;
    // The map must cover the program and the sphere: beyond its nodes it is only held flat.
    const std::vector<double>& nodes = problem_.qualified->map_y_mm;
    std::vector<double> needed = problem_.y_mm;
    needed.push_back(sphere);
    for (double y : needed) {
      if (y < nodes.front() - kSameY || y > nodes.back() + kSameY) {
        throw ConfigError("planner: the reversal map covers Y " + mm(nodes.front()) + " to " +
                          mm(nodes.back()) + " mm, not Y " + mm(y) +
                          " mm (measure it there: cmmcomp-vc --qualify --map-only --y …)");
      }
    }
    sphere_compensator_ = per_y_ ? model_for(sphere) : 0;
    if (sphere_compensator_ == models.size()) {
      throw ConfigError("planner: the reference sphere's Y " + mm(sphere) +
                        " mm has no model (models for Y " + given + " mm)");
    }
    Interval y_range{};
    const bool sees_y = model_range(models[sphere_compensator_].model, "y_mm", y_range);
    if (!per_y_ && !sees_y) {
      throw ConfigError(
          "planner: the qualified reference needs a model that sees Y (a 5-input model, or a "
          "model per Y with one at the sphere's Y): the model predicts the same lag at every Y");
    }
    // A model that sees Y must have been trained where the sphere is.
    if (sees_y && (sphere < y_range.lo || sphere > y_range.hi)) {
      throw ConfigError("planner: the reference sphere's Y " + mm(sphere) +
                        " mm is outside the model's training range [" + mm(y_range.lo) + ", " +
                        mm(y_range.hi) + "]");
    }
  }

  // The search box: the limits within every model's training ranges.
  pv_ = problem_.pv_mm_s;
  pd_ = problem_.pd_mm;
  av_ = problem_.av_mm_s;
  ad_ = problem_.ad_mm;
  for (std::size_t a = 0; a < models.size(); ++a) {
    const ModelAtY& m = models[a];
    const std::string w = per_y_ ? " (" + which(m) + ")" : std::string();
    const double margin = problem_.edge_margin;
    pv_ = intersect(m.model, "pv_mm_s", ("PV" + w).c_str(), pv_, margin, a > 0);
    pd_ = intersect(m.model, "pd_mm", ("PD" + w).c_str(), pd_, margin, a > 0);
    av_ = intersect(m.model, "av_mm_s", ("AV" + w).c_str(), av_, margin, a > 0);
    ad_ = intersect(m.model, "ad_mm", ("AD" + w).c_str(), ad_, margin, a > 0);
  }
  for (std::size_t a = 0; a < models.size(); ++a) {
    Interval y_range{};
    if (!model_range(models[a].model, "y_mm", y_range)) continue;
    for (std::size_t k = 0; k < problem_.y_mm.size(); ++k) {
      const double y = problem_.y_mm[k];
      if (compensator_of_y_[k] == a && (y < y_range.lo || y > y_range.hi)) {
        throw ConfigError("planner: Y " + mm(y) + " mm is outside the model's training range [" +
                          mm(y_range.lo) + ", " + mm(y_range.hi) + "]" +
                          (per_y_ ? " (" + which(models[a]) + ")" : std::string()));
      }
    }
  }
  for (const ModelAtY& m : models) {
    auto compensator = std::make_unique<compensation::MoveCompensator>();
    std::string why;
    if (!ok(io::publish_at_its_coverage(*compensator, 0, m.model, &why))) {
      throw ConfigError("planner: " + which(m) + " cannot be served: " + why);
    }
    compensators_.push_back(std::move(compensator));
  }
  for (std::size_t k = 0; k < problem_.y_mm.size(); ++k) {
    model_ids_.push_back(io::model_id(models[compensator_of_y_[k]].model));
    model_inputs_.push_back(io::model_inputs(models[compensator_of_y_[k]].model));
  }
}

FeedSetting FeedPlanner::at(double pv, double pd, double av, double ad) const {
  return FeedSetting{pv, problem_.pa_mm_s2_model, pd, av, problem_.aa_mm_s2_model, ad};
}

double FeedPlanner::time_per_point_s(const FeedSetting& s) const {
  motion::ProbingMove move =
      motion::probing_move_mm(s.pv_mm_s, s.pa_mm_s2, s.pd_mm, s.av_mm_s, s.aa_mm_s2, s.ad_mm);
  move.dwell = problem_.dwell_s;
  move.smoothing = problem_.smoothing_s;
  motion::MoveProfile profile;
  if (!ok(motion::MoveProfile::plan(move, profile))) {
    return std::numeric_limits<double>::infinity();  // not a move: never chosen
  }
  return profile.instants().touch;
}

SettingCheck FeedPlanner::check(const FeedSetting& s, Mode mode) const {
  SettingCheck c;
  c.time_per_point_s = time_per_point_s(s);
  c.feasible = std::isfinite(c.time_per_point_s);
  c.point_bound_um = -1.0;
  compensation::MoveRequest m;
  m.pv_mm_s = s.pv_mm_s;
  m.pa_mm_s2 = s.pa_mm_s2;
  m.pd_mm = s.pd_mm;
  m.av_mm_s = s.av_mm_s;
  m.aa_mm_s2 = s.aa_mm_s2;
  m.ad_mm = s.ad_mm;
  m.z_mm = problem_.z_mm;
  m.direction = {1.0, 0.0, 0.0};
  // Qualified: the same setting's lag at the sphere, which the qualification absorbs.
  const bool qualified = mode == Mode::kUncompensated && problem_.qualified.has_value();
  compensation::Correction at_sphere;
  if (qualified) {
    m.y_mm = problem_.qualified->sphere_y_mm;
    if (compensators_[sphere_compensator_]->before_approach(m, at_sphere) != Status::kOk) {
      c.feasible = false;  // no residual without the sphere's prediction: no bound either
      return c;
    }
  }
  for (std::size_t k = 0; k < problem_.y_mm.size(); ++k) {
    const double y = problem_.y_mm[k];
    m.y_mm = y;
    compensation::Correction r;
    // Outside the training box the prediction is not trusted: such a setting is infeasible.
    if (compensators_[compensator_of_y_[k]]->before_approach(m, r) != Status::kOk) {
      c.feasible = false;
      continue;
    }
    double rae = r.rae_um;
    double u_rae = r.u95_um[3];
    if (qualified) {
      // Two predictions' errors: treated as independent (docs/planner.md).
      rae = problem_.qualified->residual_um(r.rae_um, y, at_sphere.rae_um);
      u_rae = std::hypot(r.u95_um[3], at_sphere.u95_um[3]);
    }
    const double bound = mode == Mode::kCompensated ? u_rae : std::fabs(rae) + u_rae;
    const double mae_bound = std::fabs(r.mae_um) + r.u95_um[2];
    if (bound > c.point_bound_um) {
      c.point_bound_um = bound;
      c.worst_y_mm = y;
      c.rae_um = rae;
      c.u95_rae_um = u_rae;
    }
    c.mae_bound_um = std::max(c.mae_bound_um, mae_bound);
  }
  c.feasible = c.feasible && c.point_bound_um >= 0.0 && c.point_bound_um <= problem_.budget_um &&
               c.mae_bound_um <= problem_.mae_limit_um;
  return c;
}

PlanResult FeedPlanner::grid_search(Mode mode, int n, std::vector<FeedSetting>* best) const {
  constexpr std::size_t kStarts = 16;
  PlanResult r;
  r.mode = mode;
  r.best_point_bound_um = std::numeric_limits<double>::infinity();
  // The 16 fastest feasible grid points, as the local search's starts (they may all lie in one
  // pocket; a pocket that holds no grid point is not found: docs/planner.md).
  std::vector<std::pair<SettingCheck, FeedSetting>> starts;
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      for (int c = 0; c < n; ++c) {
        for (int d = 0; d < n; ++d) {
          const FeedSetting s = at(lerp(pv_, double(a) / (n - 1)),
                                   lerp(pd_, double(b) / (n - 1)),
                                   lerp(av_, double(c) / (n - 1)),
                                   lerp(ad_, double(d) / (n - 1)));
          const SettingCheck k = check(s, mode);
          ++r.evaluations;
          if (k.point_bound_um >= 0.0 && k.point_bound_um < r.best_point_bound_um) {
            r.best_point_bound_um = k.point_bound_um;
            r.best_point_setting = s;
          }
          if (k.feasible && (!r.found || better(k, r.check))) {
            r.found = true;
            r.check = k;
            r.setting = s;
          }
          if (k.feasible) starts.emplace_back(k, s);
        }
      }
    }
  }
  if (best != nullptr) {
    std::sort(starts.begin(), starts.end(), [](const auto& x, const auto& y) {
      return x.first.time_per_point_s < y.first.time_per_point_s;
    });
    best->clear();
    for (const auto& s : starts) {
      if (best->size() >= kStarts) break;
      best->push_back(s.second);
    }
  }
  return r;
}

PlanResult FeedPlanner::brute_force(Mode mode, int points_per_input) const {
  if (points_per_input < 2) throw ConfigError("planner: brute force needs >= 2 points per input");
  return grid_search(mode, points_per_input, nullptr);
}

PlanResult FeedPlanner::plan(Mode mode) const {
  std::vector<FeedSetting> starts;
  PlanResult r = grid_search(mode, problem_.grid_points, &starts);
  if (!r.found) return r;
  // Pattern search from each start: poll all 80 neighbours on the step's lattice (a feasible
  // region's edge is often diagonal: faster PV needs a longer PD); move to the fastest feasible
  // poll; halve the step when none is faster; stop below the tolerance.
  const std::array<Interval, 4> box{pv_, pd_, av_, ad_};
  // Every direction of the 3^4 - 1 neighbours (one, two, three or four inputs at once).
  std::vector<std::array<double, 4>> directions;
  for (int code = 0; code < 81; ++code) {
    std::array<double, 4> d{};
    int c = code;
    for (double& k : d) {
      k = c % 3 - 1;
      c /= 3;
    }
    if (d != std::array<double, 4>{0, 0, 0, 0}) directions.push_back(d);
  }
  // And, fresh at every poll, directions drawn at random (seeded: the plan is reproducible):
  // where the feasible edge runs at an angle no lattice direction follows, the lattice alone
  // stalls short of the optimum (the brute-force test caught it: PV against AV on an edge).
  constexpr std::size_t kLattice = 80;
  constexpr std::size_t kRandom = 48;
  directions.resize(kLattice + kRandom);
  detail::SplitMix64 random{0x9e3779b97f4a7c15ULL};
  const auto coords = [](const FeedSetting& s) {
    return std::array<double, 4>{s.pv_mm_s, s.pd_mm, s.av_mm_s, s.ad_mm};
  };
  for (const FeedSetting& start : starts) {
    std::array<double, 4> x = coords(start);
    SettingCheck here = check(start, mode);
    ++r.evaluations;
    double h = 0.5 / (problem_.grid_points - 1);  // share of each range
    // Each accepted move strictly lowers the time and each refusal halves h (from 0.5/(N − 1) of
    // the range to the tolerance: 9 halvings at the defaults); the iteration cap bounds the rest.
    for (int iteration = 0; iteration < 10000 && h >= problem_.tolerance; ++iteration) {
      SettingCheck best_poll = here;
      std::array<double, 4> best_x = x;
      for (std::size_t k = kLattice; k < directions.size(); ++k) {
        for (double& c : directions[k]) c = random.uniform(-1.0, 1.0);
      }
      for (const auto& d : directions) {
        std::array<double, 4> y = x;
        for (std::size_t k = 0; k < 4; ++k) {
          const double width = box[k].hi - box[k].lo;
          y[k] = std::clamp(x[k] + d[k] * h * width, box[k].lo, box[k].hi);
        }
        if (y == x) continue;
        const SettingCheck c = check(at(y[0], y[1], y[2], y[3]), mode);
        ++r.evaluations;
        if (c.feasible && c.time_per_point_s < best_poll.time_per_point_s - 1e-12) {
          best_poll = c;
          best_x = y;
        }
      }
      if (best_x == x) {
        h *= 0.5;
      } else {
        x = best_x;
        here = best_poll;
      }
    }
    if (better(here, r.check)) {
      r.check = here;
      r.setting = at(x[0], x[1], x[2], x[3]);
    }
  }
  return r;
}

PlanConditions resolve_conditions(const std::vector<const io::TrainingConditions*>& models,
                                  const std::vector<std::string>& model_ids,
                                  const GivenConditions& given) {
  constexpr double kTimingTolerance = 0.010;  // what extract holds a given timing to
  if (models.empty() || models.size() != model_ids.size()) {
    throw ConfigError("resolve_conditions: one id per model, at least one model");
  }
  PlanConditions out;
  const auto acceleration = [&](std::optional<io::ConditionRange> io::TrainingConditions::*field,
                                const std::optional<double>& value,
                                const char* name,
                                const char* option) {
    if (value) {
      for (std::size_t k = 0; k < models.size(); ++k) {
        const auto& r = models[k]->*field;
        if (r && (*value < r->lo * (1 - compensation::kConditionTolerance) ||
                  *value > r->hi * (1 + compensation::kConditionTolerance))) {
          throw ConfigError(fmt::format(
              "{} {:g} mm/s², but model {} was trained at {} {:g}–{:g} mm/s²: its errors do not "
              "hold there (the compensator flags or refuses such moves)",
              option,
              *value,
              model_ids[k],
              name,
              r->lo,
              r->hi));
        }
      }
      return *value;
    }
    double v = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < models.size(); ++k) {
      const auto& r = models[k]->*field;
      if (!r) {
        throw ConfigError(fmt::format(
            "model {} does not record the {} it was trained at (a model file before format 4, "
            "or trained without it): give {} (the paper's: PA 200, AA 60 mm/s²)",
            model_ids[k],
            name,
            option));
      }
      v = std::min(v, r->hi);
    }
    for (std::size_t k = 0; k < models.size(); ++k) {
      const auto& r = models[k]->*field;
      if (v < r->lo) {
        throw ConfigError(
            fmt::format("the models were trained at {}s that do not overlap: model "
                        "{} at {:g}–{:g} mm/s²; give {}",
                        name,
                        model_ids[k],
                        r->lo,
                        r->hi,
                        option));
      }
    }
    return v;
  };
  out.pa_mm_s2 =
      acceleration(&io::TrainingConditions::pa_mm_s2, given.pa_mm_s2, "PA", "--trained-pa");
  out.aa_mm_s2 =
      acceleration(&io::TrainingConditions::aa_mm_s2, given.aa_mm_s2, "AA", "--trained-aa");
  out.acceleration_source =
      given.pa_mm_s2 || given.aa_mm_s2
          ? std::string(given.pa_mm_s2 && given.aa_mm_s2 ? "as given" : "as given and the model's")
          : std::string("the model's: the highest it was trained at");
  const auto timing = [&](std::optional<double> io::TrainingConditions::*field,
                          const std::optional<double>& value,
                          const char* name) {
    if (value) {
      for (std::size_t k = 0; k < models.size(); ++k) {
        const auto& m = models[k]->*field;
        if (m && std::abs(*m - *value) > kTimingTolerance) {
          throw ConfigError(fmt::format(
              "{} has a controller {} of {:g} s, but model {} was trained at {:g} s: its errors "
              "hold at its own controller setting (train a model at this one, or plan without "
              "--machine)",
              given.machine_label,
              name,
              *value,
              model_ids[k],
              *m));
        }
      }
      return *value;
    }
    for (std::size_t k = 0; k < models.size(); ++k) {
      const auto& m = models[k]->*field;
      if (!m) {
        throw ConfigError(fmt::format(
            "model {} does not record the controller {} it was trained at (a model file before "
            "format 4, or trained without --campaign or --machine): give --machine with the "
            "controller the model's moves ran with",
            model_ids[k],
            name));
      }
      const auto& first = models.front()->*field;
      if (std::abs(*m - *first) > kTimingTolerance) {
        throw ConfigError(
            fmt::format("models {} and {} were trained at a controller {} of {:g} "
                        "and {:g} s: plan them one at a time",
                        model_ids.front(),
                        model_ids[k],
                        name,
                        *first,
                        *m));
      }
    }
    return *(models.front()->*field);
  };
  out.dwell_s = timing(&io::TrainingConditions::dwell_s, given.dwell_s, "dwell");
  out.smoothing_s = timing(&io::TrainingConditions::smoothing_s, given.smoothing_s, "smoothing");
  out.timing_source = given.dwell_s ? given.machine_label : std::string("the model's");
  return out;
}

}  // namespace cmmcomp::planning

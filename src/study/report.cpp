// SPDX-License-Identifier: MIT
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/schema.hpp>
#include <cmmcomp/study/report.hpp>
#include <limits>
#include <string>

namespace cmmcomp::study {

namespace {

nlohmann::ordered_json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
}

/// A field that must be there: ConfigError naming it otherwise.
const Document& field(const Document& doc, const char* key) {
  if (!doc.is_object() || !doc.contains(key)) {
    throw ConfigError(fmt::format("study document: no \"{}\" field", key));
  }
  return doc.at(key);
}

/// A number with `decimals`, or "—" for null (a figure that does not exist, e.g. the coverage of a
/// model without an interval).
std::string num(const Document& v, int decimals) {
  if (!v.is_number() || !std::isfinite(v.get<double>())) return "—";
  return fmt::format("{:.{}f}", v.get<double>(), decimals);
}

/// Free text for a Markdown table cell: a `|` would end the cell.
std::string cell(std::string text) {
  for (char& c : text) c = c == '\n' || c == '\r' ? ' ' : c;  // a line break would end the row
  for (std::size_t at = text.find('|'); at != std::string::npos; at = text.find('|', at + 2)) {
    text.insert(at, "\\");
  }
  return text;
}

std::string table_header(const std::string& first, const std::string& per_parameter) {
  std::string head = "| " + first;
  std::string rule = "| ---";
  const std::size_t extra = static_cast<std::size_t>(
      std::count(first.begin(), first.end(), '|'));  // columns the caller added
  for (std::size_t i = 0; i < extra; ++i) rule += " | ---";
  for (const auto& e : kErrors) {
    head += per_parameter.empty() ? fmt::format(" | {}", e.label)
                                  : fmt::format(" | {} {}", e.label, per_parameter);
    rule += " | ---";
  }
  return head + " |\n" + rule + " |\n";
}

std::string render_accuracy(const Document& doc) {
  std::string out = table_header("test | moves trained / tested | outside domain",
                                 "mean before → after µm (reduction %, coverage %)");
  for (const Document& t : field(doc, "tests")) {
    out += fmt::format("| {} | {} / {} | {}",
                       cell(field(t, "label").get<std::string>()),
                       field(t, "train_samples").get<std::size_t>(),
                       field(t, "test_samples").get<std::size_t>(),
                       field(t, "outside").get<std::size_t>());
    for (const auto& e : kErrors) {
      const Document& p = field(t, e.key);
      out += fmt::format(" | {} → {} ({}, {})",
                         num(field(p, "mean_before_um"), 3),
                         num(field(p, "mean_after_um"), 3),
                         num(field(p, "reduction_pct"), 1),
                         num(field(p, "coverage_pct"), 1));
    }
    out += " |\n";
  }
  return out;
}

std::string render_cell_interpolant(const Document& doc) {
  std::string out =
      "| test | RPE mean before µm | cell interpolant mean \\|residual\\| µm | reduction % |\n"
      "| --- | --- | --- | --- |\n";
  for (const Document& t : field(doc, "tests")) {
    out += fmt::format("| {} | {} | {} | {} |\n",
                       cell(field(t, "label").get<std::string>()),
                       num(field(t, "rpe_mean_before_um"), 3),
                       num(field(t, "rpe_mean_after_um"), 3),
                       num(field(t, "rpe_reduction_pct"), 1));
  }
  return out;
}

std::string render_interval_coverage(const Document& doc) {
  std::string out = fmt::format("Model {} (5-input {}), nominal coverage 95 %.\n\n",
                                field(doc, "model").get<std::string>(),
                                field(doc, "model_y").get<std::string>());
  out += table_header("test set | moves | outside domain", "coverage % (mean U95 µm)");
  for (const Document& r : field(doc, "rows")) {
    out += fmt::format("| {} | {} | {}",
                       cell(field(r, "name").get<std::string>()),
                       field(r, "moves").get<std::size_t>(),
                       field(r, "outside").get<std::size_t>());
    for (const auto& e : kErrors) {
      const Document& p = field(r, e.key);
      out += fmt::format(
          " | {} ({})", num(field(p, "coverage_pct"), 1), num(field(p, "mean_u95_um"), 2));
    }
    out += " |\n";
  }
  out += "\nPooled over the held-out seeds:";
  const Document& pooled = field(doc, "pooled_coverage_pct");
  for (const auto& e : kErrors) {
    out += fmt::format(
        " {} {} %{}", e.label, num(field(pooled, e.key), 1), &e == &kErrors.back() ? "." : ",");
  }
  return out + "\n";
}

std::string render_calibration(const Document& doc) {
  const int seeds = field(doc, "seeds").get<int>();
  const auto seed = field(doc, "seed").get<std::uint64_t>();
  std::string out = fmt::format(
      "Machine {}; noise seeds {} … {}; a requirement must hold for {} of {}.\n\n"
      "The comparison at seed {} (model, paper in brackets):\n\n```text\n{}```\n",
      field(doc, "machine").get<std::string>(),
      seed,
      seed + static_cast<std::uint64_t>(seeds) - 1,
      field(doc, "needed").get<int>(),
      seeds,
      seed,
      field(doc, "comparison").get<std::string>());
  std::string rows;
  for (const Document& t : field(doc, "targets")) {
    if (field(t, "measured").get<double>() < seeds) {
      rows += fmt::format("| {} | {} of {} |\n",
                          cell(field(t, "name").get<std::string>()),
                          field(t, "measured").get<double>(),
                          seeds);
    }
  }
  if (!rows.empty()) {
    out +=
        "\nThe requirements that did not hold for every seed:\n\n| requirement | held for |\n"
        "| --- | --- |\n" +
        rows;
  }
  return out;
}

/// A number to 4 significant digits, or "—".
std::string g4(const Document& v) {
  return v.is_number() && std::isfinite(v.get<double>()) ? fmt::format("{:.4g}", v.get<double>())
                                                         : std::string("—");
}

std::string render_identify_multistart(const Document& doc) {
  std::string out =
      "| start | cost start → final | fit s | fitted (* at a plausible bound) | requirements "
      "held |\n| --- | --- | --- | --- | --- |\n";
  const Document& names = field(doc, "free_parameters");
  for (const Document& r : field(doc, "starts")) {
    const std::string failure = field(r, "failure").get<std::string>();
    if (!failure.empty()) {
      out +=
          fmt::format("| {} | failed: {} | | | |\n", field(r, "start").get<int>(), cell(failure));
      continue;
    }
    std::string fitted;
    const Document& values = field(r, "fitted_values");
    const Document& bound = field(r, "at_bound");
    for (std::size_t i = 0; i < values.size() && i < names.size(); ++i) {
      const std::string key = names[i].get<std::string>();
      fitted += fmt::format("{}{} {}{}",
                            i == 0 ? "" : ", ",
                            key.substr(key.find('.') + 1),
                            g4(values[i]),
                            i < bound.size() && bound[i].get<int>() != 0 ? "*" : "");
    }
    out += fmt::format("| {} | {} → {} | {} | {} | {} of {} |\n",
                       field(r, "start").get<int>(),
                       g4(field(r, "initial_cost")),
                       g4(field(r, "final_cost")),
                       num(field(r, "seconds"), 1),
                       fitted,
                       field(r, "held").get<int>(),
                       field(r, "requirements").get<int>());
  }
  return out;
}

std::string render_interval_calibration(const Document& doc) {
  std::string out = fmt::format(
      "Recipe {}; empirical coverage % on {} held-out moves, the network retrained at each "
      "nominal coverage.\n\n",
      field(doc, "recipe").get<std::string>(),
      field(doc, "test_moves").get<std::size_t>());
  out += table_header("nominal %", "");
  for (const Document& r : field(doc, "levels")) {
    out += fmt::format("| {:g}", field(r, "nominal_pct").get<double>());
    for (const auto& e : kErrors) out += " | " + num(field(r, e.key), 1);
    out += " |\n";
  }
  return out;
}

std::string render_cross_machine(const Document& doc) {
  std::string out = fmt::format(
      "Plan {}; the shipped model {}. Reduction % (mean \\|residual\\| µm) on {} held-out "
      "moves of each machine.\n\n",
      field(doc, "plan").get<std::string>(),
      field(doc, "shipped_model").get<std::string>(),
      field(doc, "test_moves").get<std::size_t>());
  out += "| machine | extracted";
  std::string rule = "| --- | ---";
  for (const char* who : {"own model", "shipped model"}) {
    for (const auto& e : kErrors) {
      out += fmt::format(" | {}: {}", who, e.label);
      rule += " | ---";
    }
  }
  out += " |\n" + rule + " |\n";
  for (const Document& r : field(doc, "machines")) {
    out += fmt::format("| {} | {}/{}",
                       cell(field(r, "machine").get<std::string>()),
                       field(r, "extracted").get<std::size_t>(),
                       field(r, "planned").get<std::size_t>());
    for (const char* who : {"own", "shipped"}) {
      for (const auto& e : kErrors) {
        const Document& p = field(field(r, who), e.key);
        out += fmt::format(
            " | {} ({})", num(field(p, "reduction_pct"), 1), num(field(p, "mean_after_um"), 2));
      }
    }
    out += " |\n";
  }
  return out;
}

std::string describe_setting(const Document& s) {
  return fmt::format("{} s per point at PV {} mm/s, PD {} mm, AV {} mm/s, AD {} mm",
                     num(field(s, "time_per_point_s"), 3),
                     field(s, "pv_mm_s").get<double>(),
                     field(s, "pd_mm").get<double>(),
                     field(s, "av_mm_s").get<double>(),
                     field(s, "ad_mm").get<double>());
}

std::string render_qualified_sweep(const Document& doc) {
  const std::size_t seeds = field(doc, "seeds").size();
  std::string out = fmt::format("Model {}, noise seeds {}; PA 200, AA 60 mm/s².\n\n",
                                field(doc, "model").get<std::string>(),
                                field(doc, "seeds").dump());
  out +=
      "| PV mm/s | PD mm | AV mm/s | AD mm | time per point s | qualified uncompensated | "
      "compensated |\n| --- | --- | --- | --- | --- | --- | --- |\n";
  for (const Document& s : field(doc, "settings")) {
    out += fmt::format("| {} | {} | {} | {} | {} | {} of {} seeds pass | {} of {} seeds pass |\n",
                       field(s, "pv_mm_s").get<double>(),
                       field(s, "pd_mm").get<double>(),
                       field(s, "av_mm_s").get<double>(),
                       field(s, "ad_mm").get<double>(),
                       num(field(s, "time_per_point_s"), 3),
                       field(s, "uncompensated_passes").get<int>(),
                       seeds,
                       field(s, "compensated_passes").get<int>(),
                       seeds);
  }
  const Document& unc = field(doc, "fastest_uncompensated");
  const Document& comp = field(doc, "fastest_compensated");
  out += "\nFastest qualified uncompensated setting that meets MPE_E (every Y, every seed): " +
         (unc.is_null() ? std::string("none on the grid") : describe_setting(unc)) + ".\n";
  out += "Fastest compensated setting that meets MPE_E (every Y, every seed): " +
         (comp.is_null() ? std::string("none on the grid") : describe_setting(comp)) + ".\n";
  if (!unc.is_null() && !comp.is_null()) {
    out += fmt::format("Compensation takes **{}×** less time per point ({} s against {} s).\n",
                       num(field(doc, "speedup"), 3),
                       num(field(comp, "time_per_point_s"), 3),
                       num(field(unc, "time_per_point_s"), 3));
  }
  return out;
}

/// One cycle choice of the whole-cycle comparison.
Document cycle_choice(const CycleChoice& c) {
  if (!c.found) return Document{{"found", false}, {"judged", c.judged}};
  const motion::ProbingMove& m = c.cycle;
  return Document{{"found", true},
                  {"time_s", c.time_s},
                  {"pv_mm_s", m.positioning_speed * 1e3},
                  {"pa_mm_s2", m.positioning_accel * 1e3},
                  {"av_mm_s", m.approach_speed * 1e3},
                  {"aa_mm_s2", m.approach_accel * 1e3},
                  {"ad_mm", m.approach_distance * 1e3},
                  {"dwell_s", m.dwell},
                  {"smoothing_s", m.smoothing},
                  {"residual_um", c.check.residual_um},
                  {"mae_um", c.check.mae_um},
                  {"binding", c.check.binding},
                  {"judged", c.judged}};
}

std::string render_cycle_choice(const Document& c) {
  if (!field(c, "found").get<bool>()) return "none on the grid";
  return fmt::format(
      "PV {:g}, PA {:g}, AV {:g}, AA {:g}, AD {:g}, dwell {:g} s, T {:.4g} s: {} s (residual {} "
      "um, MAE {} um; nearest its limit: {})",
      field(c, "pv_mm_s").get<double>(),
      field(c, "pa_mm_s2").get<double>(),
      field(c, "av_mm_s").get<double>(),
      field(c, "aa_mm_s2").get<double>(),
      field(c, "ad_mm").get<double>(),
      field(c, "dwell_s").get<double>(),
      field(c, "smoothing_s").get<double>(),
      num(field(c, "time_s"), 3),
      num(field(c, "residual_um"), 2),
      num(field(c, "mae_um"), 1),
      field(c, "binding").get<std::string>());
}

std::string render_cycle_speedup(const Document& doc) {
  const Document& r = field(doc, "rules");
  std::string out = fmt::format(
      "Budget {} um per point at 95 % (half of MPE_E at 20 mm), {} um of it for what a touch "
      "leaves (the rest: the repeatability at 95 %); |MAE| <= {} um and a constant-speed touch "
      "at every Y of {} mm; the uncompensated machine qualified at Y {} mm, robust over 8 "
      "variants of it. Time per point: from the start of the positioning to the touch, dwell "
      "and smoothing included. Today's qualified reference: {} s.\n\n",
      num(field(r, "budget_um"), 3),
      num(field(r, "allowance_um"), 3),
      field(r, "mae_limit_um").get<double>(),
      field(r, "y_mm").dump(),
      field(r, "sphere_y_mm").get<double>(),
      num(field(doc, "todays_reference_s"), 3));
  out +=
      "| machine | PD mm | qualified uncompensated, same freedom | oracle (a perfect model) | "
      "identified model | qualified / identified | reference / identified | length test: seeds "
      "passing every Y (qualified, compensated) |\n"
      "| --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (const Document& row : field(doc, "rows")) {
    const Document& q = field(row, "qualified");
    const Document& o = field(row, "oracle");
    const bool has_i = row.contains("identified");
    const bool both = has_i && field(q, "found").get<bool>() &&
                      field(field(row, "identified"), "found").get<bool>();
    const bool tested =
        row.contains("length_test") && field(field(row, "length_test"), "seeds").get<int>() > 0;
    out += fmt::format(
        "| {} | {:g} | {} | {} | {} | {} | {} | {} |\n",
        field(row, "machine").get<std::string>(),
        field(row, "pd_mm").get<double>(),
        render_cycle_choice(q),
        render_cycle_choice(o),
        has_i ? render_cycle_choice(field(row, "identified")) : std::string("–"),
        both ? num(Document(field(q, "time_s").get<double>() /
                            field(field(row, "identified"), "time_s").get<double>()),
                   2) +
                   "x"
             : std::string("–"),
        has_i && field(field(row, "identified"), "found").get<bool>()
            ? num(Document(field(doc, "todays_reference_s").get<double>() /
                           field(field(row, "identified"), "time_s").get<double>()),
                  2) +
                  "x"
            : std::string("–"),
        tested ? fmt::format("{} and {} of {}",
                             field(field(row, "length_test"), "qualified_passed").get<int>(),
                             field(field(row, "length_test"), "identified_passed").get<int>(),
                             field(field(row, "length_test"), "seeds").get<int>())
               : std::string("–"));
  }
  for (const Document& m : field(doc, "identified")) {
    out += fmt::format(
        "\nIdentified from its campaign: {}, cost {} over {} residuals (the truth's own cost on "
        "the same moves: {}; a fit well above it stopped in a local minimum or lacks physics the "
        "machine has, and then its 1 sigma, which assumes the model is right, understates the "
        "error).\n\n",
        field(m, "machine").get<std::string>(),
        num(field(m, "final_cost"), 1),
        field(m, "residuals").get<int>(),
        num(field(m, "truth_cost"), 1));
    out +=
        "| parameter | truth | fitted | fitted / truth − 1 | 1 sigma |\n"
        "| --- | --- | --- | --- | --- |\n";
    for (const Document& p : field(m, "parameters")) {
      const double truth = field(p, "truth").get<double>();
      const double fitted = field(p, "fitted").get<double>();
      const Document& sigma = field(p, "relative_sigma");
      out += fmt::format("| {} | {:.6g} | {:.6g} | {:+.2f} % | {} |\n",
                         field(p, "key").get<std::string>(),
                         truth,
                         fitted,
                         100.0 * (fitted / truth - 1.0),
                         sigma.is_null() ? std::string("undetermined")
                                         : fmt::format("{:.2f} %", 100.0 * sigma.get<double>()));
    }
  }
  return out;
}

std::string render_verdict(const Document& doc) {
  if (!doc.contains("targets")) return "";
  const Document& targets = field(doc, "targets");
  if (targets.empty() && field(doc, "failures").empty()) return "A measurement: no targets.\n";
  std::string known;
  for (const Document& t : targets) {
    if (t.value("known_unmet", false) && !t.value("met", false)) {
      known += (known.empty() ? "" : "; ") + t.value("name", std::string());
    }
  }
  std::string out;
  if (field(doc, "passed").get<bool>()) {
    out = fmt::format("**PASS**: {} targets", targets.size());
  } else {
    out = fmt::format("**FAIL**: {} of {} targets", field(doc, "failures").size(), targets.size());
  }
  out += known.empty() ? ", none known unmet." : fmt::format("; known unmet: {}.", known);
  out += "\n";
  for (const Document& f : field(doc, "failures")) out += "- " + f.get<std::string>() + "\n";
  return out;
}

std::string block_name(const Document& doc) {
  if (doc.contains("block") && doc.at("block").is_string()) return doc.at("block");
  return field(doc, "experiment").get<std::string>();
}

}  // namespace

Document accuracy_document(const std::vector<AccuracyResult>& results) {
  Document doc;
  doc["experiment"] = "accuracy";
  doc["tests"] = Document::array();
  for (const AccuracyResult& r : results) {
    for (const AccuracyTest& t : r.tests) {
      Document test{{"label", t.label},
                    {"recipe", r.recipe},
                    {"train_seed", t.train_seed},
                    {"test_seed", t.test_seed},
                    {"train_samples", t.train_samples},
                    {"test_samples", t.evaluation.samples},
                    {"outside", t.evaluation.outside}};
      for (std::size_t p = 0; p < kErrorCount; ++p) {
        const auto& row = t.evaluation.table[p];
        test[kErrors[p].key] = {{"mean_before_um", number_or_null(row.mean_before)},
                                {"mean_after_um", number_or_null(row.mean_after)},
                                {"reduction_pct", number_or_null(row.reduction_pct)},
                                {"coverage_pct", number_or_null(t.evaluation.coverage_pct[p])}};
      }
      doc["tests"].push_back(test);
    }
  }
  return doc;
}

Document cell_interpolant_document(const std::vector<CellInterpolantResult>& results) {
  Document doc;
  doc["experiment"] = "cell-interpolant";
  doc["tests"] = Document::array();
  for (const CellInterpolantResult& r : results) {
    for (const CellInterpolantTest& t : r.tests) {
      doc["tests"].push_back({{"label", t.label},
                              {"recipe", r.recipe},
                              {"rpe_mean_before_um", number_or_null(t.mean_before_um)},
                              {"rpe_mean_after_um", number_or_null(t.mean_after_um)},
                              {"rpe_reduction_pct", number_or_null(t.reduction_pct)}});
    }
  }
  return doc;
}

Document interval_coverage_document(const CoverageResult& result) {
  Document doc;
  doc["experiment"] = "interval-coverage";
  doc["model"] = result.model_id;
  doc["model_y"] = result.model_y_id;
  doc["rows"] = Document::array();
  for (const CoverageRow& row : result.rows) {
    Document o{{"name", row.name}, {"moves", row.moves}, {"outside", row.outside}};
    for (std::size_t p = 0; p < kErrorCount; ++p) {
      o[kErrors[p].key] = {{"coverage_pct", number_or_null(row.coverage_pct[p])},
                           {"mean_u95_um", number_or_null(row.mean_u95_um[p])}};
    }
    doc["rows"].push_back(o);
  }
  for (std::size_t p = 0; p < kErrorCount; ++p) {
    doc["pooled_coverage_pct"][kErrors[p].key] = number_or_null(result.pooled_pct[p]);
  }
  return doc;
}

Document qualified_sweep_document(const SweepResult& result) {
  Document doc;
  doc["experiment"] = "qualified-sweep";
  doc["model"] = result.model_id;
  doc["seeds"] = result.seeds;
  doc["settings"] = Document::array();
  const auto setting = [](const SweepSetting& s) {
    return Document{{"pv_mm_s", s.pv_mm_s},
                    {"pd_mm", s.pd_mm},
                    {"av_mm_s", s.av_mm_s},
                    {"ad_mm", s.ad_mm},
                    {"time_per_point_s", number_or_null(s.time_per_point_s)},
                    {"uncompensated_passes", s.uncompensated_passes},
                    {"compensated_passes", s.compensated_passes}};
  };
  for (const SweepSetting& s : result.settings) doc["settings"].push_back(setting(s));
  doc["fastest_uncompensated"] = result.fastest_uncompensated
                                     ? setting(result.settings[*result.fastest_uncompensated])
                                     : Document(nullptr);
  doc["fastest_compensated"] = result.fastest_compensated
                                   ? setting(result.settings[*result.fastest_compensated])
                                   : Document(nullptr);
  doc["speedup"] = number_or_null(result.speedup > 0 ? result.speedup
                                                     : std::numeric_limits<double>::quiet_NaN());
  return doc;
}

Document cycle_speedup_document(const CycleSpeedupResult& result) {
  Document doc;
  doc["experiment"] = "cycle-speedup";
  const CycleRules& r = result.rules;
  doc["rules"] = Document{{"budget_um", r.budget_um},
                          {"allowance_um", r.allowance_um()},
                          {"sigma_um", r.sigma_um},
                          {"k95", r.k95},
                          {"scatter_share", r.scatter_share},
                          {"mae_limit_um", r.mae_limit_um},
                          {"y_mm", r.y_mm},
                          {"sphere_y_mm", r.sphere_y_mm}};
  doc["todays_reference_s"] = todays_qualified_reference_s();
  doc["identified"] = Document::array();
  for (const IdentifiedModel& m : result.identified) {
    Document d{{"machine", m.machine.name},
               {"final_cost", m.final_cost},
               {"truth_cost", m.truth_cost},
               {"residuals", m.residuals}};
    d["parameters"] = Document::array();
    for (std::size_t i = 0; i < m.parameters.size(); ++i) {
      d["parameters"].push_back(Document{{"key", m.parameters[i]},
                                         {"truth", m.truth_values[i]},
                                         {"fitted", m.fitted_values[i]},
                                         {"relative_sigma", number_or_null(m.relative_sigma[i])}});
    }
    doc["identified"].push_back(d);
  }
  doc["rows"] = Document::array();
  for (const CycleSpeedupRow& row : result.rows) {
    Document d{{"machine", row.machine},
               {"pd_mm", row.pd_mm},
               {"qualified", cycle_choice(row.qualified)},
               {"oracle", cycle_choice(row.oracle)}};
    if (row.has_identified) {
      d["identified"] = cycle_choice(row.identified);
      d["length_test"] = Document{{"seeds", row.length_test_seeds},
                                  {"qualified_passed", row.qualified_seeds_passed},
                                  {"identified_passed", row.identified_seeds_passed}};
    }
    doc["rows"].push_back(d);
  }
  return doc;
}

Document calibration_document(const CalibrationResult& result) {
  Document doc;
  doc["experiment"] = "calibration";
  doc["machine"] = result.machine;
  doc["seed"] = result.seed;
  doc["seeds"] = result.seeds;
  doc["needed"] = result.needed;
  doc["comparison"] = dynamics::format_paper_comparison(result.first);
  return doc;
}

Document identify_multistart_document(const MultistartResult& result) {
  Document doc;
  doc["experiment"] = "identify-multistart";
  doc["free_parameters"] = result.free_parameters;
  doc["starts"] = Document::array();
  for (const MultistartRow& r : result.rows) {
    doc["starts"].push_back({{"start", r.start},
                             {"failure", r.failure},
                             {"initial_cost", number_or_null(r.initial_cost)},
                             {"final_cost", number_or_null(r.final_cost)},
                             {"seconds", number_or_null(r.seconds)},
                             {"start_values", r.start_values},
                             {"fitted_values", r.fitted_values},
                             {"at_bound", r.at_bound},
                             {"requirements", r.requirements},
                             {"held", r.held}});
  }
  return doc;
}

Document interval_calibration_document(const IntervalCalibrationResult& result) {
  Document doc;
  doc["experiment"] = "interval-calibration";
  doc["recipe"] = result.recipe;
  doc["test_moves"] = result.test_moves;
  doc["levels"] = Document::array();
  for (const IntervalCalibrationRow& r : result.rows) {
    Document row{{"nominal_pct", r.nominal_pct}};
    for (std::size_t p = 0; p < kErrorCount; ++p) {
      row[kErrors[p].key] = number_or_null(r.coverage_pct[p]);
    }
    doc["levels"].push_back(row);
  }
  return doc;
}

Document cross_machine_document(const CrossMachineResult& result) {
  Document doc;
  doc["experiment"] = "cross-machine";
  doc["plan"] = result.plan;
  doc["shipped_model"] = result.shipped_model_id;
  doc["test_moves"] = result.rows.empty() ? 0 : result.rows.front().own.samples;
  doc["machines"] = Document::array();
  const auto table = [](const training::TestSetEvaluation& e) {
    Document t;
    for (std::size_t p = 0; p < kErrorCount; ++p) {
      t[kErrors[p].key] = {{"mean_before_um", number_or_null(e.table[p].mean_before)},
                           {"mean_after_um", number_or_null(e.table[p].mean_after)},
                           {"reduction_pct", number_or_null(e.table[p].reduction_pct)}};
    }
    return t;
  };
  for (const CrossMachineRow& r : result.rows) {
    doc["machines"].push_back({{"machine", r.machine},
                               {"planned", r.planned},
                               {"extracted", r.extracted},
                               {"own", table(r.own)},
                               {"shipped", table(r.shipped)}});
  }
  return doc;
}

void add_verdict(Document& doc, const std::vector<Target>& targets, const Verdict& verdict) {
  Document a = Document::array();
  for (const Target& t : targets) {
    a.push_back({{"name", t.name},
                 {"measured", number_or_null(t.measured)},
                 {"limit", t.limit},
                 {"kind", t.kind == Target::Kind::kAtLeast ? "at least" : "at most"},
                 {"unit", t.unit},
                 {"met", t.met()},
                 {"known_unmet", t.known_unmet}});
  }
  doc["targets"] = a;
  doc["passed"] = verdict.passed;
  doc["failures"] = verdict.failures;
}

std::string render_markdown(const Document& doc) {
  const std::string experiment = field(doc, "experiment").get<std::string>();
  std::string out;
  if (doc.contains("command")) out += "`" + doc.at("command").get<std::string>() + "`\n\n";
  if (experiment == "accuracy") {
    out += render_accuracy(doc);
  } else if (experiment == "cell-interpolant") {
    out += render_cell_interpolant(doc);
  } else if (experiment == "interval-coverage") {
    out += render_interval_coverage(doc);
  } else if (experiment == "calibration") {
    out += render_calibration(doc);
  } else if (experiment == "identify-multistart") {
    out += render_identify_multistart(doc);
  } else if (experiment == "interval-calibration") {
    out += render_interval_calibration(doc);
  } else if (experiment == "cross-machine") {
    out += render_cross_machine(doc);
  } else if (experiment == "qualified-sweep") {
    out += render_qualified_sweep(doc);
  } else if (experiment == "cycle-speedup") {
    out += render_cycle_speedup(doc);
  } else {
    throw ConfigError(fmt::format("study document: unknown experiment \"{}\"", experiment));
  }
  const std::string verdict = render_verdict(doc);
  return verdict.empty() ? out : out + "\n" + verdict;
}

std::string splice_block(const std::string& page, const Document& doc) {
  const std::string name = block_name(doc);
  const std::string start = "<!-- study: " + name + " -->\n";
  const std::string end = "<!-- /study: " + name + " -->\n";
  // Every line that is exactly the marker: a block is one start line, then one end line.
  const auto lines_of = [&](const std::string& marker) {
    std::vector<std::size_t> at;
    for (std::size_t p = page.find(marker); p != std::string::npos; p = page.find(marker, p + 1)) {
      if (p == 0 || page[p - 1] == '\n') at.push_back(p);
    }
    return at;
  };
  const std::vector<std::size_t> starts = lines_of(start), ends = lines_of(end);
  if (starts.size() > 1 || ends.size() > 1 ||
      (starts.size() == 1 && ends.size() == 1 && ends[0] < starts[0])) {
    throw ConfigError(fmt::format(
        "the page's block \"{}\" is not one `{}` line followed by one `{}` line ({} and {} of "
        "them): fix the markers by hand",
        name,
        start.substr(0, start.size() - 1),
        end.substr(0, end.size() - 1),
        starts.size(),
        ends.size()));
  }
  const std::size_t a = starts.empty() ? std::string::npos : starts[0];
  const std::size_t b = ends.empty() ? std::string::npos : ends[0];
  if (a == std::string::npos || b == std::string::npos) {
    throw ConfigError(fmt::format(
        "the page has no block \"{}\": put the lines `{}` and `{}` where its table belongs "
        "(the page must use LF line ends)",
        name,
        start.substr(0, start.size() - 1),
        end.substr(0, end.size() - 1)));
  }
  return page.substr(0, a + start.size()) + render_markdown(doc) + page.substr(b);
}

PageSync sync_page(const std::string& path, const Document& doc, bool update) {
  const std::string page = io::read_file_bounded(path, "results page", std::uintmax_t{1} << 24);
  const std::string now = splice_block(page, doc);
  PageSync sync;
  if (now == page) return sync;
  sync.current = false;
  std::size_t line_start = 0;
  for (std::size_t i = 0; i < std::min(page.size(), now.size()) && page[i] == now[i]; ++i) {
    if (page[i] == '\n') line_start = i + 1;
  }
  const auto line_at = [&](const std::string& text) {
    const std::size_t e = text.find('\n', line_start);
    return text.substr(line_start, e == std::string::npos ? std::string::npos : e - line_start);
  };
  sync.first_difference = "page: " + line_at(page) + "\nnow:  " + line_at(now);
  if (update) io::write_file_atomically(path, now);
  return sync;
}

std::string command_line(int argc, const char* const* argv) {
  std::string out = "cmmcomp-study";
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--json" || arg == "--update-page" || arg.rfind("--page=", 0) == 0) continue;
    if (arg == "--page") {
      ++i;  // and its value
      continue;
    }
    out += arg.find(' ') == std::string::npos ? " " + arg : " '" + arg + "'";
  }
  return out;
}

Publication publish(const Document& result,
                    std::vector<Target> targets,
                    const ReportOptions& options) {
  const KnownUnmet known =
      options.known_unmet.empty() ? KnownUnmet{} : read_known_unmet(options.known_unmet);
  const Verdict v = check(targets, known);
  Document doc{{"experiment", result["experiment"]},
               {"block", options.block.empty() ? result["experiment"] : Document(options.block)},
               {"command", options.command}};
  doc.update(result);
  add_verdict(doc, targets, v);
  Publication out;
  out.text = options.json ? doc.dump(2) : render_markdown(doc);
  out.status = v.passed ? 0 : 1;
  if (options.page.empty()) return out;
  const PageSync sync = sync_page(options.page, doc, options.update_page);
  const std::string block = doc["block"].get<std::string>();
  if (!sync.current && options.update_page) {
    out.note = "cmmcomp-study: updated the block \"" + block + "\" of " + options.page;
  } else if (!sync.current) {
    out.note = "cmmcomp-study: the block \"" + block + "\" of " + options.page +
               " is stale: this run renders it differently, first at\n" + sync.first_difference +
               "\nRegenerate it (scripts/regenerate-results.sh, or this command with "
               "--update-page) and commit the page.";
    out.status = 1;
  }
  return out;
}

}  // namespace cmmcomp::study

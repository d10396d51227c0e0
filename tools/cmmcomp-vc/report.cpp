// SPDX-License-Identifier: MIT
/// @file Table, JSON and CSV of the length test.
#include "report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <fstream>

namespace cmmcomp::vc {

std::string model_id_hex(std::uint64_t id) { return fmt::format("{:016x}", id); }

namespace {

std::string setting_text(const ProbeSetting& s) {
  return fmt::format("PV {:g} PA {:g} PD {:g} AV {:g} AA {:g} AD {:g}",
                     s.pv_mm_s,
                     s.pa_mm_s2,
                     s.pd_mm,
                     s.av_mm_s,
                     s.aa_mm_s2,
                     s.ad_mm);
}

/// The model ids each agent answered with (usable answers), in hex, in order of first answer:
/// one id, or "a/b/c" for an agent with a model per Y; "0000000000000000" when none.
std::vector<std::string> agent_model_ids(const LengthTestResult& r) {
  std::vector<std::vector<std::uint64_t>> seen(r.agent_labels.size());
  for (const PointRecord& p : r.points) {
    for (std::size_t g = 0; g < p.answers.size() && g < seen.size(); ++g) {
      const Answer& a = p.answers[g].answer;
      if (a.usable && std::find(seen[g].begin(), seen[g].end(), a.model_id) == seen[g].end()) {
        seen[g].push_back(a.model_id);
      }
    }
  }
  std::vector<std::string> ids;
  for (const auto& agent : seen) {
    std::string text;
    for (const std::uint64_t id : agent) text += (text.empty() ? "" : "/") + model_id_hex(id);
    ids.push_back(text.empty() ? model_id_hex(0) : text);
  }
  return ids;
}

std::string mark(double e, double mpe) { return std::fabs(e) <= mpe ? " " : "*"; }
const char* pass(bool p) { return p ? "pass" : "FAIL"; }

std::string join(const std::vector<std::string>& v, const std::string& sep) {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? sep : "") + v[i];
  return out;
}

/// The uncompensated columns' suffix: "-q" when the qualification removed the static lag.
std::string q_suffix(const LengthTestResult& r) { return r.qualification ? "-q" : ""; }

/// One line on what the qualification measured and removed (qualification.hpp).
std::string qualification_text(const Qualification& q) {
  std::vector<std::string> nodes;
  const planning::QualifiedReference& ref = q.reference;
  for (std::size_t i = 0; i < ref.map_y_mm.size(); ++i) {
    nodes.push_back(fmt::format("Y {:g} {:+.2f}", ref.map_y_mm[i], ref.map_um[i]));
  }
  std::vector<std::string> offsets;
  for (std::size_t i = 0; i < q.settings.size(); ++i) {
    offsets.push_back(fmt::format("{} {:+.2f}", q.settings[i].name, q.offsets_um[i]));
  }
  return fmt::format(
      "  qualified (-q columns): reversal map at {} ({} touches a node): {} µm; probe qualified "
      "on a sphere at Y {:g} mm: {} µm; {} touches in all; a -q point is scale + (map(Y) + "
      "offset)·d\n",
      setting_text(q.plan.map_setting),
      q.plan.touches,
      join(nodes, ", "),
      q.plan.sphere_y_mm,
      join(offsets, ", "),
      q.touches_used);
}

}  // namespace

std::string headline(const LengthTestResult& r) {
  const double speedup = r.slow_time_per_point_s / r.fast_time_per_point_s;
  const std::string qualified = r.qualification ? "qualified " : "";
  std::string out;
  for (std::size_t g = 0; g < r.agent_labels.size(); ++g) {
    std::vector<std::string> gained;  // Y where compensation turns a fail into a pass
    std::vector<std::string> passes;
    for (const YSummary& y : r.per_y) {
      if (y.fast_compensated_pass[g]) passes.push_back(fmt::format("{:g}", y.y_mm));
      if (y.fast_compensated_pass[g] && !y.fast_uncompensated_pass) {
        gained.push_back(fmt::format("{:g}", y.y_mm));
      }
    }
    out += fmt::format(
        "fast + {} compensation meets MPE_E at Y = {} mm{}; {:.2f} s per point instead of "
        "{:.2f} s for the {}slow reference ({:.1f}x faster).\n",
        r.agent_labels[g],
        passes.empty() ? std::string("none") : join(passes, ", "),
        gained.empty() ? " (fast " + qualified + "uncompensated fails nowhere it passes)"
                       : " where fast " + qualified +
                             "uncompensated fails at Y = " + join(gained, ", ") + " mm",
        r.fast_time_per_point_s,
        r.slow_time_per_point_s,
        qualified,
        speedup);
  }
  if (r.agent_labels.empty()) out = "no agent: nothing compensated\n";
  return out;
}

std::string format_report(const LengthProgram& program, const LengthTestResult& r) {
  std::string out;
  out += fmt::format("Length test (ISO 10360-2 style, bidirectional, {} repeat(s) per length)\n",
                     program.repeats);
  out += fmt::format("  fast: {}  ({:.3f} s per point, compensated)\n",
                     setting_text(program.fast),
                     r.fast_time_per_point_s);
  out += fmt::format("  slow: {}  ({:.3f} s per point, uncompensated reference)\n",
                     setting_text(program.slow),
                     r.slow_time_per_point_s);
  const auto ids = agent_model_ids(r);
  for (std::size_t g = 0; g < r.agent_labels.size(); ++g) {
    out += fmt::format("  agent {}: {}, model {}\n", r.agent_labels[g], r.agent_places[g], ids[g]);
  }
  if (r.qualification) out += qualification_text(*r.qualification);
  out +=
      "\nLength error E = measured − nominal [µm] (worst repeat); * = |E| > MPE_E = 1.9 + "
      "L/300 µm\n";
  const std::string q = q_suffix(r);
  std::string head = fmt::format(
      "{:>6} {:>6} {:>7} {:>9} {:>9}", "Y mm", "L mm", "MPE_E", "slow" + q, "fast-unc" + q);
  for (const auto& l : r.agent_labels) head += fmt::format(" {:>9}", "fast-" + l);
  out += head + "\n";
  for (const CaseResult& c : r.cases) {
    std::string line = fmt::format("{:>6g} {:>6g} {:>7.2f} {:>8.2f}{} {:>8.2f}{}",
                                   c.y_mm,
                                   c.length_mm,
                                   c.mpe_e_um,
                                   c.slow_um,
                                   mark(c.slow_um, c.mpe_e_um),
                                   c.fast_uncompensated_um,
                                   mark(c.fast_uncompensated_um, c.mpe_e_um));
    for (double e : c.fast_compensated_um) {
      line += fmt::format(" {:>8.2f}{}", e, mark(e, c.mpe_e_um));
    }
    out += line + "\n";
  }
  out += "\nPer Y: largest |E| [µm] and whether every length met MPE_E\n";
  head = fmt::format("{:>6} {:>13} {:>13}", "Y mm", "slow" + q, "fast-unc" + q);
  for (const auto& l : r.agent_labels) head += fmt::format(" {:>13}", "fast-" + l);
  out += head + "\n";
  for (const YSummary& y : r.per_y) {
    std::string line = fmt::format("{:>6g} {:>8.2f} {:4} {:>8.2f} {:4}",
                                   y.y_mm,
                                   y.slow_max_um,
                                   pass(y.slow_pass),
                                   y.fast_uncompensated_max_um,
                                   pass(y.fast_uncompensated_pass));
    for (std::size_t g = 0; g < y.fast_compensated_max_um.size(); ++g) {
      line += fmt::format(
          " {:>8.2f} {:4}", y.fast_compensated_max_um[g], pass(y.fast_compensated_pass[g]));
    }
    out += line + "\n";
  }
  if (r.unusable_answers > 0) {
    out += fmt::format("\nwarning: {} answers could not be applied (see the point log)\n",
                       r.unusable_answers);
  }
  out += "\n" + headline(r);
  return out;
}

nlohmann::json report_json(const LengthProgram& program, const LengthTestResult& r) {
  using nlohmann::json;
  auto setting = [](const ProbeSetting& s, double t) {
    return json{{"pv_mm_s", s.pv_mm_s},
                {"pa_mm_s2", s.pa_mm_s2},
                {"pd_mm", s.pd_mm},
                {"av_mm_s", s.av_mm_s},
                {"aa_mm_s2", s.aa_mm_s2},
                {"ad_mm", s.ad_mm},
                {"time_per_point_s", t}};
  };
  json j;
  j["program"] = {{"lengths_mm", program.lengths_mm},
                  {"y_mm", program.y_mm},
                  {"x0_mm", program.x0_mm},
                  {"repeats", program.repeats}};
  j["settings"] = {{"fast", setting(program.fast, r.fast_time_per_point_s)},
                   {"slow", setting(program.slow, r.slow_time_per_point_s)}};
  j["speedup"] = r.slow_time_per_point_s / r.fast_time_per_point_s;
  const auto ids = agent_model_ids(r);
  j["agents"] = json::array();
  for (std::size_t g = 0; g < r.agent_labels.size(); ++g) {
    j["agents"].push_back(
        {{"label", r.agent_labels[g]}, {"where", r.agent_places[g]}, {"model_id", ids[g]}});
  }
  j["cases"] = json::array();
  for (const CaseResult& c : r.cases) {
    json comp = json::object();
    for (std::size_t g = 0; g < c.fast_compensated_um.size(); ++g) {
      comp[r.agent_labels[g]] = c.fast_compensated_um[g];
    }
    j["cases"].push_back({{"y_mm", c.y_mm},
                          {"length_mm", c.length_mm},
                          {"mpe_e_um", c.mpe_e_um},
                          {"slow_um", c.slow_um},
                          {"fast_uncompensated_um", c.fast_uncompensated_um},
                          {"fast_compensated_um", comp}});
  }
  j["per_y"] = json::array();
  for (const YSummary& y : r.per_y) {
    json comp = json::object();
    for (std::size_t g = 0; g < y.fast_compensated_max_um.size(); ++g) {
      comp[r.agent_labels[g]] = {{"max_abs_um", y.fast_compensated_max_um[g]},
                                 {"pass", static_cast<bool>(y.fast_compensated_pass[g])}};
    }
    j["per_y"].push_back(
        {{"y_mm", y.y_mm},
         {"slow", {{"max_abs_um", y.slow_max_um}, {"pass", y.slow_pass}}},
         {"fast_uncompensated",
          {{"max_abs_um", y.fast_uncompensated_max_um}, {"pass", y.fast_uncompensated_pass}}},
         {"fast_compensated", comp}});
  }
  j["qualification"] = nullptr;
  if (r.qualification) {
    const Qualification& q = *r.qualification;
    json map = json::array();
    for (std::size_t i = 0; i < q.reference.map_y_mm.size(); ++i) {
      map.push_back({{"y_mm", q.reference.map_y_mm[i]}, {"rae_um", q.reference.map_um[i]}});
    }
    json offsets = json::object();
    for (std::size_t i = 0; i < q.settings.size(); ++i)
      offsets[q.settings[i].name] = q.offsets_um[i];
    j["qualification"] = {
        {"sphere_y_mm", q.plan.sphere_y_mm},
        {"touches_per_measurement", q.plan.touches},
        {"touches", q.touches_used},
        {"map_setting",
         setting(q.plan.map_setting,
                 time_per_point_s(q.plan.map_setting, program.dwell_s, program.smoothing_s))},
        {"map", map},
        {"offsets_um", offsets}};
  }
  j["unusable_answers"] = r.unusable_answers;
  j["headline"] = headline(r);
  return j;
}

void write_points_csv(const std::string& path, const LengthTestResult& r) {
  std::ofstream out(path, std::ios::trunc);
  if (!out) throw Error("cannot write " + path);
  out << "index,setting,y_mm,length_mm,repeat,face,direction,pv_mm_s,pa_mm_s2,pd_mm,av_mm_s,"
         "aa_mm_s2,ad_mm,true_mm,twin_rae_um,scale_mm,agent,status,flags,predicted_rae_um,"
         "correction_x_um,corrected_mm,applied,model_id,time_per_point_s,qualified_mm\n";
  for (const PointRecord& p : r.points) {
    const std::string common = fmt::format(
        "{},{},{:g},{:g},{},{},{},{:g},{:g},{:g},{:g},{:g},{:g},"
        "{:.6f},{:.4f},{:.7f}",
        p.index,
        p.setting.name,
        p.y_mm,
        p.length_mm,
        p.repeat,
        to_string(p.face),
        direction_of(p.face),
        p.setting.pv_mm_s,
        p.setting.pa_mm_s2,
        p.setting.pd_mm,
        p.setting.av_mm_s,
        p.setting.aa_mm_s2,
        p.setting.ad_mm,
        p.true_mm,
        p.rae_um,
        p.scale_mm);
    // The point an uncompensated controller reports: the scale point, or with --qualify the
    // scale point less the map's and the qualification's lag.
    const std::string qualified = fmt::format(",{:.7f}", p.qualified_mm);
    if (p.answers.empty()) {
      out << common << fmt::format(",-,,,,,{:.7f},0,,{:.4f}", p.scale_mm, p.time_s) << qualified
          << '\n';
      continue;
    }
    for (std::size_t g = 0; g < p.answers.size(); ++g) {
      const Answer& a = p.answers[g].answer;
      out << common
          << fmt::format(",{},{},{},{:.4f},{:.4f},{:.7f},{},{},{:.4f}",
                         r.agent_labels[g],
                         a.status,
                         a.flags,
                         a.rae_um,
                         a.correction_um[0],
                         p.answers[g].corrected_mm,
                         a.usable ? 1 : 0,
                         model_id_hex(a.model_id),
                         p.time_s)
          << qualified << '\n';
    }
  }
  if (!out) throw Error("cannot write " + path);
}

}  // namespace cmmcomp::vc

// SPDX-License-Identifier: MIT
/// @file A model's training conditions from its sources (include/cmmcomp/measure/conditions.hpp).
#include <fmt/format.h>

#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/measure/conditions.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace cmmcomp::measure {

io::TrainingConditions training_conditions(const std::vector<DatasetRow>& rows,
                                           const ConditionSources& sources) {
  io::TrainingConditions c = io::dataset_conditions(rows);
  if (sources.pa_mm_s2) c.pa_mm_s2 = sources.pa_mm_s2;
  if (sources.aa_mm_s2) c.aa_mm_s2 = sources.aa_mm_s2;
  const io::TrainingConditions from_campaigns = campaign_conditions(sources.campaigns);
  c.dwell_s = from_campaigns.dwell_s;
  c.smoothing_s = from_campaigns.smoothing_s;
  c.axis = from_campaigns.axis;
  c.noise_floor = from_campaigns.noise_floor;
  if (sources.machine) {
    const dynamics::Machine& m = *sources.machine;
    c.machine = m.name;
    const auto take = [&](std::optional<double>& slot, double value, const char* what) {
      if (slot && std::abs(*slot - value) > 0.010) {
        throw ConfigError(fmt::format(
            "--machine {}: controller {} {} s, but the campaign ran with {} s: give the machine "
            "file the campaign's controller setting",
            sources.machine_label,
            what,
            value,
            *slot));
      }
      if (!slot) slot = value;
    };
    take(c.dwell_s, m.parameters.controller_dwell_s, "dwell");
    take(c.smoothing_s, m.parameters.controller_smoothing_s, "smoothing");
  }
  if (!sources.axis.empty()) {
    if (!c.axis.empty() && c.axis != sources.axis) {
      throw ConfigError("--axis " + sources.axis + ", but the campaign ran on axis " + c.axis);
    }
    c.axis = sources.axis;
  }
  if (!sources.noise_floor.empty()) c.noise_floor = sources.noise_floor;
  return c;
}

std::string describe_conditions(const io::TrainingConditions& c) {
  const auto range = [](const std::optional<io::ConditionRange>& r) {
    if (!r) return std::string("unknown");
    return r->lo == r->hi ? fmt::format("{:g}", r->lo) : fmt::format("{:g}..{:g}", r->lo, r->hi);
  };
  const auto value = [](const std::optional<double>& v) {
    return v ? fmt::format("{:g} s", *v) : std::string("unknown");
  };
  std::string noise = "unknown";
  if (!c.noise_floor.empty()) {
    noise = fmt::format("{:.3g}, {:.3g}, {:.3g}, {:.3g} um",
                        c.noise_floor[0],
                        c.noise_floor[1],
                        c.noise_floor[2],
                        c.noise_floor[3]);
  }
  return fmt::format(
      "PA {} mm/s2, AA {} mm/s2, dwell {}, smoothing {}, axis {}, machine {}, noise floor {}",
      range(c.pa_mm_s2),
      range(c.aa_mm_s2),
      value(c.dwell_s),
      value(c.smoothing_s),
      c.axis.empty() ? "unknown" : c.axis,
      c.machine.empty() ? "unknown" : c.machine,
      noise);
}

io::ConditionRange parse_condition_range(const std::string& text, const std::string& option) {
  const auto number = [&](const std::string& t) {
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (t.empty() || *end != '\0' || !std::isfinite(v) || v <= 0) {
      throw ConfigError(option + ": '" + text + "' is not LO or LO:HI with 0 < LO <= HI [mm/s2]");
    }
    return v;
  };
  const auto colon = text.find(':');
  const io::ConditionRange r =
      colon == std::string::npos
          ? io::ConditionRange{number(text), number(text)}
          : io::ConditionRange{number(text.substr(0, colon)), number(text.substr(colon + 1))};
  if (r.lo > r.hi) throw ConfigError(option + ": '" + text + "' has LO > HI");
  return r;
}

std::vector<double> parse_noise_floor(const std::string& text) {
  if (text == "table1") return {paper::kTable1Std.begin(), paper::kTable1Std.end()};
  std::vector<double> out;
  std::stringstream list(text);
  for (std::string item; std::getline(list, item, ',');) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(v) || v < 0) {
      throw ConfigError("--noise-floor: '" + item + "' is not a number >= 0");
    }
    out.push_back(v);
  }
  if (out.size() != 4) {
    throw ConfigError("--noise-floor: expected 4 values (MPE, RPE, MAE, RAE [um]) or 'table1'");
  }
  return out;
}

}  // namespace cmmcomp::measure

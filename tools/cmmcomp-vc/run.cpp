// SPDX-License-Identifier: MIT
/// @file cmmcomp-vc's run: the program from the options, the twin, the agents behind their
/// protocols (a model per Y gathered into one source), the length test and its report.
#include <fmt/format.h>

#include <cmath>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/vc/correction_source.hpp>
#include <cmmcomp/vc/ipp_probe.hpp>
#include <cmmcomp/vc/length_test.hpp>
#include <cmmcomp/vc/per_y_source.hpp>
#include <cmmcomp/vc/twin_probe.hpp>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "agent_spec.hpp"
#include "can_link.hpp"
#include "commands.hpp"
#include "modbus_link.hpp"
#include "report.hpp"

namespace cmmcomp::tools::vc {

int run(const Options& opt) {
  using namespace cmmcomp::vc;
  LengthProgram program;
  program.lengths_mm = parse_number_list(opt.lengths, "--lengths");
  program.y_mm = parse_number_list(opt.y, "--y");
  program.repeats = opt.repeats;
  program.x0_mm = opt.x0_mm;
  if (!opt.fast.empty()) program.fast = parse_setting(opt.fast, program.fast);
  if (!opt.slow.empty()) program.slow = parse_setting(opt.slow, program.slow);
  program.qualify = opt.qualify;
  program.qualification.sphere_y_mm = opt.sphere_y_mm;
  program.qualification.touches = opt.qualify_touches;
  if (!opt.map_setting.empty()) {
    program.qualification.map_setting =
        parse_setting(opt.map_setting, program.qualification.map_setting);
  }
  program.qualification.map_setting.name = "map";
  program.validate();

  cmmcomp::dynamics::MeasurementNoise noise;
  noise.enabled = !opt.no_noise;
  noise.seed = opt.seed;
  const cmmcomp::dynamics::Machine machine = opt.machine.empty()
                                                 ? cmmcomp::dynamics::default_machine()
                                                 : cmmcomp::dynamics::load_machine(opt.machine);
  for (const std::string& w : cmmcomp::dynamics::implausible_parameters(machine.parameters)) {
    std::fprintf(stderr, "warning: %s: %s\n", opt.machine.c_str(), w.c_str());
  }
  // The touches: the twin in this process, or the machine behind an I++ DME server.
  std::unique_ptr<TouchErrorModel> touches;
  IppProbe* ipp_probe = nullptr;
  if (opt.ipp_proxied && opt.ipp.empty()) {
    throw cmmcomp::ConfigError("--ipp-proxied needs --ipp HOST:PORT (the proxy)");
  }
  if (opt.ipp.empty()) {
    touches = std::make_unique<TwinProbe>(machine, noise);
  } else {
    const std::size_t colon = opt.ipp.rfind(':');
    const std::string port_text = colon == std::string::npos ? "" : opt.ipp.substr(colon + 1);
    if (colon == std::string::npos || colon == 0 || port_text.empty() || port_text.size() > 5 ||
        port_text.find_first_not_of("0123456789") != std::string::npos ||
        std::stol(port_text) > 65535) {
      throw cmmcomp::ConfigError("--ipp: '" + opt.ipp + "' is not HOST:PORT");
    }
    try {
      auto probe = std::make_unique<IppProbe>(opt.ipp.substr(0, colon),
                                              static_cast<std::uint16_t>(std::stol(port_text)));
      ipp_probe = probe.get();
      touches = std::move(probe);
    } catch (const cmmcomp::Error& e) {
      throw UnreachableError(e.what());
    }
  }
  TouchErrorModel& twin = *touches;
  // The twin's controller dwells and smooths every move: that time counts per point.
  program.dwell_s = machine.parameters.controller_dwell_s;
  program.smoothing_s = machine.parameters.controller_smoothing_s;

  // --map-only: the reversal map alone, as cmmcomp-plan's arguments; no agent, no program.
  if (opt.map_only) {
    const Qualification q = qualify(program.qualification, program.y_mm, {}, twin);
    std::string nodes;
    for (std::size_t i = 0; i < q.reference.map_y_mm.size(); ++i) {
      nodes +=
          fmt::format("{}{}={:.4f}", i ? "," : "", q.reference.map_y_mm[i], q.reference.map_um[i]);
    }
    std::printf("--sphere-y %s --reversal-map %s\n",
                fmt::format("{}", q.reference.sphere_y_mm).c_str(),
                nodes.c_str());
    return 0;
  }

  std::vector<AgentSpec> specs;
  if (!opt.modbus.empty()) specs.push_back(parse_agent_spec("agent=modbus:" + opt.modbus));
  if (!opt.can.empty()) {
    specs.push_back(parse_agent_spec("agent=can:" + opt.can + ":" + opt.can_base_id));
  }
  if (!opt.modbus.empty() && !opt.can.empty()) {
    specs[0].label = "modbus";
    specs[1].label = "can";
  }
  for (const auto& a : opt.agents) specs.push_back(parse_agent_spec(a));
  if (specs.empty() && !opt.ipp_proxied) {
    throw cmmcomp::ConfigError("no agent: give --modbus tcp:HOST:PORT, --can IFACE or --agent");
  }
  for (std::size_t i = 0; i < specs.size(); ++i) {
    for (std::size_t k = 0; k < i; ++k) {
      if (specs[i].label != specs[k].label) continue;
      // One label may name several agents only as a model per Y: LABEL@Y, every Y its own.
      if (!specs[i].has_y || !specs[k].has_y) {
        throw cmmcomp::ConfigError("two agents labelled '" + specs[i].label +
                                   "' (several agents share a label only as LABEL@Y, one per Y)");
      }
      if (std::fabs(specs[i].y_mm - specs[k].y_mm) <= PerYSource::kSameY) {
        throw cmmcomp::ConfigError("two agents labelled '" + specs[i].label + "' for Y " +
                                   fmt::format("{:g}", specs[i].y_mm) + " mm");
      }
    }
  }

  // Every Y of the program needs an agent of each per-Y label, checked before connecting.
  for (const AgentSpec& s : specs) {
    if (!s.has_y) continue;
    for (double y : program.y_mm) {
      bool served = false;
      for (const AgentSpec& t : specs) {
        served = served || (t.label == s.label && std::fabs(t.y_mm - y) <= PerYSource::kSameY);
      }
      if (!served) {
        throw cmmcomp::ConfigError(
            fmt::format("agent '{}' has no agent for Y {:g} mm of the program (give {}@{:g}=…)",
                        s.label,
                        y,
                        s.label,
                        y));
      }
    }
  }
  const auto connect = [&](const AgentSpec& s) -> std::unique_ptr<CorrectionSource> {
    // A per-Y agent records into its own file: the label and Y before the extension.
    const std::string name = s.has_y ? fmt::format("{}-y{}", s.label, s.y_mm) : s.label;
    const std::string record =
        opt.record.empty() ? std::string() : recording_path_for(opt.record, name, specs.size() > 1);
    if (s.is_can) {
      return std::make_unique<CanLink>(s.label, s.endpoint, s.can_base_id, opt.timeout_ms, record);
    }
    return std::make_unique<ModbusLink>(
        s.label, s.endpoint, opt.modbus_unit, opt.timeout_ms, record);
  };
  std::vector<std::unique_ptr<CorrectionSource>> links;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    if (!specs[i].has_y) {
      links.push_back(connect(specs[i]));
      continue;
    }
    bool first = true;  // the label's first per-Y agent gathers them all
    for (std::size_t k = 0; k < i; ++k) first = first && specs[k].label != specs[i].label;
    if (!first) continue;
    std::vector<std::pair<double, std::unique_ptr<CorrectionSource>>> per_y;
    for (const AgentSpec& s : specs) {
      if (s.label == specs[i].label) per_y.emplace_back(s.y_mm, connect(s));
    }
    links.push_back(std::make_unique<PerYSource>(specs[i].label, std::move(per_y)));
  }
  if (opt.ipp_proxied) {
    for (const AgentSpec& s : specs) {
      if (s.label == "ipp-proxy") {
        throw cmmcomp::ConfigError("the label 'ipp-proxy' is --ipp-proxied's");
      }
    }
    links.push_back(std::make_unique<IppProxySource>(*ipp_probe, "ipp-proxy", "ipp " + opt.ipp));
  }
  std::vector<CorrectionSource*> agents;
  agents.reserve(links.size());
  for (auto& l : links) agents.push_back(l.get());

  const LengthTestResult result = run_length_test(program, twin, agents);
  links.clear();  // closes the sessions: recordings are complete from here on

  if (!opt.csv.empty()) write_points_csv(opt.csv, result);
  std::vector<std::string> plots;
  if (!opt.plot.empty()) plots = write_plots(opt.plot, program, result);
  if (opt.json) {
    std::printf("%s\n", report_json(program, result).dump(2).c_str());
  } else {
    std::printf("%s", format_report(program, result).c_str());
    for (const auto& p : plots) std::printf("wrote %s\n", p.c_str());
    if (!opt.csv.empty()) std::printf("wrote %s\n", opt.csv.c_str());
  }
  return result.unusable_answers == 0 ? 0 : 1;
}

int failure_status(const std::exception& e) {
  const bool usage = dynamic_cast<const cmmcomp::vc::UnreachableError*>(&e) != nullptr ||
                     dynamic_cast<const cmmcomp::ConfigError*>(&e) != nullptr;
  return usage ? 2 : 1;
}

}  // namespace cmmcomp::tools::vc

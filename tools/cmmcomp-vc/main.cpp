// SPDX-License-Identifier: MIT
/// @file cmmcomp-vc: a virtual CMM controller that runs an ISO 10360-2 style length test at
/// speed on the digital twin and asks cmmcomp-agent for each correction over Modbus TCP or CAN.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/plugins/can_server.hpp>
#include <cmmcomp/vc/length_test.hpp>
#include <cmmcomp/vc/per_y_source.hpp>
#include <cmmcomp/vc/twin_probe.hpp>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "../common/usage.hpp"
#include "agent_spec.hpp"
#include "can_link.hpp"
#include "modbus_link.hpp"
#include "report.hpp"

namespace {

struct Options {
  std::string modbus;
  int modbus_unit = 1;
  std::string can;
  std::string can_base_id =
      cmmcomp::plugins::format_can_base_id(cmmcomp::plugins::can::kDefaultBaseId);
  std::vector<std::string> agents;
  std::string lengths = "20,50,100,200,400";
  std::string y = "0,250,500";
  int repeats = 3;
  double x0_mm = 100;
  std::string fast;
  std::string slow;
  std::uint64_t seed = 1;
  bool no_noise = false;
  std::string machine;
  std::string csv;
  bool json = false;
  std::string plot;
  std::string record;
  int timeout_ms = 2000;
  bool qualify = false;
  bool map_only = false;
  double sphere_y_mm = 250;
  int qualify_touches = 10;
  std::string map_setting;
};

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
  TwinProbe twin(machine, noise);
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
  if (specs.empty()) {
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

}  // namespace

static int run_tool(int argc, char** argv) {
  CLI::App app{
      "cmmcomp-vc: a virtual CMM controller. Runs an ISO 10360-2 style bidirectional length "
      "test on the digital twin at a fast (compensated) and a slow (reference) setting, asks "
      "cmmcomp-agent for every fast point's correction over Modbus TCP or CAN, and reports the "
      "length errors against MPE_E = 1.9 + L/300 um and the time per point."};
  Options opt;
  app.add_option("--modbus", opt.modbus, "agent on Modbus TCP, tcp:HOST:PORT (label 'agent')");
  app.add_option("--modbus-unit", opt.modbus_unit, "Modbus unit id")->capture_default_str();
  app.add_option("--can", opt.can, "agent on this CAN interface, e.g. vcan0 (label 'agent')");
  app.add_option("--can-base-id", opt.can_base_id, "11-bit base identifier for --can")
      ->capture_default_str();
  app.add_option("--agent",
                 opt.agents,
                 "LABEL=modbus:tcp:HOST:PORT or LABEL=can:IFACE[:BASE_ID]; repeat to compare "
                 "agents (each answers every fast point). LABEL@Y=…: the agent of LABEL for the "
                 "points at Y only (a model per Y; give one for every Y of the program)");
  app.add_option("--lengths", opt.lengths, "nominal lengths [mm]")->capture_default_str();
  app.add_option("--y", opt.y, "carriage positions Y [mm]")->capture_default_str();
  app.add_option("--repeats", opt.repeats, "measurements per length and case")
      ->capture_default_str();
  app.add_option("--x0", opt.x0_mm, "X of every length's first face [mm]")->capture_default_str();
  app.add_option("--fast",
                 opt.fast,
                 "fast setting over PV 100 PD 60 AV 16 AD 10 PA 200 AA 60, e.g. pv=80,av=12");
  app.add_option(
      "--slow", opt.slow, "slow reference over PV 20 PD 60 AV 1 AD 2 PA 200 AA 60, e.g. av=2");
  app.add_option("--seed", opt.seed, "seed of the Table 1 measurement noise")
      ->capture_default_str();
  app.add_flag("--no-noise", opt.no_noise, "the twin without measurement noise");
  app.add_option("--machine", opt.machine, "machine file (default: the embedded machine)");
  app.add_option("--csv", opt.csv, "log every point to this CSV");
  app.add_flag("--json", opt.json, "print the report as JSON");
  app.add_option("--plot", opt.plot, "write length-error PNGs (one per Y) into this directory");
  app.add_option("--record",
                 opt.record,
                 "record the sessions: Modbus transcript / candump -l log (docs/recordings.md); "
                 "with several agents FILE gets the label before its extension");
  CLI::Option* qualify =
      app.add_flag("--qualify",
                   opt.qualify,
                   "qualify the uncompensated columns as a CMM does: a static reversal map over Y "
                   "and the probe qualified at each setting on a reference sphere (README, "
                   "\"Qualified reference\")");
  app.add_option("--sphere-y", opt.sphere_y_mm, "with --qualify: the reference sphere's Y [mm]")
      ->capture_default_str()
      ->needs(qualify);
  app.add_option("--qualify-touches",
                 opt.qualify_touches,
                 "with --qualify: touches averaged for each map node and qualification")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000))
      ->needs(qualify);
  app.add_option("--map-setting",
                 opt.map_setting,
                 "with --qualify: the reversal map's quasi-static setting over PV 20 PD 60 AV 1 "
                 "AD 2 PA 200 AA 60")
      ->needs(qualify);
  CLI::Option* map_only =
      app.add_flag("--map-only",
                   opt.map_only,
                   "with --qualify: measure the reversal map only and print it as cmmcomp-plan's "
                   "--sphere-y and --reversal-map (no agent needed)")
          ->needs(qualify);
  app.add_option("--timeout-ms", opt.timeout_ms, "answer timeout per request")
      ->capture_default_str()
      ->check(CLI::Range(1, 60'000));
  // --map-only runs no program: what only a program uses cannot go with it.
  for (const char* name :
       {"--modbus", "--can", "--agent", "--csv", "--json", "--plot", "--record"}) {
    map_only->excludes(app.get_option(name));
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cmmcomp::tools::usage_exit(app, e);
  }
  try {
    return run(opt);
  } catch (const cmmcomp::vc::UnreachableError& e) {
    std::fprintf(stderr, "cmmcomp-vc: %s\n", e.what());
    return 2;
  } catch (const cmmcomp::ConfigError& e) {
    std::fprintf(stderr, "cmmcomp-vc: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cmmcomp-vc: %s\n", e.what());
    return 1;
  }
}

int main(int argc, char** argv) {
  return cmmcomp::tools::guarded_main("cmmcomp-vc", run_tool, argc, argv);
}

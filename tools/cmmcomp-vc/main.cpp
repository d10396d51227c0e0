// SPDX-License-Identifier: MIT
/// @file cmmcomp-vc: a virtual CMM controller that runs an ISO 10360-2 style length test at
/// speed on the digital twin and asks cmmcomp-agent for each correction over Modbus TCP or CAN.
#include <CLI/CLI.hpp>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/plugins/can_server.hpp>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "agent_spec.hpp"
#include "can_link.hpp"
#include "length_test.hpp"
#include "modbus_link.hpp"
#include "report.hpp"
#include "twin_probe.hpp"

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
  program.validate();

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
      if (specs[i].label == specs[k].label) {
        throw cmmcomp::ConfigError("two agents labelled '" + specs[i].label + "'");
      }
    }
  }

  cmmcomp::dynamics::MeasurementNoise noise;
  noise.enabled = !opt.no_noise;
  noise.seed = opt.seed;
  const cmmcomp::dynamics::Machine machine = opt.machine.empty()
                                                 ? cmmcomp::dynamics::default_machine()
                                                 : cmmcomp::dynamics::load_machine(opt.machine);
  TwinProbe twin(machine, noise);
  // The twin's controller dwells and smooths every move: that time counts per point.
  program.dwell_s = machine.parameters.controller_dwell_s;
  program.smoothing_s = machine.parameters.controller_smoothing_s;

  std::vector<std::unique_ptr<CorrectionSource>> links;
  for (const AgentSpec& s : specs) {
    const std::string record = opt.record.empty()
                                   ? std::string()
                                   : recording_path_for(opt.record, s.label, specs.size() > 1);
    if (s.is_can) {
      links.push_back(
          std::make_unique<CanLink>(s.label, s.endpoint, s.can_base_id, opt.timeout_ms, record));
    } else {
      links.push_back(std::make_unique<ModbusLink>(
          s.label, s.endpoint, opt.modbus_unit, opt.timeout_ms, record));
    }
  }
  std::vector<CorrectionSource*> agents;
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

int main(int argc, char** argv) {
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
                 "agents (each answers every fast point)");
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
  app.add_option("--timeout-ms", opt.timeout_ms, "answer timeout per request")
      ->capture_default_str()
      ->check(CLI::Range(1, 60'000));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" with status 0; every real usage error is status 2.
    return app.exit(e) == 0 ? 0 : 2;
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

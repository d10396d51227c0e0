// SPDX-License-Identifier: MIT
/// @file cmmcomp-vc's options: the agents, the length-test program, the twin and the outputs.
#include <memory>

#include "commands.hpp"

namespace cmmcomp::tools::vc {

Command add_options(CLI::App& app) {
  auto opt = std::make_shared<Options>();
  app.add_option("--modbus", opt->modbus, "agent on Modbus TCP, tcp:HOST:PORT (label 'agent')");
  app.add_option("--modbus-unit", opt->modbus_unit, "Modbus unit id")->capture_default_str();
  app.add_option("--can", opt->can, "agent on this CAN interface, e.g. vcan0 (label 'agent')");
  app.add_option("--can-base-id", opt->can_base_id, "11-bit base identifier for --can")
      ->capture_default_str();
  app.add_option("--agent",
                 opt->agents,
                 "LABEL=modbus:tcp:HOST:PORT or LABEL=can:IFACE[:BASE_ID]; repeat to compare "
                 "agents (each answers every fast point). LABEL@Y=…: the agent of LABEL for the "
                 "points at Y only (a model per Y; give one for every Y of the program)");
  app.add_option("--lengths", opt->lengths, "nominal lengths [mm]")->capture_default_str();
  app.add_option("--y", opt->y, "carriage positions Y [mm]")->capture_default_str();
  app.add_option("--repeats", opt->repeats, "measurements per length and case")
      ->capture_default_str();
  app.add_option("--x0", opt->x0_mm, "X of every length's first face [mm]")->capture_default_str();
  app.add_option("--fast",
                 opt->fast,
                 "fast setting over PV 100 PD 60 AV 16 AD 10 PA 200 AA 60, e.g. pv=80,av=12");
  app.add_option(
      "--slow", opt->slow, "slow reference over PV 20 PD 60 AV 1 AD 2 PA 200 AA 60, e.g. av=2");
  app.add_option("--seed", opt->seed, "seed of the Table 1 measurement noise")
      ->capture_default_str();
  app.add_flag("--no-noise", opt->no_noise, "the twin without measurement noise");
  app.add_option("--machine", opt->machine, "machine file (default: the embedded machine)");
  app.add_option("--ipp",
                 opt->ipp,
                 "take the touches from this I++ DME server, HOST:PORT (e.g. cmmcomp-sim "
                 "serve-ipp) instead of the twin in this process; its noise is the server's, "
                 "--machine gives the dwell and smoothing counted per point "
                 "(docs/protocol-ippdme.md)");
  app.add_flag("--ipp-proxied",
               opt->ipp_proxied,
               "the --ipp server is a compensating proxy (cmmcomp-agent --ipp-proxy): the "
               "corrections it applies to the touches are an agent labelled ipp-proxy; the "
               "touches are the server's (the proxy's correction taken off)");
  app.add_option("--csv", opt->csv, "log every point to this CSV");
  app.add_flag("--json", opt->json, "print the report as JSON");
  app.add_option("--plot", opt->plot, "write length-error PNGs (one per Y) into this directory");
  app.add_option("--record",
                 opt->record,
                 "record the sessions: Modbus transcript / candump -l log (docs/recordings.md); "
                 "with several agents FILE gets the label before its extension");
  CLI::Option* qualify =
      app.add_flag("--qualify",
                   opt->qualify,
                   "qualify the uncompensated columns as a CMM does: a static reversal map over Y "
                   "and the probe qualified at each setting on a reference sphere (README, "
                   "\"Qualified reference\")");
  app.add_option("--sphere-y", opt->sphere_y_mm, "with --qualify: the reference sphere's Y [mm]")
      ->capture_default_str()
      ->needs(qualify);
  app.add_option("--qualify-touches",
                 opt->qualify_touches,
                 "with --qualify: touches averaged for each map node and qualification")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000))
      ->needs(qualify);
  app.add_option("--map-setting",
                 opt->map_setting,
                 "with --qualify: the reversal map's quasi-static setting over PV 20 PD 60 AV 1 "
                 "AD 2 PA 200 AA 60")
      ->needs(qualify);
  CLI::Option* map_only =
      app.add_flag("--map-only",
                   opt->map_only,
                   "with --qualify: measure the reversal map only and print it as cmmcomp-plan's "
                   "--sphere-y and --reversal-map (no agent needed)")
          ->needs(qualify);
  app.add_option("--timeout-ms", opt->timeout_ms, "answer timeout per request")
      ->capture_default_str()
      ->check(CLI::Range(1, 60'000));
  // --map-only runs no program: what only a program uses cannot go with it.
  for (const char* name :
       {"--modbus", "--can", "--agent", "--csv", "--json", "--plot", "--record"}) {
    map_only->excludes(app.get_option(name));
  }
  return {&app, [opt] { return run(*opt); }};
}

}  // namespace cmmcomp::tools::vc

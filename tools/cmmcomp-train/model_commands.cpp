// SPDX-License-Identifier: MIT
/// @file cmmcomp-train eval (Table 5 of a model on a test dataset, the held-out check, the
/// paper's Fig. 5) and export (a model as a constexpr C++ header or a C source for the firmware).
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cmmcomp/training/evaluation.hpp>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <variant>

#include "commands.hpp"

namespace cmmcomp::tools::train {
namespace {

struct EvalCommand {
  std::string model, data, plot;
  bool json = false, check = false;
};

template <typename Inputs>
int run_eval(const cmmcomp::io::ModelFileOf<Inputs>& file,
             const std::string& data,
             bool json,
             const std::string& plot,
             bool check) {
  const auto rows = cmmcomp::io::read_dataset_csv(data);
  const cmmcomp::training::TestSetEvaluation e =
      cmmcomp::training::evaluate_test_set<Inputs>(file.model, file.interval, rows, data);
  const cmmcomp::training::HeldOutCheck verdict = cmmcomp::training::held_out_check(
      e.table, e.coverage_pct, 100.0 * file.interval.coverage, e.samples);
  const cmmcomp::training::TestSetReportHeader header{
      file.model_id, Inputs::kCount, data, file.interval.coverage, file.format_version};
  const cmmcomp::training::HeldOutCheck* checked = check ? &verdict : nullptr;
  if (json) {
    std::printf("%s\n", cmmcomp::training::format_test_set_json(e, header, checked).c_str());
  } else {
    std::printf("%s", cmmcomp::training::format_test_set_report(e, header, checked).c_str());
  }
  const bool has_interval = file.interval.available();
  if (!plot.empty()) {
    // The paper's Fig. 5: measured, predicted and residual for 50 test samples per parameter.
    const std::string dat = plot + ".dat";
    const std::string gp = plot + ".gp";
    const cmmcomp::training::Fig5Plot fig =
        cmmcomp::training::fig5_plot(e.predictions,
                                     dat,
                                     plot,
                                     file.model_id,
                                     has_interval ? 100.0 * file.interval.coverage : 0.0);
    cmmcomp::io::write_file_atomically(dat, fig.data);
    cmmcomp::io::write_file_atomically(gp, fig.script);
    const std::string command = "gnuplot '" + gp + "'";
    if (std::system(command.c_str()) != 0) {
      throw cmmcomp::Error("gnuplot failed to draw " + plot + " (is gnuplot installed?)");
    }
    std::printf("wrote %s\n", plot.c_str());
  }
  return check && !verdict.passed ? 1 : 0;
}

struct ExportCommand {
  std::string model, header, c_source, symbol = "cmmcomp_model", scalar = "double";
};

int run_export(const ExportCommand& cmd) {
  // Any input set the compensator serves; the file's names say which.
  const auto any = cmmcomp::io::load_compensation_model(cmd.model);
  if (cmd.header.empty() && cmd.c_source.empty()) {
    std::fprintf(stderr, "cmmcomp-train export: give --header or --c-source\n");
    return 2;
  }
  const bool c_source = !cmd.c_source.empty();
  const bool single = cmd.scalar == "float";
  const std::string text = std::visit(
      [&](const auto& file) {
        return c_source ? cmmcomp::io::export_model_c_source(file, cmd.symbol, single)
                        : cmmcomp::io::export_model_header(file, cmd.symbol, single);
      },
      any);
  const std::string& path = c_source ? cmd.c_source : cmd.header;
  cmmcomp::io::write_file_atomically(path, text);
  std::printf("wrote %s (model id %s)\n", path.c_str(), cmmcomp::io::model_id(any).c_str());
  return 0;
}

}  // namespace

Command add_eval(CLI::App& app) {
  auto cmd = std::make_shared<EvalCommand>();
  CLI::App* eval = app.add_subcommand("eval", "Table 5 of a model on a test dataset");
  eval->add_option("model", cmd->model, "model file")->required();
  eval->add_option("data", cmd->data, "test dataset")->required();
  eval->add_flag("--json", cmd->json, "print one JSON object keyed mpe rpe mae rae");
  eval->add_option("--plot", cmd->plot, "draw the paper's Fig. 5 to this PNG (gnuplot)");
  eval->add_flag("--check",
                 cmd->check,
                 "the held-out check: exit 1 unless every reduction reaches the paper's Table 5 "
                 "and every interval covers within 3 points of its nominal coverage (or the "
                 "binomial 2-sigma band of the sample count, if wider)");
  return {eval, [cmd] {
            // Any input set the compensator serves; the file's names say which.
            const auto any = cmmcomp::io::load_compensation_model(cmd->model);
            return std::visit(
                [&](const auto& file) {
                  return run_eval(file, cmd->data, cmd->json, cmd->plot, cmd->check);
                },
                any);
          }};
}

Command add_export(CLI::App& app) {
  auto cmd = std::make_shared<ExportCommand>();
  CLI::App* exp = app.add_subcommand(
      "export", "write a model as a constexpr C++ header or a C source for the firmware ABI");
  exp->add_option("model", cmd->model, "model file")->required();
  auto* header_opt = exp->add_option("--header", cmd->header, "output: constexpr C++ header");
  auto* c_opt =
      exp->add_option("--c-source",
                      cmd->c_source,
                      "output: C99 source of a cmmcomp_fw_model (cmmcomp/compensator_fw.h)");
  header_opt->excludes(c_opt);
  exp->add_option("--symbol", cmd->symbol, "C or C++ name of the model")->capture_default_str();
  exp->add_option("--scalar", cmd->scalar, "precision of the exported parameters: double or float")
      ->check(CLI::IsMember({"double", "float"}))
      ->capture_default_str();
  return {exp, [cmd] { return run_export(*cmd); }};
}

}  // namespace cmmcomp::tools::train

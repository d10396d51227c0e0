// SPDX-License-Identifier: MIT
/// @file cmmcomp-study render: result documents (an experiment's --json output) into their blocks
/// of a results page.
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/study/report.hpp>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "commands.hpp"
#include "reporting.hpp"

namespace cmmcomp::tools::study {
namespace {

using cmmcomp::study::Document;

struct RenderCommand {
  std::vector<std::string> documents;
  Output out;
};

/// Renders result documents (the JSON of `--json`) into the page's blocks.
int run_render(const std::vector<std::string>& documents, const Output& out) {
  int status = 0;
  for (const std::string& path : documents) {
    const Document doc = Document::parse(
        cmmcomp::io::read_file_bounded(path, "study document", std::uintmax_t{1} << 24),
        nullptr,
        false);
    if (doc.is_discarded()) {
      throw cmmcomp::ConfigError(path + ": not JSON (expected an experiment's --json output)");
    }
    cmmcomp::study::PageSync sync;
    try {
      sync = cmmcomp::study::sync_page(out.page, doc, out.update_page);
    } catch (const nlohmann::json::exception& e) {
      throw cmmcomp::ConfigError(path + ": not a study document: " + e.what());
    }
    if (!sync.current) {
      std::fprintf(
          stderr,
          "cmmcomp-study: %s the block \"%s\" of %s from %s\n",
          out.update_page ? "updated" : "stale:",
          (doc.contains("block") && doc["block"].is_string() ? doc["block"].get<std::string>()
                                                             : std::string())
              .c_str(),
          out.page.c_str(),
          path.c_str());
      if (!out.update_page) status = 1;
    }
  }
  return status;
}

}  // namespace

Command add_render(CLI::App& app, const std::string& command) {
  auto cmd = std::make_shared<RenderCommand>();
  cmd->out.command = command;
  CLI::App* render = app.add_subcommand(
      "render", "render result documents (--json output) into their blocks of a results page");
  render->add_option("documents", cmd->documents, "result documents (JSON)")
      ->required()
      ->check(CLI::ExistingFile);
  render->add_option("--page", cmd->out.page, "the results page")
      ->required()
      ->check(CLI::ExistingFile);
  render->add_flag("--check", "fail when a block is stale instead of writing the page");
  return {render, [cmd, render] {
            cmd->out.update_page = render->count("--check") == 0;
            return run_render(cmd->documents, cmd->out);
          }};
}

}  // namespace cmmcomp::tools::study

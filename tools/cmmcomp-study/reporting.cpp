// SPDX-License-Identifier: MIT
/// @file The reporting options, publication and progress of cmmcomp-study's experiments.
#include "reporting.hpp"

#include <unistd.h>

#include <cstdio>
#include <string>

namespace cmmcomp::tools::study {

void add_reporting(CLI::App* sub, Output& out) {
  sub->add_option("--known-unmet", out.known_unmet, "targets known to be unmet, one per line")
      ->check(CLI::ExistingFile);
  sub->add_flag("--json", out.json, "print the results and the verdict as JSON");
  sub->add_option("--page", out.page, "check this results page's block (docs/results.md)")
      ->check(CLI::ExistingFile);
  sub->add_flag("--update-page", out.update_page, "write the block instead of checking it")
      ->needs(sub->get_option("--page"));
  sub->add_option("--block", out.block, "the block's name (default: the experiment's)");
}

int finish(const cmmcomp::study::Document& result,
           const std::vector<cmmcomp::study::Target>& targets,
           const Output& out) {
  const cmmcomp::study::Publication p = cmmcomp::study::publish(result, targets, out);
  std::printf("%s\n", p.text.c_str());
  if (!p.note.empty()) std::fprintf(stderr, "%s\n", p.note.c_str());
  return p.status;
}

cmmcomp::study::RunOptions run_options() {
  cmmcomp::study::RunOptions o;
  if (isatty(fileno(stderr)) != 0) {
    o.progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  }
  return o;
}

}  // namespace cmmcomp::tools::study

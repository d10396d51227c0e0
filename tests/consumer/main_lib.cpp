// SPDX-License-Identifier: MIT
/// @file Uses the installed compiled library.
#include <cmmcomp/io/profile_report.hpp>
#include <cstdio>

int main() {
  cmmcomp::motion::MoveProfile p;
  if (!cmmcomp::ok(cmmcomp::motion::MoveProfile::plan(cmmcomp::motion::baseline_move(), p))) {
    return 1;
  }
  const std::string text = cmmcomp::io::describe_profile(p);
  std::fputs(text.c_str(), stdout);
  return text.find("touch") != std::string::npos ? 0 : 1;
}

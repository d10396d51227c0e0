// SPDX-License-Identifier: MIT
/// @file The trace CSV writer.
#include <fmt/format.h>

#include <cmmcomp/dynamics/trace_csv.hpp>
#include <iterator>

namespace cmmcomp::dynamics {

std::string format_trace_csv(const std::vector<TraceSample>& trace) {
  std::string csv;
  for (const TraceColumn& c : kTraceColumns)
    csv += fmt::format("{}{}", csv.empty() ? "" : ",", c.name);
  csv += '\n';
  for (const TraceSample& s : trace) {
    for (std::size_t k = 0; k < kTraceColumns.size(); ++k) {
      fmt::format_to(
          std::back_inserter(csv), "{}{:.9g}", k == 0 ? "" : ",", s.*(kTraceColumns[k].field));
    }
    csv += '\n';
  }
  return csv;
}

}  // namespace cmmcomp::dynamics

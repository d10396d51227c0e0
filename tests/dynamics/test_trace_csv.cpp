// SPDX-License-Identifier: MIT
/// @file The trace CSV (dynamics/trace_csv.hpp): its columns are the documented ones, in order,
/// and a simulated move's trace is written one sample per row.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmmcomp/dynamics/bridge_model.hpp>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/dynamics/trace_csv.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <sstream>
#include <string>

namespace cmmcomp::dynamics {
namespace {

TEST(TraceCsv, ColumnsAreTheDocumentedOnesInOrder) {
  const std::string doc = io::read_file_bounded(
      std::string(CMMCOMP_DOCS_DIR) + "/machine-model.md", "document", io::kMaxTextFileBytes);
  const std::size_t section = doc.find("## The trace CSV");
  ASSERT_NE(section, std::string::npos);
  std::size_t previous = section;
  for (const TraceColumn& c : kTraceColumns) {
    const std::size_t at = doc.find(std::string("| `") + c.name + "` |", section);
    ASSERT_NE(at, std::string::npos) << c.name;
    EXPECT_GT(at, previous) << c.name << " is out of the document's order";
    previous = at;
  }
}

TEST(TraceCsv, OneRowPerSampleUnderTheHeader) {
  SimulationOptions o;
  o.record_trace = true;
  BridgeSimulator sim(default_machine(), o);
  const SimulationResult r = sim.simulate(motion::baseline_move(), 0.25);
  ASSERT_GT(r.trace.size(), 10u);
  const std::string csv = format_trace_csv(r.trace);
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t_s,commanded_mm,scale_mm,tip_mm,error_um,velocity_mm_s,acceleration_mm_s2");
  std::size_t rows = 0;
  while (std::getline(in, line)) {
    ++rows;
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 6) << line;
  }
  EXPECT_EQ(rows, r.trace.size());
  std::istringstream last(csv.substr(csv.rfind('\n', csv.size() - 2) + 1));
  double t = 0;
  last >> t;
  EXPECT_NEAR(t, r.trace.back().t_s, 1e-8 * (1 + t));
}

}  // namespace
}  // namespace cmmcomp::dynamics

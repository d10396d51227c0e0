// SPDX-License-Identifier: MIT
/// @file libFuzzer target: the compensating I++ proxy's line logic (tools/serving/ipp_proxy.hpp,
/// docs/protocol-ippdme.md) on hostile input from both sides. The input is split into lines at
/// LF; each goes to the proxy as a client line, then through a Session over a fixed-error machine,
/// whose answers go back through the proxy; each input line also goes to the proxy as a server
/// line (a hostile server). The compensator serves the shipped model on axis 0.
/// Invariants (abort on violation): a line the proxy does not rewrite passes unchanged; a
/// rewritten line keeps its tag, parses as a data answer, ends with `CmmcompFlags(n)` (and its CR
/// when it had one) and fits twice the longest line; a corrected point has all three marks.
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/io/default_model.hpp>
#include <cmmcomp/ipp/line.hpp>
#include <cmmcomp/ipp/session.hpp>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "ipp_proxy.hpp"

namespace {

using namespace cmmcomp;

class FixedMachine : public ipp::Machine {
 public:
  motion::ControllerCapabilities capabilities() const override {
    return motion::fixed_timing_capabilities(0.5, 0.05);
  }
  ipp::Point3 volume_min() const override { return {-1000, 0, -1000}; }
  ipp::Point3 volume_max() const override { return {1000, 2000, 1000}; }
  ipp::Touch probe(const ipp::ReconstructedMove& move, std::uint64_t index) override {
    ipp::Touch t;
    t.ok = move.pd_mm < 500.0;  // some moves refused: the error path too
    t.problem = "refused";
    t.rae_um = 1.5 + static_cast<double>(index % 3);
    t.seconds = 0.5;
    return t;
  }
};

const compensation::MoveCompensator& compensator() {
  static const std::unique_ptr<compensation::MoveCompensator> c = [] {
    auto m = std::make_unique<compensation::MoveCompensator>();
    if (io::publish(*m, 0, io::CompensationModelFile{io::default_model_file()}) != Status::kOk) {
      std::abort();
    }
    return m;
  }();
  return *c;
}

void check(serving::IppProxyLogic& logic, std::string_view line) {
  const std::string in(line);
  const std::string_view passed = logic.from_server(in);
  if (passed == in) return;
  const std::size_t body = !in.empty() && in.back() == '\r' ? in.size() - 1 : in.size();
  if (passed.size() > 2 * ipp::kMaxLineBytes + body) std::abort();
  if (passed.substr(0, 5) != std::string_view(in).substr(0, 5)) std::abort();
  const bool cr = body < in.size();
  if (cr != (!passed.empty() && passed.back() == '\r')) std::abort();
  const std::string_view text = cr ? passed.substr(0, passed.size() - 1) : passed;
  ipp::AnswerLine a;
  if (ipp::parse_answer(text, a) != ipp::ParseStatus::kOk) std::abort();
  if (a.kind != ipp::AnswerLine::Kind::kData) std::abort();
  const std::size_t flags = text.rfind(", CmmcompFlags(");
  if (flags == std::string_view::npos || text.back() != ')') std::abort();
  const bool corrected = text.find(", CmmcompCorrection(") != std::string_view::npos;
  if (corrected != (text.find(", CmmcompU95(") != std::string_view::npos)) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  FixedMachine machine;
  ipp::Session session(machine);
  serving::IppProxyLogic logic(compensator());
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= input.size()) {
    std::size_t end = input.find('\n', start);
    if (end == std::string_view::npos) end = input.size();
    const std::string_view line = input.substr(start, end - start);
    start = end + 1;
    logic.from_client(line);
    out.clear();
    session.receive(line, out);
    while (session.has_work()) session.finish(session.start_next(), out);
    for (const std::string& answer : out) check(logic, answer);
    check(logic, line);  // the same bytes from a hostile server
  }
  return 0;
}

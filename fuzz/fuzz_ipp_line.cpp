// SPDX-License-Identifier: MIT
/// @file libFuzzer target: I++ DME lines through the parser and the server's session logic
/// (docs/protocol-ippdme.md). The input is split into lines at LF; each is parsed as a command
/// and as an answer (an `Error(…)` too), then fed to a Session over a fixed-error machine whose
/// queued commands run at once. Invariants (abort on violation): every non-blank line gets at
/// least one answer; every answer line parses as an answer with a tag, and an error answer's
/// data as `Error(…)` with a number of the table; a parsed argument list stays inside the line.
#include <cmmcomp/ipp/error_codes.hpp>
#include <cmmcomp/ipp/line.hpp>
#include <cmmcomp/ipp/session.hpp>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

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

bool inside(std::string_view view, std::string_view line) {
  return view.empty() ||
         (view.data() >= line.data() && view.data() + view.size() <= line.data() + line.size());
}

void check_answer(const std::string& answer) {
  ipp::AnswerLine a;
  if (ipp::parse_answer(answer, a) != ipp::ParseStatus::kOk) std::abort();
  if (a.kind != ipp::AnswerLine::Kind::kError) return;
  ipp::ErrorAnswer e;
  if (ipp::parse_error(a.data, e) != ipp::ParseStatus::kOk) std::abort();
  bool known = false;
  for (const ipp::ErrorInfo& info : ipp::kErrors) {
    known = known || ipp::error_number(info.code) == e.number;
  }
  if (!known) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  FixedMachine machine;
  ipp::Session session(machine);
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= input.size()) {
    std::size_t end = input.find('\n', start);
    if (end == std::string_view::npos) end = input.size();
    const std::string_view line = input.substr(start, end - start);
    start = end + 1;

    ipp::CommandLine c;
    if (ipp::parse_command(line, c) == ipp::ParseStatus::kOk) {
      if (!inside(c.name, line)) std::abort();
      for (int i = 0; i < c.args.size(); ++i) {
        if (!inside(c.args[i].text, line)) std::abort();
      }
    }
    ipp::AnswerLine a;
    if (ipp::parse_answer(line, a) == ipp::ParseStatus::kOk && !inside(a.data, line)) std::abort();
    ipp::ErrorAnswer e;
    (void)ipp::parse_error(line, e);

    out.clear();
    session.receive(line, out);
    while (session.has_work()) session.finish(session.start_next(), out);
    const bool blank = line.empty() || line == "\r";
    if (!blank && out.empty()) std::abort();
    for (const std::string& answer : out) check_answer(answer);
  }
  return 0;
}

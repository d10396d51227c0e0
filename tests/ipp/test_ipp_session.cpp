// SPDX-License-Identifier: MIT
/// @file The I++ DME session logic without sockets, over a fake machine: every command of the
/// subset, its error paths, the fast queue and AbortE while a command runs.
#include <gtest/gtest.h>

#include <cmmcomp/ipp/line.hpp>
#include <cmmcomp/ipp/session.hpp>
#include <random>
#include <string>
#include <vector>

namespace ipp = cmmcomp::ipp;

namespace {

/// A machine with the default machine's ranges and a fixed touch error.
class FakeMachine : public ipp::Machine {
 public:
  cmmcomp::motion::ControllerCapabilities capabilities() const override {
    cmmcomp::motion::ControllerCapabilities c =
        cmmcomp::motion::fixed_timing_capabilities(0.5, 0.05);
    c[cmmcomp::motion::Setting::kPositioningSpeed] = {1e-3, 0.5};
    c[cmmcomp::motion::Setting::kApproachDistance] = {0.5e-3, 20e-3};
    return c;
  }
  ipp::Point3 volume_min() const override { return {-1000, 0, -1000}; }
  ipp::Point3 volume_max() const override { return {1000, 2000, 1000}; }
  ipp::Touch probe(const ipp::ReconstructedMove& move, std::uint64_t index) override {
    moves.push_back(move);
    indices.push_back(index);
    ipp::Touch t;
    t.ok = !refuse;
    t.problem = "refused by the fake";
    t.rae_um = 2.5;
    t.seconds = 1.25;
    return t;
  }
  bool refuse = false;
  std::vector<ipp::ReconstructedMove> moves;
  std::vector<std::uint64_t> indices;
};

struct Harness {
  FakeMachine machine;
  ipp::Session session{machine};

  /// Receives `line` and runs everything that waits: every answer line.
  std::vector<std::string> run(const std::string& line) {
    std::vector<std::string> out;
    session.receive(line, out);
    while (session.has_work()) session.finish(session.start_next(), out);
    return out;
  }
};

/// The error number of an error answer line, -1 for another line.
int error_number(const std::string& line) {
  ipp::AnswerLine a;
  ipp::ErrorAnswer e;
  if (ipp::parse_answer(line, a) != ipp::ParseStatus::kOk ||
      a.kind != ipp::AnswerLine::Kind::kError ||
      ipp::parse_error(a.data, e) != ipp::ParseStatus::kOk) {
    return -1;
  }
  return e.number;
}

using Lines = std::vector<std::string>;

}  // namespace

TEST(IppSession, ASessionOfTheSubsetAnswersAsTheSpecificationSays) {
  Harness h;
  EXPECT_EQ(h.run("00001 StartSession()"), (Lines{"00001 &", "00001 %"}));
  EXPECT_EQ(h.run("00002 IsHomed()"), (Lines{"00002 &", "00002 # IsHomed(0)", "00002 %"}));
  EXPECT_EQ(h.run("00003 Home()"), (Lines{"00003 &", "00003 %"}));
  EXPECT_EQ(h.run("00004 IsHomed()"), (Lines{"00004 &", "00004 # IsHomed(1)", "00004 %"}));
  EXPECT_EQ(h.run("00005 EnableUser()"), (Lines{"00005 &", "00005 %"}));
  EXPECT_EQ(h.run("00006 IsUserEnabled()"),
            (Lines{"00006 &", "00006 # IsUserEnabled(1)", "00006 %"}));
  EXPECT_EQ(h.run("00007 DisableUser()"), (Lines{"00007 &", "00007 %"}));
  EXPECT_EQ(h.run("00008 GetProp(Tool.GoToPar.Speed.Max(), Tool.GoToPar.Speed.Min(), "
                  "Tool.PtMeasPar.Approach.Def())"),
            (Lines{"00008 &",
                   "00008 # Tool.GoToPar.Speed.Max(500), Tool.GoToPar.Speed.Min(1), "
                   "Tool.PtMeasPar.Approach.Def(10)",
                   "00008 %"}));
  EXPECT_EQ(h.run("00009 SetProp(Tool.GoToPar.Speed(30), Tool.PtMeasPar.Approach.Act(4))"),
            (Lines{"00009 &", "00009 %"}));
  EXPECT_EQ(
      h.run("00010 GetProp(Tool.GoToPar.Speed(), Tool.PtMeasPar.Approach.Act())"),
      (Lines{
          "00010 &", "00010 # Tool.GoToPar.Speed(30), Tool.PtMeasPar.Approach.Act(4)", "00010 %"}));
  EXPECT_EQ(h.run("E0001 GetPropE(Tool.PtMeasPar.Search())"),
            (Lines{"E0001 &", "E0001 # Tool.PtMeasPar.Search(2)", "E0001 %"}));
  EXPECT_EQ(h.run("00011 OnPtMeasReport(IJK(), X(), Y(), Z())"), (Lines{"00011 &", "00011 %"}));
  EXPECT_EQ(h.run("00012 GoTo(X(20), Y(100), Z(5))"), (Lines{"00012 &", "00012 %"}));
  EXPECT_EQ(h.run("00013 GoTo(X(14))"), (Lines{"00013 &", "00013 %"}));
  EXPECT_EQ(h.run("00014 Get(X(), Z())"), (Lines{"00014 &", "00014 # X(14), Z(5)", "00014 %"}));
  // Nominal (10, 100, 5), IJK (1, 0, 0): pre-hit (14, 100, 5), where the last GoTo (6 mm) ended.
  // The fake's RAE 2.5 um along d = (-1, 0, 0): the scale reads X = 10 + 0.0025.
  EXPECT_EQ(h.run("00015 PtMeas(X(10), Y(100), Z(5), IJK(1, 0, 0))"),
            (Lines{"00015 &", "00015 # IJK(1, 0, 0), X(10.0025), Y(100), Z(5)", "00015 %"}));
  ASSERT_EQ(h.machine.moves.size(), 1u);
  const ipp::ReconstructedMove& m = h.machine.moves[0];
  EXPECT_DOUBLE_EQ(m.pv_mm_s, 30.0);
  EXPECT_DOUBLE_EQ(m.pd_mm, 6.0);
  EXPECT_DOUBLE_EQ(m.ad_mm, 4.0);
  EXPECT_DOUBLE_EQ(m.av_mm_s, 12.0);
  EXPECT_DOUBLE_EQ(m.y_mm, 100.0);
  EXPECT_EQ(h.machine.indices[0], 0u);
  EXPECT_EQ(h.run("00016 Get(X(), Y(), Z())"),
            (Lines{"00016 &", "00016 # X(11), Y(100), Z(5)", "00016 %"}));  // retracted 1 mm
  EXPECT_EQ(h.run("E0002 GetErrStatusE()"), (Lines{"E0002 &", "E0002 # ErrStatus(0)", "E0002 %"}));
  Lines daemon = h.run("00017 StopDaemon(E1234)");
  ASSERT_EQ(daemon.size(), 3u);
  EXPECT_EQ(error_number(daemon[1]), 513);
  EXPECT_EQ(daemon[2], "00017 %");
  EXPECT_EQ(h.run("00018 StopAllDaemons()"), (Lines{"00018 &", "00018 %"}));
  const Lines supported = h.run("00019 GetSupportedCommands()");
  EXPECT_EQ(supported.size(), static_cast<std::size_t>(ipp::kSupportedCommandCount) + 2);
  EXPECT_EQ(supported[1], "00019 # StartSession");
  EXPECT_EQ(h.run("00022 SetTool(\"Probe1\")"), (Lines{"00022 &", "00022 %"}));
  EXPECT_EQ(h.run("00023 ChangeTool(\"Probe1\")"), (Lines{"00023 &", "00023 %"}));
  EXPECT_EQ(h.run("00024 OnPtMeasReport(X(), R())"), (Lines{"00024 &", "00024 %"}));
  EXPECT_EQ(h.run("00025 PtMeas(X(10), Y(100), Z(5), IJK(1, 0, 0))")[1],
            "00025 # X(10.0025), R(0)");
  EXPECT_EQ(h.run("00020 ClearAllErrors()"), (Lines{"00020 &", "00020 %"}));
  EXPECT_EQ(h.run("00021 EndSession()"), (Lines{"00021 &", "00021 %"}));
  EXPECT_FALSE(h.session.started());
}

TEST(IppSession, RefusedCommandsGetOneErrorLineAndChangeNothing) {
  Harness h;
  struct Case {
    std::string line;
    int error;
  };
  EXPECT_EQ(error_number(h.run("00001 GoTo(X(1))")[0]), 508);  // before StartSession
  h.run("00002 StartSession()");
  const std::vector<Case> cases = {
      {"00003 StartSession()", 508},
      {"00004 Frobnicate()", 507},
      {"00005 ScanOnLine(0,0,0,1,0,0,0,0,1,1,5)", 501},
      {"00006 Home(1)", 502},
      {"00007 SetProp(Tool.GoToPar.Speed(501))", 504},
      {"00008 SetProp(Tool.GoToPar.Speed(-1))", 504},
      {"00009 SetProp(Tool.GoToPar.Speed.Max(100))", 510},
      {"00010 SetProp(Tool.GoToPar.Jerk(100))", 510},
      {"00011 SetProp(Tool.GoToPar.Speed(\"fast\"))", 502},
      {"00012 GetProp(Tool.GoToPar.Speed(3))", 502},
      {"00013 GoTo(X(1), X(2))", 502},
      {"00014 GoTo(Tool.A(45))", 506},
      {"00015 GoTo(X())", 509},
      {"00016 GoTo(Y(-5))", 1008},
      {"00017 PtMeas(X(1), Y(2), Z(3))", 502},
      {"00018 PtMeas(X(1), Y(2), Z(3), IJK(0, 0, 0))", 1010},
      {"00019 OnPtMeasReport(ER())", 506},
      {"00027 SetTool(3)", 509},
      {"00028 ChangeTool(\"a\", \"b\")", 502},
      {"00020 StopDaemon(00012)", 502},
      {"00021 GetErrStatusE()", 1},
      {"E0022 GoTo(X(1))", 1},
      {"00000 Home()", 1},
      {"E0000 GetErrStatusE()", 1},
      {"00023Home()", 2},
      {"00024 GoTo(X(12345678901234567))", 509},
      {"00025 GoTo(X(1)", 502},
      {std::string("00026 Home(\0)", 13), 7},
      {"junk", 1},
      {std::string(2000, 'x'), 8},
  };
  for (const Case& c : cases) {
    const Lines out = h.run(c.line);
    ASSERT_EQ(out.size(), 1u) << c.line;
    EXPECT_EQ(error_number(out[0]), c.error) << c.line << " -> " << out[0];
  }
  EXPECT_TRUE(h.run("").empty());  // a blank line is no command
  EXPECT_EQ(h.run("00030 GetProp(Tool.GoToPar.Speed())")[1], "00030 # Tool.GoToPar.Speed(40)");
  EXPECT_FALSE(h.session.in_error());
}

TEST(IppSession, AReusedTagAndAFullQueueAreRefused) {
  FakeMachine machine;
  ipp::SessionOptions o;
  o.max_queued = 3;
  ipp::Session s(machine, o);
  Lines out;
  s.receive("00001 StartSession()", out);
  s.receive("00002 GoTo(X(1))", out);
  s.receive("00002 GoTo(X(2))", out);  // 00002 still waits
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(error_number(out[2]), 1);
  s.receive("00003 GoTo(X(3))", out);
  s.receive("00004 GoTo(X(4))", out);  // the 4th waiting command
  EXPECT_EQ(error_number(out.back()), 0);
  out.clear();
  while (s.has_work()) s.finish(s.start_next(), out);
  EXPECT_EQ(out, (Lines{"00001 %", "00002 %", "00003 %"}));
  s.receive("00002 GoTo(X(5))", out);  // done: the tag is free again
  EXPECT_EQ(out.back(), "00002 &");
}

TEST(IppSession, TheFastQueueAnswersWhileAMoveRunsAndAbortEEndsIt) {
  Harness h;
  h.run("00001 StartSession()");
  Lines out;
  h.session.receive("00002 GoTo(X(100))", out);
  h.session.receive("00003 GoTo(X(200))", out);
  EXPECT_EQ(out, (Lines{"00002 &", "00003 &"}));
  ipp::Executed running = h.session.start_next();  // 00002 moves
  EXPECT_GT(running.seconds, 2.0);                 // 100 mm at 40 mm/s
  EXPECT_TRUE(h.session.running());
  out.clear();
  h.session.receive("E0001 GetPropE(Tool.GoToPar.Speed())", out);
  h.session.receive("00002 GetProp(Tool.GoToPar.Speed())", out);  // 00002 is running
  EXPECT_EQ(out[0], "E0001 &");
  EXPECT_EQ(out[1], "E0001 # Tool.GoToPar.Speed(40)");
  EXPECT_EQ(out[2], "E0001 %");
  EXPECT_EQ(error_number(out[3]), 1);
  out.clear();
  h.session.receive("E0002 AbortE()", out);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(out[0], "E0002 &");
  EXPECT_EQ(error_number(out[1]), 6);  // the waiting 00003
  EXPECT_EQ(out[2], "00003 %");
  EXPECT_EQ(out[3], "E0002 %");
  out.clear();
  h.session.finish(std::move(running), out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(error_number(out[0]), 6);
  EXPECT_EQ(out[1], "00002 %");
  EXPECT_TRUE(h.session.in_error());
  EXPECT_DOUBLE_EQ(h.session.position().x, 0.0);  // an aborted move leaves the machine at its start
  EXPECT_EQ(h.run("E0003 GetErrStatusE()")[1], "E0003 # ErrStatus(1)");
  EXPECT_EQ(error_number(h.run("00004 GoTo(X(1))")[0]), 514);
  EXPECT_EQ(h.run("00005 ClearAllErrors()"), (Lines{"00005 &", "00005 %"}));
  EXPECT_EQ(h.run("00006 GoTo(X(1))"), (Lines{"00006 &", "00006 %"}));
}

TEST(IppSession, APtMeasTheMachineCannotRunIsAnErrorAndTheErrorState) {
  Harness h;
  h.run("00001 StartSession()");
  h.machine.refuse = true;
  const Lines out = h.run("00002 PtMeas(X(1), Y(2), Z(3), IJK(0, 0, 1))");
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0], "00002 &");
  EXPECT_EQ(error_number(out[1]), 511);
  EXPECT_NE(out[1].find("refused by the fake"), std::string::npos);
  EXPECT_EQ(out[2], "00002 %");
  EXPECT_TRUE(h.session.in_error());
  h.machine.refuse = false;
  h.run("00003 ClearAllErrors()");
  // The point index counts the points measured: the refused one took none.
  h.run("00004 PtMeas(X(1), Y(2), Z(3), IJK(0, 0, 1))");
  EXPECT_EQ(h.machine.indices.back(), 0u);
}

TEST(IppSession, HostileLinesAreAnsweredWithOneLineEachAndNeverThrow) {
  Harness h;
  h.run("00001 StartSession()");
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> byte(0, 255), length(1, 300);
  for (int trial = 0; trial < 3000; ++trial) {
    std::string line(static_cast<std::size_t>(length(rng)), ' ');
    for (char& c : line) c = static_cast<char>(byte(rng));
    if (trial % 2 == 0) line = "00777 PtMeas(" + line;
    Lines out;
    ASSERT_NO_THROW(h.session.receive(line, out));
    if (line.find_first_not_of('\r') != std::string::npos) {
      EXPECT_GE(out.size(), 1u);
    }
    while (h.session.has_work()) h.session.finish(h.session.start_next(), out);
  }
}

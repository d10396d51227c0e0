// SPDX-License-Identifier: MIT
/// @file Conformance of the I++ DME server on the twin, through the project's client over TCP:
/// every command of the subset and its error paths, PtMeas results against BridgeSimulator,
/// reproducible noise, the fast queue and AbortE during a real-time move, one client session at
/// a time, and hostile clients (an over-long line, a trickle, a client that never reads).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmmcomp/dynamics/bridge_model.hpp>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/ipp_number.hpp>
#include <cmmcomp/ipp/client.hpp>
#include <cmmcomp/ipp/line.hpp>
#include <cmmcomp/ipp/server.hpp>
#include <cmmcomp/ipp/session.hpp>
#include <cmmcomp/motion/move_profile.hpp>
#include <cmmcomp/vc/ipp_probe.hpp>
#include <cmmcomp/vc/ipp_twin_machine.hpp>
#include <cmmcomp/vc/length_test.hpp>
#include <cmmcomp/vc/twin_probe.hpp>
#include <fstream>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace ipp = cmmcomp::ipp;
namespace dynamics = cmmcomp::dynamics;

namespace {

/// The twin served on a free loopback port by a thread, for one test.
class TwinServer {
 public:
  explicit TwinServer(bool noise = false,
                      std::uint64_t seed = 1,
                      bool realtime = false,
                      std::size_t max_output = 1u << 20,
                      double send_timeout_s = 2.0)
      : machine_(dynamics::default_machine(), noise_of(noise, seed)), session_(machine_) {
    ipp::ServerOptions o;
    o.port = 0;
    o.realtime = realtime;
    o.max_output_bytes = max_output;
    o.send_timeout_s = send_timeout_s;
    o.log = [this](const std::string& line) {
      const std::lock_guard<std::mutex> lock(log_mutex_);
      log_.push_back(line);
    };
    server_ = std::make_unique<ipp::Server>(session_, o);
    thread_ = std::thread([this] { server_->run(); });
  }
  ~TwinServer() {
    server_->request_stop();
    thread_.join();
  }
  std::uint16_t port() const { return server_->port(); }
  /// True when the server logged `line`.
  bool logged(const std::string& line) const {
    const std::lock_guard<std::mutex> lock(log_mutex_);
    return std::find(log_.begin(), log_.end(), line) != log_.end();
  }
  std::unique_ptr<ipp::Client> client() const {
    return std::make_unique<ipp::Client>("127.0.0.1", port());
  }

 private:
  static dynamics::MeasurementNoise noise_of(bool on, std::uint64_t seed) {
    dynamics::MeasurementNoise n;
    n.enabled = on;
    n.seed = seed;
    return n;
  }
  cmmcomp::vc::IppTwinMachine machine_;
  ipp::Session session_;
  std::unique_ptr<ipp::Server> server_;
  std::thread thread_;
  mutable std::mutex log_mutex_;
  std::vector<std::string> log_;
};

/// The only error number of a transaction (-1 when it has none or several).
int error_of(const ipp::Transaction& t) { return t.errors.size() == 1 ? t.errors[0].number : -1; }

std::string n(double v) { return cmmcomp::io::format_ipp_number(v); }

/// A client with a session: connects until the server has seen its previous client leave (it
/// refuses a connection while it still serves one) and StartSession succeeds.
std::unique_ptr<ipp::Client> next_session(const TwinServer& server) {
  for (int attempt = 0; attempt < 1000; ++attempt) {
    try {
      auto c = server.client();
      if (c->call("StartSession()").ok()) return c;
    } catch (const cmmcomp::Error&) {
      // refused and closed: the previous client was still being served; connect again
    }
  }
  throw cmmcomp::Error("no session after 1000 connections");
}

}  // namespace

TEST(IppConformance, EveryCommandOfTheSubsetAnswersAsDocumented) {
  TwinServer server;
  auto c = server.client();
  const dynamics::Machine machine = dynamics::default_machine();
  using S = cmmcomp::motion::Setting;

  EXPECT_TRUE(c->call("StartSession()").ok());
  EXPECT_TRUE(c->call("Home()").ok());
  ipp::Transaction t = c->call("IsHomed()");
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t.data, std::vector<std::string>{"IsHomed(1)"});
  EXPECT_TRUE(c->call("EnableUser()").ok());
  EXPECT_EQ(c->call("IsUserEnabled()").data, std::vector<std::string>{"IsUserEnabled(1)"});
  EXPECT_TRUE(c->call("DisableUser()").ok());
  EXPECT_EQ(c->call("IsUserEnabled()").data, std::vector<std::string>{"IsUserEnabled(0)"});

  // Min() and Max() are the machine's capabilities.
  t = c->call(
      "GetProp(Tool.GoToPar.Speed.Min(), Tool.GoToPar.Speed.Max(), "
      "Tool.PtMeasPar.Approach.Max())");
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t.data[0],
            "Tool.GoToPar.Speed.Min(" + n(machine.capabilities[S::kPositioningSpeed].min * 1e3) +
                "), Tool.GoToPar.Speed.Max(" +
                n(machine.capabilities[S::kPositioningSpeed].max * 1e3) +
                "), Tool.PtMeasPar.Approach.Max(" +
                n(machine.capabilities[S::kApproachDistance].max * 1e3) + ")");
  EXPECT_TRUE(c->call("SetProp(Tool.PtMeasPar.Search(3), Tool.PtMeasPar.Retract(2))").ok());
  t = c->call("GetProp(Tool.PtMeasPar.Search(), Tool.PtMeasPar.Retract.Act())");
  EXPECT_EQ(t.data,
            std::vector<std::string>{"Tool.PtMeasPar.Search(3), Tool.PtMeasPar.Retract.Act(2)"});
  t = c->call("GetPropE(Tool.PtMeasPar.Search.Def())");
  EXPECT_EQ(t.tag[0], 'E');
  EXPECT_EQ(t.data, std::vector<std::string>{"Tool.PtMeasPar.Search.Def(2)"});

  // A point probed along -X at Y = 400 mm, as plan.ipp probes it: start 50 mm out, positioning
  // 40 mm at 40 mm/s to the pre-hit point, approach 10 mm at 12 mm/s.
  EXPECT_TRUE(c->call("SetProp(Tool.GoToPar.Speed(40), Tool.GoToPar.Accel(200))").ok());
  EXPECT_TRUE(c->call("GoTo(X(50), Y(400), Z(-20))").ok());
  EXPECT_TRUE(c->call("GoTo(X(10), Y(400), Z(-20))").ok());
  t = c->call("Get(X(), Y(), Z())");
  EXPECT_EQ(t.data, std::vector<std::string>{"X(10), Y(400), Z(-20)"});
  EXPECT_TRUE(c->call("SetProp(Tool.PtMeasPar.Speed(12), Tool.PtMeasPar.Accel(60), "
                      "Tool.PtMeasPar.Approach(10))")
                  .ok());
  EXPECT_TRUE(c->call("OnPtMeasReport(X(), Y(), Z(), IJK())").ok());
  t = c->call("PtMeas(X(0), Y(400), Z(-20), IJK(1, 0, 0))");
  ASSERT_TRUE(t.ok()) << t.lines.back();
  dynamics::BridgeSimulator twin(machine);
  const double rae_um =
      twin.simulate(cmmcomp::motion::probing_move_mm(40, 200, 40, 12, 60, 10), 0.4).errors_um.rae;
  ASSERT_GT(std::fabs(rae_um), 0.5);  // the twin's error is there to see
  // d = (-1, 0, 0): the scale reads nominal - RAE * d.
  EXPECT_EQ(t.data,
            std::vector<std::string>{"X(" + n(rae_um * 1e-3) + "), Y(400), Z(-20), IJK(1, 0, 0)"});
  // After the touch the probe retracted 2 mm along IJK.
  EXPECT_EQ(c->call("Get(X())").data, std::vector<std::string>{"X(2)"});

  // A point probed along +Z, the PtMeas positioning itself (from the retract point, 2 mm back
  // along X, then to the pre-hit point 5 mm under the nominal): PD is that distance.
  EXPECT_TRUE(c->call("SetProp(Tool.PtMeasPar.Approach(5))").ok());
  t = c->call("PtMeas(X(2), Y(400), Z(0), IJK(0, 0, -1))");
  ASSERT_TRUE(t.ok());
  const double pd = std::hypot(0.0, 15.0);  // from (2, 400, -20) to (2, 400, -5)
  const double rae2 =
      twin.simulate(cmmcomp::motion::probing_move_mm(40, 200, pd, 12, 60, 5), 0.4).errors_um.rae;
  EXPECT_EQ(t.data,
            std::vector<std::string>{"X(2), Y(400), Z(" + n(-rae2 * 1e-3) + "), IJK(0, 0, -1)"});

  t = c->call("GetErrStatusE()");
  EXPECT_EQ(t.data, std::vector<std::string>{"ErrStatus(0)"});
  t = c->call("StopDaemon(E0042)");
  EXPECT_TRUE(t.acknowledged && t.done);
  EXPECT_EQ(error_of(t), 513);
  EXPECT_TRUE(c->call("StopAllDaemons()").ok());
  t = c->call("GetSupportedCommands()");
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t.data.size(), static_cast<std::size_t>(ipp::kSupportedCommandCount));
  for (int i = 0; i < ipp::kSupportedCommandCount; ++i) {
    EXPECT_EQ(t.data[static_cast<std::size_t>(i)], ipp::kSupportedCommands[i]);
  }
  EXPECT_TRUE(c->call("ClearAllErrors()").ok());
  EXPECT_TRUE(c->call("EndSession()").ok());
  EXPECT_EQ(error_of(c->call("Home()")), 508);  // the session ended
}

TEST(IppConformance, ErrorPathsGetTheSpecificationsNumbers) {
  TwinServer server;
  auto c = server.client();
  const dynamics::Machine machine = dynamics::default_machine();
  ipp::Transaction t = c->call("GoTo(X(1))");
  EXPECT_EQ(error_of(t), 508) << "a command before StartSession";
  EXPECT_FALSE(t.acknowledged);
  ASSERT_TRUE(c->call("StartSession()").ok());
  EXPECT_EQ(error_of(c->call("StartSession()")), 508);
  EXPECT_EQ(error_of(c->call("Frobnicate(1)")), 507);
  EXPECT_EQ(error_of(c->call("ScanOnLine(0, 0, 0, 10, 0, 0, 0, 0, 1, 1)")), 501);
  EXPECT_EQ(error_of(c->call("Home(1)")), 502);
  EXPECT_EQ(error_of(c->call("GoTo(X(1), X(2))")), 502);
  EXPECT_EQ(error_of(c->call("GoTo(X())")), 509);
  EXPECT_EQ(error_of(c->call("GoTo(Tool.A(90))")), 506);
  EXPECT_EQ(error_of(c->call("GoTo(Y(-1))")), 1008);
  EXPECT_EQ(error_of(c->call("PtMeas(X(1), Y(2), Z(3), IJK(0, 0, 0))")), 1010);
  EXPECT_EQ(error_of(c->call("PtMeas(X(1), Y(2))")), 502);
  EXPECT_EQ(error_of(c->call("GetProp(Tool.Name())")), 510);
  EXPECT_EQ(error_of(c->call("SetProp(Tool.GoToPar.Speed.Max(5))")), 510);
  // A value outside Min()..Max() (the machine's capability) is refused and nothing changes.
  const double max_mm_s =
      machine.capabilities[cmmcomp::motion::Setting::kPositioningSpeed].max * 1e3;
  t = c->call("SetProp(Tool.PtMeasPar.Speed(5), Tool.GoToPar.Speed(" + n(max_mm_s + 1) + "))");
  EXPECT_EQ(error_of(t), 504);
  EXPECT_EQ(t.errors[0].severity, 1);
  EXPECT_NE(t.errors[0].text.find("Tool.GoToPar.Speed"), std::string::npos);
  EXPECT_EQ(c->call("GetProp(Tool.PtMeasPar.Speed())").data,
            std::vector<std::string>{"Tool.PtMeasPar.Speed(12)"});
  // Fast-queue rules: a fast command needs an E tag, a normal one must not have it.
  c->send_raw("00900 GetErrStatusE()\r\n");
  EXPECT_EQ(error_of(c->wait("00900")), 1);
  c->send_raw("E0900 Home()\r\n");
  EXPECT_EQ(error_of(c->wait("E0900")), 1);
  c->send_raw("00000 Home()\r\n");
  EXPECT_NE(c->wait_event().find("Error(2, 0001"), std::string::npos);
  // Lines without a tag, without the space, with a NUL.
  c->send_raw("junk\r\n");
  EXPECT_NE(c->wait_event().find("Error(2, 0001"), std::string::npos);
  c->send_raw("00901Home()\r\n");
  EXPECT_EQ(error_of(c->wait("00901")), 2);
  c->send_raw(std::string("00902 Home(\0)\r\n", 15));
  EXPECT_NE(c->wait_event().find("Error(3, 0007"), std::string::npos);
  // The session still works.
  EXPECT_TRUE(c->call("IsHomed()").ok());
}

TEST(IppConformance, TheTwinsRefusalIsAnErrorAndClearAllErrorsEndsTheErrorState) {
  TwinServer server;
  auto c = server.client();
  ASSERT_TRUE(c->call("StartSession()").ok());
  // Y beyond the twin's carriage range is outside the volume; a PtMeas whose positioning the
  // twin refuses: PD over MoveLimits (10 m) cannot be run.
  EXPECT_TRUE(c->call("GoTo(X(-9999), Y(10), Z(0))").ok());
  ipp::Transaction t = c->call("PtMeas(X(9999), Y(10), Z(0), IJK(-1, 0, 0))");
  EXPECT_TRUE(t.acknowledged && t.done);
  EXPECT_EQ(error_of(t), 511);
  EXPECT_EQ(c->call("GetErrStatusE()").data, std::vector<std::string>{"ErrStatus(1)"});
  EXPECT_EQ(error_of(c->call("GoTo(X(0))")), 514);
  EXPECT_TRUE(c->call("ClearAllErrors()").ok());
  EXPECT_TRUE(c->call("GoTo(X(0))").ok());
}

TEST(IppConformance, NoiseIsSeededAndReproducible) {
  const auto run = [](bool noise, std::uint64_t seed) {
    TwinServer server(noise, seed);
    auto c = server.client();
    std::vector<std::string> points;
    EXPECT_TRUE(c->call("StartSession()").ok());
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(c->call("GoTo(X(50), Y(300), Z(0))").ok());
      EXPECT_TRUE(c->call("GoTo(X(10), Y(300), Z(0))").ok());
      const ipp::Transaction t = c->call("PtMeas(X(0), Y(300), Z(0), IJK(1, 0, 0))");
      EXPECT_TRUE(t.ok());
      points.push_back(t.data.empty() ? "" : t.data[0]);
    }
    return points;
  };
  const std::vector<std::string> clean = run(false, 1);
  EXPECT_EQ(clean[0], clean[1]);  // the twin is deterministic
  const std::vector<std::string> a = run(true, 5), b = run(true, 5), other = run(true, 6);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, clean);
  EXPECT_NE(a[0], a[1]);  // each point its own noise sample
  EXPECT_NE(a, other);
}

TEST(IppConformance, TheFastQueueAnswersDuringARealTimeMoveAndAbortEEndsIt) {
  TwinServer server(false, 1, true);
  auto c = server.client();
  ASSERT_TRUE(c->call("StartSession()").ok());
  ASSERT_TRUE(c->call("SetProp(Tool.GoToPar.Speed(1), Tool.GoToPar.Accel(10))").ok());
  const std::string slow = c->send("GoTo(X(500))");  // 500 s of machine time
  const std::string queued = c->send("Home()");
  ipp::Transaction t = c->call("GetErrStatusE()");
  EXPECT_EQ(t.data, std::vector<std::string>{"ErrStatus(0)"});
  t = c->call("GetPropE(Tool.GoToPar.Speed())");
  EXPECT_EQ(t.data, std::vector<std::string>{"Tool.GoToPar.Speed(1)"});
  // The tag of the running GoTo is in use.
  c->send_raw(slow + " IsHomed()\r\n");
  EXPECT_TRUE(c->call("AbortE()").ok());
  const ipp::Transaction moved = c->wait(slow);
  ASSERT_EQ(moved.errors.size(), 2u);
  EXPECT_EQ(moved.errors[0].number, 1);  // the reused tag
  EXPECT_EQ(moved.errors[1].number, 6);  // aborted
  EXPECT_TRUE(moved.done);
  EXPECT_EQ(error_of(c->wait(queued)), 6);
  EXPECT_EQ(c->call("GetErrStatusE()").data, std::vector<std::string>{"ErrStatus(1)"});
  EXPECT_TRUE(c->call("ClearAllErrors()").ok());
  EXPECT_EQ(c->call("Get(X())").data, std::vector<std::string>{"X(0)"});  // stayed at its start
}

TEST(IppConformance, ASecondConnectionGetsAnErrorAndIsClosed) {
  TwinServer server;
  auto first = server.client();
  ASSERT_TRUE(first->call("StartSession()").ok());  // the server has accepted it
  auto second = server.client();
  const std::string e = second->wait_event();
  EXPECT_NE(e.find("Error(3, 0508"), std::string::npos) << e;
  EXPECT_NE(e.find("another client session is active"), std::string::npos) << e;
  EXPECT_TRUE(second->wait_closed(10.0));
  EXPECT_TRUE(first->call("IsHomed()").ok());  // the first is served on
  first.reset();
  // Once the first left, the next client gets a session (the old one ended with it).
  EXPECT_TRUE(next_session(server)->call("IsHomed()").ok());
}

TEST(IppConformance, HostileClientsAreAnsweredOrDroppedAndTheServerServesOn) {
  TwinServer server(false, 1, false, 64 * 1024);
  {
    // Trickled one byte at a time: answered as any line.
    auto c = server.client();
    for (char ch : std::string("00001 StartSession()\r\n")) c->send_raw(std::string(1, ch));
    EXPECT_TRUE(c->wait("00001").ok());
    // An over-long line without LF: an error with the server's tag, then the connection closes.
    c->send_raw(std::string(3000, 'A'));
    EXPECT_NE(c->wait_event().find("Error(3, 0008"), std::string::npos);
    EXPECT_TRUE(c->wait_closed(10.0));
  }
  {
    // A client that never reads: dropped once its answers pile up; the server is not blocked.
    auto c = server.client();
    std::string batch;
    for (int i = 0; i < 500; ++i) batch += "E0001 GetPropE(Tool.GoToPar.Speed())\r\n";
    bool dropped = false;
    for (int k = 0; k < 20000 && !dropped; ++k) {
      try {
        c->send_raw(batch);
      } catch (const std::exception&) {
        dropped = true;  // the server closed the connection: the send fails
      }
    }
    EXPECT_TRUE(dropped);
  }
  EXPECT_TRUE(server.logged("client dropped: protocol error"));
  EXPECT_TRUE(server.logged("client dropped: it does not read its answers"));
  EXPECT_TRUE(next_session(server)->call("IsHomed()").ok());
}

TEST(IppConformance, RealtimeAnswersAGoToAfterItsMachineTime) {
  // A send timeout shorter than the move: it counts from when the answers wait, so a client that
  // reads is not dropped however long the server was silent before.
  TwinServer server(false, 1, true, 1u << 20, 0.1);
  auto c = server.client();
  ASSERT_TRUE(c->call("StartSession()").ok());
  ASSERT_TRUE(c->call("SetProp(Tool.GoToPar.Speed(100), Tool.GoToPar.Accel(500))").ok());
  cmmcomp::motion::MoveProfile profile;
  ASSERT_TRUE(cmmcomp::ok(cmmcomp::motion::MoveProfile::plan(
      cmmcomp::motion::probing_move_mm(100, 500, 20, 12, 60, 10), profile)));
  const double machine_s = profile.instants().positioning_end;  // 20 mm at 100 mm/s, 500 mm/s^2
  const auto start = std::chrono::steady_clock::now();
  EXPECT_TRUE(c->call("GoTo(X(20))").ok());
  const double took =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GE(took, machine_s - 1e-3);  // never before the move could have ended
  EXPECT_GT(machine_s, 0.1);
  EXPECT_TRUE(c->call("IsHomed()").ok());
  EXPECT_FALSE(server.logged("client dropped: nothing could be sent to it for the send timeout"));
}

TEST(IppTranscript, TheDocumentsTranscriptIsWhatTheServerAnswers) {
  std::ifstream in(std::string(CMMCOMP_SOURCE_DIR) + "/docs/protocol-ippdme.md");
  ASSERT_TRUE(in);
  std::vector<std::string> documented, commands;
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    if (line == "```transcript") {
      inside = true;
    } else if (inside && line == "```") {
      break;
    } else if (inside) {
      documented.push_back(line);
      if (line.rfind("> ", 0) == 0) commands.push_back(line.substr(2));
    }
  }
  ASSERT_FALSE(commands.empty()) << "no ```transcript block in docs/protocol-ippdme.md";
  TwinServer server;
  auto c = server.client();
  std::vector<std::string> answered;
  for (const std::string& command : commands) {
    c->send_raw(command + "\r\n");
    answered.push_back("> " + command);
    for (const std::string& a : c->wait(command.substr(0, 5)).lines) answered.push_back("< " + a);
  }
  std::string block;
  for (const std::string& l : answered) block += l + "\n";
  EXPECT_EQ(documented, answered) << "the server (default machine) answers:\n" << block;
}

TEST(IppProbe, TheLengthTestOverIppHasTheTwinsTouchesAndVerdicts) {
  TwinServer server;  // no noise: the server's touches are the twin's
  cmmcomp::vc::IppProbe remote("127.0.0.1", server.port(), 0.0);
  dynamics::MeasurementNoise off;
  cmmcomp::vc::TwinProbe local(dynamics::default_machine(), off);
  for (const cmmcomp::vc::ProbeSetting& s :
       {cmmcomp::vc::default_fast_setting(), cmmcomp::vc::default_slow_setting()}) {
    for (double y : {0.0, 250.0, 500.0}) {
      const double want = local.rae_um(s, y, 0);
      EXPECT_NEAR(remote.rae_um(s, y, 0), want, 2e-3) << s.name << " at Y " << y;
    }
  }
  cmmcomp::vc::LengthProgram program;
  program.lengths_mm = {20, 200};
  program.repeats = 2;
  const cmmcomp::vc::LengthTestResult over_ipp = run_length_test(program, remote, {});
  const cmmcomp::vc::LengthTestResult in_process = run_length_test(program, local, {});
  ASSERT_EQ(over_ipp.per_y.size(), in_process.per_y.size());
  for (std::size_t i = 0; i < over_ipp.per_y.size(); ++i) {
    EXPECT_EQ(over_ipp.per_y[i].slow_pass, in_process.per_y[i].slow_pass);
    EXPECT_EQ(over_ipp.per_y[i].fast_uncompensated_pass,
              in_process.per_y[i].fast_uncompensated_pass);
    EXPECT_NEAR(over_ipp.per_y[i].fast_uncompensated_max_um,
                in_process.per_y[i].fast_uncompensated_max_um,
                5e-3);
  }
  // The fast setting's uncompensated error is there to see (this is not a test of zeros).
  EXPECT_GT(std::fabs(in_process.per_y[0].fast_uncompensated_max_um), 1.0);
}

TEST(IppConformance, ABurstOfCommandsRunsInOrderAndOnlyAMovingServerFillsItsQueue) {
  {
    TwinServer server;
    auto c = server.client();
    std::string burst = "00001 StartSession()\r\n";
    for (int i = 2; i <= 200; ++i) {
      burst += ipp::make_tag(ipp::Tag::Queue::kNormal, i).view();
      burst += " GoTo(X(" + std::to_string(i) + "))\r\n";
    }
    c->send_raw(burst);  // one write: the server reads many lines at once
    for (int i = 1; i <= 200; ++i) {
      EXPECT_TRUE(c->wait(std::string(ipp::make_tag(ipp::Tag::Queue::kNormal, i).view())).ok());
    }
    EXPECT_EQ(c->call("Get(X())").data, std::vector<std::string>{"X(200)"});
  }
  TwinServer server(false, 1, true);
  auto c = server.client();
  ASSERT_TRUE(c->call("StartSession()").ok());
  ASSERT_TRUE(c->call("SetProp(Tool.GoToPar.Speed(1), Tool.GoToPar.Accel(10))").ok());
  const std::string slow = c->send("GoTo(X(500))");  // 500 s: everything after it waits
  std::vector<std::string> tags;
  for (int i = 0; i < 70; ++i) tags.push_back(c->send("IsHomed()"));
  EXPECT_TRUE(c->call("AbortE()").ok());
  for (std::size_t i = 0; i < tags.size(); ++i) {
    // 64 wait (then AbortE ends them: 0006); the 65th and later find the queue full (0000).
    EXPECT_EQ(error_of(c->wait(tags[i])), i < 64 ? 6 : 0) << i;
  }
  EXPECT_EQ(error_of(c->wait(slow)), 6);
}

TEST(IppConformance, ANistStylePointProbingProgramRunsThrough) {
  // The commands and number forms of NIST's point-probing test programs: Home, a tool, the
  // PtMeasPar and GoToPar properties set and read back, R() in the report, signed zeros in IJK,
  // and four points on the faces of a block, the PtMeas positioning itself between them.
  TwinServer server;
  auto c = server.client();
  const std::vector<std::string> setup = {
      "StartSession()",
      "Home()",
      "SetTool(\"Probe1\")",
      "GoTo(X(60), Y(60), Z(150))",
      "ChangeTool(\"Probe1\")",
      "SetProp(Tool.PtMeasPar.Approach(8))",
      "SetProp(Tool.PtMeasPar.Search(8))",
      "SetProp(Tool.PtMeasPar.Retract(8))",
      "SetProp(Tool.GoToPar.Speed(25))",
      "OnPtMeasReport(X(), Y(), Z(), R())",
      "GoTo(X(60), Y(60), Z(80))",
      "GoTo(X(60), Y(60), Z(30))",
  };
  for (const std::string& command : setup) EXPECT_TRUE(c->call(command).ok()) << command;
  EXPECT_EQ(c->call("IsHomed()").data, std::vector<std::string>{"IsHomed(1)"});
  EXPECT_EQ(c->call("GetProp(Tool.PtMeasPar.Approach())").data,
            std::vector<std::string>{"Tool.PtMeasPar.Approach(8)"});
  struct Face {
    const char* command;
    int axis;  ///< the coordinate the twin's error moves: 0 = X, 1 = Y
    double nominal;
  };
  const Face faces[] = {{"PtMeas(X(85.0), Y(60.0), Z(30.0), IJK(-1.0, 0.0, 0.0))", 0, 85.0},
                        {"PtMeas(X(35.0), Y(60.0), Z(30.0), IJK(+1.0, 0.0, 0.0))", 0, 35.0},
                        {"PtMeas(X(60.0), Y(85.0), Z(30.0), IJK(+0.0,-1.0, 0.0))", 1, 85.0},
                        {"PtMeas(X(60.0), Y(35.0), Z(30.0), IJK(-0.0,+1.0, 0.0))", 1, 35.0}};
  for (const Face& f : faces) {
    const ipp::Transaction t = c->call(f.command);
    ASSERT_TRUE(t.ok()) << f.command << ": " << t.lines.back();
    ASSERT_EQ(t.data.size(), 1u);
    ipp::ItemList items;
    ASSERT_EQ(items.parse(t.data[0]), ipp::ParseStatus::kOk);
    double v[4];
    int k = 0;
    for (int i = items.first(); i >= 0 && k < 4; i = items[i].next_sibling) {
      v[k++] = items[items[i].first_child].number;
    }
    ASSERT_EQ(k, 4) << t.data[0];
    EXPECT_EQ(v[3], 0.0);  // R(0)
    // The probed coordinate carries the twin's error (a few um, never zero on this machine);
    // the others are the nominal's.
    const double error_um = (v[f.axis] - f.nominal) * 1e3;
    EXPECT_GT(std::fabs(error_um), 0.5) << t.data[0];
    EXPECT_LT(std::fabs(error_um), 50.0) << t.data[0];
    EXPECT_EQ(v[1 - f.axis], 60.0);
    EXPECT_EQ(v[2], 30.0);
  }
  EXPECT_TRUE(c->call("GoTo(X(60), Y(60), Z(100))").ok());
  EXPECT_TRUE(c->call("EndSession()").ok());
}

// SPDX-License-Identifier: MIT
/// @file The compensating I++ DME proxy (tools/serving/ipp_proxy.hpp) between the project's
/// client and the twin's I++ server, on loopback: a program's transcript through the proxy and
/// directly differs only in the PtMeas data lines, each corrected by what the compensator says
/// for the move the test rebuilds itself; points the proxy cannot compensate pass marked; hostile
/// clients and a second client.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/io/ipp_number.hpp>
#include <cmmcomp/ipp/client.hpp>
#include <cmmcomp/ipp/line.hpp>
#include <cmmcomp/ipp/server.hpp>
#include <cmmcomp/ipp/session.hpp>
#include <cmmcomp/vc/ipp_twin_machine.hpp>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "ipp_proxy.hpp"
#include "model_slots.hpp"
#include "tools/agent/agent_process.hpp"

namespace ipp = cmmcomp::ipp;
namespace serving = cmmcomp::serving;
namespace compensation = cmmcomp::compensation;
using cmmcomp::io::format_ipp_number;

namespace {

/// The twin served on a free loopback port by a thread.
class TwinServer {
 public:
  TwinServer() : machine_(cmmcomp::dynamics::default_machine(), {}), session_(machine_) {
    ipp::ServerOptions o;
    o.port = 0;
    o.log = [](const std::string& l) { std::fprintf(stderr, "server: %s\n", l.c_str()); };
    server_ = std::make_unique<ipp::Server>(session_, o);
    thread_ = std::thread([this] { server_->run(); });
  }
  ~TwinServer() {
    server_->request_stop();
    thread_.join();
  }
  std::uint16_t port() const { return server_->port(); }

 private:
  cmmcomp::vc::IppTwinMachine machine_;
  ipp::Session session_;
  std::unique_ptr<ipp::Server> server_;
  std::thread thread_;
};

/// The proxy in front of `upstream_port`, serving the shipped default model on axis 0 (or no
/// model), on a thread.
class Proxy {
 public:
  explicit Proxy(std::uint16_t upstream_port,
                 bool with_model = true,
                 std::size_t max_buffered = 1u << 20,
                 double send_timeout_s = 5.0) {
    if (with_model) {
      const auto outcomes = serving::load_slots({serving::ModelSlot{0, ""}}, compensator_);
      EXPECT_TRUE(outcomes.at(0).loaded) << outcomes.at(0).error;
    }
    serving::IppProxyOptions o;
    o.listen_port = 0;
    o.upstream_port = upstream_port;
    o.max_buffered_bytes = max_buffered;
    o.send_timeout_s = send_timeout_s;
    o.log = [](const std::string& l) { std::fprintf(stderr, "proxy: %s\n", l.c_str()); };
    proxy_ = std::make_unique<serving::IppProxy>(compensator_, o);
    thread_ = std::thread([this] { proxy_->run(); });
  }
  ~Proxy() {
    proxy_->request_stop();
    thread_.join();
  }
  std::uint16_t port() const { return proxy_->port(); }
  const compensation::MoveCompensator& compensator() const { return compensator_; }
  std::unique_ptr<ipp::Client> client() const {
    return std::make_unique<ipp::Client>("127.0.0.1", port());
  }

 private:
  compensation::MoveCompensator compensator_;
  std::unique_ptr<serving::IppProxy> proxy_;
  std::thread thread_;
};

/// One probed point of the program: its nominal, normal and the move the test expects.
struct ProbePoint {
  double x, y, z;
  double i, j, k;
  double pd_mm;  ///< the positioning's length the rule gives
};

constexpr double kPv = 40, kPa = 200, kAv = 12, kAa = 60, kAd = 10, kRetract = 2;

std::string setprops() {
  return "SetProp(Tool.GoToPar.Speed(" + format_ipp_number(kPv) + "), Tool.GoToPar.Accel(" +
         format_ipp_number(kPa) + "))";
}
std::string ptmeas_props() {
  return "SetProp(Tool.PtMeasPar.Speed(" + format_ipp_number(kAv) + "), Tool.PtMeasPar.Accel(" +
         format_ipp_number(kAa) + "), Tool.PtMeasPar.Approach(" + format_ipp_number(kAd) +
         "), Tool.PtMeasPar.Retract(" + format_ipp_number(kRetract) + "))";
}

/// The program: settings, a query, errors, points probed after a GoTo to the pre-hit point and
/// points positioning themselves (with the lengths of their positionings worked out by hand).
std::vector<std::string> program(std::vector<ProbePoint>& points) {
  points.clear();
  std::vector<std::string> p = {"StartSession()",
                                "GetProp(Tool.GoToPar.Speed.Max())",
                                setprops(),
                                ptmeas_props(),
                                "GetProp(Tool.PtMeasPar.Approach())",
                                "NoSuchCommand()",
                                "OnPtMeasReport(X(), Y(), Z(), IJK())"};
  // Probed along −X after a 40 mm GoTo that ends at the pre-hit point.
  p.push_back("GoTo(X(50), Y(250), Z(-20))");
  p.push_back("GoTo(X(10), Y(250), Z(-20))");
  p.push_back("PtMeas(X(0), Y(250), Z(-20), IJK(1, 0, 0))");
  points.push_back({0, 250, -20, 1, 0, 0, 40});
  // Probed along +X, positioning itself from the retract point (X 2) to the pre-hit point -50.
  p.push_back("PtMeas(X(-40), Y(250), Z(-20), IJK(-1, 0, 0))");
  points.push_back({-40, 250, -20, -1, 0, 0, 2.0 - (-50.0)});
  p.push_back("Get(X(), Y(), Z())");
  // A 60 mm GoTo in X and Y, then a point at Y 700 along −X.
  p.push_back("GoTo(X(70), Y(700), Z(-20))");
  p.push_back("GoTo(X(10), Y(700), Z(-20))");
  p.push_back("PtMeas(X(0), Y(700), Z(-20), IJK(1, 0, 0))");
  points.push_back({0, 700, -20, 1, 0, 0, 60});
  p.push_back("GetErrStatusE()");
  p.push_back("EndSession()");
  return p;
}

std::vector<ipp::Transaction> run_program(ipp::Client& c, const std::vector<std::string>& p) {
  std::vector<ipp::Transaction> out;
  for (const std::string& command : p) out.push_back(c.call(command));
  return out;
}

/// The data line the proxy should write for `direct` (the server's data line of `point`).
std::string expected_line(const std::string& direct,
                          const ProbePoint& point,
                          const compensation::MoveCompensator& compensator) {
  compensation::MoveRequest r;
  const double n = std::sqrt(point.i * point.i + point.j * point.j + point.k * point.k);
  r.direction = {-point.i / n, -point.j / n, -point.k / n};
  r.axis = 0;
  r.pv_mm_s = kPv;
  r.pa_mm_s2 = kPa;
  r.pd_mm = point.pd_mm;
  r.av_mm_s = kAv;
  r.aa_mm_s2 = kAa;
  r.ad_mm = kAd;
  r.y_mm = point.y;
  r.z_mm = point.z;
  compensation::Correction c;
  EXPECT_TRUE(cmmcomp::ok(compensator.before_approach(r, c)));
  EXPECT_NE(c.correction_um[0], 0.0);
  ipp::AnswerLine a;
  EXPECT_EQ(ipp::parse_answer(direct, a), ipp::ParseStatus::kOk);
  ipp::ItemList items;
  EXPECT_EQ(items.parse(a.data), ipp::ParseStatus::kOk);
  std::string data;
  int axis = 0;
  for (int i = items.first(); i >= 0; i = items[i].next_sibling) {
    if (!data.empty()) data += ", ";
    if (axis < 3) {
      const double reported = items[items[i].first_child].number;
      data += std::string(items[i].text) + "(" +
              format_ipp_number(reported + c.correction_um[static_cast<std::size_t>(axis)] * 1e-3) +
              ")";
      ++axis;
    } else {
      data += "IJK(" + format_ipp_number(-r.direction[0]) + ", " +
              format_ipp_number(-r.direction[1]) + ", " + format_ipp_number(-r.direction[2]) + ")";
    }
  }
  data += ", CmmcompCorrection(" + format_ipp_number(c.correction_um[0] * 1e-3) + ", " +
          format_ipp_number(c.correction_um[1] * 1e-3) + ", " +
          format_ipp_number(c.correction_um[2] * 1e-3) + ")";
  char id[24];
  std::snprintf(id, sizeof id, "%016llx", static_cast<unsigned long long>(c.model_id));
  data += ", CmmcompU95(" + format_ipp_number(c.u95_um[3] * 1e-3) + "), CmmcompModel(\"" + id +
          "\"), CmmcompFlags(" + std::to_string(c.flags) + ")";
  return std::string(a.tag.view()) + " # " + data;
}

TEST(IppProxy, TranscriptDiffersFromTheDirectOneOnlyInTheCorrectedPtMeasData) {
  std::vector<ProbePoint> points;
  const std::vector<std::string> p = program(points);
  TwinServer direct_server, proxied_server;
  Proxy proxy(proxied_server.port());
  auto direct = std::make_unique<ipp::Client>("127.0.0.1", direct_server.port());
  const std::vector<ipp::Transaction> want = run_program(*direct, p);
  const std::vector<ipp::Transaction> got = run_program(*proxy.client(), p);
  ASSERT_EQ(got.size(), want.size());
  std::size_t point = 0, lines = 0, differing = 0;
  for (std::size_t t = 0; t < want.size(); ++t) {
    ASSERT_EQ(got[t].lines.size(), want[t].lines.size()) << p[t];
    const bool is_ptmeas = p[t].rfind("PtMeas(", 0) == 0;
    for (std::size_t l = 0; l < want[t].lines.size(); ++l) {
      ++lines;
      const std::string& w = want[t].lines[l];
      if (is_ptmeas && w.find(" # ") == 5) {
        ASSERT_LT(point, points.size());
        EXPECT_EQ(got[t].lines[l], expected_line(w, points[point], proxy.compensator()))
            << "direct: " << w;
        EXPECT_NE(got[t].lines[l], w);
        ++point;
        ++differing;
      } else {
        EXPECT_EQ(got[t].lines[l], w) << p[t];
      }
    }
  }
  EXPECT_EQ(point, points.size());
  EXPECT_EQ(differing, points.size());
  EXPECT_GE(lines, 40u);
}

TEST(IppProxyTranscript, TheDocumentsProxyTranscriptIsWhatTheProxyAnswers) {
  std::ifstream in(CMMCOMP_DOCS_DIR "/protocol-ippdme.md");
  ASSERT_TRUE(in);
  std::vector<std::string> documented, commands;
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    if (line == "```proxy-transcript") {
      inside = true;
    } else if (inside && line == "```") {
      break;
    } else if (inside) {
      documented.push_back(line);
      if (line.rfind("> ", 0) == 0) commands.push_back(line.substr(2));
    }
  }
  ASSERT_FALSE(commands.empty()) << "no ```proxy-transcript block in docs/protocol-ippdme.md";
  TwinServer server;
  Proxy proxy(server.port());
  auto c = proxy.client();
  std::vector<std::string> answered;
  for (const std::string& command : commands) {
    c->send_raw(command + "\r\n");
    answered.push_back("> " + command);
    for (const std::string& a : c->wait(command.substr(0, 5)).lines) answered.push_back("< " + a);
  }
  std::string block;
  for (const std::string& l : answered) block += l + "\n";
  EXPECT_EQ(documented, answered) << "the proxy (shipped model, default machine) answers:\n"
                                  << block;
}

/// Reads from `fd` until `needle` came or the peer closed (bounded by a timeout).
std::string read_until(int fd, const std::string& needle, double timeout_s = 10.0) {
  std::string got;
  const auto end = std::chrono::steady_clock::now() +
                   std::chrono::milliseconds(static_cast<int>(timeout_s * 1000));
  while (got.find(needle) == std::string::npos && std::chrono::steady_clock::now() < end) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 100) <= 0) continue;
    char b[4096];
    const ssize_t n = ::recv(fd, b, sizeof b, 0);
    if (n <= 0) break;
    got.append(b, static_cast<std::size_t>(n));
  }
  return got;
}

int connect_to(std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  ::inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
  EXPECT_EQ(::connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a), 0);
  return fd;
}

void send_all(int fd, const std::string& bytes) {
  ASSERT_EQ(::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL),
            static_cast<ssize_t>(bytes.size()));
}

TEST(IppProxy, RawBytesWithoutAPointAreTheServersByteForByte) {
  // Lines without CR, binary junk, a reused tag and a line split across two writes: the bytes
  // the client gets are the server's, byte for byte.
  const std::string session =
      "00001 StartSession()\n" + std::string("00002 ") + setprops() + "\r\n00003 " +
      ptmeas_props() +
      "\r\n00004 Get\x01(X())\r\n\xff\xfe junk\r\n00005 GoTo(X(10), Y(250), Z(-20))\r\n"
      "00005 GoTo(X(10), Y(250), Z(-20))\r\n00006 EndSession()\r\n";
  std::string answers[2];
  for (int via_proxy = 0; via_proxy < 2; ++via_proxy) {
    TwinServer server;
    std::unique_ptr<Proxy> proxy;
    if (via_proxy == 1) proxy = std::make_unique<Proxy>(server.port());
    const int fd = connect_to(via_proxy == 1 ? proxy->port() : server.port());
    const std::size_t half = session.size() / 2;
    send_all(fd, session.substr(0, half));
    send_all(fd, session.substr(half));
    answers[via_proxy] = read_until(fd, "00006 %\r\n");
    ::close(fd);
  }
  EXPECT_NE(answers[0].find("00006 %\r\n"), std::string::npos) << answers[0];
  EXPECT_NE(answers[0].find("0007"), std::string::npos) << answers[0];  // the junk's error
  EXPECT_EQ(answers[1], answers[0]);
}

TEST(IppProxy, AClientThatHalfClosesAfterItsProgramGetsEveryAnswerAsWithoutTheProxy) {
  // `printf … | socat - TCP:…` sends the program, then shuts its side: the server answers every
  // line, and so must the proxy (it passes the end on, and the answers back).
  std::vector<ProbePoint> points;
  const std::vector<std::string> lines = program(points);
  auto tag = [](std::size_t n) {
    std::string t = std::to_string(n);
    return std::string(5 - t.size(), '0') + t;
  };
  std::string session;
  for (std::size_t i = 0; i < lines.size(); ++i) session += tag(i + 1) + " " + lines[i] + "\r\n";
  const std::string last = tag(lines.size()) + " %\r\n";
  std::string answers[2];
  for (int via_proxy = 0; via_proxy < 2; ++via_proxy) {
    TwinServer server;
    std::unique_ptr<Proxy> proxy;
    if (via_proxy == 1) proxy = std::make_unique<Proxy>(server.port());
    const int fd = connect_to(via_proxy == 1 ? proxy->port() : server.port());
    send_all(fd, session);
    ::shutdown(fd, SHUT_WR);
    answers[via_proxy] = read_until(fd, last);
    ::close(fd);
  }
  ASSERT_NE(answers[0].find(last), std::string::npos) << answers[0];
  EXPECT_NE(answers[1].find(last), std::string::npos) << answers[1];
  // Line for line the same, but the corrected PtMeas data.
  std::size_t differing = 0;
  std::size_t a = 0, b = 0;
  while (a < answers[0].size() && b < answers[1].size()) {
    const std::size_t ea = answers[0].find('\n', a), eb = answers[1].find('\n', b);
    if (ea == std::string::npos || eb == std::string::npos) break;
    const std::string la = answers[0].substr(a, ea - a), lb = answers[1].substr(b, eb - b);
    if (la != lb) {
      ++differing;
      EXPECT_NE(lb.find("CmmcompFlags("), std::string::npos) << la << " / " << lb;
    }
    a = ea + 1;
    b = eb + 1;
  }
  EXPECT_EQ(differing, points.size());
}

TEST(IppProxy, ASecondClientGetsAnErrorAndIsClosed) {
  TwinServer server;
  Proxy proxy(server.port());
  auto first = proxy.client();
  EXPECT_TRUE(first->call("StartSession()").ok());
  const int second = connect_to(proxy.port());
  const std::string got = read_until(second, "\n");
  EXPECT_EQ(got.rfind("E0000 ! Error(3, 0508,", 0), 0u) << got;
  EXPECT_NE(got.find("another client session is active"), std::string::npos) << got;
  char b[16];
  EXPECT_EQ(::recv(second, b, sizeof b, 0), 0);  // closed
  ::close(second);
  EXPECT_TRUE(first->call("IsHomed()").ok());  // the first session goes on
}

TEST(IppProxy, AnOverLongLineGetsTheServersTreatmentAndTheNextClientIsServed) {
  TwinServer server;
  Proxy proxy(server.port());
  {
    auto c = proxy.client();
    EXPECT_TRUE(c->call("StartSession()").ok());
    c->send_raw(std::string(3000, 'A'));
    const std::string event = c->wait_event();
    EXPECT_NE(event.find("0008"), std::string::npos) << event;
    EXPECT_TRUE(c->wait_closed(10.0));
  }
  auto next = proxy.client();  // the upstream session ended with it: a new one starts
  EXPECT_TRUE(next->call("StartSession()").ok());
  EXPECT_TRUE(next->call("EndSession()").ok());
}

TEST(IppProxy, AClientThatDoesNotReadIsDroppedAndTheUpstreamGoesOn) {
  TwinServer server;
  Proxy proxy(server.port(), true, 1u << 16, 2.0);
  {
    auto c = proxy.client();
    ASSERT_TRUE(c->call("StartSession()").ok());
    std::string batch;
    for (int i = 0; i < 500; ++i) batch += "E0001 GetPropE(Tool.GoToPar.Speed())\r\n";
    bool dropped = false;
    for (int k = 0; k < 20000 && !dropped; ++k) {
      try {
        c->send_raw(batch);
      } catch (const std::exception&) {
        dropped = true;  // the proxy closed the connection: the send fails
      }
    }
    EXPECT_TRUE(dropped);
  }
  auto next = proxy.client();  // the upstream was never blocked: a new session starts
  EXPECT_TRUE(next->call("StartSession()").ok());
  EXPECT_TRUE(next->call("IsHomed()").ok());
}

/// Drives the line logic by hand: the server's lines are written here, so every cause of an
/// uncorrected point can be produced.
struct Logic {
  compensation::MoveCompensator compensator;
  std::vector<std::string> log;
  std::unique_ptr<serving::IppProxyLogic> logic;
  explicit Logic(bool with_model) {
    if (with_model) serving::load_slots({serving::ModelSlot{0, ""}}, compensator);
    logic = std::make_unique<serving::IppProxyLogic>(
        compensator, [this](const std::string& l) { log.push_back(l); });
  }
  /// A command and its answers (the data line, if any, as the proxy passes it).
  std::string run(const std::string& command, const std::string& data = "") {
    logic->from_client(command);
    const std::string tag = command.substr(0, 5);
    EXPECT_EQ(logic->from_server(tag + " &\r"), tag + " &\r");
    std::string passed;
    if (!data.empty()) passed = std::string(logic->from_server(tag + " # " + data + "\r"));
    EXPECT_EQ(logic->from_server(tag + " %\r"), tag + " %\r");
    return passed;
  }
  void setup() {
    run("00001 " + setprops());
    run("00002 " + ptmeas_props());
  }
};

TEST(IppProxyLogic, APointThatCannotBeCompensatedPassesMarkedAndIsLoggedOnce) {
  Logic no_position(true);
  no_position.setup();
  const std::string data = "X(0.001), Y(250), Z(-20)";
  // The proxy has not seen the machine move: the position is unknown.
  EXPECT_EQ(no_position.run("00003 PtMeas(X(0), Y(250), Z(-20), IJK(1, 0, 0))", data),
            "00003 # " + data + ", CmmcompFlags(256)\r");
  EXPECT_EQ(no_position.run("00004 PtMeas(X(0), Y(250), Z(-20), IJK(1, 0, 0))", data),
            "00004 # " + data + ", CmmcompFlags(256)\r");
  ASSERT_EQ(no_position.log.size(), 1u);
  EXPECT_NE(no_position.log[0].find("position"), std::string::npos) << no_position.log[0];

  Logic no_model(false);
  no_model.setup();
  no_model.run("00003 Get(X(), Y(), Z())", "X(60), Y(250), Z(-20)");
  EXPECT_EQ(no_model.run("00004 PtMeas(X(0), Y(250), Z(-20), IJK(1, 0, 0))", data),
            "00004 # " + data + ", CmmcompFlags(8)\r");

  Logic format(true);
  format.setup();
  format.run("00003 Get(X(), Y(), Z())", "X(60), Y(250), Z(-20)");
  EXPECT_EQ(format.run("00004 PtMeas(X(0), Y(250), Z(-20), IJK(1, 0, 0))", "IJK(1, 0, 0)"),
            "00004 # IJK(1, 0, 0), CmmcompFlags(512)\r");

  // After a Home the position is unknown again; a Get makes it known, and the point is corrected.
  Logic home(true);
  home.setup();
  home.run("00003 Get(X(), Y(), Z())", "X(60), Y(250), Z(-20)");
  home.run("00004 Home()");
  EXPECT_NE(home.run("00005 PtMeas(X(0), Y(250), Z(-20), IJK(1, 0, 0))", data).find("(256)"),
            std::string::npos);
  home.run("00006 Get(X(), Y(), Z())", "X(60), Y(250), Z(-20)");
  const std::string corrected = home.run("00007 PtMeas(X(0), Y(250), Z(-20), IJK(1, 0, 0))", data);
  EXPECT_NE(corrected.find("CmmcompU95("), std::string::npos) << corrected;
  EXPECT_EQ(corrected.find("X(0.001)"), std::string::npos) << corrected;
}

TEST(IppProxyLogic, ARefusedOrFailedCommandChangesNothingOrForgetsThePosition) {
  Logic l(true);
  l.setup();
  l.run("00003 Get(X(), Y(), Z())", "X(60), Y(250), Z(-20)");
  // A SetProp refused at receipt (no `&`) changes no property.
  l.logic->from_client("00004 SetProp(Tool.PtMeasPar.Speed(1000))");
  EXPECT_EQ(l.logic->from_server("00004 ! Error(1, 0504, \"x\", \"y\")"),
            "00004 ! Error(1, 0504, \"x\", \"y\")");
  const std::string data = "X(0.001), Y(250), Z(-20)";
  std::string a = l.run("00005 PtMeas(X(0), Y(250), Z(-20), IJK(1, 0, 0))", data);
  EXPECT_NE(a.find("CmmcompU95("), std::string::npos) << a;
  // A GoTo that AbortE ended: the position is unknown.
  l.logic->from_client("00006 GoTo(X(30), Y(250), Z(-20))");
  l.logic->from_server("00006 &");
  l.logic->from_server("00006 ! Error(2, 0006, \"00006\", \"Transaction aborted\")");
  l.logic->from_server("00006 %");
  a = l.run("00007 PtMeas(X(0), Y(250), Z(-20), IJK(1, 0, 0))", data);
  EXPECT_NE(a.find("CmmcompFlags(256)"), std::string::npos) << a;
}

namespace sighup {

using namespace std::chrono_literals;
using cmmcomp::test::AgentProcess;

void copy_file(const std::string& from, const std::string& to) {
  std::ifstream in(from, std::ios::binary);
  std::ofstream out(to + ".tmp", std::ios::binary);
  out << in.rdbuf();
  out.close();
  std::rename((to + ".tmp").c_str(), to.c_str());
}

/// One probed point through the proxy: its data line.
std::string probe_once(int port) {
  ipp::Client c("127.0.0.1", static_cast<std::uint16_t>(port));
  EXPECT_TRUE(c.call("StartSession()").ok());
  EXPECT_TRUE(c.call(setprops()).ok());
  EXPECT_TRUE(c.call(ptmeas_props()).ok());
  EXPECT_TRUE(c.call("GoTo(X(70), Y(250), Z(-20))").ok());
  EXPECT_TRUE(c.call("GoTo(X(10), Y(250), Z(-20))").ok());
  const ipp::Transaction t = c.call("PtMeas(X(0), Y(250), Z(-20), IJK(1, 0, 0))");
  EXPECT_TRUE(c.call("EndSession()").ok());
  return t.data.empty() ? std::string() : t.data[0];
}

TEST(IppProxyProcess, SighupSwapsTheModelAndABrokenFileKeepsTheOldOne) {
  const std::string model =
      ::testing::TempDir() + "ipp_proxy_model_" + std::to_string(::getpid()) + ".json";
  copy_file(CMMCOMP_MODELS_DIR "/default.json", model);
  AgentProcess server(CMMCOMP_SIM_PATH, {"serve-ipp", "--listen", "127.0.0.1:0"});
  const int upstream = server.port_after("listening on 127.0.0.1:");
  ASSERT_GT(upstream, 0) << server.output();
  AgentProcess proxy(CMMCOMP_AGENT_PATH,
                     {"--ipp-proxy",
                      "127.0.0.1:0",
                      "--ipp-upstream",
                      "127.0.0.1:" + std::to_string(upstream),
                      "--model",
                      model});
  const int port = proxy.port_after("I++ proxy listening on 127.0.0.1:");
  ASSERT_GT(port, 0) << proxy.output();
  const std::string before = probe_once(port);
  EXPECT_NE(before.find("CmmcompCorrection("), std::string::npos) << before;

  copy_file(CMMCOMP_MODELS_DIR "/default-y.json", model);
  proxy.signal(SIGHUP);
  ASSERT_TRUE(proxy.wait_for_output("reloaded model", 10s)) << proxy.output();
  const std::string after = probe_once(port);
  EXPECT_NE(after.find("CmmcompCorrection("), std::string::npos) << after;
  EXPECT_NE(after, before);  // another model, another correction

  {
    std::ofstream broken(model, std::ios::trunc);
    broken << "{ not a model";
  }
  proxy.signal(SIGHUP);
  ASSERT_TRUE(proxy.wait_for_output("keeps serving", 10s)) << proxy.output();
  EXPECT_EQ(probe_once(port), after);
  proxy.signal(SIGTERM);
  EXPECT_EQ(proxy.wait_exit(10s), 0) << proxy.output();
  std::remove(model.c_str());
}

}  // namespace sighup

}  // namespace

// SPDX-License-Identifier: MIT
/// @file The compensating I++ DME proxy (ipp_proxy.hpp).
#include "ipp_proxy.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/ipp_number.hpp>
#include <cmmcomp/ipp/socket.hpp>
#include <cstdio>
#include <cstring>
#include <vector>

namespace cmmcomp::serving {
namespace {

using ipp::Item;
using ipp::ItemList;
using ipp::Point3;
using ipp::Property;

/// The most transactions the proxy follows at once (a server queues at most 64 and answers a
/// refused one at once; a client with more open is not following the protocol).
constexpr std::size_t kMaxPending = 256;

enum class Kind : std::uint8_t {
  kQuiet,    ///< no motion, no state the rule needs
  kMotion,   ///< a command that may move the machine in a way the proxy does not follow
  kSetProp,  ///< its properties take effect at `%`
  kGetProp,  ///< its data line says the properties
  kGoTo,
  kPtMeas,
  kGet,  ///< its data line says the position
};

struct Pending {
  bool used = false;
  std::array<char, 5> tag{};
  Kind kind = Kind::kQuiet;
  bool acknowledged = false;
  bool failed = false;
  int duplicates = 0;  ///< the same tag sent again while open (the server refuses those)
  bool has[3] = {false, false, false};
  double xyz[3] = {0, 0, 0};
  Point3 ijk;
  int settings = 0;
  std::array<std::pair<Property, double>, ipp::kPropertyCount> set{};
  bool probed = false;
  ipp::ReconstructedMove move;
};

bool same_name(std::string_view a, const char* b) { return a == std::string_view(b); }

/// "X", "Y" or "Z".
std::string_view axis_name(int axis) {
  static constexpr char kAxes[] = "XYZ";
  return {kAxes + axis, 1};
}

/// The single number argument of call item `i`.
bool single_number(const ItemList& list, int i, double& v) {
  const Item& it = list[i];
  if (it.kind != Item::Kind::kCall || it.first_child < 0) return false;
  const Item& c = list[it.first_child];
  if (c.kind != Item::Kind::kNumber || c.next_sibling >= 0) return false;
  v = c.number;
  return true;
}

/// Commands that neither move the machine nor change what the rule needs.
constexpr const char* kQuietCommands[] = {
    "StartSession",         "EndSession", "ClearAllErrors", "IsHomed",         "DisableUser",
    "IsUserEnabled",        "GetPropE",   "GetErrStatusE",  "StopDaemon",      "StopAllDaemons",
    "GetSupportedCommands", "SetTool",    "OnPtMeasReport", "OnMoveReportE",   "OnScanReport",
    "GetDMEVersion",        "EnumProp",   "EnumAllProp",    "GetMachineClass", "GetXtdErrStatus",
    "GetErrorInfo",         "FindTool",   "EnumTools",      "GetCoordSystem",  "AbortE",
};

void format_number(double v, std::string& out) {
  // io::format_ipp_number throws for a value that is not finite; the proxy never writes one.
  out += io::format_ipp_number(v);
}

}  // namespace

struct IppProxyLogic::Impl {
  const compensation::MoveCompensator& compensator;
  std::function<void(const std::string&)> log;
  ipp::ProbingMoveTracker tracker;
  std::array<Pending, kMaxPending> pending{};
  ipp::CommandLine command;
  ipp::AnswerLine answer;
  ItemList data_items;
  std::string out;
  IppProxyCounters counters;
  std::uint32_t sequence = 0;
  std::array<const char*, 32> logged{};

  Impl(const compensation::MoveCompensator& c, std::function<void(const std::string&)> l)
      : compensator(c), log(std::move(l)) {
    out.reserve(4 * ipp::kMaxLineBytes);
  }

  void reset() {
    tracker = ipp::ProbingMoveTracker{};
    for (Pending& p : pending) p.used = false;
  }

  /// Logs `cause` the first time it occurs (a static string).
  void log_once(const char* cause) {
    for (const char*& l : logged) {
      if (l == cause) return;
      if (l == nullptr) {
        l = cause;
        if (log) log(std::string("a point passed uncorrected: ") + cause);
        return;
      }
    }
  }

  Pending* find(std::string_view tag) {
    for (Pending& p : pending) {
      if (p.used && std::string_view(p.tag.data(), 5) == tag) return &p;
    }
    return nullptr;
  }

  void from_client(std::string_view line) {
    if (ipp::parse_command(line, command) != ipp::ParseStatus::kOk) return;
    const std::string_view tag = command.tag.view();
    if (Pending* open = find(tag)) {
      ++open->duplicates;  // the server refuses it with a `!` before any `&`
      return;
    }
    Pending* slot = nullptr;
    for (Pending& p : pending) {
      if (!p.used) {
        slot = &p;
        break;
      }
    }
    if (slot == nullptr) {
      // More open transactions than a server queues: the rule no longer follows the machine.
      tracker.position_unknown();
      return;
    }
    Pending& p = *slot;
    p = Pending{};
    p.used = true;
    std::copy(tag.begin(), tag.end(), p.tag.begin());
    const std::string_view name = command.name;
    const ItemList& args = command.args;
    p.kind = Kind::kMotion;
    for (const char* q : kQuietCommands) {
      if (same_name(name, q)) p.kind = Kind::kQuiet;
    }
    if (name == "SetProp") {
      p.kind = Kind::kSetProp;
      for (int i = args.first(); i >= 0; i = args[i].next_sibling) {
        Property prop;
        double v = 0;
        if (args[i].kind == Item::Kind::kCall &&
            ipp::find_property(args[i].text.data(), args[i].text.size(), prop) &&
            single_number(args, i, v) && p.settings < ipp::kPropertyCount) {
          p.set[static_cast<std::size_t>(p.settings++)] = {prop, v};
        }
      }
    } else if (name == "GetProp") {
      p.kind = Kind::kGetProp;
    } else if (name == "Get") {
      p.kind = Kind::kGet;
    } else if (name == "GoTo" || name == "PtMeas") {
      p.kind = name == "GoTo" ? Kind::kGoTo : Kind::kPtMeas;
      bool has_ijk = false;
      for (int i = args.first(); i >= 0; i = args[i].next_sibling) {
        const Item& it = args[i];
        double v = 0;
        for (int axis = 0; axis < 3; ++axis) {
          if (it.text == axis_name(axis) && single_number(args, i, v)) {
            p.has[axis] = true;
            p.xyz[axis] = v;
          }
        }
        if (it.text == "IJK" && it.kind == Item::Kind::kCall &&
            args.count_from(it.first_child) == 3) {
          const int a = it.first_child, b = args[a].next_sibling, c = args[b].next_sibling;
          if (args[a].kind == Item::Kind::kNumber && args[b].kind == Item::Kind::kNumber &&
              args[c].kind == Item::Kind::kNumber) {
            p.ijk = {args[a].number, args[b].number, args[c].number};
            has_ijk = true;
          }
        }
      }
      if (p.kind == Kind::kPtMeas && !(p.has[0] && p.has[1] && p.has[2] && has_ijk)) {
        p.kind = Kind::kMotion;  // the server refuses it; if not, the proxy cannot follow it
      }
    }
  }

  /// The transaction ended: its effects on the rule's state.
  void finish(Pending& p) {
    p.used = false;
    if (p.failed) {
      if (p.kind != Kind::kQuiet && p.kind != Kind::kSetProp && p.kind != Kind::kGetProp &&
          p.kind != Kind::kGet) {
        tracker.position_unknown();  // an aborted or failed motion ends where it ends
      }
      return;
    }
    switch (p.kind) {
      case Kind::kQuiet:
      case Kind::kGetProp:
      case Kind::kGet:
        break;
      case Kind::kMotion:
        tracker.position_unknown();
        break;
      case Kind::kSetProp:
        for (int i = 0; i < p.settings; ++i) {
          tracker.set_property(p.set[static_cast<std::size_t>(i)].first,
                               p.set[static_cast<std::size_t>(i)].second);
        }
        break;
      case Kind::kGoTo: {
        Point3 here;
        const bool known = tracker.position(here);
        if (!(p.has[0] && p.has[1] && p.has[2]) && !known) {
          tracker.position_unknown();
          break;
        }
        tracker.moved_to({p.has[0] ? p.xyz[0] : here.x,
                          p.has[1] ? p.xyz[1] : here.y,
                          p.has[2] ? p.xyz[2] : here.z});
        break;
      }
      case Kind::kPtMeas:
        if (p.probed) {
          tracker.probed(p.move);
        } else {
          tracker.position_unknown();
        }
        break;
    }
  }

  void read_properties(std::string_view data) {
    if (data_items.parse(data) != ipp::ParseStatus::kOk) return;
    for (int i = data_items.first(); i >= 0; i = data_items[i].next_sibling) {
      std::string_view name = data_items[i].text;
      if (name.size() > 4 && name.substr(name.size() - 4) == ".Act") {
        name.remove_suffix(4);
      }
      Property prop;
      double v = 0;
      if (ipp::find_property(name.data(), name.size(), prop) && single_number(data_items, i, v)) {
        tracker.set_property(prop, v);
      }
    }
  }

  void read_position(std::string_view data) {
    if (data_items.parse(data) != ipp::ParseStatus::kOk) return;
    Point3 p;
    const bool known = tracker.position(p);
    double* axes[3] = {&p.x, &p.y, &p.z};
    bool has[3] = {false, false, false};
    for (int i = data_items.first(); i >= 0; i = data_items[i].next_sibling) {
      double v = 0;
      for (int axis = 0; axis < 3; ++axis) {
        if (data_items[i].text == axis_name(axis) && single_number(data_items, i, v)) {
          *axes[axis] = v;
          has[axis] = true;
        }
      }
    }
    if ((has[0] && has[1] && has[2]) || (known && (has[0] || has[1] || has[2]))) {
      tracker.position_is(p);
    }
  }

  /// Appends the marks: when corrected, the correction added to X, Y, Z [mm], U95 of the
  /// corrected point along d [mm] and the model's id; always the flags.
  void append_marks(const compensation::Correction* corrected, double u95_mm, std::uint32_t flags) {
    if (corrected != nullptr) {
      out += ", CmmcompCorrection(";
      for (std::size_t a = 0; a < 3; ++a) {
        if (a > 0) out += ", ";
        format_number(corrected->correction_um[a] * 1e-3, out);
      }
      out += "), CmmcompU95(";
      format_number(u95_mm, out);
      // The model that corrected the point, as the agent's protocols carry it (16 hex digits).
      char id[40];
      const int n = std::snprintf(id,
                                  sizeof id,
                                  "), CmmcompModel(\"%016llx\")",
                                  static_cast<unsigned long long>(corrected->model_id));
      out.append(id, static_cast<std::size_t>(n));
    }
    out += ", CmmcompFlags(";
    char digits[16];
    const int n = std::snprintf(digits, sizeof digits, "%u", static_cast<unsigned>(flags));
    out.append(digits, static_cast<std::size_t>(n));
    out += ")";
  }

  std::string_view rewrite(std::string_view line, Pending& p) {
    ++counters.points;
    const bool cr = !line.empty() && line.back() == '\r';
    const std::string_view body = cr ? line.substr(0, line.size() - 1) : line;
    // The positions of the three numbers in the line.
    int number_item[3] = {-1, -1, -1};
    if (data_items.parse(answer.data) == ipp::ParseStatus::kOk) {
      for (int i = data_items.first(); i >= 0; i = data_items[i].next_sibling) {
        double v = 0;
        for (int axis = 0; axis < 3; ++axis) {
          if (data_items[i].text == axis_name(axis) && single_number(data_items, i, v)) {
            number_item[axis] = data_items[i].first_child;
          }
        }
      }
    }
    const ipp::ReconstructedMove move = tracker.probing_move({p.xyz[0], p.xyz[1], p.xyz[2]}, p.ijk);
    p.move = move;
    p.probed = move.ok;
    out.clear();
    if (number_item[0] < 0 || number_item[1] < 0 || number_item[2] < 0) {
      log_once("the data line has no X(), Y() and Z() to correct (OnPtMeasReport)");
      out.append(body);
      append_marks(nullptr, 0, kIppFlagReportFormat);
      if (cr) out += '\r';
      return out;
    }
    if (!move.ok) {
      log_once(move.problem);
      out.append(body);
      append_marks(nullptr, 0, kIppFlagNotRebuilt);
      if (cr) out += '\r';
      return out;
    }
    compensation::MoveRequest r;
    r.sequence = sequence++;
    const double d[3] = {move.direction.x, move.direction.y, move.direction.z};
    int axis = 0;
    for (int i = 1; i < 3; ++i) {
      if (std::fabs(d[i]) > std::fabs(d[axis])) axis = i;
    }
    r.axis = static_cast<std::uint8_t>(axis);
    r.direction = {d[0], d[1], d[2]};
    r.pv_mm_s = move.pv_mm_s;
    r.pa_mm_s2 = move.pa_mm_s2;
    r.pd_mm = move.pd_mm;
    r.av_mm_s = move.av_mm_s;
    r.aa_mm_s2 = move.aa_mm_s2;
    r.ad_mm = move.ad_mm;
    r.y_mm = move.y_mm;
    r.z_mm = move.nominal.z;
    compensation::Correction c;
    const Status s = compensator.before_approach(r, c);
    if (!ok(s)) {
      log_once(s == Status::kNoModel                 ? "no model for the probing axis"
               : s == Status::kOutsideDomainRejected ? "the move is outside the model's domain"
                                                     : "the compensator refused the move");
      out.append(body);
      append_marks(nullptr, 0, compensation::flags_for(s));
      if (cr) out += '\r';
      return out;
    }
    // Replace the three numbers' text, in the order they come in the line.
    std::array<std::pair<std::size_t, int>, 3> spans{};
    for (int a = 0; a < 3; ++a) {
      const Item& it = data_items[number_item[a]];
      spans[static_cast<std::size_t>(a)] = {static_cast<std::size_t>(it.text.data() - line.data()),
                                            a};
    }
    std::sort(spans.begin(), spans.end());
    std::size_t at = 0;
    for (const auto& [offset, a] : spans) {
      const Item& it = data_items[number_item[a]];
      out.append(body.substr(at, offset - at));
      format_number(it.number + c.correction_um[static_cast<std::size_t>(a)] * 1e-3, out);
      at = offset + it.text.size();
    }
    out.append(body.substr(at));
    append_marks(&c, c.u95_um[3] * 1e-3, c.flags);
    if (cr) out += '\r';
    ++counters.corrected;
    return out;
  }

  std::string_view from_server(std::string_view line) {
    if (ipp::parse_answer(line, answer) != ipp::ParseStatus::kOk) return line;
    const std::string_view tag = answer.tag.view();
    Pending* p = find(tag);
    if (p == nullptr) return line;
    switch (answer.kind) {
      case ipp::AnswerLine::Kind::kAck:
        p->acknowledged = true;
        return line;
      case ipp::AnswerLine::Kind::kError:
        if (p->duplicates > 0) {
          --p->duplicates;  // the refusal of the repeated tag
        } else if (!p->acknowledged) {
          p->used = false;  // refused at receipt: nothing happened
        } else {
          p->failed = true;
        }
        return line;
      case ipp::AnswerLine::Kind::kDone:
        finish(*p);
        return line;
      case ipp::AnswerLine::Kind::kData:
        if (p->kind == Kind::kGetProp) read_properties(answer.data);
        if (p->kind == Kind::kGet) read_position(answer.data);
        if (p->kind == Kind::kPtMeas && !p->probed) return rewrite(line, *p);
        return line;
    }
    return line;
  }
};

IppProxyLogic::IppProxyLogic(const compensation::MoveCompensator& compensator,
                             std::function<void(const std::string&)> log)
    : impl_(std::make_unique<Impl>(compensator, std::move(log))) {}
IppProxyLogic::~IppProxyLogic() = default;
void IppProxyLogic::reset() noexcept { impl_->reset(); }
void IppProxyLogic::from_client(std::string_view line) noexcept { impl_->from_client(line); }
std::string_view IppProxyLogic::from_server(std::string_view line) {
  return impl_->from_server(line);
}
const IppProxyCounters& IppProxyLogic::counters() const noexcept { return impl_->counters; }

// ---- sockets ----

namespace {

using ipp::net::Clock;
using ipp::net::ms_until;
using ipp::net::no_delay;
using ipp::net::set_nonblocking;

/// Bytes that wait to be sent on a non-blocking socket.
struct Outbox {
  std::string bytes;
  Clock::time_point waiting_since;
  void add(std::string_view s) {
    if (bytes.empty()) waiting_since = Clock::now();
    bytes.append(s);
  }
  /// Sends what it can; false on a send error.
  bool flush(int fd) {
    if (bytes.empty()) return true;
    const ssize_t n = ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n > 0) {
      bytes.erase(0, static_cast<std::size_t>(n));
      waiting_since = Clock::now();
      return true;
    }
    return n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR);
  }
};

}  // namespace

struct IppProxy::Impl {
  IppProxyOptions options;
  IppProxyLogic logic;
  int listen_fd = -1;
  int wake[2] = {-1, -1};
  std::uint16_t port = 0;
  int client = -1, upstream = -1;
  std::string client_in, upstream_in;
  bool upstream_passthrough = false;  ///< inside an over-long server line: forwarded as it is
  Outbox to_client, to_upstream;
  bool closing = false;        ///< send what waits to the client, then close
  bool client_done = false;    ///< the client half-closed: it sends nothing more
  bool upstream_shut = false;  ///< and that end has been passed on to the server

  Impl(const compensation::MoveCompensator& c, const IppProxyOptions& o)
      : options(o), logic(c, o.log) {
    client_in.reserve(2 * ipp::kMaxLineBytes + 4096);
    upstream_in.reserve(2 * ipp::kMaxLineBytes + 4096);
  }
  ~Impl() {
    end_session(nullptr);
    if (listen_fd >= 0) ::close(listen_fd);
    for (int w : wake) {
      if (w >= 0) ::close(w);
    }
  }

  void log(const std::string& s) const {
    if (options.log) options.log(s);
  }

  void listen() {
    const ipp::net::Listener l =
        ipp::net::listen_tcp(options.listen_host, options.listen_port, "I++ proxy");
    listen_fd = l.fd;
    port = l.port;
    if (::pipe2(wake, O_NONBLOCK | O_CLOEXEC) != 0) {
      throw Error("I++ proxy: pipe: " + std::string(std::strerror(errno)));
    }
  }

  /// Connects to the upstream server within the timeout; -1 when it cannot.
  int connect_upstream(std::string& why) const {
    sockaddr_in a{};
    try {
      a = ipp::net::resolve(options.upstream_host, options.upstream_port, "I++ proxy");
    } catch (const Error& e) {
      why = e.what();
      return -1;
    }
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (fd < 0) {
      why = std::strerror(errno);
      return -1;
    }
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
      if (errno != EINPROGRESS) {
        why = std::strerror(errno);
        ::close(fd);
        return -1;
      }
      pollfd p{fd, POLLOUT, 0};
      const auto deadline =
          Clock::now() +
          std::chrono::microseconds(static_cast<long long>(options.connect_timeout_s * 1e6));
      int r = 0;
      do {
        r = ::poll(&p, 1, ms_until(deadline));
      } while (r < 0 && errno == EINTR);
      int error = 0;
      socklen_t len = sizeof error;
      ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &len);
      if (r <= 0 || error != 0) {
        why = r == 0 ? "timed out" : std::strerror(error != 0 ? error : errno);
        ::close(fd);
        return -1;
      }
    }
    no_delay(fd);
    return fd;
  }

  /// Ends the client's session. A client that closed its connection ends the upstream one the
  /// same way (what it sent is still delivered); one the proxy drops ends it with a reset, so the
  /// server drops at once what the client left queued (it moves nothing more for a client that
  /// is gone) and is free for the next session.
  void end_session(const char* why, bool client_closed = false) {
    if (client >= 0) {
      ::close(client);
      if (why != nullptr) log(std::string("client dropped: ") + why);
    }
    if (upstream >= 0) {
      if (!client_closed) {
        const linger reset{1, 0};
        ::setsockopt(upstream, SOL_SOCKET, SO_LINGER, &reset, sizeof reset);
      }
      ::close(upstream);
    }
    client = upstream = -1;
    client_in.clear();
    upstream_in.clear();
    upstream_passthrough = false;
    to_client.bytes.clear();
    to_upstream.bytes.clear();
    closing = false;
    client_done = false;
    upstream_shut = false;
  }

  static void refuse(int fd, const char* detail) {
    const std::string line =
        ipp::error_line("E0000", ipp::ErrorCode::kBadContext, "", detail) + "\r\n";
    const ssize_t ignored = ::send(fd, line.data(), line.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    (void)ignored;
    ::close(fd);
  }

  void accept_client() {
    const int c = ::accept4(listen_fd, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
    if (c < 0) return;
    if (client >= 0) {
      // A client that has just left is no longer the session (its end may wait behind this
      // connection in the same poll round).
      pollfd q{client, POLLRDHUP, 0};
      if (::poll(&q, 1, 0) > 0 && (q.revents & (POLLRDHUP | POLLHUP | POLLERR))) {
        end_session("it closed the connection", true);
      }
    }
    if (client >= 0) {
      refuse(c, "another client session is active");
      log("second connection refused");
      return;
    }
    std::string why;
    const int u = connect_upstream(why);
    if (u < 0) {
      const std::string detail = "the proxy cannot reach its I++ server " + options.upstream_host +
                                 ":" + std::to_string(options.upstream_port) + ": " + why;
      refuse(c, detail.c_str());
      log(detail);
      return;
    }
    no_delay(c);
    client = c;
    upstream = u;
    logic.reset();
    log("client connected");
  }

  void read_client() {
    char buffer[4096];
    const ssize_t n = ::recv(client, buffer, sizeof buffer, 0);
    if (n == 0 && !client_done) {
      // The client has sent everything (a half-close, as `… | socat` does): its last bytes and
      // the end go upstream, and the server's answers still come back, as without the proxy.
      if (!client_in.empty()) to_upstream.add(client_in);
      client_in.clear();
      client_done = true;
      return;
    }
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
      end_session(n == 0 ? "it closed the connection" : "receive error", n == 0);
      return;
    }
    if (n < 0) return;
    std::size_t start = 0;
    for (ssize_t i = 0; i < n; ++i) {
      if (buffer[i] != '\n') continue;
      client_in.append(buffer + start, static_cast<std::size_t>(i) - start);
      start = static_cast<std::size_t>(i) + 1;
      logic.from_client(client_in);
      to_upstream.add(client_in);
      to_upstream.add("\n");
      client_in.clear();
    }
    client_in.append(buffer + start, static_cast<std::size_t>(n) - start);
    if (client_in.size() > ipp::kMaxLineBytes + 1) {
      // As the server treats it: an error under the server's tag, then the connection closes.
      to_client.add(ipp::error_line("E0000",
                                    ipp::ErrorCode::kProtocolError,
                                    client_in.substr(0, 40),
                                    "a line longer than 1024 bytes: closing the connection"));
      to_client.add("\r\n");
      closing = true;
      client_in.clear();
    }
  }

  void read_upstream() {
    char buffer[4096];
    const ssize_t n = ::recv(upstream, buffer, sizeof buffer, 0);
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
      // The server ended the session: what it sent still goes to the client, then it closes.
      if (!upstream_in.empty()) to_client.add(upstream_in);
      upstream_in.clear();
      ::close(upstream);
      upstream = -1;
      closing = true;
      log("the I++ server closed the connection");
      return;
    }
    if (n < 0) return;
    std::size_t start = 0;
    for (ssize_t i = 0; i < n; ++i) {
      if (buffer[i] != '\n') continue;
      const std::string_view piece(buffer + start, static_cast<std::size_t>(i) - start);
      start = static_cast<std::size_t>(i) + 1;
      if (upstream_passthrough) {
        to_client.add(piece);
        upstream_passthrough = false;
      } else {
        upstream_in.append(piece);
        to_client.add(logic.from_server(upstream_in));
      }
      to_client.add("\n");
      upstream_in.clear();
    }
    const std::string_view rest(buffer + start, static_cast<std::size_t>(n) - start);
    if (upstream_passthrough) {
      to_client.add(rest);
    } else {
      upstream_in.append(rest);
      if (upstream_in.size() > ipp::kMaxLineBytes + 1) {
        // No I++ line is this long: passed on as it is, without a look.
        to_client.add(upstream_in);
        upstream_in.clear();
        upstream_passthrough = true;
      }
    }
  }

  void run() {
    bool stop = false;
    while (!stop) {
      if (client >= 0 && to_client.bytes.size() > options.max_buffered_bytes) {
        end_session("it does not read its answers");
        continue;
      }
      if (client >= 0 && closing && to_client.bytes.empty()) {
        end_session(upstream < 0 ? "the I++ server closed" : "protocol error");
        continue;
      }
      pollfd p[4] = {{wake[0], POLLIN, 0}, {listen_fd, POLLIN, 0}, {-1, 0, 0}, {-1, 0, 0}};
      int timeout = -1;
      if (client >= 0) {
        // The client is not read while the upstream does not take its lines (bounded).
        const bool take =
            !closing && !client_done && to_upstream.bytes.size() < options.max_buffered_bytes;
        p[2] = {client,
                static_cast<short>((take ? POLLIN : 0) | (to_client.bytes.empty() ? 0 : POLLOUT)),
                0};
        if (!to_client.bytes.empty()) {
          timeout = ms_until(
              to_client.waiting_since +
              std::chrono::microseconds(static_cast<long long>(options.send_timeout_s * 1e6)));
          if (timeout == 0) {
            end_session("nothing could be sent to it for the send timeout");
            continue;
          }
        }
      }
      if (upstream >= 0) {
        p[3] = {
            upstream, static_cast<short>(POLLIN | (to_upstream.bytes.empty() ? 0 : POLLOUT)), 0};
      }
      const int r = ::poll(p, 4, timeout);
      if (r < 0) {
        if (errno == EINTR) continue;
        throw Error("I++ proxy: poll: " + std::string(std::strerror(errno)));
      }
      if (p[0].revents & POLLIN) {
        char drain[64];
        while (::read(wake[0], drain, sizeof drain) > 0) {
        }
        stop = true;
      }
      if (p[1].revents & POLLIN) accept_client();
      if (upstream >= 0 && p[3].fd == upstream) {
        if (p[3].revents & POLLOUT) {
          if (!to_upstream.flush(upstream)) {
            end_session("send error to the I++ server");
            continue;
          }
        }
        if (p[3].revents & (POLLIN | POLLHUP | POLLERR)) read_upstream();
      }
      if (client >= 0 && p[2].fd == client) {
        if (p[2].revents & (POLLERR | POLLNVAL)) {
          end_session("connection error");
          continue;
        }
        if (p[2].revents & POLLOUT) {
          if (!to_client.flush(client)) {
            end_session("send error");
            continue;
          }
        }
        if (client >= 0 && (p[2].revents & (POLLIN | POLLHUP))) read_client();
      }
      if (client >= 0 && upstream >= 0 && !to_upstream.bytes.empty()) {
        if (!to_upstream.flush(upstream)) end_session("send error to the I++ server");
      }
      if (client_done && !upstream_shut && upstream >= 0 && to_upstream.bytes.empty()) {
        ::shutdown(upstream, SHUT_WR);  // the client's end, passed on
        upstream_shut = true;
      }
      if (client >= 0 && !to_client.bytes.empty()) {
        if (!to_client.flush(client)) end_session("send error");
      }
    }
    end_session("the proxy stops");
  }
};

IppProxy::IppProxy(const compensation::MoveCompensator& compensator, const IppProxyOptions& options)
    : impl_(std::make_unique<Impl>(compensator, options)) {
  impl_->listen();
}
IppProxy::~IppProxy() = default;
std::uint16_t IppProxy::port() const noexcept { return impl_->port; }
void IppProxy::run() { impl_->run(); }
void IppProxy::request_stop() noexcept {
  const char c = 's';
  const ssize_t ignored = ::write(impl_->wake[1], &c, 1);
  (void)ignored;
}
IppProxyCounters IppProxy::counters() const noexcept { return impl_->logic.counters(); }

void parse_host_port(const std::string& text,
                     const char* what,
                     std::string& host,
                     std::uint16_t& port) {
  const std::size_t colon = text.rfind(':');
  const std::string digits = colon == std::string::npos ? "" : text.substr(colon + 1);
  const bool all_digits =
      !digits.empty() && digits.size() <= 5 &&
      std::all_of(digits.begin(), digits.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
  if (colon == 0 || colon == std::string::npos || !all_digits || std::stol(digits) > 65535) {
    throw ConfigError(std::string(what) + ": '" + text + "' is not HOST:PORT");
  }
  host = text.substr(0, colon);
  port = static_cast<std::uint16_t>(std::stol(digits));
}

}  // namespace cmmcomp::serving

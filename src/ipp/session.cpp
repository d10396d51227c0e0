// SPDX-License-Identifier: MIT
/// @file The I++ DME session logic (session.hpp).
#include <algorithm>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/ipp_number.hpp>
#include <cmmcomp/ipp/line.hpp>
#include <cmmcomp/ipp/session.hpp>
#include <cmmcomp/motion/move_profile.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <cstring>

namespace cmmcomp::ipp {

namespace {

/// I++ DME commands of the specification this server does not implement (0501, not 0507).
constexpr const char* kKnownUnsupported[] = {
    "AlignPart",
    "AlignTool",
    "CenterPart",
    "EnumAllProp",
    "EnumProp",
    "EnumTools",
    "FindTool",
    "GetChangeToolAction",
    "GetCoordSystem",
    "GetCsyTransformation",
    "GetDMEVersion",
    "GetErrorInfo",
    "GetMachineClass",
    "GetXtdErrStatus",
    "LockAxis",
    "OnMoveReportE",
    "OnScanReport",
    "ReQualify",
    "ScanInCylEndIsPlane",
    "ScanInCylEndIsSphere",
    "ScanInPlaneEndIsCyl",
    "ScanInPlaneEndIsPlane",
    "ScanOnCircle",
    "ScanOnCircleHint",
    "ScanOnLine",
    "ScanOnLineHint",
    "ScanUnknownHint",
    "SetCoordSystem",
    "SetCsyTransformation",
    "TiltCenterPart",
    "TiltPart",
    "GetPosE",
    "ScanOnCurve",
    "ScanOnHelix",
};

enum class Kind {
  kStartSession,
  kEndSession,
  kClearAllErrors,
  kHome,
  kIsHomed,
  kEnableUser,
  kDisableUser,
  kIsUserEnabled,
  kGetProp,
  kGetPropE,
  kSetProp,
  kGoTo,
  kPtMeas,
  kOnPtMeasReport,
  kGet,
  kGetErrStatusE,
  kAbortE,
  kStopDaemon,
  kStopAllDaemons,
  kGetSupportedCommands,
  kSetTool,
  kChangeTool,
};

bool is_fast(Kind k) {
  return k == Kind::kGetPropE || k == Kind::kGetErrStatusE || k == Kind::kAbortE;
}

enum class Facet { kAct, kMax, kMin, kDef };
constexpr const char* kFacetNames[] = {"", ".Max", ".Min", ".Def"};

struct PropertyQuery {
  Property property;
  Facet facet;
  bool act_named = false;  ///< `.Act()` was written (the answer names it the same way)
};

/// An accepted command with its arguments read.
struct Command {
  Kind kind = Kind::kStartSession;
  std::string tag;
  std::string cause;  ///< the line, for error answers
  std::vector<PropertyQuery> queries;
  std::vector<std::pair<Property, double>> settings;
  bool has[3] = {false, false, false};
  double xyz[3] = {0, 0, 0};
  Point3 ijk;
  std::vector<std::string> report;  ///< OnPtMeasReport / Get: X, Y, Z, IJK in order
};

/// A refusal at receipt.
struct Refusal {
  ErrorCode code;
  std::string detail;
};

std::string_view name_of(const Item& it) { return it.text; }

}  // namespace

double default_property(Property p, const motion::ControllerCapabilities& caps) noexcept {
  constexpr paper::BaselineMove kB = paper::kBaseline;
  double v = 0;
  switch (p) {
    case Property::kGoToSpeed:
      v = kB.pv_mm_s;
      break;
    case Property::kGoToAccel:
      v = kB.pa_mm_s2;
      break;
    case Property::kPtMeasSpeed:
      v = kB.av_mm_s;
      break;
    case Property::kPtMeasAccel:
      v = kB.aa_mm_s2;
      break;
    case Property::kPtMeasApproach:
      v = kB.ad_mm;
      break;
    case Property::kPtMeasSearch:
      return 2.0;
    case Property::kPtMeasRetract:
      return 1.0;
  }
  const motion::SettingRange r = property_range(p, caps);
  return std::min(std::max(v, r.min), r.max);
}

motion::SettingRange property_range(Property p,
                                    const motion::ControllerCapabilities& caps) noexcept {
  const PropertyInfo& info = property_info(p);
  if (!info.has_setting) return {0.0, motion::MoveLimits::kMaxDistance * 1e3};
  const motion::SettingRange si = caps[info.setting];
  const double k = 1.0 / motion::setting_info(info.setting).to_si;
  return {si.min * k, si.max * k};
}

struct Session::Impl {
  Machine& machine;
  SessionOptions options;
  motion::ControllerCapabilities caps;
  bool started = false;
  bool error = false;
  bool homed = false;
  bool user_enabled = false;
  std::vector<std::string> report{"X", "Y", "Z"};
  ProbingMoveTracker tracker;
  std::uint64_t points = 0;
  std::deque<Command> queue;
  // The running command (between start_next and finish).
  bool running = false;
  bool aborted = false;
  std::string running_tag;
  ProbingMoveTracker before_running;
  std::uint64_t points_before_running = 0;

  Impl(Machine& m, const SessionOptions& o) : machine(m), options(o), caps(m.capabilities()) {
    for (const PropertyInfo& info : kProperties) {
      tracker.set_property(info.property, default_property(info.property, caps));
    }
    tracker.position_is({0, 0, 0});
  }

  bool tag_in_use(std::string_view tag) const {
    if (running && running_tag == tag) return true;
    return std::any_of(queue.begin(), queue.end(), [&](const Command& c) { return c.tag == tag; });
  }

  bool in_volume(const double* xyz, const bool* has) const {
    const Point3 lo = machine.volume_min(), hi = machine.volume_max();
    const double l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z};
    for (int i = 0; i < 3; ++i) {
      if (has[i] && !(xyz[i] >= l[i] && xyz[i] <= h[i])) return false;
    }
    return true;
  }

  // ---- reading arguments ----

  /// Each argument a call with no arguments from `allowed` (each once), into `out`.
  static bool empty_calls(const ItemList& args,
                          std::initializer_list<const char*> allowed,
                          std::vector<std::string>& out,
                          Refusal& why) {
    for (int i = args.first(); i >= 0; i = args[i].next_sibling) {
      const Item& it = args[i];
      if (it.kind != Item::Kind::kCall || it.first_child >= 0) {
        why = {ErrorCode::kIncorrectArguments, "each argument is NAME()"};
        return false;
      }
      const std::string name(name_of(it));
      if (std::find(out.begin(), out.end(), name) != out.end()) {
        why = {ErrorCode::kIncorrectArguments, name + " given twice"};
        return false;
      }
      bool ok = false;
      for (const char* a : allowed) ok = ok || name == a;
      if (!ok) {
        const bool spec = name == "R" || name == "ER" || name == "IJK" || name == "Q" ||
                          name.rfind("Tool.", 0) == 0;
        why = {spec ? ErrorCode::kArgumentNotSupported : ErrorCode::kIncorrectArguments,
               name + "() is not supported here"};
        return false;
      }
      out.push_back(name);
    }
    if (out.empty()) {
      why = {ErrorCode::kIncorrectArguments, "no argument"};
      return false;
    }
    return true;
  }

  /// X(v), Y(v), Z(v) (each once) and, with `ijk`, IJK(i, j, k).
  static bool coordinates(const ItemList& args, Command& c, bool ijk, bool& has_ijk, Refusal& why) {
    has_ijk = false;
    for (int i = args.first(); i >= 0; i = args[i].next_sibling) {
      const Item& it = args[i];
      const std::string_view name = name_of(it);
      if (it.kind != Item::Kind::kCall) {
        why = {ErrorCode::kIncorrectArguments, "each argument is NAME(value)"};
        return false;
      }
      if (name == "X" || name == "Y" || name == "Z") {
        const int axis = name[0] - 'X';
        const int child = it.first_child;
        if (child < 0 || args[child].kind != Item::Kind::kNumber || args[child].next_sibling >= 0) {
          why = {ErrorCode::kBadArgument, std::string(name) + " is not followed by a number"};
          return false;
        }
        if (c.has[axis]) {
          why = {ErrorCode::kIncorrectArguments, std::string(name) + " given twice"};
          return false;
        }
        c.has[axis] = true;
        c.xyz[axis] = args[child].number;
      } else if (ijk && name == "IJK") {
        double v[3];
        int n = 0;
        for (int k = it.first_child; k >= 0; k = args[k].next_sibling) {
          if (args[k].kind != Item::Kind::kNumber || n == 3) {
            n = 4;
            break;
          }
          v[n++] = args[k].number;
        }
        if (n != 3 || has_ijk) {
          why = {ErrorCode::kIncorrectArguments, "IJK takes three numbers, once"};
          return false;
        }
        has_ijk = true;
        c.ijk = {v[0], v[1], v[2]};
      } else if (name.substr(0, 5) == "Tool." || name == "R" || name == "ER") {
        why = {ErrorCode::kArgumentNotSupported, std::string(name) + " (no rotary axes, no ER)"};
        return false;
      } else {
        why = {ErrorCode::kIncorrectArguments, std::string(name) + " is not an argument here"};
        return false;
      }
    }
    return true;
  }

  /// The property and facet of a dotted name; false: 0510.
  static bool property_of(std::string_view name, PropertyQuery& q) {
    q.facet = Facet::kAct;
    for (int f = 1; f <= 3; ++f) {
      const std::string_view suffix = kFacetNames[f];
      if (name.size() > suffix.size() && name.substr(name.size() - suffix.size()) == suffix) {
        q.facet = static_cast<Facet>(f);
        name.remove_suffix(suffix.size());
        break;
      }
    }
    if (q.facet == Facet::kAct && name.size() > 4 && name.substr(name.size() - 4) == ".Act") {
      name.remove_suffix(4);
      q.act_named = true;
    }
    return find_property(name.data(), name.size(), q.property);
  }

  bool read_arguments(Kind kind, const CommandLine& line, Command& c, Refusal& why) const {
    const ItemList& args = line.args;
    const int n = args.count_from(args.first());
    switch (kind) {
      case Kind::kStartSession:
      case Kind::kEndSession:
      case Kind::kClearAllErrors:
      case Kind::kHome:
      case Kind::kIsHomed:
      case Kind::kEnableUser:
      case Kind::kDisableUser:
      case Kind::kIsUserEnabled:
      case Kind::kGetErrStatusE:
      case Kind::kAbortE:
      case Kind::kStopAllDaemons:
      case Kind::kGetSupportedCommands:
        if (n != 0) {
          why = {ErrorCode::kIncorrectArguments, "takes no arguments"};
          return false;
        }
        return true;
      case Kind::kGetProp:
      case Kind::kGetPropE:
        if (n == 0) {
          why = {ErrorCode::kIncorrectArguments, "no property"};
          return false;
        }
        for (int i = args.first(); i >= 0; i = args[i].next_sibling) {
          const Item& it = args[i];
          if (it.kind != Item::Kind::kCall || it.first_child >= 0) {
            why = {ErrorCode::kIncorrectArguments, "each property is NAME()"};
            return false;
          }
          PropertyQuery q{};
          if (!property_of(it.text, q)) {
            why = {ErrorCode::kBadProperty, std::string(it.text) + " is not a property here"};
            return false;
          }
          c.queries.push_back(q);
        }
        return true;
      case Kind::kSetProp:
        if (n == 0) {
          why = {ErrorCode::kIncorrectArguments, "no property"};
          return false;
        }
        for (int i = args.first(); i >= 0; i = args[i].next_sibling) {
          const Item& it = args[i];
          const int child = it.first_child;
          if (it.kind != Item::Kind::kCall || child < 0 ||
              args[child].kind != Item::Kind::kNumber || args[child].next_sibling >= 0) {
            why = {ErrorCode::kIncorrectArguments, "each property is NAME(number)"};
            return false;
          }
          PropertyQuery q{};
          if (!property_of(it.text, q)) {
            why = {ErrorCode::kBadProperty, std::string(it.text) + " is not a property here"};
            return false;
          }
          if (q.facet != Facet::kAct) {
            why = {ErrorCode::kBadProperty, std::string(it.text) + " cannot be set"};
            return false;
          }
          const double v = args[child].number;
          const motion::SettingRange r = property_range(q.property, caps);
          if (!r.contains(v)) {
            const PropertyInfo& info = property_info(q.property);
            why = {ErrorCode::kArgumentOutOfRange,
                   std::string(info.name) + " " + io::format_ipp_number(v) + " " + info.unit +
                       " is outside " + io::format_ipp_number(r.min) + " .. " +
                       io::format_ipp_number(r.max) + " " + info.unit};
            return false;
          }
          c.settings.emplace_back(q.property, v);
        }
        return true;
      case Kind::kGoTo: {
        bool has_ijk = false;
        if (!coordinates(args, c, false, has_ijk, why)) return false;
        if (!c.has[0] && !c.has[1] && !c.has[2]) {
          why = {ErrorCode::kIncorrectArguments, "no X, Y or Z"};
          return false;
        }
        if (!in_volume(c.xyz, c.has)) {
          why = {ErrorCode::kTargetOutOfVolume, "the target is outside the working volume"};
          return false;
        }
        return true;
      }
      case Kind::kPtMeas: {
        bool has_ijk = false;
        if (!coordinates(args, c, true, has_ijk, why)) return false;
        if (!c.has[0] || !c.has[1] || !c.has[2] || !has_ijk) {
          why = {ErrorCode::kIncorrectArguments, "needs X(), Y(), Z() and IJK()"};
          return false;
        }
        if (!(norm(c.ijk) > 1e-9)) {
          why = {ErrorCode::kVectorHasNoNorm, "IJK"};
          return false;
        }
        if (!in_volume(c.xyz, c.has)) {
          why = {ErrorCode::kTargetOutOfVolume, "the nominal point is outside the working volume"};
          return false;
        }
        return true;
      }
      case Kind::kOnPtMeasReport:
        return empty_calls(args, {"X", "Y", "Z", "IJK", "R"}, c.report, why);
      case Kind::kSetTool:
      case Kind::kChangeTool:
        if (n != 1) {
          why = {ErrorCode::kIncorrectArguments, "takes one tool name"};
          return false;
        }
        if (args[args.first()].kind != Item::Kind::kString) {
          why = {ErrorCode::kBadArgument, "the tool name is a string"};
          return false;
        }
        return true;
      case Kind::kGet:
        return empty_calls(args, {"X", "Y", "Z"}, c.report, why);
      case Kind::kStopDaemon: {
        Tag t;
        if (n != 1 || args[args.first()].kind != Item::Kind::kName ||
            parse_tag(args[args.first()].text, t) != ParseStatus::kOk || !t.is_event()) {
          why = {ErrorCode::kIncorrectArguments, "takes one event tag (E and four digits)"};
          return false;
        }
        return true;
      }
    }
    return false;
  }

  static bool kind_of(std::string_view name, Kind& k) {
    for (int i = 0; i < kSupportedCommandCount; ++i) {
      if (name == kSupportedCommands[i]) {
        k = static_cast<Kind>(i);
        return true;
      }
    }
    return false;
  }

  // ---- receipt ----

  void receive(std::string_view line, std::vector<std::string>& out) {
    CommandLine parsed;
    const ParseStatus st = parse_command(line, parsed);
    if (st == ParseStatus::kEmpty) return;  // a blank line between commands is no command
    std::string_view cause = line;
    if (!cause.empty() && cause.back() == '\r') cause.remove_suffix(1);
    if (st == ParseStatus::kBadTag || st == ParseStatus::kTooLong ||
        st == ParseStatus::kIllegalCharacter) {
      out.push_back(error_line("E0000", error_for(st), cause, to_string(st)));
      return;
    }
    const std::string tag(parsed.tag.view());
    if (st != ParseStatus::kOk) {
      out.push_back(error_line(tag, error_for(st), cause, to_string(st)));
      return;
    }
    if (parsed.tag.is_reserved()) {
      out.push_back(
          error_line(tag, ErrorCode::kIllegalTag, cause, "00000 and E0000 are the server's"));
      return;
    }
    Kind kind{};
    if (!kind_of(parsed.name, kind)) {
      bool spec = false;
      for (const char* n : kKnownUnsupported) spec = spec || parsed.name == n;
      out.push_back(error_line(tag,
                               spec ? ErrorCode::kUnsupportedCommand : ErrorCode::kIllegalCommand,
                               cause,
                               std::string(parsed.name)));
      return;
    }
    if (is_fast(kind) != parsed.tag.is_event()) {
      out.push_back(error_line(tag,
                               ErrorCode::kIllegalTag,
                               cause,
                               is_fast(kind) ? "a fast-queue command needs an E tag"
                                             : "an E tag is for fast-queue commands"));
      return;
    }
    if (tag_in_use(tag)) {
      out.push_back(error_line(tag, ErrorCode::kIllegalTag, cause, "the tag is in use"));
      return;
    }
    Command c;
    c.kind = kind;
    c.tag = tag;
    c.cause = std::string(cause);
    Refusal why{ErrorCode::kProtocolError, ""};
    if (!read_arguments(kind, parsed, c, why)) {
      out.push_back(error_line(tag, why.code, cause, std::string(parsed.name) + ": " + why.detail));
      return;
    }
    if (kind == Kind::kStartSession ? started : !started) {
      out.push_back(error_line(tag,
                               ErrorCode::kBadContext,
                               cause,
                               started ? "a session is open" : "no session: StartSession first"));
      return;
    }
    if (error && !is_fast(kind) && kind != Kind::kClearAllErrors && kind != Kind::kEndSession) {
      out.push_back(error_line(tag, ErrorCode::kUseClearAllErrors, cause));
      return;
    }
    if (!is_fast(kind) && queue.size() >= options.max_queued) {
      out.push_back(error_line(tag, ErrorCode::kBufferFull, cause, "too many commands waiting"));
      return;
    }
    out.push_back(ack_line(tag));
    if (kind == Kind::kStartSession) started = true;
    if (kind == Kind::kEndSession) started = false;
    if (is_fast(kind)) {
      run_fast(c, out);
    } else {
      queue.push_back(std::move(c));
    }
  }

  void run_fast(const Command& c, std::vector<std::string>& out) {
    switch (c.kind) {
      case Kind::kGetErrStatusE:
        out.push_back(data_line(c.tag, error ? "ErrStatus(1)" : "ErrStatus(0)"));
        break;
      case Kind::kGetPropE:
        out.push_back(data_line(c.tag, property_data(c.queries)));
        break;
      case Kind::kAbortE:
        for (const Command& q : queue) {
          out.push_back(error_line(q.tag, ErrorCode::kTransactionAborted, q.cause));
          out.push_back(done_line(q.tag));
        }
        queue.clear();
        if (running) aborted = true;
        error = true;
        break;
      default:
        break;
    }
    out.push_back(done_line(c.tag));
  }

  std::string property_data(const std::vector<PropertyQuery>& queries) const {
    std::string s;
    for (const PropertyQuery& q : queries) {
      const PropertyInfo& info = property_info(q.property);
      const motion::SettingRange r = property_range(q.property, caps);
      const double v = q.facet == Facet::kMax   ? r.max
                       : q.facet == Facet::kMin ? r.min
                       : q.facet == Facet::kDef ? default_property(q.property, caps)
                                                : tracker.property(q.property);
      if (!s.empty()) s += ", ";
      s += number_item(
          std::string(info.name) + (q.act_named ? ".Act" : kFacetNames[static_cast<int>(q.facet)]),
          v);
    }
    return s;
  }

  // ---- running ----

  double goto_seconds(double distance_mm) const {
    if (!(distance_mm > motion::MoveLimits::kMinDistance * 1e3)) return 0.0;
    const motion::ProbingMove m =
        motion::probing_move_mm(tracker.property(Property::kGoToSpeed),
                                tracker.property(Property::kGoToAccel),
                                std::min(distance_mm, motion::MoveLimits::kMaxDistance * 1e3),
                                tracker.property(Property::kPtMeasSpeed),
                                tracker.property(Property::kPtMeasAccel),
                                tracker.property(Property::kPtMeasApproach));
    motion::MoveProfile profile;
    if (!ok(motion::MoveProfile::plan(m, profile))) return 0.0;
    return profile.instants().positioning_end;
  }

  Executed start_next() {
    Command c = std::move(queue.front());
    queue.pop_front();
    running = true;
    aborted = false;
    running_tag = c.tag;
    before_running = tracker;
    points_before_running = points;
    Executed e;
    e.tag = c.tag;
    std::vector<std::string>& out = e.answers;
    if (error && c.kind != Kind::kClearAllErrors && c.kind != Kind::kEndSession) {
      out.push_back(error_line(c.tag, ErrorCode::kUseClearAllErrors, c.cause));
      out.push_back(done_line(c.tag));
      return e;
    }
    Point3 here{0, 0, 0};
    tracker.position(here);
    switch (c.kind) {
      case Kind::kStartSession:
      case Kind::kEndSession:
      case Kind::kStopAllDaemons:
      case Kind::kSetTool:     // one probe: every tool name is it
      case Kind::kChangeTool:  // and changing to it takes no time
        break;
      case Kind::kClearAllErrors:
        error = false;
        break;
      case Kind::kHome:
        homed = true;
        tracker.position_is({0, 0, 0});
        break;
      case Kind::kIsHomed:
        out.push_back(data_line(c.tag, homed ? "IsHomed(1)" : "IsHomed(0)"));
        break;
      case Kind::kEnableUser:
        user_enabled = true;
        break;
      case Kind::kDisableUser:
        user_enabled = false;
        break;
      case Kind::kIsUserEnabled:
        out.push_back(data_line(c.tag, user_enabled ? "IsUserEnabled(1)" : "IsUserEnabled(0)"));
        break;
      case Kind::kGetProp:
        out.push_back(data_line(c.tag, property_data(c.queries)));
        break;
      case Kind::kSetProp:
        for (const auto& [p, v] : c.settings) tracker.set_property(p, v);
        break;
      case Kind::kGoTo: {
        const Point3 target{c.has[0] ? c.xyz[0] : here.x,
                            c.has[1] ? c.xyz[1] : here.y,
                            c.has[2] ? c.xyz[2] : here.z};
        e.seconds = goto_seconds(norm(target - here));
        tracker.moved_to(target);
        break;
      }
      case Kind::kPtMeas: {
        const Point3 nominal{c.xyz[0], c.xyz[1], c.xyz[2]};
        const ReconstructedMove move = tracker.probing_move(nominal, c.ijk);
        Touch touch;
        if (move.ok) {
          touch = machine.probe(move, points);
        } else {
          touch.problem = move.problem;
        }
        if (!touch.ok) {
          error = true;
          out.push_back(
              error_line(c.tag, ErrorCode::kErrorProcessingMethod, c.cause, touch.problem));
          break;  // `%` ends every accepted command, errors before it
        }
        ++points;
        const double s = touch.rae_um * 1e-3;
        const Point3 reported = nominal - s * move.direction;
        const Point3 n = -1.0 * move.direction;
        std::string data;
        for (const std::string& item : report) {
          if (!data.empty()) data += ", ";
          if (item == "X") data += number_item("X", reported.x);
          if (item == "Y") data += number_item("Y", reported.y);
          if (item == "Z") data += number_item("Z", reported.z);
          if (item == "R") data += "R(0)";  // the twin's probe is a point
          if (item == "IJK") {
            data += "IJK(" + io::format_ipp_number(n.x) + ", " + io::format_ipp_number(n.y) + ", " +
                    io::format_ipp_number(n.z) + ")";
          }
        }
        out.push_back(data_line(c.tag, data));
        e.seconds = touch.seconds;
        tracker.probed(move);
        break;
      }
      case Kind::kOnPtMeasReport:
        report = c.report;
        break;
      case Kind::kGet: {
        std::string data;
        for (const std::string& item : c.report) {
          if (!data.empty()) data += ", ";
          data += number_item(item, item == "X" ? here.x : item == "Y" ? here.y : here.z);
        }
        out.push_back(data_line(c.tag, data));
        break;
      }
      case Kind::kStopDaemon:
        out.push_back(error_line(c.tag, ErrorCode::kDaemonDoesNotExist, c.cause));
        break;
      case Kind::kGetSupportedCommands:
        for (int i = 0; i < kSupportedCommandCount; ++i) {
          out.push_back(data_line(c.tag, kSupportedCommands[i]));
        }
        break;
      case Kind::kGetPropE:
      case Kind::kGetErrStatusE:
      case Kind::kAbortE:
        break;  // fast: never queued
    }
    out.push_back(done_line(c.tag));
    return e;
  }

  void finish(Executed executed, std::vector<std::string>& out) {
    running = false;
    if (aborted) {
      aborted = false;
      tracker = before_running;
      points = points_before_running;
      out.push_back(error_line(executed.tag, ErrorCode::kTransactionAborted, executed.tag));
      out.push_back(done_line(executed.tag));
      return;
    }
    for (std::string& line : executed.answers) out.push_back(std::move(line));
  }
};

Session::Session(Machine& machine, const SessionOptions& options)
    : impl_(std::make_unique<Impl>(machine, options)) {}
Session::~Session() = default;

void Session::receive(std::string_view line, std::vector<std::string>& out) {
  impl_->receive(line, out);
}
bool Session::has_work() const noexcept { return !impl_->queue.empty(); }
bool Session::running() const noexcept { return impl_->running; }
bool Session::aborted() const noexcept { return impl_->running && impl_->aborted; }
Executed Session::start_next() {
  if (impl_->queue.empty()) throw Error("ipp::Session::start_next: nothing waits");
  return impl_->start_next();
}
void Session::finish(Executed executed, std::vector<std::string>& out) {
  impl_->finish(std::move(executed), out);
}
void Session::disconnected() {
  impl_->queue.clear();
  impl_->started = false;
  impl_->running = false;
  impl_->aborted = false;
}
bool Session::started() const noexcept { return impl_->started; }
bool Session::in_error() const noexcept { return impl_->error; }
Point3 Session::position() const noexcept {
  Point3 p;
  impl_->tracker.position(p);
  return p;
}

}  // namespace cmmcomp::ipp

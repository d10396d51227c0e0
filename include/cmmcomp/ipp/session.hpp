// SPDX-License-Identifier: MIT
/// @file The I++ DME server's session logic, without sockets: command lines in, answer lines
/// out, over an abstract Machine that probes (docs/protocol-ippdme.md, "The subset").
///
/// Every line is answered:
///  - refused at receipt (no tag, bad syntax, unknown command, bad or out-of-range arguments, no
///    session, a tag in use, the server in its error state, the queue full): one `!` line and
///    nothing else; nothing changes;
///  - accepted: `&` at once; a fast-queue command (`E` tag: GetErrStatusE, GetPropE, AbortE)
///    then runs at once, a normal one joins the queue and runs in order (start_next/finish):
///    its `#` lines or its `!` lines, then always `%`. A PtMeas the machine could not run
///    (0511), a command AbortE ended (0006) or one that ran in the error state (0514) leave or
///    keep the server in its error state until ClearAllErrors. StopDaemon of a daemon that does
///    not exist answers `&`, `!` (0513) and `%`.
/// So a client's transaction ends at `%`, or at a `!` that came without `&`.
/// A line whose tag cannot be read is answered with the server's tag E0000.
/// Protocol state (StartSession, EndSession) changes at receipt; machine state (properties,
/// position, errors) when the command runs. Setup-level code: allocates; it throws only what the
/// Machine throws (the server ends the connection then).
#pragma once

#include <cmmcomp/ipp/move_rule.hpp>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace cmmcomp::ipp {

/// What a PtMeas got from the machine.
struct Touch {
  bool ok = false;
  /// The error at the touch along d [µm], the project's sign (docs/compensator.md): + = the tip
  /// ahead of the scale along d; the machine reports nominal − RAE · d.
  double rae_um = 0;
  double seconds = 0;   ///< the probing move's time from the positioning's start to the touch
  std::string problem;  ///< why not, when !ok
};

/// The machine a session drives.
class Machine {
 public:
  virtual ~Machine() = default;
  /// The range of each controller setting [SI]: the Min() and Max() of the properties.
  virtual motion::ControllerCapabilities capabilities() const = 0;
  /// The working volume's corners [mm]: a GoTo or PtMeas outside is refused (1008).
  virtual Point3 volume_min() const = 0;
  virtual Point3 volume_max() const = 0;
  /// Runs one probing move. `index` counts the session's points from 0 (a noise stream).
  virtual Touch probe(const ReconstructedMove& move, std::uint64_t index) = 0;
};

/// The defaults (Def()) of the properties [mm, mm/s, mm/s²]: the paper's baseline move, clamped
/// into the machine's ranges; Search 2 mm, Retract 1 mm (as cmmcomp-measure plan writes them).
double default_property(Property p, const motion::ControllerCapabilities& caps) noexcept;
/// The range (Min(), Max()) of a property [mm, mm/s, mm/s²]: its controller setting's
/// capability, or for Search and Retract 0 .. motion::MoveLimits::kMaxDistance.
motion::SettingRange property_range(Property p,
                                    const motion::ControllerCapabilities& caps) noexcept;

/// The commands of the subset, in GetSupportedCommands' order.
inline constexpr const char* kSupportedCommands[] = {
    "StartSession",  "EndSession",  "ClearAllErrors", "Home",           "IsHomed",
    "EnableUser",    "DisableUser", "IsUserEnabled",  "GetProp",        "GetPropE",
    "SetProp",       "GoTo",        "PtMeas",         "OnPtMeasReport", "Get",
    "GetErrStatusE", "AbortE",      "StopDaemon",     "StopAllDaemons", "GetSupportedCommands",
    "SetTool",       "ChangeTool",
};
inline constexpr int kSupportedCommandCount =
    static_cast<int>(sizeof(kSupportedCommands) / sizeof(kSupportedCommands[0]));

struct SessionOptions {
  std::size_t max_queued = 64;  ///< accepted normal commands waiting at most (more: 0000)
};

/// A normal command started: its answers, to go out after its machine time.
struct Executed {
  std::string tag;
  std::vector<std::string> answers;
  double seconds = 0;  ///< how long the machine moves [s] (0: no motion)
};

class Session {
 public:
  explicit Session(Machine& machine, const SessionOptions& options = {});
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  /// One line received (without its LF): appends the answers due now to `out`.
  void receive(std::string_view line, std::vector<std::string>& out);
  /// True when an accepted normal command waits to run.
  bool has_work() const noexcept;
  /// True between start_next() and finish().
  bool running() const noexcept;
  /// True when an AbortE came for the running command: finish() it now.
  bool aborted() const noexcept;
  /// Runs the next waiting command (has_work() must be true).
  Executed start_next();
  /// The running command's time passed: appends its answers, or when an AbortE came meanwhile
  /// its 0006 error (the machine then stays where the command started).
  void finish(Executed executed, std::vector<std::string>& out);
  /// The client left: the session ends as by EndSession; the waiting commands are dropped. The
  /// machine (position, homing, properties, error state) stays as it is.
  void disconnected();

  bool started() const noexcept;
  bool in_error() const noexcept;
  Point3 position() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cmmcomp::ipp

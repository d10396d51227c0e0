// SPDX-License-Identifier: MIT
/// @file A blocking I++ DME client: connect, send a command under an automatic tag, collect its
/// answers (docs/protocol-ippdme.md). Shared by the tests, the vc and the tools.
///
/// A transaction ends at its `%`, or at a `!` that came before any `&` (the command was
/// refused). Lines of other tags wait until asked for (`wait`); lines with the server's tag
/// E0000 (events, errors about no command) go to events(). Every wait is bounded by a timeout:
/// on it, or when the server closes, cmmcomp::Error. Setup-level code (allocates, throws).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace cmmcomp::ipp {

/// An `!` answer's fields.
struct ErrorReply {
  int severity = 0;
  int number = 0;
  std::string cause, text;
};

/// What one command got.
struct Transaction {
  std::string tag;
  bool acknowledged = false;       ///< `&` came
  bool done = false;               ///< `%` came
  std::vector<std::string> data;   ///< each `#` line's data
  std::vector<ErrorReply> errors;  ///< each `!` line
  std::vector<std::string> lines;  ///< every answer line, as received
  bool ok() const noexcept { return acknowledged && done && errors.empty(); }
};

class Client {
 public:
  /// Connects within `timeout_s`; throws cmmcomp::Error naming the address on failure.
  Client(const std::string& host, std::uint16_t port, double timeout_s = 5.0);
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  /// Sends `command` under the next tag (an E tag when the command's name ends in E) and returns
  /// the tag.
  std::string send(std::string_view command);
  /// Sends bytes as they are (a test's hostile line; add "\r\n" yourself).
  void send_raw(std::string_view bytes);
  /// The answers of `tag` until its transaction ends.
  Transaction wait(const std::string& tag, double timeout_s = 10.0);
  /// send + wait.
  Transaction call(std::string_view command, double timeout_s = 10.0);
  /// The next line with the server's tag E0000 (or one no tag could be read from).
  std::string wait_event(double timeout_s = 10.0);
  /// True when the server closed the connection within `timeout_s` (lines that came before are
  /// kept); false when it is still open.
  bool wait_closed(double timeout_s);

 private:
  /// Reads one line into the pending lines; false on timeout; throws when the server closed.
  bool read_more(double timeout_s);
  int fd_ = -1;
  int next_tag_ = 1;
  int next_event_tag_ = 1;
  bool closed_ = false;
  std::string rx_;
  std::map<std::string, std::vector<std::string>> pending_;
  std::vector<std::string> events_;
};

}  // namespace cmmcomp::ipp

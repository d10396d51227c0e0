// SPDX-License-Identifier: MIT
/// @file One I++ DME (ISO 22093) line: a command the client sends, or an answer the server
/// sends, parsed without allocation and without throwing; and the answer lines written.
///
/// Command: `TAG NAME(ARG, ARG, …)`, TAG five characters: `00001`…`99999` (the normal queue)
/// or `E` and four digits (`E0001`…`E9999`, the fast queue); `00000` and `E0000` are the
/// server's own (events) and refused from a client. The 6th character is a space. An argument
/// is a number (at most 16 characters: `12`, `-4.003E-01`, `+.197`), a string (`"RefTool"`, no
/// quote inside), a name (`E1234`, `Switch`, dotted: `Tool.GoToPar.Speed`) or a call: a name and
/// its own arguments in parentheses (`X(1)`, `IJK(0,0,1)`, `Tool.GoToPar.Speed.Max()`), nested
/// at most kMaxDepth deep. Spaces may surround every token.
/// Answer: `TAG &` (acknowledged), `TAG %` (done), `TAG # DATA` (data), `TAG ! Error(…)`.
///
/// Robustness (hostile input): a line longer than kMaxLineBytes, a byte below 0x20 or above
/// 0x7e (NUL included; one trailing CR is allowed), unbalanced parentheses, more than kMaxItems
/// arguments in all, a number longer than 16 characters or not finite: a ParseStatus, never an
/// exception, never a read outside the line. The views in the results point into the line the
/// caller passed and live as long as it.
#pragma once

#include <array>
#include <cmmcomp/ipp/error_codes.hpp>
#include <cstddef>
#include <string>
#include <string_view>

namespace cmmcomp::ipp {

/// The longest line accepted, without its CR LF [bytes].
inline constexpr std::size_t kMaxLineBytes = 1024;
/// The most arguments (at every depth together) one line may carry.
inline constexpr int kMaxItems = 64;
/// The deepest nesting of calls in an argument (`A(B(C(D())))` is 4).
inline constexpr int kMaxDepth = 4;
/// The most characters of a number (I++ DME parsers accept 16).
inline constexpr std::size_t kMaxNumberChars = 16;

/// What parsing a line found.
enum class ParseStatus {
  kOk = 0,
  kEmpty,             ///< nothing (or only a CR)
  kTooLong,           ///< longer than kMaxLineBytes
  kIllegalCharacter,  ///< a byte below 0x20 or above 0x7e
  kBadTag,            ///< the first five characters are no tag
  kNoSpace,           ///< the 6th character is not a space
  kNoCommand,         ///< no command name after the tag, or no answer mark
  kSyntax,            ///< arguments: unbalanced parentheses, a stray character, an empty argument
  kTooManyItems,      ///< more than kMaxItems arguments, or deeper than kMaxDepth
  kBadNumber,         ///< a number longer than kMaxNumberChars or not finite
};

/// Text for messages (a static string).
const char* to_string(ParseStatus s) noexcept;
/// The error a server answers a command line with when parsing it gave `s` (kOk: none; the
/// caller does not ask then).
ErrorCode error_for(ParseStatus s) noexcept;

/// A tag as sent.
struct Tag {
  enum class Queue { kNormal, kFast };
  Queue queue = Queue::kNormal;  ///< digits: the normal queue; `E`: the fast queue (events)
  int number = 0;                ///< 0..99999 (0 for `00000` and `E0000`, the server's)
  std::array<char, 6> text{};    ///< the five characters and a NUL

  std::string_view view() const noexcept { return {text.data(), 5}; }
  bool is_event() const noexcept { return queue == Queue::kFast; }
  /// `00000` and `E0000`: the server's tags (unsolicited errors, events), never a client's.
  bool is_reserved() const noexcept { return number == 0; }
};

/// Parses the five characters of a tag (kOk or kBadTag).
ParseStatus parse_tag(std::string_view five, Tag& out) noexcept;
/// The tag `number` of `queue` (number in 0..99999; 0..9999 for the fast queue).
Tag make_tag(Tag::Queue queue, int number) noexcept;

/// One argument.
struct Item {
  enum class Kind { kNumber, kString, kName, kCall };
  Kind kind = Kind::kName;
  std::string_view text;  ///< a number's text, a string without its quotes, a name or call name
  double number = 0.0;    ///< kNumber only
  int first_child = -1;   ///< kCall: its first argument's index in the list, -1 for none
  int next_sibling = -1;  ///< the next argument at the same level, -1 for none
};

/// The arguments of a line, as a tree in one fixed array (no allocation).
class ItemList {
 public:
  int size() const noexcept { return count_; }
  const Item& operator[](int i) const noexcept { return items_[static_cast<std::size_t>(i)]; }
  /// The index of the first top-level argument, -1 for none.
  int first() const noexcept { return first_; }
  /// The number of arguments starting at `first` and following siblings.
  int count_from(int first) const noexcept;

  /// Parses `text` (the inside of the outer parentheses) as arguments into this list.
  ParseStatus parse(std::string_view text) noexcept;

 private:
  friend class Parser;
  std::array<Item, kMaxItems> items_{};
  int count_ = 0;
  int first_ = -1;
};

/// A command line.
struct CommandLine {
  Tag tag;
  std::string_view name;  ///< `PtMeas`
  ItemList args;
};

/// Parses a command line (without LF; one trailing CR is ignored).
ParseStatus parse_command(std::string_view line, CommandLine& out) noexcept;

/// An answer line.
struct AnswerLine {
  enum class Kind { kAck, kDone, kData, kError };
  Tag tag;
  Kind kind = Kind::kAck;
  std::string_view data;  ///< after `# ` or `! ` (empty for `&`, `%`)
};
/// Parses an answer line (without LF; one trailing CR is ignored).
ParseStatus parse_answer(std::string_view line, AnswerLine& out) noexcept;

/// The four fields of an error answer's data `Error(severity, number, "cause", "text")`.
struct ErrorAnswer {
  int severity = 0;
  int number = 0;
  std::string_view cause, text;
};
/// Parses `Error(…)` (kSyntax when it is not one).
ParseStatus parse_error(std::string_view data, ErrorAnswer& out) noexcept;

// ---- writing (setup-level code: allocates) ----

/// `TAG &`, `TAG %` (no line end: the server adds CR LF).
std::string ack_line(std::string_view tag);
std::string done_line(std::string_view tag);
/// `TAG # DATA`.
std::string data_line(std::string_view tag, std::string_view data);
/// `TAG ! Error(severity, NNNN, "cause", "text[: detail]")`; a `"` or a byte outside 0x20..0x7e
/// in `cause` or `detail` becomes `'` or `?`, so the line always parses.
std::string error_line(std::string_view tag,
                       ErrorCode code,
                       std::string_view cause,
                       std::string_view detail = {});
/// `NAME(v)` with v as io::format_ipp_number writes it (throws ConfigError for a value that has
/// no I++ form).
std::string number_item(std::string_view name, double v);

}  // namespace cmmcomp::ipp

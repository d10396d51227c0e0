// SPDX-License-Identifier: MIT
/// @file The I++ DME line parser (no allocation, no exception) and the answer writers.
#include <cmath>
#include <cmmcomp/io/ipp_number.hpp>
#include <cmmcomp/ipp/line.hpp>
#include <cstdio>
#include <cstdlib>

namespace cmmcomp::ipp {
namespace {

bool is_digit(char c) noexcept { return c >= '0' && c <= '9'; }
bool is_alpha(char c) noexcept { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }
bool is_printable(char c) noexcept {
  const auto u = static_cast<unsigned char>(c);
  return u >= 0x20 && u <= 0x7e;
}

/// The line without one trailing CR, checked for length and characters.
ParseStatus clean(std::string_view& line) noexcept {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  if (line.size() > kMaxLineBytes) return ParseStatus::kTooLong;
  for (char c : line) {
    if (!is_printable(c)) return ParseStatus::kIllegalCharacter;
  }
  if (line.empty()) return ParseStatus::kEmpty;
  return ParseStatus::kOk;
}

}  // namespace

/// Recursive descent over one argument text into an ItemList.
class Parser {
 public:
  Parser(std::string_view text, ItemList& list) noexcept : s_(text), list_(list) {}

  /// args := [item {',' item}] up to `close` (')' or the end for the top level).
  ParseStatus arguments(int depth, int& first, bool top) noexcept {
    first = -1;
    int last = -1;
    skip();
    if (at_end_of_list(top)) return ParseStatus::kOk;
    for (;;) {
      int index = -1;
      const ParseStatus st = item(depth, index);
      if (st != ParseStatus::kOk) return st;
      if (last < 0) {
        first = index;
      } else {
        list_.items_[static_cast<std::size_t>(last)].next_sibling = index;
      }
      last = index;
      skip();
      if (at_end_of_list(top)) return ParseStatus::kOk;
      if (pos_ >= s_.size() || s_[pos_] != ',') return ParseStatus::kSyntax;
      ++pos_;
      skip();
    }
  }

  bool done() noexcept {
    skip();
    return pos_ == s_.size();
  }

 private:
  void skip() noexcept {
    while (pos_ < s_.size() && s_[pos_] == ' ') ++pos_;
  }
  bool at_end_of_list(bool top) const noexcept {
    return top ? pos_ == s_.size() : (pos_ < s_.size() && s_[pos_] == ')');
  }

  ParseStatus item(int depth, int& index) noexcept {
    if (list_.count_ >= kMaxItems || depth > kMaxDepth) return ParseStatus::kTooManyItems;
    index = list_.count_++;
    Item& it = list_.items_[static_cast<std::size_t>(index)];
    it = Item{};
    if (pos_ >= s_.size()) return ParseStatus::kSyntax;
    const char c = s_[pos_];
    if (c == '"') {
      const std::size_t start = ++pos_;
      while (pos_ < s_.size() && s_[pos_] != '"') ++pos_;
      if (pos_ >= s_.size()) return ParseStatus::kSyntax;
      it.kind = Item::Kind::kString;
      it.text = s_.substr(start, pos_ - start);
      ++pos_;
      return ParseStatus::kOk;
    }
    if (is_digit(c) || c == '+' || c == '-' || c == '.') return number(it);
    if (!is_alpha(c)) return ParseStatus::kSyntax;
    const std::size_t start = pos_;
    for (;;) {
      while (pos_ < s_.size() && (is_alpha(s_[pos_]) || is_digit(s_[pos_]))) ++pos_;
      if (pos_ + 1 < s_.size() && s_[pos_] == '.' && is_alpha(s_[pos_ + 1])) {
        ++pos_;
        continue;
      }
      break;
    }
    it.text = s_.substr(start, pos_ - start);
    const std::size_t after_name = pos_;
    skip();
    if (pos_ < s_.size() && s_[pos_] == '(') {
      ++pos_;
      it.kind = Item::Kind::kCall;
      int first = -1;
      const ParseStatus st = arguments(depth + 1, first, false);
      if (st != ParseStatus::kOk) return st;
      // `it` may not be referenced across the recursion's writes to other slots; re-fetch.
      Item& call = list_.items_[static_cast<std::size_t>(index)];
      call.first_child = first;
      if (pos_ >= s_.size() || s_[pos_] != ')') return ParseStatus::kSyntax;
      ++pos_;
      return ParseStatus::kOk;
    }
    pos_ = after_name;
    it.kind = Item::Kind::kName;
    return ParseStatus::kOk;
  }

  ParseStatus number(Item& it) noexcept {
    const std::size_t start = pos_;
    if (s_[pos_] == '+' || s_[pos_] == '-') ++pos_;
    std::size_t digits = 0;
    while (pos_ < s_.size() && is_digit(s_[pos_])) ++pos_, ++digits;
    if (pos_ < s_.size() && s_[pos_] == '.') {
      ++pos_;
      while (pos_ < s_.size() && is_digit(s_[pos_])) ++pos_, ++digits;
    }
    if (digits == 0) return ParseStatus::kSyntax;
    if (pos_ < s_.size() && (s_[pos_] == 'E' || s_[pos_] == 'e')) {
      ++pos_;
      if (pos_ < s_.size() && (s_[pos_] == '+' || s_[pos_] == '-')) ++pos_;
      std::size_t exponent_digits = 0;
      while (pos_ < s_.size() && is_digit(s_[pos_])) ++pos_, ++exponent_digits;
      if (exponent_digits == 0) return ParseStatus::kSyntax;
    }
    const std::size_t n = pos_ - start;
    if (n > kMaxNumberChars) return ParseStatus::kBadNumber;
    char buffer[kMaxNumberChars + 1];
    for (std::size_t i = 0; i < n; ++i) buffer[i] = s_[start + i];
    buffer[n] = '\0';
    char* end = nullptr;
    const double v = std::strtod(buffer, &end);
    if (end != buffer + n || !std::isfinite(v)) return ParseStatus::kBadNumber;
    it.kind = Item::Kind::kNumber;
    it.text = s_.substr(start, n);
    it.number = v;
    return ParseStatus::kOk;
  }

  std::string_view s_;
  std::size_t pos_ = 0;
  ItemList& list_;
};

const char* to_string(ParseStatus s) noexcept {
  switch (s) {
    case ParseStatus::kOk:
      return "ok";
    case ParseStatus::kEmpty:
      return "empty line";
    case ParseStatus::kTooLong:
      return "line longer than 1024 bytes";
    case ParseStatus::kIllegalCharacter:
      return "a byte outside printable ASCII";
    case ParseStatus::kBadTag:
      return "no tag (five digits, or E and four digits)";
    case ParseStatus::kNoSpace:
      return "the 6th character is not a space";
    case ParseStatus::kNoCommand:
      return "no command";
    case ParseStatus::kSyntax:
      return "bad argument syntax";
    case ParseStatus::kTooManyItems:
      return "more than 64 arguments or nested deeper than 4";
    case ParseStatus::kBadNumber:
      return "a number longer than 16 characters or not finite";
  }
  return "unknown";
}

ErrorCode error_for(ParseStatus s) noexcept {
  switch (s) {
    case ParseStatus::kOk:
    case ParseStatus::kEmpty:
    case ParseStatus::kNoCommand:
    case ParseStatus::kTooLong:
      return ErrorCode::kProtocolError;
    case ParseStatus::kIllegalCharacter:
      return ErrorCode::kIllegalCharacter;
    case ParseStatus::kBadTag:
      return ErrorCode::kIllegalTag;
    case ParseStatus::kNoSpace:
      return ErrorCode::kNoSpaceAtPos6;
    case ParseStatus::kSyntax:
    case ParseStatus::kTooManyItems:
      return ErrorCode::kIncorrectArguments;
    case ParseStatus::kBadNumber:
      return ErrorCode::kBadArgument;
  }
  return ErrorCode::kProtocolError;
}

ParseStatus parse_tag(std::string_view five, Tag& out) noexcept {
  if (five.size() != 5) return ParseStatus::kBadTag;
  Tag t;
  std::size_t i = 0;
  if (five[0] == 'E') {
    t.queue = Tag::Queue::kFast;
    i = 1;
  }
  int n = 0;
  for (; i < 5; ++i) {
    if (!is_digit(five[i])) return ParseStatus::kBadTag;
    n = n * 10 + (five[i] - '0');
  }
  t.number = n;
  for (std::size_t k = 0; k < 5; ++k) t.text[k] = five[k];
  t.text[5] = '\0';
  out = t;
  return ParseStatus::kOk;
}

Tag make_tag(Tag::Queue queue, int number) noexcept {
  Tag t;
  t.queue = queue;
  const bool fast = queue == Tag::Queue::kFast;
  const int limit = fast ? 10000 : 100000;
  t.number = number < 0 ? 0 : number % limit;
  int n = t.number;
  for (int k = 4; k >= (fast ? 1 : 0); --k) {
    t.text[static_cast<std::size_t>(k)] = static_cast<char>('0' + n % 10);
    n /= 10;
  }
  if (fast) t.text[0] = 'E';
  t.text[5] = '\0';
  return t;
}

int ItemList::count_from(int first) const noexcept {
  int n = 0;
  for (int i = first; i >= 0 && i < count_; i = items_[static_cast<std::size_t>(i)].next_sibling) {
    ++n;
  }
  return n;
}

ParseStatus ItemList::parse(std::string_view text) noexcept {
  count_ = 0;
  first_ = -1;
  Parser p(text, *this);
  const ParseStatus st = p.arguments(1, first_, true);
  if (st != ParseStatus::kOk) return st;
  return p.done() ? ParseStatus::kOk : ParseStatus::kSyntax;
}

ParseStatus parse_command(std::string_view line, CommandLine& out) noexcept {
  out.name = {};
  out.args.parse({});
  ParseStatus st = clean(line);
  if (st != ParseStatus::kOk) return st;
  if (line.size() < 5) return ParseStatus::kBadTag;
  st = parse_tag(line.substr(0, 5), out.tag);
  if (st != ParseStatus::kOk) return st;
  if (line.size() < 6 || line[5] != ' ') return ParseStatus::kNoSpace;
  std::size_t pos = 6;
  while (pos < line.size() && line[pos] == ' ') ++pos;
  const std::size_t name_start = pos;
  while (pos < line.size() && (is_alpha(line[pos]) || is_digit(line[pos]))) ++pos;
  if (pos == name_start || !is_alpha(line[name_start])) return ParseStatus::kNoCommand;
  out.name = line.substr(name_start, pos - name_start);
  while (pos < line.size() && line[pos] == ' ') ++pos;
  std::size_t end = line.size();
  while (end > pos && line[end - 1] == ' ') --end;
  if (pos >= end || line[pos] != '(' || line[end - 1] != ')') return ParseStatus::kSyntax;
  return out.args.parse(line.substr(pos + 1, end - pos - 2));
}

ParseStatus parse_answer(std::string_view line, AnswerLine& out) noexcept {
  ParseStatus st = clean(line);
  if (st != ParseStatus::kOk) return st;
  if (line.size() < 5) return ParseStatus::kBadTag;
  st = parse_tag(line.substr(0, 5), out.tag);
  if (st != ParseStatus::kOk) return st;
  if (line.size() < 7 || line[5] != ' ') {
    return line.size() < 6 || line[5] != ' ' ? ParseStatus::kNoSpace : ParseStatus::kNoCommand;
  }
  const char mark = line[6];
  std::string_view rest = line.substr(7);
  while (!rest.empty() && rest.front() == ' ') rest.remove_prefix(1);
  out.data = {};
  switch (mark) {
    case '&':
      out.kind = AnswerLine::Kind::kAck;
      return rest.empty() ? ParseStatus::kOk : ParseStatus::kSyntax;
    case '%':
      out.kind = AnswerLine::Kind::kDone;
      return rest.empty() ? ParseStatus::kOk : ParseStatus::kSyntax;
    case '#':
      out.kind = AnswerLine::Kind::kData;
      out.data = rest;
      return ParseStatus::kOk;
    case '!':
      out.kind = AnswerLine::Kind::kError;
      out.data = rest;
      return ParseStatus::kOk;
    default:
      return ParseStatus::kNoCommand;
  }
}

ParseStatus parse_error(std::string_view data, ErrorAnswer& out) noexcept {
  ItemList list;
  const ParseStatus st = list.parse(data);
  if (st != ParseStatus::kOk) return st;
  if (list.count_from(list.first()) != 1) return ParseStatus::kSyntax;
  const Item& call = list[list.first()];
  if (call.kind != Item::Kind::kCall || call.text != "Error") return ParseStatus::kSyntax;
  const int a = call.first_child;
  const int b = a >= 0 ? list[a].next_sibling : -1;
  const int c = b >= 0 ? list[b].next_sibling : -1;
  const int d = c >= 0 ? list[c].next_sibling : -1;
  if (d < 0 || list[d].next_sibling >= 0) return ParseStatus::kSyntax;
  if (list[a].kind != Item::Kind::kNumber || list[b].kind != Item::Kind::kNumber ||
      list[c].kind != Item::Kind::kString || list[d].kind != Item::Kind::kString) {
    return ParseStatus::kSyntax;
  }
  out.severity = static_cast<int>(list[a].number);
  out.number = static_cast<int>(list[b].number);
  out.cause = list[c].text;
  out.text = list[d].text;
  return ParseStatus::kOk;
}

std::string ack_line(std::string_view tag) { return std::string(tag) + " &"; }
std::string done_line(std::string_view tag) { return std::string(tag) + " %"; }
std::string data_line(std::string_view tag, std::string_view data) {
  std::string s(tag);
  s += " # ";
  s += data;
  return s;
}

namespace {
/// `text` made safe inside an I++ string: no quote, printable ASCII only, bounded length.
std::string quoted_safe(std::string_view text, std::size_t max) {
  std::string s;
  for (char c : text.substr(0, max)) {
    s += c == '"' ? '\'' : is_printable(c) ? c : '?';
  }
  return s;
}
}  // namespace

std::string error_line(std::string_view tag,
                       ErrorCode code,
                       std::string_view cause,
                       std::string_view detail) {
  const ErrorInfo& info = error_info(code);
  char head[48];
  std::snprintf(head, sizeof head, " ! Error(%d, %04d, \"", info.severity, error_number(code));
  std::string s(tag);
  s += head;
  s += quoted_safe(cause, 200);
  s += "\", \"";
  s += info.text;
  if (!detail.empty()) {
    s += ": ";
    s += quoted_safe(detail, 300);
  }
  s += "\")";
  return s;
}

std::string number_item(std::string_view name, double v) {
  std::string s(name);
  s += '(';
  s += io::format_ipp_number(v, "value");
  s += ')';
  return s;
}

}  // namespace cmmcomp::ipp

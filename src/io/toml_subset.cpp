// SPDX-License-Identifier: MIT
/// @file The TOML subset of the machine and agent configuration files, checked by hand.
#include <fmt/format.h>

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/toml_subset.hpp>
#include <string>

namespace cmmcomp::io {

namespace {

/// One pass over the text, line by line (the forms are in io/toml_subset.hpp).
class SubsetChecker {
 public:
  SubsetChecker(const std::string& text, const std::string& source, const char* document)
      : text_(text), source_(source), document_(document) {}

  void check() {
    while (pos_ < text_.size()) {
      line_start_ = pos_;
      check_line();
      ++line_;
    }
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw ConfigError(fmt::format("{}:{}:{}: syntax error: {} ({}, 'Syntax')",
                                  source_,
                                  line_,
                                  pos_ - line_start_ + 1,
                                  what,
                                  document_));
  }
  char peek() const { return pos_ < text_.size() ? text_[pos_] : '\n'; }
  bool at_end_of_line() const { return peek() == '\n' || peek() == '\r'; }
  void skip_blanks() {
    while (peek() == ' ' || peek() == '\t') ++pos_;
  }
  static bool is_bare(char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  }
  void expect_printable() const {
    const auto c = static_cast<unsigned char>(peek());
    if (c < 0x20 || c > 0x7e) {
      fail(c >= 0x80 ? fmt::format("byte 0x{:02X}: only strings and comments may hold "
                                   "characters beyond ASCII",
                                   c)
                     : fmt::format("control character 0x{:02X}", c));
    }
  }
  /// Steps over one character of a string or comment: printable ASCII, or one well-formed
  /// UTF-8 sequence (no overlong form, no surrogate, at most U+10FFFF).
  void text_character() {
    const auto c = static_cast<unsigned char>(peek());
    if (c < 0x80) {
      expect_printable();
      ++pos_;
      return;
    }
    const int extra = (c >= 0xC2 && c <= 0xDF)   ? 1
                      : (c >= 0xE0 && c <= 0xEF) ? 2
                      : (c >= 0xF0 && c <= 0xF4) ? 3
                                                 : -1;
    if (extra < 0) fail(fmt::format("byte 0x{:02X} does not start a UTF-8 character", c));
    std::uint32_t cp = c & (0x3Fu >> extra);
    for (int k = 1; k <= extra; ++k) {
      const std::size_t at = pos_ + static_cast<std::size_t>(k);
      const auto b = at < text_.size() ? static_cast<unsigned char>(text_[at]) : 0u;
      if ((b & 0xC0u) != 0x80u) fail("incomplete UTF-8 character");
      cp = (cp << 6) | (b & 0x3Fu);
    }
    const std::uint32_t least = extra == 1 ? 0x80u : extra == 2 ? 0x800u : 0x10000u;
    if (cp < least || cp > 0x10FFFFu || (cp >= 0xD800u && cp <= 0xDFFFu)) {
      fail(fmt::format("invalid UTF-8 character U+{:04X}", cp));
    }
    pos_ += static_cast<std::size_t>(extra) + 1;
  }
  void bare_key(const char* what) {
    if (!is_bare(peek())) {
      if (!at_end_of_line()) expect_printable();
      fail(fmt::format("expected {} (letters, digits, _ or -)", what));
    }
    while (is_bare(peek())) ++pos_;
  }
  /// The rest of the line: blanks, then nothing or a comment, then the line end.
  void end_of_line() {
    skip_blanks();
    if (peek() == '#') {
      ++pos_;
      while (!at_end_of_line()) {
        if (peek() == '\t') {
          ++pos_;
        } else {
          text_character();
        }
      }
    }
    if (peek() == '\r') {
      if (pos_ + 1 >= text_.size() || text_[pos_ + 1] != '\n') {
        fail("a carriage return must end a line (CRLF)");
      }
      ++pos_;
    } else if (!at_end_of_line()) {
      expect_printable();
      fail(fmt::format("unexpected '{}'", peek()));
    }
    if (pos_ < text_.size()) ++pos_;  // the '\n'
  }
  void string_value() {
    ++pos_;  // the opening quote
    while (peek() != '"') {
      if (at_end_of_line()) fail(key_ + "a string must end on its line with '\"'");
      if (peek() == '\\') {
        ++pos_;
        const char e = peek();
        if (e == 'u' || e == 'U') {
          const std::size_t n = e == 'u' ? 4 : 8;
          for (std::size_t k = 1; k <= n; ++k) {
            const char h = pos_ + k < text_.size() ? text_[pos_ + k] : '\n';
            if (!std::isxdigit(static_cast<unsigned char>(h))) {
              fail(key_ + fmt::format("\\{} needs {} hexadecimal digits", e, n));
            }
          }
          pos_ += n;
        } else if (e != '"' && e != '\\' && e != 'b' && e != 't' && e != 'n' && e != 'f' &&
                   e != 'r') {
          fail(key_ +
               "unknown escape (TOML's are \\\" \\\\ \\b \\t \\n \\f \\r \\uXXXX \\UXXXXXXXX)");
        }
        ++pos_;
      } else {
        text_character();
      }
    }
    ++pos_;  // the closing quote
  }
  /// 'literal': no escapes (what the writer uses when the text has no ' of its own).
  void literal_string_value() {
    ++pos_;
    while (peek() != '\'') {
      if (at_end_of_line()) fail(key_ + "a string must end on its line with \"'\"");
      text_character();
    }
    ++pos_;
  }
  static bool digits(const std::string& t, std::size_t& i) {
    const std::size_t begin = i;
    while (i < t.size() && ((t[i] >= '0' && t[i] <= '9') || (t[i] == '_' && i > begin))) ++i;
    return i > begin && t[i - 1] != '_';
  }
  /// true, false, or a decimal number: [+-] (inf | nan | D [. D] [(e|E) [+-] D]), D digits
  /// with single '_' between them. Dates, times and 0x/0o/0b integers are not in the subset.
  static bool is_scalar(const std::string& t) {
    if (t == "true" || t == "false") return true;
    std::size_t i = (!t.empty() && (t[0] == '+' || t[0] == '-')) ? 1 : 0;
    if (t.compare(i, std::string::npos, "inf") == 0 || t.compare(i, std::string::npos, "nan") == 0)
      return true;
    if (!digits(t, i)) return false;
    if (i < t.size() && t[i] == '.' && !digits(t, ++i)) return false;
    if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
      ++i;
      if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
      if (!digits(t, i)) return false;
    }
    return i == t.size() && t.find("__") == std::string::npos;
  }
  void scalar_value() {
    const std::size_t begin = pos_;
    while (is_bare(peek()) || peek() == '+' || peek() == '.') ++pos_;
    const std::string token = text_.substr(begin, pos_ - begin);
    if (!is_scalar(token)) {
      pos_ = begin;
      if (token.empty()) expect_printable();
      fail(
          fmt::format("{}'{}' is not a value here: expected a decimal number, true, false or "
                      "a \"string\"",
                      key_,
                      token.empty() ? std::string(1, peek()) : token));
    }
  }
  void check_line() {
    skip_blanks();
    if (at_end_of_line() || peek() == '#') return end_of_line();
    if (peek() == '[') {
      ++pos_;
      skip_blanks();
      const std::size_t name = pos_;
      bare_key("a section name");
      section_ = text_.substr(name, pos_ - name) + ".";
      skip_blanks();
      if (peek() != ']') fail("expected ']' after the section name");
      ++pos_;
      return end_of_line();
    }
    const std::size_t key = pos_;
    bare_key("a key, a [section] or a # comment");
    key_ = "key '" + section_ + text_.substr(key, pos_ - key) + "': ";
    skip_blanks();
    if (peek() != '=') {
      if (!at_end_of_line()) expect_printable();
      fail(key_ + "expected '=' after the key");
    }
    ++pos_;
    skip_blanks();
    if (peek() == '"') {
      string_value();
    } else if (peek() == '\'') {
      literal_string_value();
    } else {
      scalar_value();
    }
    end_of_line();
    key_.clear();
  }

  const std::string& text_;
  const std::string& source_;
  const char* document_;
  std::size_t pos_ = 0;
  std::size_t line_start_ = 0;
  int line_ = 1;
  std::string section_;  // "servo." inside [servo]
  std::string key_;      // "key 'servo.bandwidth_hz': " while its value is checked
};

}  // namespace

void check_toml_subset(const std::string& text, const std::string& source, const char* document) {
  SubsetChecker(text, source, document).check();
}

}  // namespace cmmcomp::io

// SPDX-License-Identifier: MIT
/// @file The I++ DME line parser and writer: the forms NIST's test programs use, hostile lines,
/// the error table, and a round trip over random numbers and commands.
#include <gtest/gtest.h>

#include <cmmcomp/io/ipp_number.hpp>
#include <cmmcomp/ipp/error_codes.hpp>
#include <cmmcomp/ipp/line.hpp>
#include <cstdio>
#include <fstream>
#include <random>
#include <set>
#include <string>

namespace ipp = cmmcomp::ipp;
using ipp::Item;
using ipp::ParseStatus;

namespace {

ParseStatus parse(const std::string& line) {
  ipp::CommandLine c;
  return ipp::parse_command(line, c);
}

}  // namespace

TEST(IppLine, ReadsAPtMeasAsNistWritesIt) {
  const std::string line = "00180 PtMeas(X(75.0), Y(50.0), Z(40.0), IJK(-1.0, 0.0, 0.0))\r";
  ipp::CommandLine c;
  ASSERT_EQ(ipp::parse_command(line, c), ParseStatus::kOk);
  EXPECT_EQ(c.tag.view(), "00180");
  EXPECT_FALSE(c.tag.is_event());
  EXPECT_EQ(c.tag.number, 180);
  EXPECT_EQ(c.name, "PtMeas");
  ASSERT_EQ(c.args.count_from(c.args.first()), 4);
  const Item& x = c.args[c.args.first()];
  EXPECT_EQ(x.kind, Item::Kind::kCall);
  EXPECT_EQ(x.text, "X");
  EXPECT_EQ(c.args[x.first_child].number, 75.0);
  int ijk = c.args.first();
  for (int k = 0; k < 3; ++k) ijk = c.args[ijk].next_sibling;
  EXPECT_EQ(c.args[ijk].text, "IJK");
  EXPECT_EQ(c.args.count_from(c.args[ijk].first_child), 3);
  EXPECT_EQ(c.args[c.args[ijk].first_child].number, -1.0);
}

TEST(IppLine, ReadsTheOtherFormsOfNistsPrograms) {
  ipp::CommandLine c;
  ASSERT_EQ(
      ipp::parse_command("E0003 GetPropE(Tool.GoToPar.Speed.Max(), Tool.PtMeasPar.Accel())", c),
      ParseStatus::kOk);
  EXPECT_TRUE(c.tag.is_event());
  EXPECT_EQ(c.args[c.args.first()].text, "Tool.GoToPar.Speed.Max");
  EXPECT_EQ(c.args[c.args.first()].first_child, -1);
  ASSERT_EQ(ipp::parse_command("00001 GoTo(Tool.A(45),Z(-4.003E-01),Y(-0.129), X(+1.245E01), "
                               "Tool.B(4.0) )",
                               c),
            ParseStatus::kOk);
  int i = c.args[c.args.first()].next_sibling;
  EXPECT_DOUBLE_EQ(c.args[c.args[i].first_child].number, -0.4003);
  i = c.args[c.args[i].next_sibling].next_sibling;
  EXPECT_DOUBLE_EQ(c.args[c.args[i].first_child].number, 12.45);
  ASSERT_EQ(ipp::parse_command("00002 PtMeas ( X(1.33), Y(-2.6E01), Z(+.197), IJK(2,2,2))", c),
            ParseStatus::kOk);
  ASSERT_EQ(ipp::parse_command("00003 SetTool(\"RefTool\")", c), ParseStatus::kOk);
  EXPECT_EQ(c.args[c.args.first()].kind, Item::Kind::kString);
  EXPECT_EQ(c.args[c.args.first()].text, "RefTool");
  ASSERT_EQ(ipp::parse_command("00004 StopDaemon(E1234)", c), ParseStatus::kOk);
  EXPECT_EQ(c.args[c.args.first()].kind, Item::Kind::kName);
  ASSERT_EQ(ipp::parse_command("09999 EndSession()", c), ParseStatus::kOk);
  EXPECT_EQ(c.args.first(), -1);
}

TEST(IppLine, HostileLinesGetAStatusNeverAnException) {
  const std::string nul_line("00001 Go\0To()", 13);
  struct Case {
    std::string line;
    ParseStatus expected;
  };
  const std::vector<Case> cases = {
      {"", ParseStatus::kEmpty},
      {"\r", ParseStatus::kEmpty},
      {std::string(2000, 'A'), ParseStatus::kTooLong},
      {nul_line, ParseStatus::kIllegalCharacter},
      {"00001 GoTo(X(1))\x01", ParseStatus::kIllegalCharacter},
      {"00001 GoTo(X(\xff))", ParseStatus::kIllegalCharacter},
      {"00001 GoTo(X(1))\r\r", ParseStatus::kIllegalCharacter},
      {"0001 GoTo()", ParseStatus::kBadTag},
      {"E12a4 GoTo()", ParseStatus::kBadTag},
      {"abc", ParseStatus::kBadTag},
      {"00001GoTo()", ParseStatus::kNoSpace},
      {"00001", ParseStatus::kNoSpace},
      {"00001 ", ParseStatus::kNoCommand},
      {"00001 (X(1))", ParseStatus::kNoCommand},
      {"00001 GoTo", ParseStatus::kSyntax},
      {"00001 GoTo(X(1)", ParseStatus::kSyntax},
      {"00001 GoTo(X(1)))", ParseStatus::kSyntax},
      {"00001 GoTo(X(1),)", ParseStatus::kSyntax},
      {"00001 GoTo(,X(1))", ParseStatus::kSyntax},
      {"00001 GoTo(X()2)", ParseStatus::kSyntax},
      {"00001 GoTo(X(--1))", ParseStatus::kSyntax},
      {"00001 GoTo(X(1E))", ParseStatus::kSyntax},
      {"00001 SetTool(\"open)", ParseStatus::kSyntax},
      {"00001 Cmd(A(B(C(D(E())))))", ParseStatus::kTooManyItems},
      {"00001 GoTo(X(12345678901234567))", ParseStatus::kBadNumber},
      {"00001 GoTo(X(1e999))", ParseStatus::kBadNumber},
  };
  for (const Case& c : cases) {
    EXPECT_EQ(parse(c.line), c.expected) << "line: " << c.line;
  }
  std::string many = "00001 Get(";
  for (int i = 0; i < ipp::kMaxItems + 1; ++i) many += i == 0 ? "X()" : ",X()";
  EXPECT_EQ(parse(many + ")"), ParseStatus::kTooManyItems);
  std::string deep = "00001 A(";
  for (int i = 0; i < 300; ++i) deep += "B(";
  EXPECT_EQ(parse(deep + std::string(301, ')')), ParseStatus::kTooManyItems);
  EXPECT_EQ(parse(deep), ParseStatus::kSyntax);
  EXPECT_EQ(parse("00001 Cmd(A(B(C(D()))))"), ParseStatus::kOk);
}

TEST(IppLine, RandomBytesNeverPassAsACommandWithAByteOutsidePrintableAscii) {
  std::mt19937_64 rng(39);
  std::uniform_int_distribution<int> byte(0, 255), length(0, 80);
  const std::string seed = "00012 PtMeas(X(1), Y(2), Z(3), IJK(0,0,1))";
  int ok = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    std::string line = seed;
    const int edits = 1 + trial % 4;
    for (int e = 0; e < edits; ++e) {
      const std::size_t at = static_cast<std::size_t>(length(rng)) % (line.size() + 1);
      if (trial % 3 == 0 && at < line.size()) {
        line.erase(at, 1);
      } else {
        line.insert(at, 1, static_cast<char>(byte(rng)));
      }
    }
    ipp::CommandLine c;
    const ParseStatus st = ipp::parse_command(line, c);
    bool printable = true;
    std::string body = line;
    if (!body.empty() && body.back() == '\r') body.pop_back();
    for (char ch : body) printable = printable && ch >= 0x20 && ch <= 0x7e;
    if (!printable) {
      EXPECT_NE(st, ParseStatus::kOk) << line;
    }
    if (st == ParseStatus::kOk) ++ok;
  }
  EXPECT_GT(ok, 100);  // the edits leave some lines valid: the parser is not refusing everything
}

TEST(IppLine, NumbersAndCommandsRoundTrip) {
  std::mt19937_64 rng(1294);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-6, 9);
  const char* names[] = {"X", "Y", "Z", "Tool.GoToPar.Speed", "Tool.PtMeasPar.Approach"};
  for (int trial = 0; trial < 2000; ++trial) {
    double v[3];
    std::string line = ipp::make_tag(ipp::Tag::Queue::kNormal, trial + 1).view().data();
    line = line.substr(0, 5) + " Cmd" + std::to_string(trial % 7) + "(";
    for (int k = 0; k < 3; ++k) {
      v[k] = mantissa(rng) * std::pow(10.0, exponent(rng));
      if (k > 0) line += ", ";
      line += ipp::number_item(names[(trial + k) % 5], v[k]);
    }
    line += ")";
    ipp::CommandLine c;
    ASSERT_EQ(ipp::parse_command(line, c), ParseStatus::kOk) << line;
    EXPECT_EQ(c.tag.number, trial + 1);
    EXPECT_EQ(c.name, "Cmd" + std::to_string(trial % 7));
    int i = c.args.first();
    for (int k = 0; k < 3; ++k, i = c.args[i].next_sibling) {
      ASSERT_GE(i, 0);
      EXPECT_EQ(c.args[i].text, names[(trial + k) % 5]);
      const double read = c.args[c.args[i].first_child].number;
      // format_ipp_number's resolution: 1e-6, fewer decimals from 1e8 (16 characters).
      EXPECT_NEAR(read, v[k], 0.6e-6 + std::fabs(v[k]) * 1e-13) << line;
    }
  }
}

TEST(IppLine, TagsRoundTrip) {
  for (int n : {1, 9, 10, 12345, 99999}) {
    const ipp::Tag t = ipp::make_tag(ipp::Tag::Queue::kNormal, n);
    ipp::Tag back;
    ASSERT_EQ(ipp::parse_tag(t.view(), back), ParseStatus::kOk);
    EXPECT_EQ(back.number, n);
    EXPECT_FALSE(back.is_event());
  }
  const ipp::Tag e = ipp::make_tag(ipp::Tag::Queue::kFast, 42);
  EXPECT_EQ(e.view(), "E0042");
  EXPECT_TRUE(ipp::make_tag(ipp::Tag::Queue::kFast, 0).is_reserved());
}

TEST(IppLine, AnswersAndErrorsParseAndTheWriterAlwaysWritesAParsableError) {
  ipp::AnswerLine a;
  ASSERT_EQ(
      ipp::parse_answer(
          "00401 ! Error(2, 0513, \"00401 StopDaemon(E1234)\", \"Daemon does not exist\")", a),
      ParseStatus::kOk);
  EXPECT_EQ(a.kind, ipp::AnswerLine::Kind::kError);
  ipp::ErrorAnswer e;
  ASSERT_EQ(ipp::parse_error(a.data, e), ParseStatus::kOk);
  EXPECT_EQ(e.severity, 2);
  EXPECT_EQ(e.number, 513);
  EXPECT_EQ(e.cause, "00401 StopDaemon(E1234)");
  ASSERT_EQ(ipp::parse_answer("00030 # IsHomed(1)", a), ParseStatus::kOk);
  EXPECT_EQ(a.kind, ipp::AnswerLine::Kind::kData);
  EXPECT_EQ(a.data, "IsHomed(1)");
  ASSERT_EQ(ipp::parse_answer("E0901 %", a), ParseStatus::kOk);
  EXPECT_EQ(a.kind, ipp::AnswerLine::Kind::kDone);
  EXPECT_NE(ipp::parse_answer("00001 ?", a), ParseStatus::kOk);
  EXPECT_NE(ipp::parse_answer("00001 & extra", a), ParseStatus::kOk);

  const std::string line = ipp::error_line("00012",
                                           ipp::ErrorCode::kArgumentOutOfRange,
                                           "00012 SetTool(\"x\")",
                                           std::string("bad\x01\xfe \"quoted\""));
  ASSERT_EQ(ipp::parse_answer(line, a), ParseStatus::kOk) << line;
  ASSERT_EQ(ipp::parse_error(a.data, e), ParseStatus::kOk) << line;
  EXPECT_EQ(e.number, 504);
  EXPECT_EQ(e.severity, 1);
  EXPECT_EQ(e.cause, "00012 SetTool('x')");
  EXPECT_EQ(e.text, "Argument out of range: bad?? 'quoted'");
}

TEST(IppErrors, EveryCodeHasOneRowAndTheNumbersAreUnique) {
  std::set<int> numbers;
  for (const ipp::ErrorInfo& info : ipp::kErrors) {
    EXPECT_TRUE(numbers.insert(ipp::error_number(info.code)).second);
    EXPECT_EQ(&ipp::error_info(info.code), &info);
    EXPECT_TRUE(info.severity == 0 || info.severity == 1 || info.severity == 2 ||
                info.severity == 3 || info.severity == 9);
  }
  EXPECT_EQ(numbers.size(), ipp::kErrorCount);
  // Every parse failure maps to a row of the table.
  for (int s = 1; s <= static_cast<int>(ParseStatus::kBadNumber); ++s) {
    const ipp::ErrorCode code = ipp::error_for(static_cast<ParseStatus>(s));
    EXPECT_EQ(ipp::error_info(code).code, code);
  }
}

TEST(IppErrors, TheDocumentListsEveryErrorOfTheTable) {
  std::ifstream in(std::string(CMMCOMP_SOURCE_DIR) + "/docs/protocol-ippdme.md");
  ASSERT_TRUE(in) << "docs/protocol-ippdme.md";
  std::set<std::string> rows;
  // A row of the error table: "| NNNN | S | text |".
  const auto is_row = [](const std::string& l) {
    if (l.size() < 16 || l.compare(0, 2, "| ") != 0 || l.compare(6, 3, " | ") != 0 ||
        l.compare(10, 3, " | ") != 0 || l.compare(l.size() - 2, 2, " |") != 0) {
      return false;
    }
    const auto digit = [&](std::size_t i) { return l[i] >= '0' && l[i] <= '9'; };
    return digit(2) && digit(3) && digit(4) && digit(5) && digit(9);
  };
  std::string line;
  while (std::getline(in, line)) {
    if (is_row(line)) rows.insert(line);
  }
  for (const ipp::ErrorInfo& info : ipp::kErrors) {
    char number[8];
    std::snprintf(number, sizeof number, "%04d", ipp::error_number(info.code));
    const std::string want = std::string("| ") + number + " | " + std::to_string(info.severity) +
                             " | " + info.text + " |";
    EXPECT_EQ(rows.count(want), 1u) << "the document lacks: " << want;
  }
  EXPECT_EQ(rows.size(), ipp::kErrorCount) << "the document lists errors the table does not have";
}

// SPDX-License-Identifier: MIT
/// @file The machine file: default machine, round trip, and every error a user can make.
///
/// The parameter values and keys are being recalibrated, so every case is built from
/// machine_parameter_table() and format_machine(default_machine()), never from literal keys.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/detail/did_you_mean.hpp>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace cmmcomp::dynamics {
namespace {

using Info = ParameterInfo<MachineParameters>;

const char* const kSource = "bench.toml";

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += l + "\n";
  return s;
}

bool starts_with(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

/// 0-based index of the first line starting with `prefix` at or after `from`; -1 if none.
int find_line(const std::vector<std::string>& lines, const std::string& prefix, int from = 0) {
  for (int i = from; i < static_cast<int>(lines.size()); ++i) {
    if (starts_with(lines[static_cast<std::size_t>(i)], prefix)) return i;
  }
  return -1;
}

/// 0-based index of the line holding `info`'s key inside its [section] (keys repeat across
/// sections, e.g. mass_kg).
int key_line(const std::vector<std::string>& lines, const Info& info) {
  const int section = find_line(lines, "[" + std::string(info.section) + "]");
  if (section < 0) return -1;
  const int line = find_line(lines, std::string(info.key) + " =", section + 1);
  const int next_section = find_line(lines, "[", section + 1);
  return (next_section >= 0 && line > next_section) ? -1 : line;
}

std::string full_key(const Info& info) { return std::string(info.section) + "." + info.key; }

std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

/// The default machine with capabilities as wide as a file may hold, so that any physical
/// controller timing is inside them.
Machine widest_capabilities() {
  Machine m = default_machine();
  for (const motion::SettingInfo& info : motion::kSettings)
    m.capabilities[info.setting] = info.limits;
  return m;
}

/// The default machine file (widest capabilities) with `info`'s value replaced by `value_text`;
/// `line` gets its 1-based line number.
std::string with_value(const Info& info, const std::string& value_text, int* line) {
  std::vector<std::string> lines = split_lines(format_machine(widest_capabilities()));
  const int i = key_line(lines, info);
  EXPECT_GE(i, 0) << full_key(info);
  if (i < 0) return "";
  lines[static_cast<std::size_t>(i)] = std::string(info.key) + " = " + value_text;
  *line = i + 1;
  return join_lines(lines);
}

/// The ConfigError message for `text`, "no error" if it parses; any other exception fails the
/// test by escaping.
std::string error_of(const std::string& text) {
  try {
    parse_machine(text, kSource);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

std::string at_line(int line) { return std::string(kSource) + ":" + std::to_string(line) + ":"; }

TEST(MachineFile, DefaultMachineParsesAndIsPhysical) {
  const Machine m = default_machine();
  EXPECT_FALSE(m.name.empty());
  std::string why;
  EXPECT_TRUE(is_physical(m.parameters, &why)) << why;
  EXPECT_FALSE(machine_parameter_table().empty());
  for (const Info& info : machine_parameter_table()) {
    EXPECT_TRUE(std::isfinite(info.get(m.parameters))) << full_key(info);
    EXPECT_LE(info.min, info.max) << full_key(info);
  }
}

TEST(MachineFile, EveryParameterHasAPlausibleRangeWithABasisThatHoldsTheDefaultMachine) {
  const Machine m = default_machine();
  for (const Info& info : machine_parameter_table()) {
    EXPECT_LE(info.min, info.plausible_min) << full_key(info);
    EXPECT_LT(info.plausible_min, info.plausible_max) << full_key(info);
    EXPECT_LE(info.plausible_max, info.max) << full_key(info);
    ASSERT_NE(info.basis, nullptr) << full_key(info);
    EXPECT_GT(std::string(info.basis).size(), 10U) << full_key(info);
    const double v = info.get(m.parameters);
    EXPECT_GE(v, info.plausible_min) << full_key(info);
    EXPECT_LE(v, info.plausible_max) << full_key(info);
  }
}

TEST(MachineFile, FormatOneFileNamesTheChangeAndTheCommand) {
  std::vector<std::string> lines = split_lines(format_machine(default_machine()));
  const int i = find_line(lines, "format_version");
  ASSERT_GE(i, 0);
  lines[static_cast<std::size_t>(i)] = "format_version = 1";
  const std::string msg = error_of(join_lines(lines));
  EXPECT_TRUE(contains(msg, at_line(i + 1))) << msg;
  EXPECT_TRUE(contains(msg, "format_version 1 is the drag-load machine model")) << msg;
  EXPECT_TRUE(contains(msg, "cmmcomp-sim machine -o")) << msg;
}

TEST(MachineFile, FormattedFileMarksImplausibleValuesAndPrintsTheModalFigures) {
  Machine m = default_machine();
  const std::string plain = format_machine(m);
  EXPECT_FALSE(contains(plain, "OUTSIDE")) << plain;
  EXPECT_TRUE(contains(plain, "# Derived")) << plain;
  EXPECT_TRUE(contains(plain, "structural mode:")) << plain;
  m.parameters.mode_damping_ratio = 0.5;  // physical, but no bridge mode is that damped
  const std::string marked = format_machine(m);
  EXPECT_TRUE(contains(marked, "OUTSIDE its plausible range 0.02 .. 0.1")) << marked;
  // Still a valid file: the marks and the derived figures are comments.
  EXPECT_EQ(parse_machine(marked, kSource).parameters.mode_damping_ratio, 0.5);
}

TEST(MachineFile, ModalSummaryDerivesMassAndLagsFromTheParameters) {
  MachineParameters p = default_machine().parameters;
  p.mode_frequency_hz = 20.0;
  p.mode_stiffness_N_per_m = 4e6;
  p.mode_participation = 0.5;
  p.mode_shape_growth = 1.0;
  const double omega = 2.0 * 3.14159265358979323846 * 20.0;
  const ModalSummary s = modal_summary(p);
  EXPECT_NEAR(s.mode_mass_kg, 4e6 / (omega * omega), 1e-9);
  EXPECT_NEAR(s.inertial_lag_um_per_m_s2[0], 1e6 * 0.5 / (omega * omega), 1e-9);
  EXPECT_NEAR(s.inertial_lag_um_per_m_s2[2], 2.0 * s.inertial_lag_um_per_m_s2[0], 1e-9);
  EXPECT_NEAR(s.drag_compliance_um_per_N[1], 1e6 * 1.125 * 1.125 / 4e6, 1e-12);  // φ(L/2)²
  EXPECT_NEAR(s.drag_compliance_um_per_N[2], 4.0 * s.drag_compliance_um_per_N[0], 1e-12);
}

TEST(MachineFile, TableHasUniqueKeysAndCoversDistinctFields) {
  const auto& table = machine_parameter_table();
  for (std::size_t i = 0; i < table.size(); ++i) {
    for (std::size_t j = i + 1; j < table.size(); ++j) {
      EXPECT_NE(full_key(table[i]), full_key(table[j]));
      EXPECT_NE(table[i].ref, table[j].ref) << full_key(table[i]) << " " << full_key(table[j]);
    }
  }
}

TEST(MachineFile, FormatThenParseReproducesTheDefaultMachineExactly) {
  const Machine m = default_machine();
  const Machine back = parse_machine(format_machine(m), kSource);
  EXPECT_EQ(back.name, m.name);
  EXPECT_EQ(back.description, m.description);
  for (const Info& info : machine_parameter_table()) {
    EXPECT_EQ(info.get(back.parameters), info.get(m.parameters)) << full_key(info);
  }
}

TEST(MachineFile, RoundTripKeepsEveryParameterNameAndEscapedDescription) {
  Machine m = default_machine();
  m.name = "bench \"B\" \\ 2";
  m.description = "quotes \"x\", backslashes C:\\data\\m.toml, a tab\there,\na newline, µm";
  // A new value for every parameter, inside its bounds and different from the default, with 9
  // significant digits (what a hand-written or identified file holds).
  for (const Info& info : machine_parameter_table()) {
    const double d = info.get(m.parameters);
    double v = d * 1.23456789;
    if (!(v >= info.min && v <= info.max) || v == d) v = info.min + (info.max - info.min) * 0.3125;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    v = std::strtod(buf, nullptr);
    ASSERT_TRUE(v >= info.min && v <= info.max) << full_key(info);
    info.set(m.parameters, v);
  }
  const Machine back = parse_machine(format_machine(m), kSource);
  EXPECT_EQ(back.name, m.name);
  EXPECT_EQ(back.description, m.description);
  for (const Info& info : machine_parameter_table()) {
    EXPECT_EQ(info.get(back.parameters), info.get(m.parameters)) << full_key(info);
  }
}

TEST(MachineFile, LoadMachineReadsAWrittenFile) {
  const Machine m = default_machine();
  const std::string path = ::testing::TempDir() + "cmmcomp_test_machine.toml";
  {
    std::ofstream out(path, std::ios::binary);
    out << format_machine(m);
  }
  const Machine back = load_machine(path);
  EXPECT_EQ(back.name, m.name);
  for (const Info& info : machine_parameter_table()) {
    EXPECT_EQ(info.get(back.parameters), info.get(m.parameters)) << full_key(info);
  }
  std::remove(path.c_str());
}

TEST(MachineFile, LoadMachineOnAMissingPathNamesIt) {
  const std::string path = ::testing::TempDir() + "no/such/dir/machine.toml";
  try {
    load_machine(path);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_TRUE(contains(e.what(), path)) << e.what();
  }
}

TEST(MachineFile, TomlSyntaxErrorNamesFileAndLine) {
  std::vector<std::string> lines = split_lines(format_machine(default_machine()));
  const Info& info = machine_parameter_table().front();
  const int i = key_line(lines, info);
  ASSERT_GE(i, 0);
  lines.insert(lines.begin() + i + 1, "this is = = not toml");
  const std::string msg = error_of(join_lines(lines));
  EXPECT_TRUE(contains(msg, at_line(i + 2))) << msg;
  EXPECT_TRUE(contains(msg, "syntax")) << msg;
}

// Issue 16 D9: Debian's toml++ 3.3.0 asserts or reaches `unreachable` on some malformed inputs,
// so the text is checked against the machine-file subset (docs/machine-file.md, "Syntax")
// before toml++ sees it. Each input here used to reach toml++; each must now be refused by
// the subset check, with the line and the column.
TEST(MachineFile, TextOutsideTheSubsetIsRefusedBeforeTomlSeesIt) {
  const std::string head = "format_version = 2\n";
  const struct {
    std::string text;
    std::string where;  // "line:column:"
    std::string what;
  } cases[] = {
      {head + "[#", "2:2:", "expected a section name"},
      {head + "3=1979-05-27T:", "2:3:", "'1979-05-27T' is not a value here"},
      {head + "\xc3\xa9", "2:1:", "byte 0xC3: only strings and comments"},
      {head + "# \xe2\x82", "2:3:", "incomplete UTF-8 character"},
      {head + "name = \"\xc0\xaf\"", "2:9:", "does not start a UTF-8 character"},
      {head + "name = \"\xed\xa0\x80\"", "2:9:", "invalid UTF-8 character U+D800"},
      {head + std::string("name = \"a\0b\"", 12), "2:10:", "control character 0x00"},
      {head + "name = \"a\x1b[2Jb\"", "2:10:", "control character 0x1B"},
      {head + "name = \"a\\q\"", "2:11:", "unknown escape"},
      {head + "name = \"a\\u01\"", "2:11:", "\\u needs 4 hexadecimal digits"},
      {head + "name = \"open", "2:13:", "a string must end on its line"},
      {head + "x = [1, 2]", "2:5:", "key 'x': '[' is not a value here"},
      {head + "x = {a = 1}", "2:5:", "'{' is not a value here"},
      {head + "x = 0x1F", "2:5:", "'0x1F' is not a value here"},
      {head + "x = 1__0", "2:5:", "'1__0' is not a value here"},
      {head + "x = 1.", "2:5:", "'1.' is not a value here"},
      {head + "[a.b]", "2:3:", "expected ']' after the section name"},
      {head + "[[a]]", "2:2:", "expected a section name"},
      {head + "a.b = 1", "2:2:", "key 'a': expected '=' after the key"},
      {head + "x = 1 y", "2:7:", "unexpected 'y'"},
      {head + "x = 1\rx", "2:6:", "a carriage return must end a line"},
      {head + "\tx\v= 1", "2:3:", "control character 0x0B"},
  };
  for (const auto& c : cases) {
    const std::string msg = error_of(c.text);
    EXPECT_TRUE(contains(msg, std::string(kSource) + ":" + c.where)) << c.what << ": " << msg;
    EXPECT_TRUE(contains(msg, c.what)) << msg;
    EXPECT_TRUE(contains(msg, "'Syntax'")) << msg;
  }
}

// Issue 16 D13: escapes can still spell control characters; a name gets none, a description
// tabs and line breaks only.
TEST(MachineFile, NamesAndDescriptionsRefuseControlCharacters) {
  for (const char* escape : {"\\u0000", "\\u001B", "\\t", "\\u007F"}) {
    Machine m = default_machine();
    std::string text = format_machine(m);
    const std::string name = "name = " + std::string("\"") + m.name + "\"";
    ASSERT_TRUE(contains(text, name)) << text.substr(0, 200);
    text.replace(text.find(name), name.size(), "name = \"x" + std::string(escape) + "y\"");
    EXPECT_TRUE(contains(error_of(text), "'name' holds the control character")) << escape;
  }
  Machine m = default_machine();
  m.description = "a\tb\nc";
  EXPECT_EQ(parse_machine(format_machine(m), kSource).description, m.description);
  m.description = std::string("a\x1b[31mred");
  EXPECT_TRUE(
      contains(error_of(format_machine(m)), "'description' holds the control character 0x1B"));
}

// What the subset keeps: comments and strings in UTF-8, CRLF line ends, every escape the
// writer uses, signed and underscored numbers, inf and nan (refused later as not physical).
TEST(MachineFile, TheSubsetKeepsEverythingTheWriterAndAUserWrite) {
  Machine m = default_machine();
  m.name = "bridge \"B\" \\ 2";
  m.description = "µm, ζ = 0.05, tab\tand\nnewline";
  std::string text = format_machine(m);
  text.insert(0, "# Prüfstand 3 — X axis\r\n");
  EXPECT_EQ(parse_machine(text, kSource).description, m.description);
  const Info& info = machine_parameter_table().front();
  for (const char* v : {"+30", "3_0", "30.000_1", "3e1", "3.0E+1", "300e-1"}) {
    int line = 0;
    EXPECT_EQ(error_of(with_value(info, v, &line)), "no error") << v;
  }
  for (const char* v : {"inf", "-nan"}) {
    int line = 0;
    EXPECT_TRUE(contains(error_of(with_value(info, v, &line)), "is not physical")) << v;
  }
}

TEST(MachineFile, DuplicateKeyIsASyntaxErrorAtTheSecondOccurrence) {
  std::vector<std::string> lines = split_lines(format_machine(default_machine()));
  const Info& info = machine_parameter_table().back();
  const int i = key_line(lines, info);
  ASSERT_GE(i, 0);
  lines.insert(lines.begin() + i + 1, lines[static_cast<std::size_t>(i)]);
  const std::string msg = error_of(join_lines(lines));
  EXPECT_TRUE(contains(msg, at_line(i + 2))) << msg;
}

TEST(MachineFile, MissingFormatVersionIsReported) {
  std::vector<std::string> lines = split_lines(format_machine(default_machine()));
  const int i = find_line(lines, "format_version");
  ASSERT_GE(i, 0);
  lines.erase(lines.begin() + i);
  const std::string msg = error_of(join_lines(lines));
  EXPECT_TRUE(starts_with(msg, std::string(kSource) + ":")) << msg;
  EXPECT_TRUE(contains(msg, "missing 'format_version'")) << msg;
}

TEST(MachineFile, WrongFormatVersionNamesItsLine) {
  std::vector<std::string> lines = split_lines(format_machine(default_machine()));
  const int i = find_line(lines, "format_version");
  ASSERT_GE(i, 0);
  for (const char* bad : {"5", "1.5", "0", "\"3\"", "3.0"}) {
    lines[static_cast<std::size_t>(i)] = std::string("format_version = ") + bad;
    const std::string msg = error_of(join_lines(lines));
    EXPECT_TRUE(contains(msg, at_line(i + 1))) << bad << ": " << msg;
    EXPECT_TRUE(contains(msg, "format_version")) << bad << ": " << msg;
    EXPECT_TRUE(contains(msg, std::to_string(kMachineFileVersion))) << bad << ": " << msg;
  }
}

TEST(MachineFile, UnknownTopLevelKeyNamesKeyAndLine) {
  std::vector<std::string> lines = split_lines(format_machine(default_machine()));
  const int i = find_line(lines, "name =");
  ASSERT_GE(i, 0);
  lines.insert(lines.begin() + i + 1, "colour = 3");
  const std::string msg = error_of(join_lines(lines));
  EXPECT_TRUE(contains(msg, at_line(i + 2))) << msg;
  EXPECT_TRUE(contains(msg, "unknown key 'colour'")) << msg;
}

TEST(MachineFile, UnknownSectionKeyNamesKeyAndLine) {
  std::vector<std::string> lines = split_lines(format_machine(default_machine()));
  lines.push_back("[turbo]");
  lines.push_back("boost_kg = 1");
  const std::string msg = error_of(join_lines(lines));
  EXPECT_TRUE(contains(msg, at_line(static_cast<int>(lines.size())))) << msg;
  EXPECT_TRUE(contains(msg, "'turbo.boost_kg'")) << msg;
}

TEST(MachineFile, UnknownKeyInsideAKnownSectionNamesKeyAndLine) {
  for (const Info& info : {machine_parameter_table().front(), machine_parameter_table().back()}) {
    std::vector<std::string> lines = split_lines(format_machine(default_machine()));
    const int section = find_line(lines, "[" + std::string(info.section) + "]");
    ASSERT_GE(section, 0);
    lines.insert(lines.begin() + section + 1, "bogus_key = 1");
    const std::string msg = error_of(join_lines(lines));
    EXPECT_TRUE(contains(msg, at_line(section + 2))) << msg;
    EXPECT_TRUE(contains(msg, "unknown key '" + std::string(info.section) + ".bogus_key'")) << msg;
  }
}

TEST(MachineFile, AMisspeltKeyOrSectionGetsTheClosestName) {
  std::vector<std::string> lines = split_lines(format_machine(default_machine()));
  const int i = find_line(lines, "mode_frequency_hz =");
  ASSERT_GE(i, 0);
  lines[static_cast<std::size_t>(i)] = "mode_frequncy_hz = 19";
  std::string msg = error_of(join_lines(lines));
  EXPECT_TRUE(contains(msg,
                       "unknown key 'structure.mode_frequncy_hz' (did you mean "
                       "'mode_frequency_hz'?)"))
      << msg;
  lines = split_lines(format_machine(default_machine()));
  lines.push_back("[structur]");
  lines.push_back("mass_kg = 1");
  msg = error_of(join_lines(lines));
  EXPECT_TRUE(contains(msg, "(did you mean 'structure'?)")) << msg;
  // Nothing close: no guess.
  lines = split_lines(format_machine(default_machine()));
  lines.push_back("[turbo]");
  lines.push_back("boost_kg = 1");
  EXPECT_FALSE(contains(error_of(join_lines(lines)), "did you mean")) << msg;
}

TEST(DidYouMean, TheClosestCandidateWithinATypo) {
  using cmmcomp::detail::did_you_mean;
  using cmmcomp::detail::edit_distance;
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(did_you_mean("--pvv", {"--pv", "--pd", "--av"}), " (did you mean '--pv'?)");
  EXPECT_EQ(did_you_mean("--zz", {"--pv", "--pd"}), "");
  EXPECT_EQ(did_you_mean("--pv", {"--pv"}), "") << "an exact name is not a typo";
}

TEST(MachineFile, EveryMissingKeyIsNamed) {
  for (const Info& info : machine_parameter_table()) {
    std::vector<std::string> lines = split_lines(format_machine(default_machine()));
    const int i = key_line(lines, info);
    ASSERT_GE(i, 0) << full_key(info);
    lines.erase(lines.begin() + i);
    const std::string msg = error_of(join_lines(lines));
    EXPECT_TRUE(starts_with(msg, std::string(kSource) + ":")) << msg;
    EXPECT_TRUE(contains(msg, "missing key '" + full_key(info) + "'")) << msg;
  }
}

TEST(MachineFile, NonNumericValueNamesKeyAndLine) {
  const Info& info = machine_parameter_table().front();
  for (const char* bad : {"\"fast\"", "true", "[1, 2]", "1979-05-27"}) {
    int line = 0;
    const std::string msg = error_of(with_value(info, bad, &line));
    EXPECT_TRUE(contains(msg, at_line(line))) << bad << ": " << msg;
    EXPECT_TRUE(contains(msg, "'" + full_key(info) + "'")) << bad << ": " << msg;
    EXPECT_TRUE(contains(msg, "number")) << bad << ": " << msg;
  }
}

TEST(MachineFile, EveryValueOutsideItsBoundsNamesKeyAndItsLine) {
  for (const Info& info : machine_parameter_table()) {
    const double below = info.min - std::max(1.0, std::fabs(info.min));
    const double above = info.max + std::max(1.0, std::fabs(info.max));
    for (const double v : {below, above}) {
      int line = 0;
      const std::string msg = error_of(with_value(info, number(v), &line));
      EXPECT_TRUE(contains(msg, at_line(line))) << full_key(info) << " = " << v << ": " << msg;
      EXPECT_TRUE(contains(msg, "'" + full_key(info) + "'")) << msg;
      EXPECT_TRUE(contains(msg, "physical")) << msg;
    }
    // The bounds themselves are allowed (inclusive).
    for (const double v : {info.min, info.max}) {
      int line = 0;
      EXPECT_EQ(error_of(with_value(info, number(v), &line)), "no error")
          << full_key(info) << " = " << v;
    }
  }
}

TEST(MachineFile, NanAndInfinityAreNotPhysical) {
  const Info& info = machine_parameter_table().front();
  for (const char* bad : {"nan", "inf", "-inf"}) {
    int line = 0;
    const std::string msg = error_of(with_value(info, bad, &line));
    EXPECT_TRUE(contains(msg, at_line(line))) << bad << ": " << msg;
    EXPECT_TRUE(contains(msg, "'" + full_key(info) + "'")) << bad << ": " << msg;
  }
}

TEST(MachineFile, MissingOrEmptyNameIsReported) {
  std::vector<std::string> lines = split_lines(format_machine(default_machine()));
  const int i = find_line(lines, "name =");
  ASSERT_GE(i, 0);
  std::vector<std::string> without = lines;
  without.erase(without.begin() + i);
  std::string msg = error_of(join_lines(without));
  EXPECT_TRUE(starts_with(msg, std::string(kSource) + ":")) << msg;
  EXPECT_TRUE(contains(msg, "'name'")) << msg;

  lines[static_cast<std::size_t>(i)] = "name = \"\"";
  msg = error_of(join_lines(lines));
  EXPECT_TRUE(contains(msg, "'name'")) << msg;

  lines[static_cast<std::size_t>(i)] = "name = 42";
  msg = error_of(join_lines(lines));
  EXPECT_TRUE(contains(msg, at_line(i + 1))) << msg;
  EXPECT_TRUE(contains(msg, "'name'")) << msg;
}

TEST(MachineFile, IntegerValuesAreAcceptedForFloatKeys) {
  int tested = 0;
  for (const Info& info : machine_parameter_table()) {
    // An integer inside the bounds, other than the default value where possible.
    double v = std::ceil(info.min);
    if (v == info.get(default_machine().parameters) && v + 1.0 <= info.max) v += 1.0;
    if (!(v <= info.max) || std::fabs(v) > 1e15) continue;
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0f", v);
    int line = 0;
    const Machine m = parse_machine(with_value(info, buf, &line), kSource);
    EXPECT_EQ(info.get(m.parameters), v) << full_key(info) << " = " << buf;
    ++tested;
  }
  EXPECT_GT(tested, 0);
}

TEST(MachineFile, IsPhysicalNamesTheOffendingKey) {
  for (const Info& info : machine_parameter_table()) {
    MachineParameters p = default_machine().parameters;
    info.set(p, info.min - std::max(1.0, std::fabs(info.min)));
    std::string why;
    EXPECT_FALSE(is_physical(p, &why)) << full_key(info);
    EXPECT_TRUE(contains(why, full_key(info))) << why;
    info.set(p, std::numeric_limits<double>::quiet_NaN());
    EXPECT_FALSE(is_physical(p, nullptr)) << full_key(info);
  }
}

// An unknown section is an error even without keys.
TEST(MachineFile, UnknownEmptySectionIsRejected) {
  std::vector<std::string> lines = split_lines(format_machine(default_machine()));
  lines.push_back("[turbo]");
  const std::string msg = error_of(join_lines(lines));
  EXPECT_TRUE(contains(msg, at_line(static_cast<int>(lines.size())))) << msg;
  EXPECT_TRUE(contains(msg, "unknown section 'turbo'")) << msg;
}

// Fitted machines carry full-precision values: they must survive format -> parse exactly.
TEST(MachineFile, RoundTripKeepsFullPrecision) {
  Machine m = widest_capabilities();
  for (const Info& info : machine_parameter_table()) {
    info.set(m.parameters, info.min + (info.max - info.min) / 3.0);
  }
  const Machine back = parse_machine(format_machine(m), kSource);
  for (const Info& info : machine_parameter_table()) {
    EXPECT_EQ(info.get(back.parameters), info.get(m.parameters)) << full_key(info);
  }
}

/// The default machine's file text as format 2: its version line, no [capabilities] section.
/// `text` (a format-4 file) as a file of format `version`: without the keys and sections that
/// version does not have.
std::string as_format(const std::string& text, int version) {
  std::vector<std::string> lines = split_lines(text);
  std::vector<std::string> out;
  std::string section;
  for (const std::string& line : lines) {
    if (starts_with(line, "[")) section = line.substr(1, line.find(']') - 1);
    if (section == "capabilities" && version < 3) continue;
    // A newer key, or the header of a section whose keys are all newer.
    bool newer = false;
    bool whole_section_newer = false;
    bool older_key = false;
    for (const Info& info : machine_parameter_table()) {
      if (section != info.section) continue;
      older_key = older_key || info.since_format <= version;
      whole_section_newer = !older_key;
      newer =
          newer || (info.since_format > version && starts_with(line, std::string(info.key) + " ="));
    }
    if (newer || (whole_section_newer && starts_with(line, "[" + section + "]"))) continue;
    out.push_back(
        starts_with(line, "format_version") ? "format_version = " + std::to_string(version) : line);
  }
  return join_lines(out);
}
std::string as_format_two(const std::string& text) { return as_format(text, 2); }

TEST(MachineFile, EverySettingHasAUniqueKeyAnUnitAndItsIppPropertyOrNone) {
  std::set<std::string> keys;
  for (int i = 0; i < motion::kSettingCount; ++i) {
    const motion::SettingInfo& info = motion::kSettings[i];
    EXPECT_EQ(static_cast<int>(info.setting), i) << info.key;
    EXPECT_TRUE(keys.insert(info.key).second) << info.key;
    EXPECT_LT(info.limits.min, info.limits.max) << info.key;
    if (info.ipp_property != nullptr) {
      EXPECT_TRUE(starts_with(info.ipp_property, "Tool.GoToPar.") ||
                  starts_with(info.ipp_property, "Tool.PtMeasPar."))
          << info.ipp_property;
    }
  }
  // NaN is outside every range.
  motion::ProbingMove nan_dwell = motion::baseline_move();
  nan_dwell.dwell = std::nan("");
  const motion::SettingViolation v =
      motion::first_violation(default_machine().capabilities, nan_dwell);
  EXPECT_TRUE(v.outside);
  EXPECT_EQ(v.setting, motion::Setting::kDwell);
  // The settings I++ DME has no property for: the controller's configuration.
  EXPECT_EQ(motion::setting_info(motion::Setting::kDwell).ipp_property, nullptr);
  EXPECT_EQ(motion::setting_info(motion::Setting::kSmoothing).ipp_property, nullptr);
}

TEST(MachineFile, CapabilitiesRoundTripExactlyInShortText) {
  Machine m = default_machine();
  m.capabilities[motion::Setting::kPositioningSpeed] = {0.0021, 0.4333};
  m.capabilities[motion::Setting::kApproachDistance] = {0.0003, 0.0127};
  m.capabilities[motion::Setting::kSmoothing] = {0.0, 0.15};
  const Machine back = parse_machine(format_machine(m), kSource);
  // Each written as the shortest text in the file's unit that reads back to the same value.
  for (const motion::SettingInfo& info : motion::kSettings) {
    EXPECT_EQ(back.capabilities[info.setting].min, m.capabilities[info.setting].min) << info.key;
    EXPECT_EQ(back.capabilities[info.setting].max, m.capabilities[info.setting].max) << info.key;
  }
  EXPECT_TRUE(contains(format_machine(m), "positioning_speed_max_mm_s = 433.3  #"))
      << format_machine(m);
  EXPECT_EQ(format_machine(back), format_machine(m));
  const Machine again = parse_machine(format_machine(back), kSource);
  EXPECT_EQ(format_machine(again), format_machine(back));
}

TEST(MachineFile, AFormatTwoFileHasTheFixedTimingCapabilities) {
  const Machine d = default_machine();
  const Machine m = parse_machine(as_format_two(format_machine(d)), kSource);
  EXPECT_EQ(m.parameters.controller_dwell_s, d.parameters.controller_dwell_s);
  const motion::SettingRange dwell = m.capabilities[motion::Setting::kDwell];
  EXPECT_EQ(dwell.min, d.parameters.controller_dwell_s);
  EXPECT_EQ(dwell.max, d.parameters.controller_dwell_s);
  const motion::SettingRange pv = m.capabilities[motion::Setting::kPositioningSpeed];
  EXPECT_EQ(pv.min, motion::MoveLimits::kMinSpeed);
  EXPECT_EQ(pv.max, motion::MoveLimits::kMaxSpeed);
  // Written back, it is the current format with those capabilities, and reads back to exactly
  // them (the fixed range still holds the full-precision dwell and smoothing).
  const std::string written = format_machine(m);
  EXPECT_TRUE(contains(written, "format_version = " + std::to_string(kMachineFileVersion)))
      << written;
  const Machine back = parse_machine(written, kSource);
  for (const motion::SettingInfo& info : motion::kSettings) {
    EXPECT_EQ(back.capabilities[info.setting].min, m.capabilities[info.setting].min) << info.key;
    EXPECT_EQ(back.capabilities[info.setting].max, m.capabilities[info.setting].max) << info.key;
  }
}

TEST(MachineFile, ACapabilitiesSectionInAFormatTwoFileIsRefused) {
  std::vector<std::string> lines = split_lines(format_machine(default_machine()));
  const int v = find_line(lines, "format_version");
  ASSERT_GE(v, 0);
  lines[static_cast<std::size_t>(v)] = "format_version = 2";
  const int i = find_line(lines, "[capabilities]");
  const std::string msg = error_of(join_lines(lines));
  EXPECT_TRUE(contains(msg, at_line(i + 1))) << msg;
  EXPECT_TRUE(contains(msg, "needs format_version 3")) << msg;
}

TEST(MachineFile, EveryMissingCapabilityKeyIsNamed) {
  for (const motion::SettingInfo& info : motion::kSettings) {
    for (const char* bound : {"min", "max"}) {
      const std::string key = std::string(info.key) + "_" + bound + "_" + info.unit;
      std::vector<std::string> lines = split_lines(format_machine(default_machine()));
      const int i = find_line(lines, key + " =");
      ASSERT_GE(i, 0) << key;
      lines.erase(lines.begin() + i);
      const std::string msg = error_of(join_lines(lines));
      EXPECT_TRUE(contains(msg, "missing key 'capabilities." + key + "'")) << msg;
    }
  }
}

TEST(MachineFile, ACapabilityRangeOutOfOrderOrWithoutTheControllerTimingIsRefused) {
  const auto with = [](const std::string& key, const std::string& value) {
    std::vector<std::string> lines = split_lines(format_machine(default_machine()));
    const int i = find_line(lines, key + " =");
    EXPECT_GE(i, 0) << key;
    lines[static_cast<std::size_t>(i)] = key + " = " + value;
    return error_of(join_lines(lines));
  };
  std::string msg = with("approach_speed_min_mm_s", "30");  // above its max, 20
  EXPECT_TRUE(contains(msg, "approach_speed_min_mm_s = 30")) << msg;
  EXPECT_TRUE(contains(msg, "min <= max")) << msg;
  msg = with("positioning_accel_max_mm_s2", "2e6");  // beyond MoveLimits
  EXPECT_TRUE(contains(msg, "positioning_accel_max_mm_s2")) << msg;
  msg = with("dwell_max_s", "0.5");  // the default machine's own dwell is 1.128 s
  EXPECT_TRUE(contains(msg, "controller.dwell_s")) << msg;
  EXPECT_TRUE(contains(msg, "dwell_max_s")) << msg;
  msg = with("smoothing_max_s", "nan");
  EXPECT_TRUE(contains(msg, "smoothing_max_s' must be a finite number")) << msg;
  msg = with("dwell_max_s", "\"2\"");
  EXPECT_TRUE(contains(msg, "must be a finite number")) << msg;
}

TEST(MachineFile, AMisspeltCapabilityKeyGetsTheClosestName) {
  std::vector<std::string> lines = split_lines(format_machine(default_machine()));
  const int i = find_line(lines, "dwell_max_s =");
  ASSERT_GE(i, 0);
  lines[static_cast<std::size_t>(i)] = "dwel_max_s = 2";
  const std::string msg = error_of(join_lines(lines));
  EXPECT_TRUE(contains(msg, at_line(i + 1))) << msg;
  EXPECT_TRUE(contains(msg, "unknown key 'capabilities.dwel_max_s'")) << msg;
  EXPECT_TRUE(contains(msg, "dwell_max_s")) << msg;
}

TEST(MachineFile, TheKeyRowsListEveryParameterAndCapabilityKey) {
  const std::string rows = format_machine_keys();
  for (const Info& info : machine_parameter_table()) {
    EXPECT_TRUE(contains(rows, "| " + std::string(info.section) + " | " + info.key + " | "))
        << info.key;
  }
  for (const motion::SettingInfo& info : motion::kSettings) {
    EXPECT_TRUE(contains(rows, std::string("| capabilities | ") + info.key + "_min_" + info.unit))
        << info.key;
  }
}

TEST(MachineFile, AnOlderFormatReadsWithoutTheNewerMechanisms) {
  // Format 3 has no carriage mass share and no second mode: the machine reads with the values
  // that switch them off, and is otherwise the same machine.
  Machine d = default_machine();
  d.parameters.mode_carriage_mass_share = 0.3;
  d.parameters.mode2_participation = 0.2;
  d.parameters.mode2_frequency_hz = 70.0;
  const Machine m = parse_machine(as_format(format_machine(d), 3), kSource);
  for (const Info& info : machine_parameter_table()) {
    const double expected = info.since_format > 3 ? info.absent : info.get(d.parameters);
    EXPECT_EQ(info.get(m.parameters), expected) << info.section << "." << info.key;
  }
  EXPECT_FALSE(has_second_mode(m.parameters));
  EXPECT_EQ(mode_frequency_at(m.parameters, m.parameters.beam_length_m),
            m.parameters.mode_frequency_hz);
}

TEST(MachineFile, ANewerKeyInAnOlderFormatIsRefusedWithItsLine) {
  std::vector<std::string> lines = split_lines(format_machine(default_machine()));
  const int v = find_line(lines, "format_version");
  ASSERT_GE(v, 0);
  lines[static_cast<std::size_t>(v)] = "format_version = 3";
  // Keep the format-3 file's sections, and one format-4 key in [structure].
  const std::string text = as_format(join_lines(lines), 3) + "\n";
  std::vector<std::string> with = split_lines(text);
  const int s = find_line(with, "[structure]");
  ASSERT_GE(s, 0);
  with.insert(with.begin() + s + 1, "carriage_mass_share = 0.2");
  const std::string msg = error_of(join_lines(with));
  EXPECT_TRUE(contains(msg, at_line(s + 2))) << msg;
  EXPECT_TRUE(contains(msg, "structure.carriage_mass_share")) << msg;
  EXPECT_TRUE(contains(msg, "needs format_version 4")) << msg;
}

TEST(MachineFile, EveryFormatFourKeyIsRequiredInFormatFour) {
  for (const Info& info : machine_parameter_table()) {
    if (info.since_format < 4) continue;
    std::vector<std::string> lines = split_lines(format_machine(default_machine()));
    int i = -1;
    std::string section;
    for (std::size_t k = 0; k < lines.size(); ++k) {
      if (starts_with(lines[k], "[")) section = lines[k].substr(1, lines[k].find(']') - 1);
      if (section == info.section && starts_with(lines[k], std::string(info.key) + " =")) {
        i = static_cast<int>(k);
      }
    }
    ASSERT_GE(i, 0) << info.key;
    lines.erase(lines.begin() + i);
    const std::string msg = error_of(join_lines(lines));
    EXPECT_TRUE(contains(msg, std::string("missing key '") + info.section + "." + info.key)) << msg;
  }
}

}  // namespace
}  // namespace cmmcomp::dynamics

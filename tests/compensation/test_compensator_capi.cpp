// SPDX-License-Identifier: MIT
/// @file The C ABI from C++: docs/compensator.md lists exactly the header's return codes and
/// flags with the same numbers; strerror knows every code; exceptions never cross.
#include <cmmcomp/compensator.h>
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

namespace {

const std::map<std::string, long long>& header_constants() {
  static const std::map<std::string, long long> k{
      {"CMMCOMP_OK", CMMCOMP_OK},
      {"CMMCOMP_E_ARGUMENT", CMMCOMP_E_ARGUMENT},
      {"CMMCOMP_E_IO", CMMCOMP_E_IO},
      {"CMMCOMP_E_MODEL", CMMCOMP_E_MODEL},
      {"CMMCOMP_E_NO_MEMORY", CMMCOMP_E_NO_MEMORY},
      {"CMMCOMP_E_INTERNAL", CMMCOMP_E_INTERNAL},
      {"CMMCOMP_E_INVALID_INPUT", CMMCOMP_E_INVALID_INPUT},
      {"CMMCOMP_E_NO_MODEL", CMMCOMP_E_NO_MODEL},
      {"CMMCOMP_E_OUTSIDE_DOMAIN_REJECTED", CMMCOMP_E_OUTSIDE_DOMAIN_REJECTED},
      {"CMMCOMP_FLAG_OK", CMMCOMP_FLAG_OK},
      {"CMMCOMP_FLAG_OUTSIDE_DOMAIN", CMMCOMP_FLAG_OUTSIDE_DOMAIN},
      {"CMMCOMP_FLAG_INVALID_INPUT", CMMCOMP_FLAG_INVALID_INPUT},
      {"CMMCOMP_FLAG_NO_MODEL", CMMCOMP_FLAG_NO_MODEL},
  };
  return k;
}

// Rows "| `CMMCOMP_X` | <number> | ..." of the doc's tables (decimal or 0x hex).
std::map<std::string, long long> doc_constants() {
  std::ifstream in(CMMCOMP_DOCS_DIR "/compensator.md");
  EXPECT_TRUE(in) << "cannot open docs/compensator.md";
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  const std::regex row(
      R"(\|\s*`(CMMCOMP_(?:OK|E_[A-Z_]+|FLAG_[A-Z_]+))`\s*\|\s*(-?(?:0x[0-9a-fA-F]+|[0-9]+))\s*\|)");
  std::map<std::string, long long> found;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), row); it != std::sregex_iterator();
       ++it) {
    found[(*it)[1].str()] = std::stoll((*it)[2].str(), nullptr, 0);
  }
  return found;
}

TEST(CompensatorCapi, DocTablesMatchTheHeader) { EXPECT_EQ(doc_constants(), header_constants()); }

TEST(CompensatorCapi, StrerrorKnowsEveryCode) {
  const std::string unknown = cmmcomp_strerror(12345);
  for (const auto& [name, value] : header_constants()) {
    if (name.rfind("CMMCOMP_FLAG_", 0) == 0) continue;
    EXPECT_NE(cmmcomp_strerror(static_cast<int>(value)), unknown) << name;
    EXPECT_LE(std::string(cmmcomp_strerror(static_cast<int>(value))).size(),
              CMMCOMP_MAX_MESSAGE_LENGTH);
  }
}

TEST(CompensatorCapi, MalformedInputReturnsCodesNotExceptions) {
  cmmcomp_compensator* c = nullptr;
  const std::string not_json = "\xff\xfe garbage";
  EXPECT_EQ(cmmcomp_create_from_memory(not_json.data(), not_json.size(), &c), CMMCOMP_E_MODEL);
  const std::string wrong_arch =
      R"({"format": "cmmcomp-tsk-model", "format_version": 1, "architecture": {"inputs": 1}})";
  EXPECT_EQ(cmmcomp_create_from_memory(wrong_arch.data(), wrong_arch.size(), &c), CMMCOMP_E_MODEL);
  EXPECT_EQ(cmmcomp_create_from_file("/", &c), CMMCOMP_E_IO);  // a directory
  EXPECT_EQ(c, nullptr);
}

}  // namespace

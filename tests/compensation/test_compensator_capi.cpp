// SPDX-License-Identifier: MIT
/// @file The C ABI from C++: docs/compensator.md lists exactly the header's return codes and
/// flags with the same numbers; strerror knows every code; exceptions never cross.
#include <cmmcomp/compensator.h>
#include <gtest/gtest.h>

#include <fstream>
#include <map>
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
      {"CMMCOMP_E_BUSY", CMMCOMP_E_BUSY},
      {"CMMCOMP_FLAG_OK", CMMCOMP_FLAG_OK},
      {"CMMCOMP_FLAG_OUTSIDE_DOMAIN", CMMCOMP_FLAG_OUTSIDE_DOMAIN},
      {"CMMCOMP_FLAG_INVALID_INPUT", CMMCOMP_FLAG_INVALID_INPUT},
      {"CMMCOMP_FLAG_NO_MODEL", CMMCOMP_FLAG_NO_MODEL},
      {"CMMCOMP_FLAG_NO_UNCERTAINTY", CMMCOMP_FLAG_NO_UNCERTAINTY},
  };
  return k;
}

// Rows "| `CMMCOMP_X` | <number> | ..." of the doc's tables (decimal or 0x hex). Parsed by
// hand: std::regex trips GCC 12's -Wmaybe-uninitialized under the sanitizers.
std::map<std::string, long long> doc_constants() {
  std::ifstream in(CMMCOMP_DOCS_DIR "/compensator.md");
  EXPECT_TRUE(in) << "cannot open docs/compensator.md";
  std::map<std::string, long long> found;
  std::string line;
  const std::string prefix = "| `CMMCOMP_";
  while (std::getline(in, line)) {
    if (line.rfind(prefix, 0) != 0) continue;
    const std::size_t name_end = line.find('`', 3);
    const std::size_t cell = line.find('|', name_end);
    const std::size_t cell_end = line.find('|', cell + 1);
    if (name_end == std::string::npos || cell == std::string::npos ||
        cell_end == std::string::npos) {
      continue;
    }
    const std::string value = line.substr(cell + 1, cell_end - cell - 1);
    found[line.substr(3, name_end - 3)] = std::stoll(value, nullptr, 0);
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

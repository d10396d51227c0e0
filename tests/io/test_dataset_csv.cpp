// SPDX-License-Identifier: MIT
/// @file The dataset CSV schema: round trip and every error a user can make.
#include <gtest/gtest.h>

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <sstream>
#include <string>

namespace cmmcomp::io {
namespace {

const std::string kHeader =
    "pv_mm_s,pd_mm,av_mm_s,ad_mm,pa_mm_s2,aa_mm_s2,y_mm,mpe_um,rpe_um,mae_um,rae_um\n";

std::string error_of(const std::string& text) {
  try {
    parse_dataset_csv(text, "data.csv");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(DatasetCsv, RoundTripKeepsFullPrecision) {
  DatasetRow r{40, 40, 12, 10, 200, 60, 250, 13.622, -5.861123456, 7.545, 3.919};
  const std::string text = format_dataset_csv({r, r});
  EXPECT_EQ(text.substr(0, kHeader.size()), kHeader);
  const auto rows = parse_dataset_csv(text, "mem");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].rpe_um, -5.861123456);
  EXPECT_EQ(rows[0].y_mm, 250);
}

TEST(DatasetCsv, AcceptsAnyColumnOrderExtraColumnsCommentsAndCrlf) {
  const std::string text =
      "# a comment\r\nrun,rae_um,mae_um,rpe_um,mpe_um,y_mm,aa_mm_s2,pa_mm_s2,ad_mm,av_mm_s,pd_mm,"
      "pv_mm_s\r\n\r\n1,4,3,2,1,250,60,200,10,12,40,70\r\n";
  const auto rows = parse_dataset_csv(text, "mem");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].pv_mm_s, 70);
  EXPECT_EQ(rows[0].rae_um, 4);
}

TEST(DatasetCsv, ErrorsNameFileLineAndColumn) {
  EXPECT_EQ(error_of(""), "data.csv: empty file (no header)");
  EXPECT_EQ(error_of(kHeader), "data.csv: no data rows after the header");
  EXPECT_NE(error_of("pv_mm_s,pd_mm\n1,2\n").find("data.csv:1: missing column 'av_mm_s'"),
            std::string::npos);
  EXPECT_EQ(error_of(kHeader + "40,40,12,10,200,60,250,13,5,7,abc\n"),
            "data.csv:2: column 'rae_um': 'abc' is not a number");
  EXPECT_EQ(error_of(kHeader + "40,40,12,10,200,60,250,nan,5,7,3\n"),
            "data.csv:2: column 'mpe_um': 'nan' is not finite");
  EXPECT_EQ(error_of(kHeader + "40,40,12,10,200,60,250,13,5,7,3\n40,40,12\n"),
            "data.csv:3: 3 cells, the header has 11");
  EXPECT_EQ(error_of(kHeader + "40,40,12,10,200,60,250,13,5,7,\n"),
            "data.csv:2: column 'rae_um': '' is not a number");
  EXPECT_EQ(error_of(kHeader + "40,40,12,10,200,60,250,13,5,7,1e999\n"),
            "data.csv:2: column 'rae_um': '1e999' is not a number");
}

// Issue 16 D12: subnormals, a byte-order mark, a file cut inside its last cell, absurd values.
TEST(DatasetCsv, HostileButValidAndInvalidCells) {
  const std::string row = "40,40,12,10,200,60,250,13,5,7,";
  EXPECT_EQ(parse_dataset_csv(kHeader + row + "4.9e-324\n", "mem").at(0).rae_um, 4.9e-324);
  EXPECT_EQ(parse_dataset_csv("\xEF\xBB\xBF" + kHeader + row + "3\n", "mem").size(), 1u);
  EXPECT_EQ(error_of(kHeader + row + "3.25"),
            "data.csv:2: the last line has no line end: the file may have been cut inside a cell "
            "(if it is complete, end it with a line break)");
  EXPECT_EQ(error_of(kHeader + "1e308,40,12,10,200,60,250,13,5,7,3\n"),
            "data.csv:2: column 'pv_mm_s': '1e308' is outside (0 .. 2000] (docs/dataset-csv.md)");
  EXPECT_EQ(error_of(kHeader + "40,0,12,10,200,60,250,13,5,7,3\n"),
            "data.csv:2: column 'pd_mm': '0' is outside (0 .. 10000] (docs/dataset-csv.md)");
  EXPECT_EQ(error_of(kHeader + "40,40,12,10,200,60,250,-1,5,7,3\n"),
            "data.csv:2: column 'mpe_um': '-1' is outside [0 .. 10000] (docs/dataset-csv.md)");
  DatasetRow bad{40, 40, 12, 10, 200, 60, 250, 13, 5, 7, 1.7e308};
  try {
    format_dataset_csv({DatasetRow{40, 40, 12, 10, 200, 60, 250, 13, 5, 7, 3}, bad});
    FAIL() << "wrote a row the reader refuses";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("dataset row 2: column 'rae_um': ", 0), 0u) << e.what();
  }
}

// The columns in schema.hpp are the ones the document lists, in its order, with its ranges.
TEST(DatasetCsv, ColumnsAndRangesAreTheDocumentedOnes) {
  const std::string doc = read_file_bounded(
      std::string(CMMCOMP_DOCS_DIR) + "/dataset-csv.md", "document", kMaxTextFileBytes);
  const auto number = [](double v) {
    std::ostringstream o;
    o << v;
    return o.str();
  };
  std::size_t previous = 0;
  for (const DatasetColumn& column : kDatasetColumns) {
    const DatasetColumnRange& r = column.range;
    const std::string cell =
        std::string(r.min_exclusive ? "(" : "[") + number(r.min) + " .. " + number(r.max) + "] |\n";
    const std::string head = std::string("| `") + column.name + "` |";
    const std::size_t at = doc.find(head);
    ASSERT_NE(at, std::string::npos) << head;
    EXPECT_GT(at, previous) << column.name << " is out of the document's order";
    previous = at;
    const std::string line = doc.substr(at, doc.find('\n', at) + 1 - at);
    EXPECT_GE(line.size(), cell.size());
    EXPECT_EQ(line.substr(line.size() - cell.size()), cell) << line;
  }
}

TEST(DatasetCsv, MissingFileIsAClearError) {
  try {
    read_dataset_csv("/nonexistent/data.csv");
    FAIL() << "no exception";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(),
                 "/nonexistent/data.csv: cannot open dataset CSV (No such file or directory)");
  }
}

}  // namespace
}  // namespace cmmcomp::io

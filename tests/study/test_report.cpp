// SPDX-License-Identifier: MIT
/// @file Result documents and the results page (cmmcomp/study/report.hpp): the rendering, the
/// block that is replaced and nothing else, a stale page found and rewritten, the errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/study/report.hpp>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace cmmcomp::study {
namespace {

CoverageResult two_rows() {
  CoverageResult r;
  r.model_id = "0123456789abcdef";
  r.model_y_id = "fedcba9876543210";
  CoverageRow a;
  a.name = "held out";
  a.moves = 270;
  a.coverage_pct = {94.07, 97.0, 96.3, 97.04};
  a.mean_u95_um = {2.704, 1.71, 1.27, 0.674};
  CoverageRow b = a;
  b.name = "no interval";
  b.coverage_pct.fill(std::numeric_limits<double>::quiet_NaN());
  r.rows = {a, b};
  r.pooled_pct = {94.9, 96.4, 96.2, 97.5};
  r.targets = {{"seed 2: mpe under-covers", 94.07, 92.0, Target::Kind::kAtLeast, "%"},
               {"pooled: rpe over-covers", 99.0, 98.0, Target::Kind::kAtMost, "%"}};
  return r;
}

Document judged(const CoverageResult& r, const KnownUnmet& known) {
  Document doc = interval_coverage_document(r);
  doc["command"] = "cmmcomp-study interval-coverage --model m.json";
  std::vector<Target> targets = r.targets;
  add_verdict(doc, targets, check(targets, known));
  return doc;
}

TEST(StudyReport, RendersTheTableTheCommandAndTheVerdict) {
  const std::string md = render_markdown(judged(two_rows(), {"pooled: rpe over-covers"}));
  EXPECT_EQ(md.rfind("`cmmcomp-study interval-coverage --model m.json`\n\n", 0), 0u) << md;
  EXPECT_NE(
      md.find("| held out | 270 | 0 | 94.1 (2.70) | 97.0 (1.71) | 96.3 (1.27) | 97.0 (0.67) |"),
      std::string::npos)
      << md;
  // A figure that does not exist is a dash, never "nan" (the JSON holds null).
  EXPECT_NE(md.find("| no interval | 270 | 0 | — (2.70) |"), std::string::npos) << md;
  EXPECT_EQ(md.find("nan"), std::string::npos) << md;
  EXPECT_NE(md.find("**PASS**: 2 targets; known unmet: pooled: rpe over-covers."),
            std::string::npos)
      << md;
  const std::string failed = render_markdown(judged(two_rows(), {}));
  EXPECT_NE(failed.find("**FAIL**: 1 of 2 targets"), std::string::npos) << failed;
  EXPECT_NE(failed.find("- pooled: rpe over-covers"), std::string::npos) << failed;
  // Every Markdown table row has as many cells as its header.
  std::istringstream lines(md);
  std::size_t columns = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.empty() || line[0] != '|') continue;
    const auto cells = static_cast<std::size_t>(std::count(line.begin(), line.end(), '|'));
    if (columns == 0) columns = cells;
    EXPECT_EQ(cells, columns) << line;
  }
  EXPECT_EQ(columns, 8u);
}

TEST(StudyReport, APipeInATableCellIsEscaped) {
  CoverageResult r = two_rows();
  r.rows[0].name = "mean |MAE|\nbefore";
  const std::string md = render_markdown(judged(r, {"pooled: rpe over-covers"}));
  EXPECT_NE(md.find("| mean \\|MAE\\| before | 270 |"), std::string::npos) << md;  // no line break
}

TEST(StudyReport, TheDocumentRoundTripsThroughJson) {
  const Document doc = judged(two_rows(), {"pooled: rpe over-covers"});
  const Document back = Document::parse(doc.dump());
  EXPECT_EQ(render_markdown(back), render_markdown(doc));
  EXPECT_TRUE(back["rows"][1]["mpe"]["coverage_pct"].is_null());
}

TEST(StudyReport, SpliceReplacesTheBlockAndNothingElse) {
  Document doc = judged(two_rows(), {"pooled: rpe over-covers"});
  doc["block"] = "coverage";
  const std::string before =
      "# Page\n\nprose\n<!-- study: coverage -->\nold table\n"
      "<!-- /study: coverage -->\nafter\n<!-- study: other -->\nkeep\n"
      "<!-- /study: other -->\n";
  const std::string after = splice_block(before, doc);
  EXPECT_EQ(after,
            "# Page\n\nprose\n<!-- study: coverage -->\n" + render_markdown(doc) +
                "<!-- /study: coverage -->\nafter\n<!-- study: other -->\nkeep\n"
                "<!-- /study: other -->\n");
  EXPECT_EQ(splice_block(after, doc), after);  // idempotent
}

TEST(StudyReport, APageWithoutTheBlockOrAnUnknownExperimentIsAnError) {
  Document doc = judged(two_rows(), {});
  try {
    (void)splice_block("# Page\n<!-- study: interval-coverage -->\n", doc);
    FAIL() << "a block without its end marker was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("<!-- /study: interval-coverage -->"), std::string::npos)
        << e.what();
  }
  // A marker inside a line is not a marker.
  EXPECT_THROW((void)splice_block("x <!-- study: interval-coverage -->\n"
                                  "<!-- /study: interval-coverage -->\n",
                                  doc),
               ConfigError);
  // A block twice, or its end before its start, is refused: a splice would lose the text between.
  const std::string start = "<!-- study: interval-coverage -->\n";
  const std::string end = "<!-- /study: interval-coverage -->\n";
  EXPECT_THROW((void)splice_block(start + "a\n" + start + "prose\n" + end, doc), ConfigError);
  EXPECT_THROW((void)splice_block(start + end + "x\n" + start + end, doc), ConfigError);
  EXPECT_THROW((void)splice_block(end + "x\n" + start, doc), ConfigError);
  doc["experiment"] = "no-such-experiment";
  EXPECT_THROW((void)render_markdown(doc), ConfigError);
  EXPECT_THROW((void)render_markdown(Document{{"experiment", "accuracy"}}), ConfigError);
}

TEST(StudyReport, SyncFindsAStalePageAndUpdatesIt) {
  const std::string path = ::testing::TempDir() + "cmmcomp-report-page.md";
  {
    std::ofstream(path) << "intro\n<!-- study: interval-coverage -->\nstale\n"
                           "<!-- /study: interval-coverage -->\n";
  }
  const Document doc = judged(two_rows(), {"pooled: rpe over-covers"});
  PageSync s = sync_page(path, doc, false);
  EXPECT_FALSE(s.current);
  EXPECT_NE(s.first_difference.find("page: stale"), std::string::npos) << s.first_difference;
  s = sync_page(path, doc, true);
  EXPECT_FALSE(s.current);
  EXPECT_TRUE(sync_page(path, doc, false).current);
  std::remove(path.c_str());
}

TEST(StudyReport, TheCommandLineIsWhatAUserTypes) {
  const char* argv[] = {"/build/tools/cmmcomp-study",
                        "interval-coverage",
                        "--json",
                        "--page",
                        "docs/results.md",
                        "--model",
                        "my model.json",
                        "--update-page",
                        "--page=p.md"};
  EXPECT_EQ(command_line(9, argv), "cmmcomp-study interval-coverage --model 'my model.json'");
}

}  // namespace
}  // namespace cmmcomp::study

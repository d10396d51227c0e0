// SPDX-License-Identifier: MIT
/// @file Tests of the JSON model file: round trip, validation of every corruption, checksum,
/// the constexpr header export and the example in docs/model-file.md.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_seed.hpp"

#if __has_include("data/models/golden_2x3x1.hpp")
#include "data/models/golden_2x3x1.hpp"
#define CMMCOMP_HAVE_GOLDEN_HEADER 1
#endif

namespace cmmcomp::io {
namespace {

/// tests/ (this file is tests/io/test_model_file.cpp), for the golden files and docs/.
std::string tests_dir() {
  std::string f = __FILE__;
  for (int up = 0; up < 2; ++up) f = f.substr(0, f.find_last_of('/'));
  return f;
}
std::string golden_json_path() { return tests_dir() + "/data/models/golden_2x3x1.json"; }
std::string golden_header_path() { return tests_dir() + "/data/models/golden_2x3x1.hpp"; }
std::string doc_path() { return tests_dir() + "/../docs/model-file.md"; }

bool regenerate() { return std::getenv("CMMCOMP_REGENERATE_GOLDEN") != nullptr; }

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}
void write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

template <int I, int S, int O>
bool bit_identical(const fuzzy::TskModel<double, I, S, O>& a,
                   const fuzzy::TskModel<double, I, S, O>& b) {
  return std::memcmp(a.params.values.data(),
                     b.params.values.data(),
                     sizeof(double) * a.params.values.size()) == 0 &&
         std::memcmp(a.ranges.data(), b.ranges.data(), sizeof(fuzzy::InputRange) * I) == 0;
}

template <int I, int S, int O>
void expect_same(const ModelFile<I, S, O>& a, const ModelFile<I, S, O>& b) {
  EXPECT_TRUE(bit_identical(a.model, b.model));
  EXPECT_EQ(a.input_names, b.input_names);
  EXPECT_EQ(a.input_units, b.input_units);
  EXPECT_EQ(a.output_names, b.output_names);
  EXPECT_EQ(a.output_units, b.output_units);
  EXPECT_EQ(a.training, b.training);
  EXPECT_EQ(a.interval, b.interval);
  EXPECT_EQ(a.interval_method, b.interval_method);
  EXPECT_EQ(a.interval_samples, b.interval_samples);
}

ModelMetadata metadata(int outputs) {
  ModelMetadata t;
  t.data_file_sha256 = sha256_hex("golden dataset");
  t.method = "ceres-levenberg-marquardt";
  t.lambda = 1e-6;
  for (int o = 0; o < outputs; ++o) t.cv_rmse.push_back(0.25 * (o + 1) + 1.0 / 3.0);
  t.trained_at = "2024-05-01T12:00:00Z";
  t.seed = 20190601u;
  t.tool_version = "cmmcomp-train 0.1.0 (test)";
  return t;
}

/// A random valid model, with awkward doubles (-0, subnormals, huge, 17-digit) mixed in.
template <int I, int S, int O>
ModelFile<I, S, O> random_model(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> n(0.0, 10.0);
  ModelFile<I, S, O> f;
  for (std::size_t i = 0; i < static_cast<std::size_t>(I); ++i) {
    f.model.ranges[i].lo = -100.0 + 200.0 * u(rng);
    f.model.ranges[i].hi = f.model.ranges[i].lo + 0.1 + 200.0 * u(rng);
    f.input_names[i] = "in" + std::to_string(i);
    f.input_units[i] = i == 0 ? "\xc2\xb5m \"quoted\" \\ slash" : "mm/s";
  }
  for (std::size_t o = 0; o < static_cast<std::size_t>(O); ++o) {
    f.output_names[o] = "out" + std::to_string(o);
    f.output_units[o] = "um";
  }
  const double specials[] = {-0.0,
                             4.9406564584124654e-324,
                             2.2250738585072014e-308,
                             1e300,
                             -1.7976931348623157e308 / 4,
                             0.1 + 0.2,
                             1.0 / 3.0,
                             123456789.0};
  if (u(rng) < 0.5) {  // half of them carry an interval calibration
    f.interval.coverage = 0.5 + 0.49 * u(rng);
    for (std::size_t o = 0; o < static_cast<std::size_t>(O); ++o) {
      f.interval.half_width[o] = 10.0 * u(rng);
      f.interval.extrapolation_gain[o] = o == 0 ? 0.0 : 3.0 * u(rng);
    }
    f.interval_method = "split-conformal (test)";
    f.interval_samples = 1 + static_cast<std::uint64_t>(100 * u(rng));
  }
  auto& p = f.model.params;
  for (int i = 0; i < I; ++i) {
    for (int s = 0; s < S; ++s) {
      p.centre(i, s) = -0.2 + 1.4 * u(rng);
      p.width(i, s) = 0.01 + u(rng);
    }
  }
  for (int o = 0; o < O; ++o) {
    for (int j = 0; j < p.kRules; ++j) {
      for (int k = 0; k <= I; ++k) {
        const double r = u(rng);
        p.consequent(o, j, k) = r < 0.05 ? specials[static_cast<std::size_t>(r * 160)] : n(rng);
      }
    }
  }
  p.width(0, 0) = 4.9406564584124654e-324;  // smallest positive width is still valid
  f.training = metadata(O);
  f.training.seed = rng();
  return f;
}

/// The golden model: 2 inputs × 3 sets × 1 output, values fixed and exactly reproducible.
ModelFile<2, 3, 1> golden_model() {
  ModelFile<2, 3, 1> f;
  f.model.ranges = {{{10.0, 80.0}, {1.0, 20.0}}};
  f.input_names = {"pv_mm_s", "av_mm_s"};
  f.input_units = {"mm/s", "mm/s"};
  f.output_names = {"mpe_um"};
  f.output_units = {"um"};
  auto& p = f.model.params;
  const double centres[2][3] = {{0.0, 0.5, 1.0}, {0.1, 0.5, 0.9}};
  const double widths[2][3] = {{0.3, 0.3, 0.3}, {0.25, 0.5, 0.75}};
  for (int i = 0; i < 2; ++i) {
    for (int s = 0; s < 3; ++s) {
      p.centre(i, s) = centres[i][s];
      p.width(i, s) = widths[i][s];
    }
  }
  for (int j = 0; j < p.kRules; ++j) {
    for (int k = 0; k <= 2; ++k) {
      p.consequent(0, j, k) = ((j * 7 + k * 3) % 11 - 5) + 0.1 * (k + 1) + (j == 4 ? 1.0 / 3.0 : 0);
    }
  }
  f.training = metadata(1);
  return f;
}

/// The example in docs/model-file.md: 1 input × 2 sets × 1 output.
ModelFile<1, 2, 1> doc_example_model() {
  ModelFile<1, 2, 1> f;
  f.model.ranges = {{{5.0, 80.0}}};
  f.input_names = {"pv_mm_s"};
  f.input_units = {"mm/s"};
  f.output_names = {"mpe_um"};
  f.output_units = {"um"};
  auto& p = f.model.params;
  p.centre(0, 0) = 0.0;
  p.centre(0, 1) = 1.0;
  p.width(0, 0) = 0.5;
  p.width(0, 1) = 0.5;
  p.consequent(0, 0, 0) = 1.25;
  p.consequent(0, 0, 1) = 2.0;
  p.consequent(0, 1, 0) = 3.5;
  p.consequent(0, 1, 1) = -0.75;
  f.training.data_file_sha256 = sha256_hex("pv_mm_s,mpe_um\n");
  f.training.method = "ceres-levenberg-marquardt";
  f.training.lambda = 0.001;
  f.training.cv_rmse = {0.31};
  f.training.trained_at = "2024-05-01T12:00:00Z";
  f.training.seed = 42;
  f.training.tool_version = "cmmcomp-train 0.1.0";
  return f;
}

/// `text` with the first occurrence of `from` replaced by `to` (which must exist).
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "test bug: '" << from << "' not in the text";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

/// The ConfigError message parsing `text` as <2,3,1> gives ("" if it loads).
std::string error_of(const std::string& text) {
  try {
    (void)parse_model_json<2, 3, 1>(text, "model.json");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

#define EXPECT_REJECTED(text, fragment)                                \
  do {                                                                 \
    const std::string message_ = error_of(text);                       \
    EXPECT_NE(message_.find(fragment), std::string::npos)              \
        << "expected '" << (fragment) << "' in: '" << message_ << "'"; \
    EXPECT_EQ(message_.rfind("model.json: ", 0), 0u) << message_;      \
  } while (false)

TEST(Sha256, KnownVectors) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256_hex(std::string(1000000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(ModelFile, UtcTimestampIsIso8601) {
  const std::string now = utc_timestamp_now();
  ModelFile<1, 2, 1> f = doc_example_model();
  f.training.trained_at = now;
  EXPECT_NO_THROW((void)format_model_json(f)) << now;
}

template <int I, int S, int O>
void round_trip_random(int count) {
  SCOPED_TRACE(test::seed_message());
  std::mt19937_64 rng(test::seed() + static_cast<std::uint64_t>(I * 100 + S * 10 + O));
  for (int c = 0; c < count; ++c) {
    const ModelFile<I, S, O> original = random_model<I, S, O>(rng);
    const std::string text = format_model_json(original);
    const ModelFile<I, S, O> back = parse_model_json<I, S, O>(text, "random.json");
    expect_same(original, back);
    EXPECT_EQ(back.checksum.size(), 64u);
    EXPECT_EQ(back.model_id, back.checksum.substr(0, 16));
    EXPECT_EQ(format_model_json(back), text);  // writing is deterministic
  }
}

TEST(ModelFile, RoundTripIsBitIdenticalFourOutputNetwork) {
  round_trip_random<4, 3, 4>(test::soak_count(20));
}
TEST(ModelFile, RoundTripIsBitIdenticalPaperNetwork) {
  round_trip_random<4, 3, 1>(test::soak_count(20));
}
TEST(ModelFile, RoundTripIsBitIdenticalFiveInputs) {
  round_trip_random<5, 3, 4>(test::soak_count(5));
}
TEST(ModelFile, RoundTripIsBitIdenticalSmall) { round_trip_random<2, 3, 1>(test::soak_count(50)); }

TEST(ModelFile, FiveInputNetworkHas243Rules) {
  std::mt19937_64 rng(test::seed());
  const std::string text = format_model_json(random_model<5, 3, 4>(rng));
  EXPECT_NE(text.find("\"rules\": 243"), std::string::npos);
  EXPECT_NE(text.find("\"parameter_count\": 5862"), std::string::npos);
  const ModelArchitecture a = read_model_architecture(text, "m.json");
  EXPECT_EQ(a.inputs, 5);
  EXPECT_EQ(a.sets_per_input, 3);
  EXPECT_EQ(a.outputs, 4);
}

TEST(ModelFile, StructuredArraysFollowTheFlatLayout) {
  const std::string text = format_model_json(golden_model());
  EXPECT_NE(text.find("\"centres\": [\n      [0.0, 0.5, 1.0],\n      [0.1, 0.5, 0.9]\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("\"widths\": [\n      [0.3, 0.3, 0.3],\n      [0.25, 0.5, 0.75]\n"),
            std::string::npos);
  // Every nested element against the typed accessors (tsk_params.hpp), on a 4 x 3 x 4 model.
  std::mt19937_64 rng(test::seed());
  const ModelFile<4, 3, 4> f = random_model<4, 3, 4>(rng);
  const nlohmann::json doc = nlohmann::json::parse(format_model_json(f));
  const nlohmann::json& params = doc.at("parameters");
  const auto& p = f.model.params;
  for (int i = 0; i < 4; ++i) {
    for (int s = 0; s < 3; ++s) {
      const auto ui = static_cast<std::size_t>(i);
      const auto us = static_cast<std::size_t>(s);
      EXPECT_EQ(params.at("centres").at(ui).at(us).get<double>(), p.centre(i, s));
      EXPECT_EQ(params.at("widths").at(ui).at(us).get<double>(), p.width(i, s));
    }
  }
  for (int o = 0; o < 4; ++o) {
    for (int j = 0; j < 81; ++j) {
      for (int k = 0; k < 5; ++k) {
        const double v = params.at("consequents")
                             .at(static_cast<std::size_t>(o))
                             .at(static_cast<std::size_t>(j))
                             .at(static_cast<std::size_t>(k))
                             .get<double>();
        EXPECT_EQ(std::memcmp(&v, &p.consequent(o, j, k), sizeof v), 0)
            << o << " " << j << " " << k;
      }
    }
  }
}

TEST(ModelFile, ChecksumIsSha256OfTheSortedCompactDumpWithoutChecksum) {
  const std::string text = format_model_json(golden_model());
  nlohmann::json doc = nlohmann::json::parse(text);
  const std::string stored = doc.at("checksum").get<std::string>();
  doc.erase("checksum");
  EXPECT_EQ(stored, sha256_hex(doc.dump()));
  EXPECT_EQ((parse_model_json<2, 3, 1>(text, "m.json").model_id), stored.substr(0, 16));
}

// ----------------------------------------------------------------------------------------------
// Rejections.

TEST(ModelFileRejects, EveryChangedDigit) {
  const std::string text = format_model_json(golden_model());
  int digits = 0;
  for (std::size_t at = 0; at < text.size(); ++at) {
    const char c = text[at];
    if (c < '0' || c > '9') continue;
    for (char to : {static_cast<char>('0' + (c - '0' + 1) % 10),
                    static_cast<char>('0' + (c - '0' + 9) % 10)}) {
      std::string bad = text;
      bad[at] = to;
      EXPECT_NE(error_of(bad), "") << "digit at byte " << at << " changed to " << to << " loads";
    }
    ++digits;
  }
  EXPECT_GT(digits, 250);
}

TEST(ModelFileRejects, ChangedValueAsChecksumMismatch) {
  const std::string text = format_model_json(golden_model());
  EXPECT_REJECTED(replaced(text, "[0.25, 0.5, 0.75]", "[0.25, 0.5, 0.76]"), "checksum mismatch");
  EXPECT_REJECTED(replaced(text, "\"seed\": 20190601", "\"seed\": 20190602"), "checksum mismatch");
  EXPECT_REJECTED(replaced(text, "\"name\": \"pv_mm_s\"", "\"name\": \"pv_mm_S\""),
                  "checksum mismatch");
  const std::size_t at = text.find("\"checksum\": \"") + 13;
  std::string bad = text;
  bad[at] = bad[at] == 'a' ? 'b' : 'a';
  EXPECT_REJECTED(bad, "checksum mismatch");
  EXPECT_REJECTED(replaced(text, "\"checksum\": \"", "\"checksum\": \"0"), "not 64 lower-case hex");
}

TEST(ModelFileRejects, SameValueWrittenDifferently) {
  const std::string text = format_model_json(golden_model());
  EXPECT_REJECTED(replaced(text, "[0.25, 0.5, 0.75]", "[0.25, 0.50, 0.75]"),
                  "parameters.widths[1][1]: number '0.50' is not written as this library");
  EXPECT_REJECTED(replaced(text, "[0.25, 0.5, 0.75]", "[2.5e-1, 0.5, 0.75]"), "'2.5e-1'");
  // A 17th digit that does not change the double is caught too.
  const std::string sum = "0.30000000000000004";
  ASSERT_NE(text.find(sum), std::string::npos) << text;
  EXPECT_EQ(0.1 + 0.2, 0.30000000000000005);
  EXPECT_REJECTED(replaced(text, sum, "0.30000000000000005"), "is not written as this library");
}

TEST(ModelFileRejects, NotJsonOrTruncated) {
  const std::string text = format_model_json(golden_model());
  EXPECT_REJECTED("", "not valid JSON");
  EXPECT_REJECTED("hello", "not valid JSON (truncated or corrupted?) at byte 1");
  EXPECT_REJECTED("[1, 2]", "a model file is a JSON object, got array");
  for (std::size_t n = 0; n + 1 < text.size(); n += 53) {
    EXPECT_REJECTED(text.substr(0, n), "not valid JSON");
  }
  EXPECT_REJECTED(text.substr(0, text.size() - 3), "not valid JSON");
  EXPECT_REJECTED(replaced(text, "\"format\"", "format"), "at byte 6");
}

TEST(ModelFileRejects, WrongFormatOrVersion) {
  const std::string text = format_model_json(golden_model());
  EXPECT_REJECTED(replaced(text, "cmmcomp-tsk-model", "cmmcomp-machine"),
                  "format is 'cmmcomp-machine', expected 'cmmcomp-tsk-model'");
  EXPECT_REJECTED(replaced(text, "\"format_version\": 4", "\"format_version\": 5"),
                  "format_version 5 is not supported (this library reads versions 1 to 4)");
  EXPECT_REJECTED(replaced(text, "\"format_version\": 4", "\"format_version\": \"4\""),
                  "format_version \"4\" is not supported");
  EXPECT_REJECTED(replaced(text, "\"format_version\": 4,", ""), "missing key 'format_version'");
  EXPECT_REJECTED(replaced(text, "\"format\": \"cmmcomp-tsk-model\",", ""), "missing key 'format'");
}

/// `text` (a model file) re-signed: its checksum recomputed after an edit, so the test
/// reaches the check it means instead of stopping at the checksum.
std::string resigned(const std::string& text) {
  nlohmann::ordered_json doc = nlohmann::ordered_json::parse(text);
  doc.erase("checksum");
  const nlohmann::json sorted = nlohmann::json::parse(doc.dump());
  doc["checksum"] = sha256_hex(sorted.dump());
  return doc.dump(2);
}

/// The golden model written as format version 1 (no `uncertainty` key), as the library before
/// the interval wrote it.
std::string version_1_text() {
  nlohmann::ordered_json doc = nlohmann::ordered_json::parse(format_model_json(golden_model()));
  doc["format_version"] = 1;
  doc.erase("uncertainty");
  doc.erase("conditions");
  return resigned(doc.dump());
}

TEST(ModelFile, Version1StillLoadsWithNoUncertainty) {
  const ModelFile<2, 3, 1> f = parse_model_json<2, 3, 1>(version_1_text(), "v1.json");
  EXPECT_EQ(f.format_version, kModelFileVersionNoUncertainty);
  EXPECT_FALSE(f.interval.available());
  EXPECT_TRUE(bit_identical(f.model, golden_model().model));
  EXPECT_EQ(f.training, golden_model().training);
  // A version-1 file may not carry the version-2 key, even null.
  nlohmann::ordered_json doc = nlohmann::ordered_json::parse(version_1_text());
  doc["uncertainty"] = nullptr;
  EXPECT_REJECTED(resigned(doc.dump()), "unknown key 'uncertainty'");
}

TEST(ModelFile, RequiresTheUncertaintyKey) {
  nlohmann::ordered_json doc = nlohmann::ordered_json::parse(format_model_json(golden_model()));
  doc.erase("uncertainty");
  EXPECT_REJECTED(resigned(doc.dump()), "missing key 'uncertainty'");
}

ModelFile<2, 3, 1> calibrated_golden_model() {
  ModelFile<2, 3, 1> f = golden_model();
  f.interval.coverage = 0.95;
  f.interval.half_width = {0.75};
  f.interval.extrapolation_gain = {1.5};
  f.interval.corner_gain = {0.5};
  f.interval_method = "split-conformal (test)";
  f.interval_samples = 54;
  return f;
}

/// The calibrated golden model written as format version 2 (no `corner_gain`), as the library
/// before the corner gain wrote it.
std::string version_2_text() {
  nlohmann::ordered_json doc =
      nlohmann::ordered_json::parse(format_model_json(calibrated_golden_model()));
  doc["format_version"] = 2;
  doc["uncertainty"].erase("corner_gain");
  doc.erase("conditions");
  return resigned(doc.dump());
}

TEST(ModelFile, Version2StillLoadsWithNoCornerGain) {
  const ModelFile<2, 3, 1> f = parse_model_json<2, 3, 1>(version_2_text(), "v2.json");
  EXPECT_EQ(f.format_version, kModelFileVersionNoCornerGain);
  ASSERT_TRUE(f.interval.available());
  EXPECT_EQ(f.interval.half_width[0], 0.75);
  EXPECT_EQ(f.interval.extrapolation_gain[0], 1.5);
  EXPECT_EQ(f.interval.corner_gain[0], 0.0);
  // A version-2 file may not carry the version-3 key.
  nlohmann::ordered_json doc = nlohmann::ordered_json::parse(version_2_text());
  doc["uncertainty"]["corner_gain"] = {0.5};
  EXPECT_REJECTED(resigned(doc.dump()), "unknown key 'uncertainty.corner_gain'");
  // The shipped default model as it was written in version 2 (before the corner gain) loads.
  const auto v2 = load_model_file<4, 3, 4>(tests_dir() + "/data/models/default-v2.json");
  EXPECT_EQ(v2.format_version, kModelFileVersionNoCornerGain);
  EXPECT_TRUE(v2.interval.available());
  for (double k : v2.interval.corner_gain) EXPECT_EQ(k, 0.0);
}

ModelFile<2, 3, 1> conditioned_golden_model() {
  ModelFile<2, 3, 1> f = golden_model();
  f.conditions.pa_mm_s2 = ConditionRange{200.0, 200.0};
  f.conditions.aa_mm_s2 = ConditionRange{40.0, 80.0};
  f.conditions.dwell_s = 1.128;
  f.conditions.smoothing_s = 0.099;
  f.conditions.axis = "x";
  f.conditions.machine = "paper-default";
  f.conditions.noise_floor = {1.321};
  return f;
}

TEST(ModelFileConditions, RoundTripAndUnknown) {
  const ModelFile<2, 3, 1> f = conditioned_golden_model();
  const std::string text = format_model_json(f);
  const ModelFile<2, 3, 1> back = parse_model_json<2, 3, 1>(text, "c.json");
  EXPECT_EQ(back.conditions, f.conditions);
  EXPECT_FALSE(back.conditions.unknown());
  EXPECT_EQ(format_model_json(back), text);
  // Nothing known: every key present and null.
  const std::string bare = format_model_json(golden_model());
  EXPECT_NE(bare.find("\"conditions\": {\"pa_mm_s2\": null, \"aa_mm_s2\": null, \"dwell_s\": null"),
            std::string::npos)
      << bare;
  const auto bare_file = parse_model_json<2, 3, 1>(bare, "b.json");
  EXPECT_TRUE(bare_file.conditions.unknown());
  // The conditions are covered by the checksum: another dwell is another model.
  ModelFile<2, 3, 1> other = f;
  other.conditions.dwell_s = 0.5;
  const auto other_file = parse_model_json<2, 3, 1>(format_model_json(other), "o.json");
  EXPECT_NE(other_file.model_id, back.model_id);
}

TEST(ModelFileConditions, Version3LoadsWithEveryConditionUnknown) {
  nlohmann::ordered_json doc =
      nlohmann::ordered_json::parse(format_model_json(conditioned_golden_model()));
  doc["format_version"] = 3;
  doc.erase("conditions");
  const ModelFile<2, 3, 1> f = parse_model_json<2, 3, 1>(resigned(doc.dump()), "v3.json");
  EXPECT_EQ(f.format_version, kModelFileVersionNoConditions);
  EXPECT_TRUE(f.conditions.unknown());
  // A version-3 file may not carry the version-4 key; a version-4 file must.
  doc["conditions"] = nullptr;
  EXPECT_REJECTED(resigned(doc.dump()), "unknown key 'conditions'");
  nlohmann::ordered_json v4 =
      nlohmann::ordered_json::parse(format_model_json(conditioned_golden_model()));
  v4.erase("conditions");
  EXPECT_REJECTED(resigned(v4.dump()), "missing key 'conditions'");
}

TEST(ModelFileConditions, BadValuesAreRefusedNamingTheKey) {
  const auto rejected = [](const std::function<void(nlohmann::ordered_json&)>& edit) {
    nlohmann::ordered_json doc =
        nlohmann::ordered_json::parse(format_model_json(conditioned_golden_model()));
    edit(doc["conditions"]);
    return error_of(resigned(doc.dump()));
  };
  EXPECT_NE(rejected([](auto& c) {
              c["pa_mm_s2"]["lo"] = 300.0;
            }).find("conditions.pa_mm_s2 = [300, 200] must be finite with 0 < lo <= hi"),
            std::string::npos);
  EXPECT_NE(rejected([](auto& c) { c["aa_mm_s2"]["lo"] = 0.0; }).find("conditions.aa_mm_s2"),
            std::string::npos);
  EXPECT_NE(rejected([](auto& c) {
              c["dwell_s"] = -0.1;
            }).find("conditions.dwell_s = -0.1 must be finite and >= 0"),
            std::string::npos);
  EXPECT_NE(rejected([](auto& c) {
              c["noise_floor"] = {1.0, 2.0};
            }).find("conditions.noise_floor"),
            std::string::npos);
  EXPECT_NE(rejected([](auto& c) { c["axis"] = ""; }).find("conditions.axis is empty"),
            std::string::npos);
  EXPECT_NE(rejected([](auto& c) { c["smoothing"] = 0.1; }).find("unknown key"), std::string::npos);
  EXPECT_NE(rejected([](auto& c) { c.erase("machine"); }).find("missing key 'conditions.machine'"),
            std::string::npos);
  // The writer refuses what the reader would.
  ModelFile<2, 3, 1> bad = conditioned_golden_model();
  bad.conditions.smoothing_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(format_model_json(bad), ConfigError);
}

TEST(ModelFileConditions, ExportsCarryThePaAndAa) {
  const std::string header = export_model_header(conditioned_golden_model(), "m");
  EXPECT_NE(header.find("inline constexpr cmmcomp::compensation::Conditions m_conditions = "
                        "{{200.0, 200.0}, {40.0, 80.0}};"),
            std::string::npos)
      << header;
  EXPECT_NE(
      header.find(
          "/// conditions: PA 200.0..200.0 mm/s2, AA 40.0..80.0 mm/s2, dwell 1.1279999999999999 s"),
      std::string::npos)
      << header;
  const std::string unknown = export_model_header(golden_model(), "m");
  EXPECT_NE(unknown.find("m_conditions = {{0.0, 0.0}, {0.0, 0.0}};"), std::string::npos);
}

TEST(ModelFile, Version3RequiresTheCornerGain) {
  nlohmann::ordered_json doc =
      nlohmann::ordered_json::parse(format_model_json(calibrated_golden_model()));
  doc["uncertainty"].erase("corner_gain");
  EXPECT_REJECTED(resigned(doc.dump()), "missing key 'uncertainty.corner_gain'");
}

TEST(ModelFile, RoundTripKeepsTheCalibration) {
  const ModelFile<2, 3, 1> f = calibrated_golden_model();
  const std::string text = format_model_json(f);
  EXPECT_NE(text.find("\"uncertainty\": {"), std::string::npos) << text;
  const ModelFile<2, 3, 1> back = parse_model_json<2, 3, 1>(text, "v2.json");
  EXPECT_EQ(back.format_version, kModelFileVersion);
  expect_same(back, f);
  EXPECT_TRUE(back.interval.available());
  EXPECT_EQ(format_model_json(back), text);
  // The calibration is covered by the checksum.
  EXPECT_REJECTED(replaced(text, "0.75", "0.76"), "checksum mismatch");
}

TEST(ModelFileRejects, CorruptUncertainty) {
  const std::string text = format_model_json(calibrated_golden_model());
  const auto edit = [&](const std::string& from, const std::string& to) {
    return resigned(replaced(text, from, to));
  };
  EXPECT_REJECTED(edit("\"coverage\": 0.95", "\"coverage\": 1.5"), "uncertainty.coverage = 1.5");
  EXPECT_REJECTED(edit("\"coverage\": 0.95", "\"coverage\": 0"),
                  "uncertainty.coverage = 0 (write null for no calibration)");
  EXPECT_REJECTED(edit("\"half_width\": [0.75]", "\"half_width\": [-0.75]"),
                  "uncertainty.half_width[0] = -0.75 must be finite and >= 0");
  EXPECT_REJECTED(edit("\"half_width\": [0.75]", "\"half_width\": [0.75, 1]"),
                  "uncertainty.half_width");
  EXPECT_REJECTED(edit("\"extrapolation_gain\": [1.5]", "\"extrapolation_gain\": [-1]"),
                  "uncertainty.extrapolation_gain[0] = -1");
  EXPECT_REJECTED(edit("\"corner_gain\": [0.5]", "\"corner_gain\": [-0.5]"),
                  "uncertainty.corner_gain[0] = -0.5 must be finite and >= 0");
  EXPECT_REJECTED(edit("\"corner_gain\": [0.5]", "\"corner_gain\": [0.5, 1]"),
                  "uncertainty.corner_gain");
  EXPECT_REJECTED(edit("\"calibration_samples\": 54", "\"calibration_samples\": 0"),
                  "uncertainty.calibration_samples must be > 0");
  EXPECT_REJECTED(edit("\"method\": \"split-conformal (test)\"", "\"method\": \"\""),
                  "uncertainty.method is empty");
  EXPECT_REJECTED(edit("\"coverage\": 0.95", "\"coverage_\": 0.95"), "coverage_");
  nlohmann::ordered_json doc = nlohmann::ordered_json::parse(text);
  doc["uncertainty"] = 5;
  EXPECT_REJECTED(resigned(doc.dump()), "uncertainty");
  // Writing refuses an invalid calibration too.
  ModelFile<2, 3, 1> bad = calibrated_golden_model();
  bad.interval.half_width = {std::nan("")};
  EXPECT_THROW((void)format_model_json(bad), ConfigError);
}

TEST(ModelFileRejects, ArchitectureMismatchNamesBoth) {
  const std::string text = format_model_json(golden_model());
  try {
    (void)parse_model_json<4, 3, 4>(text, "model.json");
    FAIL() << "loaded";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(),
                 "model.json: architecture is 2 inputs x 3 sets x 1 outputs, but this program "
                 "expects 4 x 3 x 4");
  }
  EXPECT_REJECTED(replaced(text, "\"sets_per_input\": 3", "\"sets_per_input\": 2"),
                  "architecture.rules = 9 but sets_per_input^inputs = 4");
  EXPECT_REJECTED(replaced(text, "\"parameter_count\": 39", "\"parameter_count\": 40"),
                  "architecture.parameter_count = 40 but the sizes give 39");
  EXPECT_REJECTED(replaced(text, "\"gaussian\"", "\"triangular\""), "only 'gaussian'");
  EXPECT_REJECTED(replaced(text, "\"first-order\"", "\"zero-order\""), "only 'first-order'");
  EXPECT_REJECTED(replaced(text, "\"inputs\": 2,", "\"inputs\": 0,"),
                  "architecture.inputs = 0 is out of range");
  EXPECT_REJECTED(replaced(text, "\"inputs\": 2,", "\"inputs\": 2.0,"),
                  "architecture.inputs must be an integer, got number 2.0");
}

TEST(ModelFileRejects, MissingOrUnknownKeysAreNamed) {
  const std::string text = format_model_json(golden_model());
  EXPECT_REJECTED(replaced(text, "\"method\": \"ceres-levenberg-marquardt\",", ""),
                  "missing key 'training.method'");
  EXPECT_REJECTED(replaced(text, ", \"unit\": \"mm/s\"", ""), "missing key 'inputs[0].unit'");
  EXPECT_REJECTED(replaced(text, ", \"hi\": 80.0", ""), "missing key 'inputs[0].hi'");
  EXPECT_REJECTED(replaced(text, "\"lambda\": ", "\"lambda_\": "),
                  "unknown key 'training.lambda_'");
  EXPECT_REJECTED(replaced(text, "\"format\": ", "\"comment\": \"x\", \"format\": "),
                  "unknown key 'comment'");
  EXPECT_REJECTED(replaced(text, "\"centres\": ", "\"centers\": "),
                  "unknown key 'parameters.centers'");
  EXPECT_REJECTED(replaced(text, "\"checksum\": ", "\"checksum_\": "), "unknown key 'checksum_'");
  const std::size_t at = text.find(",\n  \"checksum\"");
  ASSERT_NE(at, std::string::npos);
  EXPECT_REJECTED(text.substr(0, at) + "\n}\n", "missing key 'checksum'");
  EXPECT_REJECTED(replaced(text, "\"method\": ", "\"method\": \"x\", \"method\": "),
                  "key 'training.method' occurs twice");
}

TEST(ModelFileRejects, WrongArrayLengthsAndTypes) {
  const std::string text = format_model_json(golden_model());
  EXPECT_REJECTED(replaced(text, "[0.25, 0.5, 0.75]", "[0.25, 0.5]"),
                  "parameters.widths[1] has 2 elements, expected 3");
  EXPECT_REJECTED(replaced(text, "[0.25, 0.5, 0.75]", "0.25"),
                  "parameters.widths[1] must be an array, got number 0.25");
  EXPECT_REJECTED(replaced(text, "\"cv_rmse\": [", "\"cv_rmse\": [1.0, "),
                  "training.cv_rmse has 2 elements, expected 1");
  EXPECT_REJECTED(
      replaced(text, "\"outputs\": [\n", "\"outputs\": [{\"name\": \"x\", \"unit\": \"\"},\n"),
      "outputs has 2 elements, expected 1");
  EXPECT_REJECTED(replaced(text, "\"seed\": 20190601", "\"seed\": -1"),
                  "training.seed must be an integer >= 0, got number -1");
  EXPECT_REJECTED(replaced(text, "\"name\": \"pv_mm_s\"", "\"name\": 7"),
                  "inputs[0].name must be a string, got number 7");
}

TEST(ModelFileRejects, BadValues) {
  const std::string text = format_model_json(golden_model());
  EXPECT_REJECTED(replaced(text, "[0.25, 0.5, 0.75]", "[0.25, -0.3, 0.75]"),
                  "model.json: parameters.widths[1][1] = -0.3 must be > 0");
  EXPECT_REJECTED(replaced(text, "[0.25, 0.5, 0.75]", "[0.25, 0.0, 0.75]"),
                  "parameters.widths[1][1] = 0 must be > 0");
  EXPECT_REJECTED(replaced(text, "[0.25, 0.5, 0.75]", "[0.25, \"NaN\", 0.75]"),
                  "parameters.widths[1][1] must be a number, got string \"NaN\"");
  EXPECT_REJECTED(replaced(text, "[0.25, 0.5, 0.75]", "[0.25, null, 0.75]"),
                  "parameters.widths[1][1] must be a number, got null");
  EXPECT_REJECTED(replaced(text, "[0.25, 0.5, 0.75]", "[0.25, NaN, 0.75]"), "not valid JSON");
  EXPECT_REJECTED(
      replaced(text, "[0.0, 0.5, 1.0]", "[0.0, 1e999, 1.0]"),
      "not valid JSON: [json.exception.out_of_range.406] number overflow parsing '1e999'");
  EXPECT_REJECTED(replaced(text, "\"hi\": 80.0", "\"hi\": 10.0"),
                  "inputs[0]: lo = 10 must be < hi = 10");
  EXPECT_REJECTED(replaced(text, "\"hi\": 80.0", "\"hi\": -5.0"),
                  "inputs[0]: lo = 10 must be < hi = -5");
  EXPECT_REJECTED(replaced(text, "\"lambda\": 1e-06", "\"lambda\": -1e-06"),
                  "training.lambda = -1e-06 must be finite and >= 0");
  EXPECT_REJECTED(replaced(text, "2024-05-01T12:00:00Z", "2024-05-01 12:00:00"),
                  "training.trained_at = '2024-05-01 12:00:00' is not ISO-8601 UTC");
  EXPECT_REJECTED(replaced(text, "\"name\": \"av_mm_s\"", "\"name\": \"pv_mm_s\""),
                  "inputs[1].name 'pv_mm_s' is a duplicate");
  EXPECT_REJECTED(replaced(text, "\"name\": \"av_mm_s\"", "\"name\": \"\""),
                  "inputs[1].name is empty");
  EXPECT_REJECTED(replaced(text, "\"data_file_sha256\": \"", "\"data_file_sha256\": \"X"),
                  "training.data_file_sha256 = 'X");
}

TEST(ModelFileRejects, WritingAnInvalidModel) {
  ModelFile<2, 3, 1> f = golden_model();
  f.model.params.width(1, 2) = -0.5;
  try {
    (void)format_model_json(f);
    FAIL() << "written";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "model to write: parameters.widths[1][2] = -0.5 must be > 0");
  }
  f = golden_model();
  f.model.params.consequent(0, 3, 1) = std::nan("");
  EXPECT_THROW((void)format_model_json(f), ConfigError);
  f = golden_model();
  f.training.cv_rmse.clear();
  EXPECT_THROW((void)format_model_json(f), ConfigError);
  f = golden_model();
  f.output_units[0] = "u\nm";
  EXPECT_THROW((void)format_model_json(f), ConfigError);
  EXPECT_THROW((void)export_model_header(golden_model(), "1model"), ConfigError);
  EXPECT_THROW((void)export_model_header(golden_model(), "ns::model"), ConfigError);
}

// ----------------------------------------------------------------------------------------------
// Files.

TEST(ModelFile, SaveAndLoad) {
  const std::string path = ::testing::TempDir() + "cmmcomp_test_model_file.json";
  std::mt19937_64 rng(test::seed());
  const ModelFile<4, 3, 4> f = random_model<4, 3, 4>(rng);
  const std::string id = save_model_file(path, f);
  const ModelFile<4, 3, 4> back = load_model_file<4, 3, 4>(path);
  expect_same(f, back);
  EXPECT_EQ(back.model_id, id);
  EXPECT_EQ(read_file(path), format_model_json(f));
  EXPECT_EQ(sha256_file_hex(path), sha256_hex(read_file(path)));
  std::remove(path.c_str());
}

TEST(ModelFileRejects, FileThatCannotBeOpened) {
  const std::string path = ::testing::TempDir() + "no/such/dir/model.json";
  try {
    (void)load_model_file<4, 3, 4>(path);
    FAIL() << "loaded";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": cannot open model file (No such file or directory)");
  }
  EXPECT_THROW((void)save_model_file(path, golden_model()), Error);
  EXPECT_THROW((void)sha256_file_hex(path), ConfigError);
}

// ----------------------------------------------------------------------------------------------
// Golden files and the header export.

TEST(ModelFileGolden, JsonIsWhatTheWriterProduces) {
  const std::string text = format_model_json(golden_model());
  if (regenerate()) write_file(golden_json_path(), text);
  EXPECT_EQ(read_file(golden_json_path()), text)
      << "regenerate with CMMCOMP_REGENERATE_GOLDEN=1 if the format changed on purpose";
  expect_same(load_model_file<2, 3, 1>(golden_json_path()), golden_model());
}

TEST(ModelFileGolden, CheckedInHeaderIsWhatTheExportProduces) {
  const ModelFile<2, 3, 1> f = load_model_file<2, 3, 1>(golden_json_path());
  const std::string header = export_model_header(f, "golden_2x3x1_model");
  if (regenerate()) write_file(golden_header_path(), header);
  EXPECT_EQ(read_file(golden_header_path()), header)
      << "regenerate with CMMCOMP_REGENERATE_GOLDEN=1 if the export changed on purpose";
}

#ifdef CMMCOMP_HAVE_GOLDEN_HEADER
static_assert(golden_2x3x1_model.ranges[0].lo == 10.0, "usable in constant expressions");
static_assert(golden_2x3x1_model.params.values[1] == 0.1, "centre(1, 0): set 0, input 1");
#endif

TEST(ModelFileGolden, ConstexprModelEvaluatesBitIdentically) {
#ifndef CMMCOMP_HAVE_GOLDEN_HEADER
  FAIL() << "tests/data/models/golden_2x3x1.hpp is missing; run with CMMCOMP_REGENERATE_GOLDEN=1";
#else
  const ModelFile<2, 3, 1> f = load_model_file<2, 3, 1>(golden_json_path());
  EXPECT_TRUE(bit_identical(f.model, golden_2x3x1_model));
  EXPECT_EQ(std::string(golden_2x3x1_model_model_id), f.model_id);
  EXPECT_EQ(std::string(golden_2x3x1_model_checksum), f.checksum);
  std::mt19937_64 rng(test::seed());
  std::uniform_real_distribution<double> u(-20.0, 100.0);
  for (int n = 0; n < 2000; ++n) {
    const std::array<double, 2> x = {u(rng), u(rng)};
    std::array<double, 1> a{};
    std::array<double, 1> b{};
    const Status sa = fuzzy::evaluate(f.model, x, a, fuzzy::DomainPolicy::kExtrapolate);
    const Status sb = fuzzy::evaluate(golden_2x3x1_model, x, b, fuzzy::DomainPolicy::kExtrapolate);
    ASSERT_EQ(sa, sb);
    ASSERT_TRUE(ok(sa));
    ASSERT_EQ(std::memcmp(a.data(), b.data(), sizeof a), 0) << x[0] << " " << x[1];
  }
#endif
}

TEST(ModelFile, ExportOfLargeNetworksIsExact) {
  std::mt19937_64 rng(test::seed());
  const ModelFile<5, 3, 4> f = random_model<5, 3, 4>(rng);
  const std::string header = export_model_header(f, "m");
  EXPECT_NE(header.find("inline constexpr cmmcomp::fuzzy::TskModel<double, 5, 3, 4> m = {"),
            std::string::npos);
  EXPECT_NE(header.find("-0.0,"), std::string::npos);  // the sign of zero survives
  EXPECT_NE(header.find("4.9406564584124654e-324,"), std::string::npos);
  // Self-contained on the core: the evaluator, the interval's and the conditions' types.
  std::vector<std::string> includes;
  for (std::size_t at = header.find("#include"); at != std::string::npos;
       at = header.find("#include", at + 1)) {
    includes.push_back(header.substr(at, header.find('\n', at) - at));
  }
  EXPECT_EQ(includes,
            (std::vector<std::string>{"#include <cmmcomp/compensation/conditions.hpp>",
                                      "#include <cmmcomp/fuzzy/prediction_interval.hpp>",
                                      "#include <cmmcomp/fuzzy/tsk_evaluator.hpp>"}));
  EXPECT_NE(header.find("inline constexpr cmmcomp::fuzzy::IntervalCalibration<4> m_interval = "),
            std::string::npos);
}

// ----------------------------------------------------------------------------------------------
// The documentation.

TEST(ModelFileDoc, ExampleParses) {
  if (regenerate()) std::cout << format_model_json(doc_example_model());
  const std::string doc = read_file(doc_path());
  ASSERT_FALSE(doc.empty()) << doc_path();
  const std::string open = "```json\n";
  const std::size_t begin = doc.find(open);
  ASSERT_NE(begin, std::string::npos);
  const std::size_t end = doc.find("```", begin + open.size());
  const std::string example = doc.substr(begin + open.size(), end - begin - open.size());
  const ModelFile<1, 2, 1> f = parse_model_json<1, 2, 1>(example, "docs/model-file.md");
  expect_same(f, doc_example_model());
  EXPECT_NE(doc.find(f.model_id), std::string::npos) << "the doc should quote the model id";
}

}  // namespace
}  // namespace cmmcomp::io

namespace cmmcomp::io {
namespace {

// A model file nested 65 000 deep (130 kB) overflowed the stack when its error message dumped
// the value whole (issue 16, D1): it is refused before parsing, with a short message.
TEST(ModelFileHostile, DeepNestingIsRefusedBeforeParsing) {
  const std::string deep = std::string(65000, '[') + std::string(65000, ']');
  const std::string message = error_of(deep);
  EXPECT_NE(message.find("nested deeper than 32 levels"), std::string::npos) << message;
  EXPECT_LT(message.size(), 200u);
  const std::string deep_object = "{\"a\":" + std::string(40, '[') + std::string(40, ']') + "}";
  EXPECT_NE(error_of(deep_object).find("nested deeper"), std::string::npos);
  // Brackets inside strings do not count.
  const std::string in_string = "{\"format\": \"" + std::string(100, '[') + "\"}";
  EXPECT_EQ(error_of(in_string).find("nested deeper"), std::string::npos);
}

TEST(ModelFileHostile, OversizedTextIsRefused) {
  const std::string huge(kMaxModelFileBytes + 1, ' ');
  EXPECT_NE(error_of(huge).find("more than the 4194304 bytes"), std::string::npos);
}

}  // namespace
}  // namespace cmmcomp::io

// SPDX-License-Identifier: MIT
/// @file Golden vectors of the shipped models: the inputs, and the host's statuses and output
/// bits (docs/firmware.md, "Golden vectors"). One generator, used to write the committed file
/// on the host and to check it on every target (host, aarch64 under qemu-aarch64, Cortex-M7
/// under qemu-system-arm), so the list of cases cannot drift between them.
///
/// Needs only the core and <cstdio>: it runs on bare metal with newlib and semihosting.
#pragma once

#include <cinttypes>
#include <cmmcomp/detail/splitmix64.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/status.hpp>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "default-float.hpp"  // data/models/: cmmcomp-train export --scalar float of default.json
#include "default-y.hpp"      // data/models/: cmmcomp-train export of default-y.json
#include "default.hpp"        // data/models/: cmmcomp-train export of default.json

namespace cmmcomp::golden {

static_assert(!fuzzy::find_problem(default_model), "the shipped 4-input model is valid");
static_assert(!fuzzy::find_problem(default_y_model), "the shipped 5-input model is valid");

/// The float forms of the shipped models: the exported float header, and a compile-time
/// conversion for the 5-input one (read-only memory either way).
inline constexpr const auto& kDefaultModelF = default_model_f;
inline constexpr auto kDefaultYModelF = fuzzy::convert_model<float>(default_y_model);

/// Largest |float − double| accepted on an output [µm] for an input inside the model's
/// ranges (or clamped into them): the and docs/firmware.md's limit.
inline constexpr double kFloatToleranceUm = 1e-3;

/// True when `a` and `b` hold the same ranges and parameters.
template <typename Model>
constexpr bool same_model(const Model& a, const Model& b) {
  for (std::size_t i = 0; i < a.ranges.size(); ++i) {
    if (a.ranges[i].lo != b.ranges[i].lo || a.ranges[i].hi != b.ranges[i].hi) return false;
  }
  for (std::size_t k = 0; k < a.params.values.size(); ++k) {
    if (a.params.values[k] != b.params.values[k]) return false;
  }
  return true;
}
// The exported float header holds exactly what the compile-time conversion gives.
static_assert(same_model(default_model_f, fuzzy::convert_model<float>(default_model)),
              "export --scalar float rounds each parameter to the nearest float");

/// Header of the CSV file; every value a bit pattern in hex, so no target's printf or strtod
/// is trusted with a decimal conversion. The decimal columns after it are for people only.
inline constexpr char kHeader[] =
    "model,scalar,policy,x0,x1,x2,x3,x4,status,mpe,rpe,mae,rae,"
    "mpe_um_decimal,rpe_um_decimal,mae_um_decimal,rae_um_decimal";

/// One case: a shipped model (0: default, 1: default-y), a precision, a policy and the raw
/// inputs (x4 unused, 0, by the 4-input model).
struct Case {
  int model = 0;
  bool single = false;  ///< float model
  fuzzy::DomainPolicy policy = fuzzy::DomainPolicy::kClamp;
  double x[5] = {0, 0, 0, 0, 0};
};

/// The result of a case on this target.
struct Result {
  Status status = Status::kOk;
  double y[4] = {0, 0, 0, 0};  ///< 0 where the evaluator left the output untouched
};

inline const char* model_name(int model) { return model == 0 ? "default" : "default-y"; }
inline int inputs_of(int model) { return model == 0 ? 4 : 5; }

inline std::uint64_t bits(double v) {
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}
inline double from_bits(std::uint64_t b) {
  double v;
  std::memcpy(&v, &b, sizeof v);
  return v;
}

inline Result run(const Case& c) {
  Result r;
  std::array<double, 4> y{0, 0, 0, 0};
  if (c.model == 0) {
    const std::array<double, 4> x{c.x[0], c.x[1], c.x[2], c.x[3]};
    r.status = c.single ? fuzzy::evaluate(kDefaultModelF, x, y, c.policy)
                        : fuzzy::evaluate(default_model, x, y, c.policy);
  } else {
    const std::array<double, 5> x{c.x[0], c.x[1], c.x[2], c.x[3], c.x[4]};
    r.status = c.single ? fuzzy::evaluate(kDefaultYModelF, x, y, c.policy)
                        : fuzzy::evaluate(default_y_model, x, y, c.policy);
  }
  for (int o = 0; o < 4; ++o) r.y[o] = y[static_cast<unsigned>(o)];
  return r;
}

inline const fuzzy::InputRange& range_of(int model, int input) {
  return model == 0 ? default_model.ranges[static_cast<unsigned>(input)]
                    : default_y_model.ranges[static_cast<unsigned>(input)];
}

/// Calls `visit(const Case&)` for every case, in the file's order: for each model and
/// precision, the 3^n grid of (lo, mid, hi) under kClamp; then, under each policy, 16 seeded
/// random points over the ranges widened by 25 % each side, and for each input in turn NaN,
/// +inf, −inf, +1e300, −1e300 and 0 with the others at mid-range.
template <typename Visit>
void for_each_case(Visit&& visit) {
  for (int model = 0; model < 2; ++model) {
    const int n = inputs_of(model);
    for (int single = 0; single < 2; ++single) {
      Case c;
      c.model = model;
      c.single = single != 0;
      const auto mid = [&](int i) { return 0.5 * (range_of(model, i).lo + range_of(model, i).hi); };
      int grid = 1;
      for (int i = 0; i < n; ++i) grid *= 3;
      for (int g = 0; g < grid; ++g) {
        int code = g;
        for (int i = n - 1; i >= 0; --i) {
          const fuzzy::InputRange& r = range_of(model, i);
          const int level = code % 3;
          code /= 3;
          c.x[i] = level == 0 ? r.lo : (level == 1 ? mid(i) : r.hi);
        }
        c.policy = fuzzy::DomainPolicy::kClamp;
        visit(c);
      }
      for (const fuzzy::DomainPolicy policy : fuzzy::kDomainPolicies) {
        c.policy = policy;
        detail::SplitMix64 rng{0x5eed0000u + static_cast<std::uint64_t>(model)};
        for (int k = 0; k < 16; ++k) {
          for (int i = 0; i < 5; ++i) c.x[i] = 0.0;
          for (int i = 0; i < n; ++i) {
            const fuzzy::InputRange& r = range_of(model, i);
            const double span = r.hi - r.lo;
            c.x[i] = rng.uniform(r.lo - 0.25 * span, r.hi + 0.25 * span);
          }
          visit(c);
        }
        const double specials[] = {std::numeric_limits<double>::quiet_NaN(),
                                   std::numeric_limits<double>::infinity(),
                                   -std::numeric_limits<double>::infinity(),
                                   1e300,
                                   -1e300,
                                   0.0};
        for (int i = 0; i < n; ++i) {
          for (const double v : specials) {
            for (int j = 0; j < 5; ++j) c.x[j] = j < n ? mid(j) : 0.0;
            c.x[i] = v;
            visit(c);
          }
        }
      }
    }
  }
}

/// Writes the CSV of every case's host result to `out`. Returns the number of cases.
inline int write_vectors(std::FILE* out) {
  std::fprintf(out, "%s\n", kHeader);
  int count = 0;
  for_each_case([&](const Case& c) {
    const Result r = run(c);
    std::fprintf(out,
                 "%s,%s,%s",
                 model_name(c.model),
                 c.single ? "float" : "double",
                 fuzzy::to_string(c.policy));
    for (const double v : c.x) std::fprintf(out, ",%016" PRIx64, bits(v));
    std::fprintf(out, ",%d", static_cast<int>(r.status));
    for (const double v : r.y) std::fprintf(out, ",%016" PRIx64, bits(v));
    for (const double v : r.y) std::fprintf(out, ",%.6f", v);
    std::fprintf(out, "\n");
    ++count;
  });
  return count;
}

/// Outcome of check_vectors.
struct CheckReport {
  int cases = 0;          ///< cases generated
  int lines = 0;          ///< data lines read
  int mismatches = 0;     ///< lines whose status or output bits differ from this target's
  int malformed = 0;      ///< lines that are not the case the generator expects there
  int float_checked = 0;  ///< float cases compared with double (inside the ranges or clamped)
  double float_max_diff_um = 0.0;  ///< largest |float − double| among them
  bool ok() const {
    return cases > 0 && lines == cases && mismatches == 0 && malformed == 0 &&
           float_max_diff_um <= kFloatToleranceUm;
  }
};

namespace detail_parse {
/// Next comma- or newline-terminated field of `p` (advanced past it) into `field`.
inline bool next_field(const char*& p, const char* end, char* field, std::size_t size) {
  std::size_t n = 0;
  while (p < end && *p != ',' && *p != '\n' && *p != '\r') {
    if (n + 1 >= size) return false;
    field[n++] = *p++;
  }
  field[n] = '\0';
  if (p < end && *p == ',') ++p;
  return true;
}
inline bool hex64(const char* s, std::uint64_t& v) {
  char* tail = nullptr;
  v = std::strtoull(s, &tail, 16);
  return tail != s && *tail == '\0';
}
}  // namespace detail_parse

/// Checks the CSV text `text` (`size` bytes) against this target's results: every line must be
/// the case the generator produces at that position, with the same status and the same output
/// bits. `report_mismatch(line, message)` is called for the first 10 problems.
template <typename Report>
CheckReport check_vectors(const char* text, std::size_t size, Report&& report_mismatch) {
  using detail_parse::hex64;
  using detail_parse::next_field;
  CheckReport rep;
  const char* p = text;
  const char* end = text + size;
  const auto skip_line = [&] {
    while (p < end && *p != '\n') ++p;
    if (p < end) ++p;
  };
  skip_line();  // header
  int line = 1;
  const auto problem = [&](const char* message) {
    if (rep.mismatches + rep.malformed <= 10) report_mismatch(line, message);
  };
  for_each_case([&](const Case& c) {
    ++rep.cases;
    if (p >= end) return;
    ++line;
    ++rep.lines;
    char f[32];
    bool good = next_field(p, end, f, sizeof f) && std::strcmp(f, model_name(c.model)) == 0;
    good = good && next_field(p, end, f, sizeof f) &&
           std::strcmp(f, c.single ? "float" : "double") == 0;
    good =
        good && next_field(p, end, f, sizeof f) && std::strcmp(f, fuzzy::to_string(c.policy)) == 0;
    for (const double v : c.x) {
      std::uint64_t b = 0;
      good = good && next_field(p, end, f, sizeof f) && hex64(f, b) && b == bits(v);
    }
    const Result r = run(c);
    char* tail = nullptr;
    long status = 0;
    if (good && next_field(p, end, f, sizeof f)) {
      status = std::strtol(f, &tail, 10);
      good = tail != f && *tail == '\0';
    } else {
      good = false;
    }
    std::uint64_t y[4] = {0, 0, 0, 0};
    for (auto& b : y) good = good && next_field(p, end, f, sizeof f) && hex64(f, b);
    skip_line();
    if (!good) {
      ++rep.malformed;
      problem("not the case the generator expects here (regenerate the file?)");
      return;
    }
    bool same = status == static_cast<long>(r.status);
    for (int o = 0; o < 4; ++o) same = same && y[o] == bits(r.y[o]);
    if (!same) {
      ++rep.mismatches;
      problem("status or output bits differ from the host's");
    }
    // Float against double on this target, where the inputs are (or are clamped) in range.
    if (c.single && (r.status == Status::kOk || (r.status == Status::kOutsideDomain &&
                                                 c.policy == fuzzy::DomainPolicy::kClamp))) {
      Case d = c;
      d.single = false;
      const Result rd = run(d);
      ++rep.float_checked;
      for (int o = 0; o < 4; ++o) {
        const double diff = r.y[o] > rd.y[o] ? r.y[o] - rd.y[o] : rd.y[o] - r.y[o];
        if (diff > rep.float_max_diff_um) rep.float_max_diff_um = diff;
      }
    }
  });
  if (p < end) {
    while (p < end && (*p == '\n' || *p == '\r')) ++p;
    if (p < end) {
      ++rep.malformed;  // lines beyond the generated cases
      report_mismatch(line + 1, "more lines than cases");
    }
  }
  return rep;
}

/// Prints `rep` in the one format every target's test matches ("golden: PASS").
inline void print_report(const CheckReport& rep, const char* target) {
  std::printf(
      "golden (%s): %d cases, %d lines, %d mismatches, %d malformed; float vs double: max %.3g um "
      "over %d in-range cases (limit %.0e)\n",
      target,
      rep.cases,
      rep.lines,
      rep.mismatches,
      rep.malformed,
      rep.float_max_diff_um,
      rep.float_checked,
      kFloatToleranceUm);
  std::printf("golden: %s\n", rep.ok() ? "PASS" : "FAIL");
}

}  // namespace cmmcomp::golden

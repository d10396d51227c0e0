// SPDX-License-Identifier: MIT
/// @file Targets and their check (include/cmmcomp/study/acceptance.hpp).
#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <cmmcomp/study/acceptance.hpp>
#include <sstream>

namespace cmmcomp::study {

KnownUnmet parse_known_unmet(const std::string& text) {
  KnownUnmet names;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back())) != 0) {
      line.pop_back();
    }
    std::size_t start = 0;
    while (start < line.size() && std::isspace(static_cast<unsigned char>(line[start])) != 0) {
      ++start;
    }
    line.erase(0, start);
    if (line.empty() || line[0] == '#') continue;
    names.insert(line);
  }
  return names;
}

KnownUnmet read_known_unmet(const std::string& path) {
  return parse_known_unmet(io::read_file_bounded(path, "known-unmet list", 1 << 20));
}

Verdict check(std::vector<Target>& targets, const KnownUnmet& known) {
  Verdict v;
  KnownUnmet seen;
  for (Target& t : targets) {
    t.known_unmet = known.count(t.name) != 0;
    if (t.known_unmet) seen.insert(t.name);
    const char* relation = t.kind == Target::Kind::kAtLeast ? ">=" : "<=";
    if (t.known_unmet && t.met()) {
      v.failures.push_back(fmt::format(
          "{}: listed as known unmet, but now met ({:.4g} {} {} {:.4g} {}): update the list and "
          "the docs that explain it",
          t.name,
          t.measured,
          t.unit,
          relation,
          t.limit,
          t.unit));
    } else if (!t.known_unmet && !t.met()) {
      v.failures.push_back(fmt::format("{}: {:.4g} {} misses {} {:.4g} {}",
                                       t.name,
                                       t.measured,
                                       t.unit,
                                       relation,
                                       t.limit,
                                       t.unit));
    }
  }
  for (const std::string& name : known) {
    if (seen.count(name) == 0) {
      v.failures.push_back(name + ": listed as known unmet, but not measured here (a stale list?)");
    }
  }
  v.passed = v.failures.empty();
  return v;
}

double noise_floor_um(std::size_t parameter) {
  constexpr double kPi = 3.14159265358979323846;
  return std::sqrt(2.0 / kPi) * paper::kTable1Std.at(parameter);
}

std::vector<Target> table5_targets(const std::string& prefix,
                                   const std::array<training::Table5Row, kErrorCount>& table,
                                   bool check_reduction,
                                   double residual_factor) {
  std::vector<Target> targets;
  for (std::size_t p = 0; p < kErrorCount; ++p) {
    const std::string key = kErrors[p].key;
    if (check_reduction) {
      targets.push_back({prefix + key + "_reduction",
                         table[p].reduction_pct,
                         paper::kTable5Reduction[p],
                         Target::Kind::kAtLeast,
                         "%"});
    }
    targets.push_back({prefix + key + "_residual",
                       table[p].mean_after,
                       residual_factor * noise_floor_um(p),
                       Target::Kind::kAtMost,
                       "um"});
  }
  return targets;
}

}  // namespace cmmcomp::study

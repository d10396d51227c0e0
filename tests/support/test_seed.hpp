// SPDX-License-Identifier: MIT
/// @file Seed and soak count for randomized tests: CMMCOMP_TEST_SEED, CMMCOMP_TEST_SOAK.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <string>

namespace cmmcomp::test {

/// The seed for randomized tests: $CMMCOMP_TEST_SEED, or a fixed default. Print it on failure
/// (use SCOPED_TRACE(seed_message())) so a failure can be replayed.
inline std::uint64_t seed() {
  const char* env = std::getenv("CMMCOMP_TEST_SEED");
  return env != nullptr ? std::strtoull(env, nullptr, 10) : 20190601u;
}

inline std::string seed_message() { return "CMMCOMP_TEST_SEED=" + std::to_string(seed()); }

/// How many random cases a property test runs: $CMMCOMP_TEST_SOAK or `fallback`.
inline int soak_count(int fallback) {
  const char* env = std::getenv("CMMCOMP_TEST_SOAK");
  return env != nullptr ? std::atoi(env) : fallback;
}

}  // namespace cmmcomp::test

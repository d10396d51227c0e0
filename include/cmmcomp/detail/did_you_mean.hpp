// SPDX-License-Identifier: MIT
/// @file "Did you mean …?" for a misspelt name: the closest candidate by edit distance, when it
/// is close enough to be a typo (at most a third of the name's letters, and at most 3, differ).
/// Setup only (allocates): messages about options, keys and sections.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

namespace cmmcomp::detail {

/// Levenshtein distance between `a` and `b` (insertions, deletions, substitutions).
inline std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

/// " (did you mean 'x'?)" for the closest of `candidates` to `word`, or "" when none is close.
inline std::string did_you_mean(const std::string& word,
                                const std::vector<std::string>& candidates) {
  const std::size_t limit = std::min<std::size_t>(3, std::max<std::size_t>(1, word.size() / 3));
  std::size_t best = limit + 1;
  std::string closest;
  for (const std::string& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best && d > 0) {
      best = d;
      closest = c;
    }
  }
  return closest.empty() ? std::string() : " (did you mean '" + closest + "'?)";
}

}  // namespace cmmcomp::detail

// SPDX-License-Identifier: MIT
/// @file The subset of TOML the project's configuration files are written in (machine files,
/// the agent's config), checked before a TOML parser sees the text.
///
/// Debian's toml++ 3.3.0 asserts or reaches `unreachable` on some malformed inputs (upstream
/// issue #295), so it only ever parses lines of these forms, in printable ASCII (UTF-8 inside
/// strings and comments): blank, `# comment`, `[section]`, `key = value` with a decimal number,
/// `true`/`false` or a one-line basic or literal string as the value, each optionally followed
/// by a comment (docs/machine-file.md, "Syntax").
#pragma once

#include <string>

namespace cmmcomp::io {

/// Throws ConfigError "source:line:column: syntax error: what (document, 'Syntax')" at the first
/// character outside the subset. Setup only.
void check_toml_subset(const std::string& text, const std::string& source, const char* document);

}  // namespace cmmcomp::io

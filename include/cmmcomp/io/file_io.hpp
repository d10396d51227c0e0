// SPDX-License-Identifier: MIT
/// @file Reading untrusted files with bounds, and writing outputs so that a failure never leaves
/// a half-written file or destroys a good one (docs/fuzzing.md, "Files"). Setup only.
#pragma once

#include <cstdint>
#include <string>

namespace cmmcomp::io {

/// Largest model file any reader accepts [bytes]: the C ABI's CMMCOMP_MAX_MODEL_BYTES (the
/// shipped 5-input model is 129 kB).
inline constexpr std::uintmax_t kMaxModelFileBytes = std::uintmax_t{4} * 1024u * 1024u;
/// Largest dataset CSV, machine file or other text input read whole [bytes].
inline constexpr std::uintmax_t kMaxTextFileBytes = std::uintmax_t{256} * 1024u * 1024u;

/// The whole content of `path`, which must be a regular file (after symbolic links) of at most
/// `max_bytes`. Never blocks on a FIFO or device (it is opened non-blocking and refused). Throws
/// ConfigError naming the file and `what` ("model file", …): cannot open, not a regular file
/// (a directory, FIFO or device), larger than the limit, read error.
std::string read_file_bounded(const std::string& path, const char* what, std::uintmax_t max_bytes);

/// Writes `text` to `path` so that `path` is, at every instant, either what it was before or
/// the complete new text: a temporary file in the same directory, written, flushed and
/// fsync'ed, then renamed over `path` (permissions 0666 & ~umask, as a plain create). A `path`
/// that exists and is not a regular file (/dev/stdout, a FIFO, a device) is written in place,
/// and every step is checked, so /dev/full fails. Throws Error naming `path` and the failing
/// step; the temporary file is removed and `path` is untouched.
void write_file_atomically(const std::string& path, const std::string& text);

}  // namespace cmmcomp::io

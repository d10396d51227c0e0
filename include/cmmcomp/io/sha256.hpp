// SPDX-License-Identifier: MIT
/// @file SHA-256 (FIPS 180-4) as lower-case hex: the model file's checksum and the fingerprint of
/// a training data file (docs/model-file.md).
#pragma once

#include <string>

namespace cmmcomp::io {

/// SHA-256 of `bytes`, 64 lower-case hex digits.
std::string sha256_hex(const std::string& bytes);
/// SHA-256 of a file's bytes (for `ModelMetadata::data_file_sha256`). Throws ConfigError when
/// the file cannot be read (a bounded read, io::read_file_bounded).
std::string sha256_file_hex(const std::string& path);

}  // namespace cmmcomp::io

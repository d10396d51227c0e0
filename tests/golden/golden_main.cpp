// SPDX-License-Identifier: MIT
/// @file golden_vectors: writes the golden-vector file on the host, or checks one on this target
/// (the host, or aarch64 under qemu-aarch64). The Cortex-M7 image checks the same file, linked
/// into it (tests/firmware/golden_image.cpp).
///
///   golden_vectors --write FILE   write every case's result (through FILE.tmp, then renamed)
///   golden_vectors --check FILE   exit 0 when every line matches this target's result
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "golden_vectors.hpp"

namespace {

int usage() {
  std::fprintf(stderr, "usage: golden_vectors --write FILE | --check FILE\n");
  return 2;
}

#if defined(__aarch64__)
constexpr const char* kTarget = "aarch64";
#elif defined(__x86_64__)
constexpr const char* kTarget = "x86-64";
#else
constexpr const char* kTarget = "host";
#endif

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) return usage();
  const std::string mode = argv[1];
  const std::string path = argv[2];
  if (mode == "--write") {
    const std::string tmp = path + ".tmp";
    std::FILE* out = std::fopen(tmp.c_str(), "w");
    if (out == nullptr) {
      std::fprintf(stderr, "golden_vectors: cannot write %s\n", tmp.c_str());
      return 1;
    }
    const int count = cmmcomp::golden::write_vectors(out);
    const bool written = std::fflush(out) == 0 && std::ferror(out) == 0;
    if (std::fclose(out) != 0 || !written || std::rename(tmp.c_str(), path.c_str()) != 0) {
      std::fprintf(stderr, "golden_vectors: writing %s failed; nothing replaced\n", path.c_str());
      std::remove(tmp.c_str());
      return 1;
    }
    std::printf("golden_vectors: wrote %d cases to %s\n", count, path.c_str());
    return 0;
  }
  if (mode != "--check") return usage();
  std::FILE* in = std::fopen(path.c_str(), "rb");
  if (in == nullptr) {
    std::fprintf(stderr, "golden_vectors: cannot read %s\n", path.c_str());
    return 1;
  }
  std::vector<char> text;
  char buffer[65536];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, in)) > 0;) {
    text.insert(text.end(), buffer, buffer + n);
  }
  std::fclose(in);
  const auto rep =
      cmmcomp::golden::check_vectors(text.data(), text.size(), [&](int line, const char* message) {
        std::printf("%s:%d: %s\n", path.c_str(), line, message);
      });
  cmmcomp::golden::print_report(rep, kTarget);
  return rep.ok() ? 0 : 1;
}

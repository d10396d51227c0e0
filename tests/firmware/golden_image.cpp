// SPDX-License-Identifier: MIT
/// @file The golden vectors checked on the Cortex-M7 (QEMU mps2-an500): the committed file is
/// linked into the image (golden_data.S), every case is evaluated here and compared bit for bit
/// with the host's result (tests/golden/golden_vectors.hpp).
#include <cstddef>
#include <cstdio>

#include "golden/golden_vectors.hpp"

extern "C" const char cmmcomp_golden_csv[];
extern "C" const char cmmcomp_golden_csv_end[];

int main() {
  const auto size = static_cast<std::size_t>(cmmcomp_golden_csv_end - cmmcomp_golden_csv);
  const auto rep =
      cmmcomp::golden::check_vectors(cmmcomp_golden_csv, size, [](int line, const char* message) {
        std::printf("default-models.csv:%d: %s\n", line, message);
      });
  cmmcomp::golden::print_report(rep, "cortex-m7");
  return rep.ok() ? 0 : 1;
}

// SPDX-License-Identifier: MIT
/// @file Counts heap allocations (operator new in every form, malloc, calloc, realloc) made
/// while an AllocationCounter is alive, to prove that an RT call does not allocate.
///
/// Link support/allocation_counter.cpp into the test executable: it replaces the global
/// operator new/delete and interposes malloc/calloc/realloc/free (glibc: forwarding to
/// __libc_malloc and friends). This conflicts with AddressSanitizer, which interposes the same
/// functions, so such tests are not built in sanitizer builds.
#pragma once

#include <cstddef>

namespace cmmcomp::test {

/// Allocations counted while at least one AllocationCounter is alive (all threads).
class AllocationCounter {
 public:
  AllocationCounter() noexcept;
  ~AllocationCounter();
  AllocationCounter(const AllocationCounter&) = delete;
  AllocationCounter& operator=(const AllocationCounter&) = delete;

  /// Allocations (new, new[], malloc, calloc, realloc) since this counter was created.
  std::size_t count() const noexcept;

 private:
  std::size_t start_;
};

}  // namespace cmmcomp::test

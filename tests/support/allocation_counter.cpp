// SPDX-License-Identifier: MIT
/// @file Replacement operator new/delete and malloc interposition behind AllocationCounter.
#include "support/allocation_counter.hpp"

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

// glibc's own allocator entry points: the interposed malloc family forwards to them, so the
// counter needs no dlsym (which itself allocates).
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* p, std::size_t size);
void* __libc_memalign(std::size_t alignment, std::size_t size);
void __libc_free(void* p);
}

namespace {

std::atomic<int> g_active{0};
std::atomic<std::size_t> g_count{0};

void record() noexcept {
  if (g_active.load(std::memory_order_relaxed) > 0) {
    g_count.fetch_add(1, std::memory_order_relaxed);
  }
}

void* allocate(std::size_t size) noexcept {
  record();
  return __libc_malloc(size == 0 ? 1 : size);
}

void* allocate_aligned(std::size_t size, std::align_val_t alignment) noexcept {
  record();
  return __libc_memalign(static_cast<std::size_t>(alignment), size == 0 ? 1 : size);
}

void* allocate_or_throw(std::size_t size) {
  void* p = allocate(size);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}

void* allocate_aligned_or_throw(std::size_t size, std::align_val_t alignment) {
  void* p = allocate_aligned(size, alignment);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}

}  // namespace

namespace cmmcomp::test {

AllocationCounter::AllocationCounter() noexcept : start_(g_count.load()) { g_active.fetch_add(1); }

AllocationCounter::~AllocationCounter() { g_active.fetch_sub(1); }

std::size_t AllocationCounter::count() const noexcept { return g_count.load() - start_; }

}  // namespace cmmcomp::test

extern "C" {
void* malloc(std::size_t size) {
  record();
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) {
  record();
  return __libc_calloc(count, size);
}
void* realloc(void* p, std::size_t size) {
  record();
  return __libc_realloc(p, size);
}
void free(void* p) { __libc_free(p); }
}

void* operator new(std::size_t size) { return allocate_or_throw(size); }
void* operator new[](std::size_t size) { return allocate_or_throw(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return allocate(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return allocate(size); }
void* operator new(std::size_t size, std::align_val_t a) {
  return allocate_aligned_or_throw(size, a);
}
void* operator new[](std::size_t size, std::align_val_t a) {
  return allocate_aligned_or_throw(size, a);
}
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  return allocate_aligned(size, a);
}
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  return allocate_aligned(size, a);
}

void operator delete(void* p) noexcept { __libc_free(p); }
void operator delete[](void* p) noexcept { __libc_free(p); }
void operator delete(void* p, std::size_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::size_t) noexcept { __libc_free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { __libc_free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { __libc_free(p); }
void operator delete(void* p, std::align_val_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { __libc_free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { __libc_free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { __libc_free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  __libc_free(p);
}

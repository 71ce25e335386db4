// glibc lets a program interpose malloc: these wrappers count the calls and hand them to
// glibc's own allocator (__libc_*), so every block still belongs to glibc and its free(),
// memalign() and friends stay valid. Under AddressSanitizer, which owns malloc, nothing is
// counted (allocation_count() stays 0).
#include "alloc_counter.hpp"

#include <atomic>
#include <cstddef>

#if defined(__SANITIZE_ADDRESS__)
#define STIFFMSA_BENCH_COUNT_ALLOCATIONS 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define STIFFMSA_BENCH_COUNT_ALLOCATIONS 0
#endif
#endif
#ifndef STIFFMSA_BENCH_COUNT_ALLOCATIONS
#define STIFFMSA_BENCH_COUNT_ALLOCATIONS 1
#endif

#if STIFFMSA_BENCH_COUNT_ALLOCATIONS

extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* block, std::size_t size);
}

namespace {
std::atomic<std::uint64_t> allocations{0};
void count() { allocations.fetch_add(1, std::memory_order_relaxed); }
}  // namespace

extern "C" {
void* malloc(std::size_t size) {
  count();
  return __libc_malloc(size);
}
void* calloc(std::size_t n, std::size_t size) {
  count();
  return __libc_calloc(n, size);
}
void* realloc(void* block, std::size_t size) {
  count();
  return __libc_realloc(block, size);
}
}

std::uint64_t bench::allocation_count() { return allocations.load(std::memory_order_relaxed); }
#else
std::uint64_t bench::allocation_count() { return 0; }
#endif

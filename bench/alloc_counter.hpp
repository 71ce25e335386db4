#pragma once
// Counts heap allocations (malloc, calloc, realloc) made by the whole process: operator new,
// Eigen and SuiteSparse all allocate through malloc. Linking alloc_counter.cpp into a program
// turns the counting on; the benchmarks report the allocations per pose.
#include <cstdint>

namespace bench {
std::uint64_t allocation_count();
}

// Counts a test binary's heap allocations, for tests that a per-sample path allocates nothing.
#pragma once

#include <cstdint>

namespace windfdi::test {

/// malloc calls in this process so far: operator new and Eigen's dynamic arrays both come through malloc.
/// Only in binaries built with allocation_counter.cpp.
uint64_t allocations();

}  // namespace windfdi::test

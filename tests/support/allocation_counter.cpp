// malloc, interposed to count the calls (glibc's own allocator does the work): see allocation_counter.hpp.
#include "allocation_counter.hpp"

#include <atomic>
#include <cstddef>

namespace {
std::atomic<uint64_t> g_allocations{0};
}

extern "C" void* __libc_malloc(std::size_t size);  // NOLINT: glibc's allocator under the interposed name

// An executable's malloc takes the place of libc's for every library in the process (ELF interposition).
extern "C" void* malloc(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}

namespace windfdi::test {

uint64_t allocations() { return g_allocations.load(std::memory_order_relaxed); }

}  // namespace windfdi::test

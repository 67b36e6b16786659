// Counts a process's malloc calls (LD_PRELOAD) and writes the count at exit to $MALLOC_COUNT_FILE: the
// allocations per sample of tests/perf/replay_allocations.sh, a number the machine's noise does not move.
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
static atomic_ulong n_malloc;
static void* (*real_malloc)(size_t);
void* malloc(size_t s) {
  if (!real_malloc) real_malloc = dlsym(RTLD_NEXT, "malloc");
  atomic_fetch_add(&n_malloc, 1);
  return real_malloc(s);
}
__attribute__((destructor)) static void report(void) {
  FILE* f = fopen(getenv("MALLOC_COUNT_FILE") ? getenv("MALLOC_COUNT_FILE") : "/dev/stderr", "w");
  if (f) {
    fprintf(f, "%lu\n", (unsigned long)n_malloc);
    fclose(f);
  }
}

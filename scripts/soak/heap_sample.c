// LD_PRELOAD shim for scripts/soak.sh: samples the process's live heap from
// inside it, every $RIPPLE_HEAP_SAMPLE_MS milliseconds (default 1000),
// appending "<seconds since start> <rss_kB> <live_bytes> <heap_bytes>" to
// $RIPPLE_HEAP_SAMPLE_FILE. RSS alone cannot tell a growing heap from an
// allocator that keeps freed memory: under AddressSanitizer freed blocks
// wait in a quarantine (256 MB by default) and freed pages are not returned
// to the system, so RSS rises while the program's live data stays flat.
//   live_bytes: bytes the program holds (allocated and not yet freed);
//   heap_bytes: what the allocator has mapped for the heap (live, the
//     quarantine, its free lists and caches).
// Under ASan these come from <sanitizer/allocator_interface.h>; otherwise
// from glibc's mallinfo2 (in use: uordblks + hblkhd; heap: arena + hblkhd).
// With $RIPPLE_HEAP_STATS_EVERY=N, every N-th sample also has ASan print its
// allocator's statistics to stderr (mapped memory per size class): which
// block sizes the heap grew in.
#define _GNU_SOURCE
#include <malloc.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

// Weak: resolved when the executable carries the sanitizer runtime.
size_t __sanitizer_get_current_allocated_bytes(void) __attribute__((weak));
size_t __sanitizer_get_heap_size(void) __attribute__((weak));
void __asan_print_accumulated_stats(void) __attribute__((weak));

static double Now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + t.tv_nsec * 1e-9;
}

static long RssKb(void) {
  long pages = 0, rss = 0;
  FILE* f = fopen("/proc/self/statm", "r");
  if (!f) return 0;
  if (fscanf(f, "%ld %ld", &pages, &rss) != 2) rss = 0;
  fclose(f);
  return rss * (sysconf(_SC_PAGESIZE) / 1024);
}

static void Sample(FILE* out, double start_s) {
  size_t live, heap;
  if (__sanitizer_get_current_allocated_bytes && __sanitizer_get_heap_size) {
    live = __sanitizer_get_current_allocated_bytes();
    heap = __sanitizer_get_heap_size();
  } else {
    const struct mallinfo2 m = mallinfo2();
    live = m.uordblks + m.hblkhd;
    heap = m.arena + m.hblkhd;
  }
  fprintf(out, "%.1f %ld %zu %zu\n", Now() - start_s, RssKb(), live, heap);
  fflush(out);
}

static void* Loop(void* arg) {
  FILE* out = arg;
  const char* ms_env = getenv("RIPPLE_HEAP_SAMPLE_MS");
  const long ms = ms_env ? atol(ms_env) : 1000;
  const struct timespec period = {ms / 1000, (ms % 1000) * 1000000L};
  const char* stats_env = getenv("RIPPLE_HEAP_STATS_EVERY");
  const long stats_every = stats_env ? atol(stats_env) : 0;
  const double start_s = Now();
  for (long i = 1;; ++i) {
    Sample(out, start_s);
    if (stats_every > 0 && i % stats_every == 0 &&
        __asan_print_accumulated_stats) {
      fprintf(stderr, "\nheap_sample: stats at %.1f s\n", Now() - start_s);
      __asan_print_accumulated_stats();
    }
    nanosleep(&period, NULL);
  }
  return NULL;
}

__attribute__((constructor)) static void Start(void) {
  const char* path = getenv("RIPPLE_HEAP_SAMPLE_FILE");
  if (!path) return;
  FILE* out = fopen(path, "w");
  if (!out) return;
  pthread_t t;
  pthread_attr_t attr;
  pthread_attr_init(&attr);
  pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED);
  if (pthread_create(&t, &attr, Loop, out) != 0) fclose(out);
  pthread_attr_destroy(&attr);
}

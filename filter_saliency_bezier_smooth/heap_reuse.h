// Large blocks freed during a filter run are kept for the run's next allocations instead of being
// handed back to the kernel and faulted in again, page by page.
//
// Why: glibc serves every block above its mmap threshold (at most 32 MB) with a fresh mapping and
// unmaps it when freed. A run on millions of vertices allocates and frees arrays of tens of MB
// dozens of times (snapshots, step buffers, per-stage tables), and each one costs a page fault per
// 4 kB on first touch, taken under the kernel's locks by both threads: about 7 % of the 2.2M-vertex
// run's processor time (perf), 16.0 s instead of 17.6 s without it (tools/smooth_mesh on the
// bench/scale.py mesh), for 70-100 MB more peak memory (freed blocks do not always fit the next
// request). Afterwards glibc's defaults are set again and the free memory is returned (the mmap
// threshold then stays where it was instead of adapting: glibc stops adapting it once a program
// sets these parameters).
#pragma once

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace saliency_bezier {

class HeapReuse {
public:
  HeapReuse() {
#ifdef __GLIBC__
    mallopt(M_MMAP_MAX, 0);               // no block gets its own mapping...
    mallopt(M_TRIM_THRESHOLD, kNoTrim);   // ...and the heap's free top stays for the next one
#endif
  }
  ~HeapReuse() {
#ifdef __GLIBC__
    mallopt(M_MMAP_MAX, kDefaultMmapMax);
    mallopt(M_TRIM_THRESHOLD, kDefaultTrimThreshold);
    malloc_trim(0);
#endif
  }
  HeapReuse(const HeapReuse &) = delete;
  HeapReuse &operator=(const HeapReuse &) = delete;

private:
  // glibc's defaults (malloc/malloc.c: DEFAULT_MMAP_MAX, DEFAULT_TRIM_THRESHOLD).
  static constexpr int kDefaultMmapMax = 65536, kDefaultTrimThreshold = 128 * 1024;
  static constexpr int kNoTrim = 2147483647;
};

} // namespace saliency_bezier

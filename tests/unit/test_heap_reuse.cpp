// filter_saliency_bezier_smooth/heap_reuse.h: during a filter run a large block is served from the
// heap (not mapped afresh) and, once freed, kept for the run's next large block; afterwards glibc
// maps large blocks again and the freed memory goes back to the system.
#include <gtest/gtest.h>

#include <filter_saliency_bezier_smooth/heap_reuse.h>

#include <cstdlib>
#include <cstring>

#if defined(__SANITIZE_ADDRESS__)
#define SBS_OWN_MALLOC 1 // the sanitizer's allocator, which ignores mallopt
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SBS_OWN_MALLOC 1
#endif
#endif

namespace {
constexpr size_t kBlock = 64u << 20; // above glibc's largest mmap threshold (32 MB)

// A block as a run's array is: allocated and written.
char *touchedBlock() {
  char *p = static_cast<char *>(std::malloc(kBlock));
  if (p) std::memset(p, 1, kBlock);
  return p;
}
} // namespace

TEST(HeapReuse, LargeBlocksComeFromTheHeapDuringARunAndAreReturnedAfter) {
#if !defined(__GLIBC__) || defined(SBS_OWN_MALLOC)
  GTEST_SKIP() << "glibc's allocator only";
#else
  const struct mallinfo2 start = mallinfo2();
  {
    const saliency_bezier::HeapReuse heap;
    char *first = touchedBlock();
    ASSERT_NE(first, nullptr);
    const struct mallinfo2 holding = mallinfo2();
    EXPECT_EQ(holding.hblks, start.hblks);           // not a mapping of its own
    EXPECT_GE(holding.arena, start.arena + kBlock);  // but heap
    std::free(first);
    const struct mallinfo2 freed = mallinfo2();
    EXPECT_GE(freed.arena, start.arena + kBlock); // kept, not trimmed
    char *second = touchedBlock();                // reuses it: the heap does not grow
    ASSERT_NE(second, nullptr);
    EXPECT_EQ(mallinfo2().arena, freed.arena);
    std::free(second);
  }
  const struct mallinfo2 after = mallinfo2();
  EXPECT_LT(after.arena, start.arena + kBlock / 2); // given back
  char *later = touchedBlock();
  ASSERT_NE(later, nullptr);
  EXPECT_EQ(mallinfo2().hblks, start.hblks + 1); // mapped again, as glibc does by default
  std::free(later);
#endif
}

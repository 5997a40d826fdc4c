// SPDX-License-Identifier: MIT
// keep_freed_memory (pce/sim/allocator.hpp): large blocks come from the heap, and the heap
// keeps them once freed. The first test shows what glibc does without it, so the second
// cannot pass by accident. (ctest runs each test in its own process; run directly, the
// order below keeps the first one's premise.)
#include <pce/sim/allocator.hpp>

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace {

constexpr std::size_t kBlock = std::size_t(96) << 20;  // 96 MiB, beyond glibc's largest mmap threshold (32 MiB)

#if defined(__GLIBC__)
/// Allocates and touches kBlock bytes; returns the growth of mmapped bytes while it is held.
std::size_t mapped_growth_of_a_large_block(std::size_t* arena_after_free) {
  const std::size_t before = mallinfo2().hblkhd;
  char* p = static_cast<char*>(std::malloc(kBlock));
  EXPECT_NE(p, nullptr);
  std::memset(p, 1, kBlock);
  const std::size_t growth = mallinfo2().hblkhd - before;
  std::free(p);
  if (arena_after_free) *arena_after_free = mallinfo2().arena;
  return growth;
}
#endif

TEST(KeepFreedMemory, WithoutItGlibcMapsALargeBlock) {
#if defined(__GLIBC__)
  EXPECT_GE(mapped_growth_of_a_large_block(nullptr), kBlock);
#else
  GTEST_SKIP() << "not glibc";
#endif
}

TEST(KeepFreedMemory, ServesALargeBlockFromTheHeapAndKeepsItOnceFreed) {
#if defined(__GLIBC__)
  ASSERT_TRUE(pce::sim::keep_freed_memory());
  std::size_t arena = 0;
  EXPECT_EQ(mapped_growth_of_a_large_block(&arena), 0u);
  EXPECT_GE(arena, kBlock);  // freed, and still the process's: the next factor reuses it
#else
  EXPECT_FALSE(pce::sim::keep_freed_memory());
#endif
}

}  // namespace

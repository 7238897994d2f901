#include "server/app/memory_policy.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace {

// GCC names the sanitizers by macros, Clang by __has_feature.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define STRATA_TEST_SANITIZER_ALLOCATOR 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define STRATA_TEST_SANITIZER_ALLOCATOR 1
#endif
#endif
#if defined(STRATA_TEST_SANITIZER_ALLOCATOR)
constexpr bool kSanitizerAllocator = true;
#else
constexpr bool kSanitizerAllocator = false;
#endif

/// Keeps the compiler from taking a malloc/free pair out.
void escape(void* p) {
  asm volatile("" : : "g"(p) : "memory");
}

TEST(MemoryPolicy, AScanSizedBlockComesFromTheHeapAndStaysThereWhenFreed) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "the allocator settings are glibc's";
#else
  if (kSanitizerAllocator)
    GTEST_SKIP() << "a sanitizer's allocator does not take glibc's settings";
  ASSERT_TRUE(strata::app::keep_freed_memory());
  // 8 MiB: a local map's kd-tree. With glibc's defaults it is mapped on its own (above the 128 KiB
  // threshold) and unmapped when freed; kept, it comes from the heap and the heap keeps it.
  const struct mallinfo2 before = mallinfo2();
  constexpr std::size_t kBlock = 8 * 1024 * 1024;
  void* block = std::malloc(kBlock);
  ASSERT_NE(block, nullptr);
  std::memset(block, 1, kBlock);
  escape(block);
  const struct mallinfo2 held = mallinfo2();
  EXPECT_EQ(held.hblks, before.hblks) << "the block was mapped on its own";
  std::free(block);
  const struct mallinfo2 after = mallinfo2();
  EXPECT_GE(after.arena, held.arena) << "the heap gave the freed block back";
  EXPECT_GE(after.fordblks, kBlock) << "the freed block is not among the heap's free memory";
#endif
}

}  // namespace

#include "server/app/memory_policy.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace strata::app {
namespace {

/// glibc's largest mmap threshold on 64-bit (half its 64 MiB arena heap; mallopt refuses more). Blocks
/// below it come from the heap and go back to the heap when freed; only larger ones (a whole map's
/// buffers, not a scan's) are mapped and unmapped each time.
constexpr int kMmapThreshold = 32 * 1024 * 1024;
/// Free memory at the heap's top kept before it is trimmed. glibc's default (128 KiB, raised as the
/// mmap threshold moves) trimmed and faulted in the scan path's buffers every scan; 256 MiB keeps them,
/// and still returns what a one-off load (a large map file) leaves behind.
constexpr int kTrimThreshold = 256 * 1024 * 1024;

}  // namespace

bool keep_freed_memory() {
#if defined(__GLIBC__)
  // Both are set: setting either one by hand turns off glibc's own adjustment of the other, and the
  // trim threshold alone (with the mmap threshold left at 128 KiB) made the scan path twice as slow.
  const bool mmap = mallopt(M_MMAP_THRESHOLD, kMmapThreshold) == 1;
  const bool trim = mallopt(M_TRIM_THRESHOLD, kTrimThreshold) == 1;
  return mmap && trim;
#else
  return false;
#endif
}

}  // namespace strata::app

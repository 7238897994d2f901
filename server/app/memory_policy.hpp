#pragma once

namespace strata::app {

/// Tells the C library's allocator to keep freed memory mapped instead of handing it back to the kernel
/// at once, so the scan path's per-scan buffers (the local map's kd-tree, the thinned clouds, the voxel
/// hashes: megabytes each) land on pages already touched. Returned memory costs a page fault per 4 KiB
/// when it is taken again, and on a virtual machine a fault is dear: the 32-beam revolution's
/// registration and mapping took 35-39 ms with glibc's defaults and 31-32 ms with this
/// (docs/benchmarks.md, "The allocator keeps what it freed"). The price is resident memory that stays at
/// the process's peak. Call it first thing in main(), before any thread starts. Logs nothing; returns
/// false where the C library does not take the settings (not glibc, or a sanitizer's allocator).
bool keep_freed_memory();

}  // namespace strata::app

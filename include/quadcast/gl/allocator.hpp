// quadcast/gl/allocator.hpp -- keep freed memory for reuse in processes that draw with a software GL
#pragma once

// Mesa's llvmpipe allocates its vertex and binning buffers per draw, megabytes each. With glibc's
// defaults a block that large comes from a fresh mmap and goes back to the system when freed, so
// every frame faults its pages in again, on the thread that runs the vertex stage. In a virtual
// machine a page fault costs microseconds: the same frame of 10k spheres without a cull pass took
// 56-66 ms against 44-52 ms once freed blocks stay in the heap (`quadcast render --frames 9` on the
// scene of `bench spheres`, 1024x768, Mesa 22.3 llvmpipe, 2 cores; the ranges are over one day's
// runs as the machine's load varied, 56 against 44 ms in one interleaved run). glibc raises its mmap threshold by
// itself after freeing a large block, so a process that happened to free one first was fast and
// one that had not was slow.
//
// `keep_freed_memory` serves blocks up to `mmap_threshold` bytes from the heap and returns its
// free top to the system only beyond `trim_threshold` bytes (mallopt M_MMAP_THRESHOLD,
// M_TRIM_THRESHOLD). It changes the whole process's allocator, so the library never calls it: the
// quadcast command calls it at start, and a host application may. Returns false where the C
// library is not glibc or refuses the values (the maximum mmap threshold on 64-bit glibc is 32 MiB).

#include <cstddef>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace quadcast::gl {

inline bool keep_freed_memory(std::size_t mmap_threshold = std::size_t(32) << 20, std::size_t trim_threshold = std::size_t(64) << 20) {
#if defined(__GLIBC__)
    if (mmap_threshold > std::size_t(32) << 20 || trim_threshold > std::size_t(1) << 30) return false;
    return mallopt(M_MMAP_THRESHOLD, static_cast<int>(mmap_threshold)) == 1 && mallopt(M_TRIM_THRESHOLD, static_cast<int>(trim_threshold)) == 1;
#else
    (void)mmap_threshold;
    (void)trim_threshold;
    return false;
#endif
}

}  // namespace quadcast::gl

#include "heap_pages.hpp"

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>

// mallinfo2 (the heap's top chunk) is glibc 2.33's.
#if defined(__linux__) && defined(__GLIBC__) && defined(MADV_HUGEPAGE)
#if __GLIBC_PREREQ(2, 33)
#define TRAVERSE_HEAP_HUGE_PAGES 1
#endif
#endif

namespace traverse::app {

std::size_t set_up_heap(std::size_t huge_bytes) {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
  return huge_bytes > 0 ? back_heap_with_huge_pages(huge_bytes) : 0;
}

std::size_t back_heap_with_huge_pages(std::size_t bytes) {
#ifdef TRAVERSE_HEAP_HUGE_PAGES
  constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
  constexpr std::uintptr_t kHeader = 2 * sizeof(std::size_t);  // a glibc chunk's header
  constexpr int kDefaultTopPad = 128 << 10;                    // glibc's M_TOP_PAD
  void* brk0 = sbrk(0);
  if (brk0 == reinterpret_cast<void*>(-1)) return 0;
  // The heap's top chunk (its free end, which glibc grows with brk) starts keepcost bytes
  // below the break. A block from there up to 2 chunk headers before the first 2 MiB
  // boundary above the break (so that the block does not fit the top chunk, and the heap
  // grows) puts the top chunk's own header in the 4 KiB page before the boundary, and every
  // later allocation from the top beyond it.
  const std::uintptr_t top = reinterpret_cast<std::uintptr_t>(brk0) - mallinfo2().keepcost;
  const std::uintptr_t boundary = (reinterpret_cast<std::uintptr_t>(brk0) + kHuge) & ~(kHuge - 1);
  mallopt(M_TOP_PAD, static_cast<int>(bytes + kHuge));
  void* filler = std::malloc(boundary - top - 3 * kHeader);  // chunk size: boundary - top - 2 kHeader
  mallopt(M_TOP_PAD, kDefaultTopPad);
  if (!filler) return 0;
  const std::uintptr_t end = reinterpret_cast<std::uintptr_t>(sbrk(0)) & ~(kHuge - 1);
  const std::uintptr_t first = boundary;
  if (end <= first || reinterpret_cast<std::uintptr_t>(filler) != top + kHeader) {  // not laid out as expected
    std::free(filler);
    return 0;
  }
  if (madvise(reinterpret_cast<void*>(first), end - first, MADV_HUGEPAGE) != 0) return 0;
  return end - first;  // the filler stays allocated: the heap below the boundary is not reused
#else
  (void)bytes;
  return 0;
#endif
}

}  // namespace traverse::app

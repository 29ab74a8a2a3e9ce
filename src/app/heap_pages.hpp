#pragma once
// How the process's heap is set up (Linux, glibc): memory once touched is kept and reused, and
// the heap's first megabytes lie on transparent huge pages, so that the memory a run touches
// costs one page fault per 2 MiB instead of one per 4 KiB (docs/benchmarks.md, "Huge pages for
// the heap"; docs/developer.md, "Start-up").
#include <cstddef>

namespace traverse::app {

/// glibc's malloc keeps what it was given: blocks below 32 MiB from the heap (no mmap of their
/// own), no trimming of the heap's top below 256 MiB free. Then, with `huge_bytes` > 0,
/// back_heap_with_huge_pages(huge_bytes); returns what that marked.
std::size_t set_up_heap(std::size_t huge_bytes);

/// Makes the heap's next `bytes` (whole 2 MiB pages) eligible for transparent huge pages:
/// grows the heap by that much at once (glibc's M_TOP_PAD), lets the allocations that follow
/// start at a 2 MiB boundary (a block filling the heap's top up to there, kept and never
/// touched) and marks the range MADV_HUGEPAGE. Nothing in the range is touched here. Needs
/// glibc's mmap threshold above 2 MiB (set_up_heap sets it). Returns the bytes marked (0 when
/// the heap is not glibc's contiguous brk heap as expected, or a step failed: then the heap is
/// as glibc makes it, on 4 KiB pages).
std::size_t back_heap_with_huge_pages(std::size_t bytes);

}  // namespace traverse::app

#include "core/Memory.h"

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>

namespace ambler {

namespace {

constexpr std::uintptr_t kHugePage = std::uintptr_t(2) << 20;

constexpr int kGlibcTopPad = 128 << 10;

// The heap grown by `bytes` at once (address space only) and marked for
// transparent huge pages, so that a first touch there maps 2 MiB instead
// of 4 KiB. Nothing changes where the heap cannot grow or the kernel has
// no huge pages: it is only a hint.
void reserveHugePageHeap(std::size_t bytes) {
  const auto begin = reinterpret_cast<std::uintptr_t>(sbrk(0));
  mallopt(M_TOP_PAD, int(bytes));
  void* volatile block = malloc(std::size_t(1) << 20);  // volatile: kept by the optimizer
  free(block);
  mallopt(M_TOP_PAD, kGlibcTopPad);
  const auto end = reinterpret_cast<std::uintptr_t>(sbrk(0));
  const auto first = (begin + kHugePage - 1) & ~(kHugePage - 1), last = end & ~(kHugePage - 1);
  if (last > first) (void)madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
}

}  // namespace

void keepFreedMemoryForReuse() {
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest on 64-bit
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
}

void adviseHugePagesForTheHeap() { reserveHugePageHeap(std::size_t(256) << 20); }

}  // namespace ambler

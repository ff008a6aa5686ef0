#pragma once

namespace ambler {

// Per-scan buffers (maps, images, clouds) are megabytes each, allocated and
// freed with every scan. By default glibc serves such blocks with fresh
// mmap'd pages and gives them back on free, so every scan pays a page fault
// for each 4 KiB it touches: a quarter of an elevation map's build time on
// the reference machine. Called first in each program's main: blocks up to
// 32 MiB come from the heap, and freed memory stays with the process for
// the next scan (its footprint stays at its peak).
void keepFreedMemoryForReuse();

// The heap's first 256 MiB advised for transparent huge pages: a one-shot
// `ambler-cli register` touches tens of MB of fresh memory, and at 4 KiB a
// page the faults were a fifth of its time on the reference VM
// (docs/mapping.md). Not for ambler-gs, whose threads share the heap: the
// first touch of a huge page zeroes 2 MiB in whichever thread makes it,
// the GUI thread's included, which then stalls while the operator waits.
void adviseHugePagesForTheHeap();

}  // namespace ambler

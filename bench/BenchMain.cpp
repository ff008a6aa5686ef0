// Every benchmark program's main: the heap set up as in the programs
// (core/Memory.h), so that a benchmark measures what they pay per scan.
#include <benchmark/benchmark.h>

#include "core/Memory.h"

int main(int argc, char** argv) {
  ambler::keepFreedMemoryForReuse();
  ambler::adviseHugePagesForTheHeap();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

#include "core/Memory.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace {

// The VmFlags of the mapping holding `address` (/proc/self/smaps), or "".
std::string flagsOfMappingAt(const void* address) {
  const auto at = reinterpret_cast<std::uintptr_t>(address);
  std::ifstream smaps("/proc/self/smaps");
  bool inside = false;
  for (std::string line; std::getline(smaps, line);) {
    std::uintptr_t begin = 0, end = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> begin >> dash >> end && dash == '-') {
      inside = begin <= at && at < end;
    } else if (inside && line.rfind("VmFlags:", 0) == 0) {
      return line.substr(8);
    }
  }
  return "";
}

TEST(Memory, HeapBlocksAfterTheCallLieInHugePageAdvisedMemory) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer serves malloc from its own mappings";
#endif
  if (!std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled"))
    GTEST_SKIP() << "this kernel has no transparent huge pages";
  ambler::keepFreedMemoryForReuse();
  ambler::adviseHugePagesForTheHeap();
  // 16 MiB: below the mmap threshold the call sets (32 MiB), so from the
  // heap; its middle lies past any unaligned start of the advised range.
  constexpr std::size_t kBytes = std::size_t(16) << 20;
  char* block = static_cast<char*>(std::malloc(kBytes));
  ASSERT_NE(block, nullptr);
  const std::string flags = flagsOfMappingAt(block + kBytes / 2);
  std::free(block);
  EXPECT_NE(flags.find(" hg"), std::string::npos) << "VmFlags:" << flags;
}

}  // namespace

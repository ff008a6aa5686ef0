#include "core/Memory.h"

#include <malloc.h>

namespace ambler {

void keepFreedMemoryForReuse() {
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest on 64-bit
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
}

}  // namespace ambler

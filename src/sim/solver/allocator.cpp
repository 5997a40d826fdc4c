// SPDX-License-Identifier: MIT
// glibc's allocator kept from returning memory (allocator.hpp).
#include <pce/sim/allocator.hpp>

#include <climits>  // also defines __GLIBC__ under glibc (through <features.h>)

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace pce::sim {

bool keep_freed_memory() {
#if defined(__GLIBC__)
  const bool no_mmap = mallopt(M_MMAP_MAX, 0) == 1;
  const bool no_trim = mallopt(M_TRIM_THRESHOLD, INT_MAX) == 1;
  return no_mmap && no_trim;
#else
  return false;
#endif
}

}  // namespace pce::sim

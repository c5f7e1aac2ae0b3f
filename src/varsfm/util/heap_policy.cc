#include "varsfm/util/heap_policy.h"

#include <climits>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace varsfm {

void KeepFreedMemoryForReuse() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, INT_MAX);
#endif
}

}  // namespace varsfm

#pragma once
// Large OpenCV matrix buffers kept for reuse while features are extracted. SIFT's scale space of a
// photo above about 4 megapixels (and at most max_image_size, feature/sift.h) holds float images
// of over 64 MB (its doubled first octave). A worker thread allocates from a malloc arena of its
// own, whose heaps cannot hold such a block, so glibc maps every one afresh and unmaps it when it
// is freed (util/heap_policy.h keeps freed memory only in the main arena's heap): each photo's
// scale space was faulted in again page by page, the extraction of 3072 x 2049 photos spending
// more time in the kernel than with one thread (bench/results/2026-12-05-s22-explored.md). While a
// ScopedMatBufferPool lives, cv::Mat buffers of at least `min_bytes` come from a pool shared by
// every thread and go back to it when freed; the pool's blocks are freed when it ends, and when a
// large buffer of a size it does not hold is asked for. Pools alive at once (two extractions in
// one process) share one pool, the first one's `min_bytes`, until the last ends.
#include <cstddef>

namespace varsfm {

class ScopedMatBufferPool {
 public:
  explicit ScopedMatBufferPool(size_t min_bytes = size_t{16} << 20);
  ~ScopedMatBufferPool();
  ScopedMatBufferPool(const ScopedMatBufferPool&) = delete;
  ScopedMatBufferPool& operator=(const ScopedMatBufferPool&) = delete;

  // The bytes of the blocks the pool holds for reuse (none once it ended).
  static size_t FreeBytes();
};

}  // namespace varsfm

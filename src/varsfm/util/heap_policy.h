#pragma once
// How the process's heap treats large blocks. glibc's malloc serves every block above its mmap
// threshold (at most 32 MB) with a fresh mapping and unmaps it when the block is freed, so the
// next large block is faulted in again page by page, each page zeroed by the kernel. The stages
// allocate and free blocks of hundreds of MB many times over (a global bundle adjustment's Schur
// blocks, the surface cut's graph): at 1000 photos the mapper spent 16 of its 111 CPU seconds in
// those page faults (bench/results/2026-12-03-heap-policy.md).
namespace varsfm {

// Serves large blocks from the heap and keeps freed memory there for the next allocation
// instead of returning it to the kernel (glibc: M_MMAP_MAX 0, M_TRIM_THRESHOLD at its maximum).
// The resident size then stays at the process's peak until it exits. A no-op elsewhere. For a
// program's main(), before any thread starts.
void KeepFreedMemoryForReuse();

}  // namespace varsfm

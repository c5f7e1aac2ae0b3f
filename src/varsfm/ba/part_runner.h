#pragma once
// The Schur solver's unit of parallel work. The work is cut into a fixed number of parts,
// whatever the number of threads, and every sum over parts is taken in part order: the result is
// then the same bit for bit with any number of threads (Ceres' multi-threaded sums depend on the
// scheduling).
#include <algorithm>
#include <optional>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace varsfm {

constexpr int kSchurParts = 8;

// Runs fn(0) ... fn(kSchurParts - 1), on the calling thread alone or on up to `num_threads`
// threads.
class PartRunner {
 public:
  explicit PartRunner(int num_threads) {
    if (num_threads > 1) arena_.emplace(std::min(num_threads, kSchurParts));
  }
  template <typename Fn>
  void Run(const Fn& fn) {
    if (!arena_) {
      for (int k = 0; k < kSchurParts; ++k) fn(k);
      return;
    }
    arena_->execute([&] { tbb::parallel_for(0, kSchurParts, [&](int k) { fn(k); }); });
  }

 private:
  std::optional<tbb::task_arena> arena_;
};

}  // namespace varsfm

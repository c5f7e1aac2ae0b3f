#pragma once
// Bytes that concurrent tasks take from one capacity while they work, so that tasks of unequal
// size (photos of several cameras) are bounded by what they hold together, not by their count.
#include <condition_variable>
#include <cstddef>
#include <mutex>

namespace varsfm {

class ByteBudget {
 public:
  // `capacity` 0: unbounded (every request proceeds at once).
  explicit ByteBudget(size_t capacity) : capacity_(capacity) {}
  ByteBudget(const ByteBudget&) = delete;
  ByteBudget& operator=(const ByteBudget&) = delete;

  // The bytes a task holds until the lease ends.
  class Lease {
   public:
    Lease(Lease&& other) noexcept : budget_(other.budget_), bytes_(other.bytes_) {
      other.budget_ = nullptr;
    }
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    Lease& operator=(Lease&&) = delete;
    ~Lease();

   private:
    friend class ByteBudget;
    Lease(ByteBudget* budget, size_t bytes) : budget_(budget), bytes_(bytes) {}
    ByteBudget* budget_;
    size_t bytes_;
  };

  // Waits until `bytes` fit beside the bytes held. A request while nothing is held proceeds
  // whatever its size, so that one larger than the capacity runs alone instead of never. A
  // caller inside a TBB task must not hold a lease while its thread may take other tasks that
  // acquire (tbb::this_task_arena::isolate): a blocked thread would never end its own lease.
  Lease Acquire(size_t bytes);

  size_t HeldBytes() const;

 private:
  void Release(size_t bytes);

  const size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable released_;
  size_t held_ = 0;
};

}  // namespace varsfm

#include "varsfm/feature/mat_buffer_pool.h"

#include <atomic>
#include <limits>
#include <map>
#include <mutex>
#include <new>

#include <opencv2/core/core_c.h>  // CV_AUTOSTEP
#include <opencv2/core.hpp>

namespace varsfm {
namespace {

// cv::Mat's allocator as OpenCV's own (StdMatAllocator, modules/core/src/matrix.cpp), its large
// buffers taken from and given back to a pool while one is active. The object lives as long as
// the program: a matrix allocated while a pool was active may be freed after it ended.
class PooledMatAllocator final : public cv::MatAllocator {
 public:
  cv::UMatData* allocate(int dims, const int* sizes, int type, void* data0, size_t* step,
                         cv::AccessFlag, cv::UMatUsageFlags) const override {
    size_t total = CV_ELEM_SIZE(type);
    for (int i = dims - 1; i >= 0; --i) {
      if (step) {
        if (data0 && step[i] != CV_AUTOSTEP) {
          CV_Assert(total <= step[i]);
          total = step[i];
        } else {
          step[i] = total;
        }
      }
      total *= sizes[i];
    }
    // The buffer first, as OpenCV's allocator: a failed allocation then leaks no UMatData.
    uchar* data = data0 ? static_cast<uchar*>(data0) : Take(total);
    auto* u = new cv::UMatData(this);
    u->data = u->origdata = data;
    u->size = total;
    if (data0) u->flags |= cv::UMatData::USER_ALLOCATED;
    return u;
  }

  bool allocate(cv::UMatData* u, cv::AccessFlag, cv::UMatUsageFlags) const override {
    return u != nullptr;
  }

  void deallocate(cv::UMatData* u) const override {
    if (!u) return;
    CV_Assert(u->urefcount == 0 && u->refcount == 0);
    if (!(u->flags & cv::UMatData::USER_ALLOCATED)) Give(u->origdata, u->size);
    delete u;
  }

  // The first of the pools alive at once installs the allocator (and keeps OpenCV's, to restore)
  // and sets the pooled size; the others share its pool.
  void Activate(size_t min_bytes) {
    std::lock_guard lock(mutex_);
    if (users_++ > 0) return;
    previous_ = cv::Mat::getDefaultAllocator();
    min_bytes_ = min_bytes;
    cv::Mat::setDefaultAllocator(this);
  }

  size_t FreeBytes() const {
    std::lock_guard lock(mutex_);
    size_t total = 0;
    for (const auto& [bytes, block] : free_) total += bytes;
    return total;
  }

  // The last of the pools alive at once restores OpenCV's allocator and frees the pooled
  // blocks; buffers in use are freed when their matrices are.
  void Deactivate() {
    std::lock_guard lock(mutex_);
    if (--users_ > 0) return;
    cv::Mat::setDefaultAllocator(previous_);
    for (const auto& [bytes, block] : free_) cv::fastFree(block);
    free_.clear();
    min_bytes_ = kInactive;
  }

 private:
  // A pooled block of exactly `bytes`, else a new one. A large request the pool cannot serve
  // (a photo of another size) frees the pooled blocks first: kept, the blocks of every size met
  // would add up to a scale space per size in a folder of photos of many sizes.
  uchar* Take(size_t bytes) const {
    std::multimap<size_t, void*> unused;
    if (bytes >= min_bytes_) {  // small buffers, most of them, pass without the lock
      std::lock_guard lock(mutex_);
      if (bytes >= min_bytes_) {
        const auto it = free_.find(bytes);
        if (it != free_.end()) {
          uchar* block = static_cast<uchar*>(it->second);
          free_.erase(it);
          return block;
        }
        unused.swap(free_);
      }
    }
    for (const auto& [size, block] : unused) cv::fastFree(block);
    return static_cast<uchar*>(cv::fastMalloc(bytes));
  }

  void Give(uchar* block, size_t bytes) const {
    if (bytes >= min_bytes_) {
      std::lock_guard lock(mutex_);
      if (bytes >= min_bytes_) {
        try {  // reached from ~Mat (noexcept): a node the heap cannot give frees the block
          free_.emplace(bytes, block);
          return;
        } catch (const std::bad_alloc&) {
        }
      }
    }
    cv::fastFree(block);
  }

  mutable std::mutex mutex_;
  mutable std::multimap<size_t, void*> free_;  // by size: a scale space asks the same sizes again
  // Buffers of at least this many bytes are pooled; kInactive while no pool lives.
  static constexpr size_t kInactive = std::numeric_limits<size_t>::max();
  std::atomic<size_t> min_bytes_{kInactive};
  int users_ = 0;                         // pools alive
  cv::MatAllocator* previous_ = nullptr;  // OpenCV's default allocator before the first
};

PooledMatAllocator& Allocator() {
  static auto* allocator = new PooledMatAllocator;  // never destroyed (see above)
  return *allocator;
}

}  // namespace

ScopedMatBufferPool::ScopedMatBufferPool(size_t min_bytes) { Allocator().Activate(min_bytes); }

size_t ScopedMatBufferPool::FreeBytes() { return Allocator().FreeBytes(); }

ScopedMatBufferPool::~ScopedMatBufferPool() { Allocator().Deactivate(); }

}  // namespace varsfm

#include "varsfm/feature/mat_buffer_pool.h"

#include <gtest/gtest.h>

#include <memory>
#include <thread>

#include <opencv2/core.hpp>

namespace varsfm {
namespace {

constexpr size_t kMinBytes = size_t{1} << 20;

// A freed large buffer is handed out again, to another thread too.
TEST(ScopedMatBufferPool, ReusesLargeBuffersAcrossThreads) {
  const ScopedMatBufferPool pool(kMinBytes);
  const uchar* first = nullptr;
  {
    cv::Mat large(1024, 1024, CV_32F, cv::Scalar(1.0f));  // 4 MB
    first = large.data;
  }
  EXPECT_EQ(ScopedMatBufferPool::FreeBytes(), size_t{4} << 20);
  const uchar* again = nullptr;
  std::thread([&again] {
    cv::Mat large(1024, 1024, CV_32F);
    again = large.data;
    EXPECT_EQ(ScopedMatBufferPool::FreeBytes(), 0u);  // taken from the pool, not malloc'ed
  }).join();
  EXPECT_EQ(again, first);
  cv::Mat small(16, 16, CV_8U, cv::Scalar(7));
  EXPECT_EQ(small.at<uchar>(3, 4), 7);
}

// OpenCV's own allocator is back once the pool ends; a matrix made while it lived outlives it.
TEST(ScopedMatBufferPool, RestoresTheDefaultAllocatorAndOutlivesItsMatrices) {
  cv::MatAllocator* const before = cv::Mat::getDefaultAllocator();
  cv::Mat kept;
  {
    const ScopedMatBufferPool pool(kMinBytes);
    EXPECT_NE(cv::Mat::getDefaultAllocator(), before);
    kept = cv::Mat(1024, 1024, CV_32F, cv::Scalar(2.0f));
    cv::Mat freed(1024, 1024, CV_32F);  // back to the pool, freed when the pool ends
  }
  EXPECT_EQ(cv::Mat::getDefaultAllocator(), before);
  EXPECT_EQ(ScopedMatBufferPool::FreeBytes(), 0u);
  EXPECT_EQ(kept.at<float>(100, 200), 2.0f);
  kept.release();  // freed after its pool: must not touch the pool's freed blocks
}

// A large buffer of a size the pool does not hold frees what it holds (photos of many sizes
// would otherwise leave a scale space per size); a small one leaves it.
TEST(ScopedMatBufferPool, ALargeBufferOfAnotherSizeEmptiesThePool) {
  const ScopedMatBufferPool pool(kMinBytes);
  { cv::Mat a(1024, 1024, CV_32F), b(1024, 512, CV_32F); }
  EXPECT_EQ(ScopedMatBufferPool::FreeBytes(), size_t{6} << 20);
  { cv::Mat small(16, 16, CV_32F); }
  EXPECT_EQ(ScopedMatBufferPool::FreeBytes(), size_t{6} << 20);
  {
    cv::Mat reused(1024, 1024, CV_32F);  // taken from the pool
    EXPECT_EQ(ScopedMatBufferPool::FreeBytes(), size_t{2} << 20);
  }
  cv::Mat other(2048, 1024, CV_32F);
  EXPECT_EQ(ScopedMatBufferPool::FreeBytes(), 0u);
  other.release();
  EXPECT_EQ(ScopedMatBufferPool::FreeBytes(), size_t{8} << 20);
}

// Two extractions in one process: their pools, alive at once and ending in either order, share
// one pool; OpenCV's allocator is back when the last ends.
TEST(ScopedMatBufferPool, PoolsAliveAtOnceShareOnePool) {
  cv::MatAllocator* const before = cv::Mat::getDefaultAllocator();
  auto first = std::make_unique<ScopedMatBufferPool>(kMinBytes);
  cv::MatAllocator* const pooled = cv::Mat::getDefaultAllocator();
  auto second = std::make_unique<ScopedMatBufferPool>(kMinBytes);
  EXPECT_EQ(cv::Mat::getDefaultAllocator(), pooled);
  { cv::Mat large(1024, 1024, CV_32F); }
  first.reset();  // the first ends before the second
  EXPECT_EQ(cv::Mat::getDefaultAllocator(), pooled);
  EXPECT_EQ(ScopedMatBufferPool::FreeBytes(), size_t{4} << 20);
  second.reset();
  EXPECT_EQ(cv::Mat::getDefaultAllocator(), before);
  EXPECT_EQ(ScopedMatBufferPool::FreeBytes(), 0u);
}

}  // namespace
}  // namespace varsfm

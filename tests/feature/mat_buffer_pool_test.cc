#include "varsfm/feature/mat_buffer_pool.h"

#include <gtest/gtest.h>

#include <thread>

#include <opencv2/core.hpp>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

constexpr size_t kMinBytes = size_t{1} << 20;

// A freed large buffer is handed out again, to another thread too; a small one is not pooled.
TEST(ScopedMatBufferPool, ReusesLargeBuffersAcrossThreads) {
  const ScopedMatBufferPool pool(kMinBytes);
  const uchar* first = nullptr;
  {
    cv::Mat large(1024, 1024, CV_32F, cv::Scalar(1.0f));  // 4 MB
    first = large.data;
  }
  const uchar* again = nullptr;
  std::thread([&again] {
    cv::Mat large(1024, 1024, CV_32F);
    again = large.data;
  }).join();
  EXPECT_EQ(again, first);

  // Another size: a buffer of its own.
  cv::Mat other(512, 1024, CV_32F);
  EXPECT_NE(other.data, first);
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
  EXPECT_EQ(kept.at<float>(100, 200), 2.0f);
  kept.release();  // freed after its pool: must not touch the pool's freed blocks
}

TEST(ScopedMatBufferPool, OneAtATime) {
  const ScopedMatBufferPool pool(kMinBytes);
  EXPECT_THROW(ScopedMatBufferPool second(kMinBytes), Error);
}

}  // namespace
}  // namespace varsfm

#include "varsfm/dense/zncc.h"

#include <cmath>
#include <cstring>

#include <opencv2/imgproc.hpp>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "varsfm/util/error.h"

namespace varsfm {

ZnccImage::ZnccImage(const cv::Mat& gray, int radius, double min_std) {
  if (gray.empty() || gray.type() != CV_8UC1) Fail("ZNCC: images must be 8-bit gray");
  if (radius < 1 || radius > kMaxRadius)
    Fail("ZNCC: window radius {} outside 1..{}", radius, kMaxRadius);
  width_ = gray.cols, height_ = gray.rows, radius_ = radius;
  stride_ = static_cast<size_t>(width_) + 16;
  pixels_.assign(stride_ * height_, 0);
  for (int y = 0; y < height_; ++y)
    std::memcpy(&pixels_[y * stride_], gray.ptr<uint8_t>(y), static_cast<size_t>(width_));

  // Exact integer window sums: S fits int32 (an image's total does), Q is integral in double.
  cv::Mat sum, sqsum;
  cv::integral(gray, sum, sqsum, CV_32S, CV_64F);
  const int r = radius;
  const int64_t n = static_cast<int64_t>(2 * r + 1) * (2 * r + 1);
  // Flat when n Q - S^2 = n^2 var <= n^2 min_std^2.
  const double min_norm2 = static_cast<double>(n * n) * min_std * min_std;
  sum_.assign(size(), 0), inv_norm_.assign(size(), 0.f);
  for (int y = r; y < height_ - r; ++y) {
    for (int x = r; x < width_ - r; ++x) {
      const int32_t s = sum.at<int32_t>(y + r + 1, x + r + 1) - sum.at<int32_t>(y - r, x + r + 1) -
                        sum.at<int32_t>(y + r + 1, x - r) + sum.at<int32_t>(y - r, x - r);
      const auto q = static_cast<int64_t>(
          sqsum.at<double>(y + r + 1, x + r + 1) - sqsum.at<double>(y - r, x + r + 1) -
          sqsum.at<double>(y + r + 1, x - r) + sqsum.at<double>(y - r, x - r));
      const int64_t norm2 = n * q - static_cast<int64_t>(s) * s;
      const size_t i = Index(x, y);
      sum_[i] = s;
      if (static_cast<double>(norm2) > min_norm2)
        inv_norm_[i] = static_cast<float>(1.0 / std::sqrt(static_cast<double>(norm2)));
    }
  }
}

ZnccWindow::ZnccWindow(const ZnccImage& image, int x, int y) {
  const int r = image.radius_, side = 2 * r + 1;
  rows_ = side, chunks_ = (side + 7) / 8;
  area_ = static_cast<int64_t>(side) * side;
  const size_t i = image.Index(x, y);
  sum_ = image.sum_[i], inv_norm_ = image.inv_norm_[i];
#if defined(__SSE2__)
  // 8 pixels at a time (rows are padded, so the reads stay inside). Lanes past the window's
  // width are masked to 0, so the 8-wide products of Score ignore whatever the other image
  // holds there. This runs once per pixel propagation tries, so it is worth a few lines.
  const __m128i zero = _mm_setzero_si128();
  __m128i masks[(2 * ZnccImage::kMaxRadius + 1 + 7) / 8];
  for (int c = 0; c < chunks_; ++c) {
    alignas(16) int16_t lanes[8];
    for (int l = 0; l < 8; ++l) lanes[l] = 8 * c + l < side ? -1 : 0;
    masks[c] = _mm_load_si128(reinterpret_cast<const __m128i*>(lanes));
  }
  for (int dy = 0; dy < side; ++dy) {
    const uint8_t* row = &image.pixels_[(y - r + dy) * image.stride_ + (x - r)];
    for (int c = 0; c < chunks_; ++c) {
      const __m128i v =
          _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(row + 8 * c)), zero);
      _mm_store_si128(reinterpret_cast<__m128i*>(&pixels_[(dy * chunks_ + c) * 8]),
                      _mm_and_si128(v, masks[c]));
    }
  }
#else
  for (int dy = 0; dy < side; ++dy) {
    const uint8_t* row = &image.pixels_[(y - r + dy) * image.stride_ + (x - r)];
    for (int dx = 0; dx < side; ++dx) pixels_[dy * chunks_ * 8 + dx] = row[dx];
  }
#endif
}

float ZnccWindow::Score(const ZnccImage& other, int x, int y) const {
  const size_t j = other.Index(x, y);
  const float inv_norm = other.inv_norm_[j];
  if (inv_norm_ == 0.f || inv_norm == 0.f) return -1.f;
  const int r = other.radius_;
  const uint8_t* q = &other.pixels_[(y - r) * other.stride_ + (x - r)];
  int32_t cross = 0;
#if defined(__SSE2__)
  const __m128i zero = _mm_setzero_si128();
  __m128i acc = zero;
  const int16_t* p = pixels_;
  for (int row = 0; row < rows_; ++row, q += other.stride_) {
    for (int c = 0; c < chunks_; ++c, p += 8) {
      const __m128i b =
          _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(q + 8 * c)), zero);
      const __m128i a = _mm_load_si128(reinterpret_cast<const __m128i*>(p));
      acc = _mm_add_epi32(acc, _mm_madd_epi16(a, b));  // 16-bit products, summed in pairs
    }
  }
  acc = _mm_add_epi32(acc, _mm_shuffle_epi32(acc, _MM_SHUFFLE(1, 0, 3, 2)));
  acc = _mm_add_epi32(acc, _mm_shuffle_epi32(acc, _MM_SHUFFLE(2, 3, 0, 1)));
  cross = _mm_cvtsi128_si32(acc);
#else
  const int16_t* p = pixels_;
  for (int row = 0; row < rows_; ++row, q += other.stride_, p += chunks_ * 8)
    for (int dx = 0; dx < rows_; ++dx) cross += p[dx] * q[dx];
#endif
  const int64_t cov = area_ * cross - static_cast<int64_t>(sum_) * other.sum_[j];  // n^2 cov
  return static_cast<float>(static_cast<double>(cov) * inv_norm_ * inv_norm);
}

}  // namespace varsfm

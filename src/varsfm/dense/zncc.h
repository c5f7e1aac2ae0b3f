#pragma once
// Zero-mean normalised cross-correlation (ZNCC) of square windows, the similarity of match
// propagation (Lhuillier & Quan, PAMI 2002, section 3.1), made cheap enough to be evaluated
// tens of millions of times per image pair:
// - each image keeps, per pixel, its window sum S and 1 / sqrt(n Q - S^2) (Q: sum of squares,
//   n: window area) from integral images, so a ZNCC needs only the cross sum C of the two
//   windows: ZNCC = (n C - S1 S2) / (sqrt(n Q1 - S1^2) sqrt(n Q2 - S2^2));
// - C is a sum of products of 8-bit intensities, computed in exact integer arithmetic (8 lanes
//   of 16-bit products at a time where SSE2 exists), so results do not depend on summation
//   order or vector width;
// - the window of image 1 is unpacked once (ZnccWindow) and compared with the many candidate
//   windows of image 2 that propagation tries for it.
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace varsfm {

// An 8-bit gray image with per-pixel window statistics for one window radius.
class ZnccImage {
 public:
  static constexpr int kMaxRadius = 7;  // windows up to 15x15

  // Windows whose intensity standard deviation is at most `min_std` are "flat": their ZNCC is
  // undefined or noise-dominated and they never match. Throws varsfm::Error for a non-8-bit
  // image or a radius outside 1..kMaxRadius.
  ZnccImage(const cv::Mat& gray, int radius, double min_std);

  int width() const { return width_; }
  int height() const { return height_; }
  int radius() const { return radius_; }
  // Whether the whole window of (x, y) lies in the image.
  bool Inside(int x, int y) const {
    return x >= radius_ && y >= radius_ && x < width_ - radius_ && y < height_ - radius_;
  }
  size_t Index(int x, int y) const { return static_cast<size_t>(y) * width_ + x; }
  size_t size() const { return static_cast<size_t>(width_) * height_; }
  int At(int x, int y) const { return pixels_[static_cast<size_t>(y) * stride_ + x]; }
  bool Flat(size_t index) const { return inv_norm_[index] == 0.f; }

 private:
  friend class ZnccWindow;
  int width_ = 0, height_ = 0, radius_ = 0;
  size_t stride_ = 0;            // rows are padded so 16-byte reads past a window stay inside
  std::vector<uint8_t> pixels_;  // row-major, `stride_` bytes per row
  std::vector<int32_t> sum_;     // window sum S per pixel (0 off the Inside area)
  std::vector<float> inv_norm_;  // 1 / sqrt(n Q - S^2), 0 for flat or off-image windows
};

// The window around one pixel of an image, ready to be correlated with windows of another.
class ZnccWindow {
 public:
  // (x, y) must satisfy image.Inside(x, y).
  ZnccWindow(const ZnccImage& image, int x, int y);
  bool Flat() const { return inv_norm_ == 0.f; }
  // ZNCC in [-1, 1] with the window of (x, y) in `other` (same radius; other.Inside(x, y)),
  // or -1 when either window is flat.
  float Score(const ZnccImage& other, int x, int y) const;

 private:
  int rows_ = 0, chunks_ = 0;  // window rows; 8-pixel chunks per row
  int64_t area_ = 0;
  int32_t sum_ = 0;
  float inv_norm_ = 0;
  // Rows of `chunks_` x 8 lanes, lanes past the window 0; only the first rows_ x chunks_ x 8
  // are written (no zero-fill of the rest: a window is built per pixel tried).
  alignas(16) int16_t pixels_[(2 * ZnccImage::kMaxRadius + 1) * 16];
};

}  // namespace varsfm

#pragma once
// The innermost loop of PatchMatch's photometric cost (patchmatch.cc): the reference window's
// samples warped into a source view by a plane's homography, interpolated bilinearly, and the
// bilateral-weighted sums of the warped intensities that the NCC needs (Schoenberger et al.
// 2016, eq. 9). Eight samples at a time: one AVX2 register where the CPU has AVX2 (a target
// attribute on that kernel alone, so the library still runs on any x86-64), two SSE2 registers
// otherwise, a plain loop where there is no SSE2. Every path does each lane's operations in the
// same order (no FMA: the AVX2 kernel does not enable it) and adds up the lanes' partial sums the
// same way, so all give the same bits.

#include <algorithm>
#include <cstddef>

namespace varsfm {

inline constexpr int kWarpLanes = 8;

// The window's samples: offsets from the pixel's centre, the reference's intensities and the
// bilateral weights. Each array holds `count` samples padded with zeros to a whole number of
// kWarpLanes (a padded sample is the centre, with weight 0) and is 32-byte aligned.
struct WarpWindow {
  const float* dx = nullptr;
  const float* dy = nullptr;
  const float* value = nullptr;
  const float* weight = nullptr;
  int count = 0;
};

// A source view's intensities, row-major, with pixel centres at (i + 0.5, j + 0.5).
struct WarpSource {
  const float* pixels = nullptr;
  int width = 0, height = 0;
};

// The bilinear intensity at (x, y), pixel centres at (i + 0.5, j + 0.5), clamped to the border.
// Forced inline: PatchMatch runs it for every reference window sample, and GCC at -O2 leaves it
// a call.
[[gnu::always_inline]] inline float SampleBilinear(const WarpSource& s, float x, float y) {
  x = std::clamp(x - 0.5f, 0.0f, s.width - 1.001f);
  y = std::clamp(y - 0.5f, 0.0f, s.height - 1.001f);
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
  const float* r0 = s.pixels + static_cast<size_t>(y0) * s.width + x0;
  const float* r1 = r0 + s.width;
  return (r0[0] + fx * (r0[1] - r0[0])) * (1 - fy) + (r1[0] + fx * (r1[1] - r1[0])) * fy;
}

// Over the window, with v the warped source intensity, r the reference's and w the weight:
// sum w v, sum w v^2 and sum w v r.
struct WarpSums {
  float s = 0, ss = 0, rs = 0;
};

// Which implementation: the best the CPU runs (AVX2, else SSE2, else plain), or one by name
// (tests compare them).
enum class WarpKernel { kBest, kPlain, kSse2, kAvx2 };

// Whether this build and CPU have `kernel`.
bool WarpKernelAvailable(WarpKernel kernel);

// The window warped by the homography H (column-major 3 x 3) whose image of the window's centre
// is h0 = H (px, py, 1), clamped to the source's border. False when a sample falls behind the
// source camera (homogeneous z at most 1e-6); `sums` is then unspecified. A `kernel` that is not
// available runs as kBest.
bool WarpAndSum(const WarpWindow& window, const WarpSource& source, const float* H, const float* h0,
                WarpSums* sums, WarpKernel kernel = WarpKernel::kBest);

}  // namespace varsfm

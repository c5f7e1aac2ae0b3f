#include "varsfm/dense/window_warp.h"

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "varsfm/util/random.h"

namespace varsfm {
namespace {

constexpr int kWidth = 64, kHeight = 48;

// A window of (2k + 1)^2 samples `step` pixels apart, padded with zeros to whole groups of
// kWarpLanes, its reference intensities and weights random.
struct TestWindow {
  alignas(32) float dx[256] = {}, dy[256] = {}, value[256] = {}, weight[256] = {};
  int count = 0;

  TestWindow(int k, int step, Rng& rng) {
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (int j = -k; j <= k; ++j)
      for (int i = -k; i <= k; ++i) {
        dx[count] = static_cast<float>(i * step), dy[count] = static_cast<float>(j * step);
        value[count] = unit(rng), weight[count] = unit(rng);
        ++count;
      }
  }
  WarpWindow view() const { return {dx, dy, value, weight, count}; }

  // The first n samples only, the rest zeros (the padding WarpWindow asks for).
  void Truncate(int n) {
    for (int i = n; i < count; ++i) dx[i] = dy[i] = value[i] = weight[i] = 0;
    count = n;
  }
};

std::vector<float> RandomImage(Rng& rng) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> pixels(kWidth * kHeight);
  for (float& p : pixels) p = unit(rng);
  return pixels;
}

// A homography near a shift with a little rotation, scale and perspective, column-major.
std::array<float, 9> RandomHomography(Rng& rng) {
  std::uniform_real_distribution<float> small(-0.1f, 0.1f), shift(-20.0f, 20.0f);
  std::array<float, 9> H = {1 + small(rng),
                            small(rng),
                            0.002f * small(rng),
                            small(rng),
                            1 + small(rng),
                            0.002f * small(rng),
                            kWidth / 2 + shift(rng),
                            kHeight / 2 + shift(rng),
                            1.0f};
  return H;
}

// The definition in double precision: each sample's bilinear intensity (centres at i + 0.5,
// clamped to the border) and the weighted sums.
WarpSums DirectSums(const TestWindow& w, const std::vector<float>& pixels,
                    const std::array<float, 9>& H, double px, double py) {
  double s = 0, ss = 0, rs = 0;
  for (int i = 0; i < w.count; ++i) {
    const double u = px + w.dx[i], v = py + w.dy[i];
    const double hx = H[0] * u + H[3] * v + H[6], hy = H[1] * u + H[4] * v + H[7];
    const double hz = H[2] * u + H[5] * v + H[8];
    const double x = std::clamp(hx / hz - 0.5, 0.0, kWidth - 1.001);
    const double y = std::clamp(hy / hz - 0.5, 0.0, kHeight - 1.001);
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const double fx = x - x0, fy = y - y0;
    const float* r0 = &pixels[y0 * kWidth + x0];
    const float* r1 = r0 + kWidth;
    const double sample =
        (r0[0] + fx * (r0[1] - r0[0])) * (1 - fy) + (r1[0] + fx * (r1[1] - r1[0])) * fy;
    const double wv = w.weight[i] * sample;
    s += wv, ss += wv * sample, rs += wv * w.value[i];
  }
  return {static_cast<float>(s), static_cast<float>(ss), static_cast<float>(rs)};
}

uint32_t Bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof(u));
  return u;
}

TEST(WindowWarp, EveryKernelGivesTheDefinitionsSumsAndTheSameBits) {
  Rng rng(7);
  const std::vector<float> pixels = RandomImage(rng);
  const WarpSource source{pixels.data(), kWidth, kHeight};
  int compared = 0;
  for (int k = 1; k <= 7; ++k) {  // 9 to 225 samples: whole and partial groups of lanes
    const TestWindow w(k, k > 3 ? 1 : 2, rng);
    for (int trial = 0; trial < 20; ++trial) {
      const std::array<float, 9> H = RandomHomography(rng);
      const float px = 20.5f, py = 16.5f;
      const float h0[3] = {H[0] * px + H[3] * py + H[6], H[1] * px + H[4] * py + H[7],
                           H[2] * px + H[5] * py + H[8]};
      // The window's samples are offsets from the centre: the kernel's H maps them through
      // h0 + H.col(0) dx + H.col(1) dy.
      WarpSums plain;
      ASSERT_TRUE(WarpAndSum(w.view(), source, H.data(), h0, &plain, WarpKernel::kPlain));
      const WarpSums direct = DirectSums(w, pixels, H, px, py);
      EXPECT_NEAR(plain.s, direct.s, 1e-4 * w.count);
      EXPECT_NEAR(plain.ss, direct.ss, 1e-4 * w.count);
      EXPECT_NEAR(plain.rs, direct.rs, 1e-4 * w.count);
      for (const WarpKernel kernel : {WarpKernel::kSse2, WarpKernel::kAvx2, WarpKernel::kBest}) {
        if (!WarpKernelAvailable(kernel)) continue;
        WarpSums sums;
        ASSERT_TRUE(WarpAndSum(w.view(), source, H.data(), h0, &sums, kernel));
        EXPECT_EQ(Bits(sums.s), Bits(plain.s));
        EXPECT_EQ(Bits(sums.ss), Bits(plain.ss));
        EXPECT_EQ(Bits(sums.rs), Bits(plain.rs));
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 0);
}

// A square window always leaves one sample after whole groups of lanes; any count (1 to 49
// samples: 0 to 7 left over) gives the same bits in every kernel too.
TEST(WindowWarp, AnySampleCountGivesTheSameBitsInEveryKernel) {
  Rng rng(9);
  const std::vector<float> pixels = RandomImage(rng);
  const WarpSource source{pixels.data(), kWidth, kHeight};
  int compared = 0;
  for (int n = 1; n <= 49; ++n) {
    TestWindow w(3, 1, rng);
    w.Truncate(n);
    const std::array<float, 9> H = RandomHomography(rng);
    const float h0[3] = {H[0] * 20.5f + H[3] * 16.5f + H[6], H[1] * 20.5f + H[4] * 16.5f + H[7],
                         H[2] * 20.5f + H[5] * 16.5f + H[8]};
    WarpSums plain;
    ASSERT_TRUE(WarpAndSum(w.view(), source, H.data(), h0, &plain, WarpKernel::kPlain));
    for (const WarpKernel kernel : {WarpKernel::kSse2, WarpKernel::kAvx2}) {
      if (!WarpKernelAvailable(kernel)) continue;
      WarpSums sums;
      ASSERT_TRUE(WarpAndSum(w.view(), source, H.data(), h0, &sums, kernel));
      EXPECT_EQ(Bits(sums.s), Bits(plain.s)) << n << " samples";
      EXPECT_EQ(Bits(sums.ss), Bits(plain.ss)) << n << " samples";
      EXPECT_EQ(Bits(sums.rs), Bits(plain.rs)) << n << " samples";
      ++compared;
    }
  }
  EXPECT_GT(compared, 0);
}

TEST(WindowWarp, ASampleBehindTheSourceFailsInEveryKernel) {
  Rng rng(11);
  const std::vector<float> pixels = RandomImage(rng);
  const TestWindow w(2, 2, rng);
  // z = 1 - 0.3 dx: the samples at dx = 4 fall behind the source (z = -0.2), the centre does not.
  const std::array<float, 9> H = {1, 0, -0.3f, 0, 1, 0, 30, 20, 1};
  const float h0[3] = {30, 20, 1};
  for (const WarpKernel kernel :
       {WarpKernel::kPlain, WarpKernel::kSse2, WarpKernel::kAvx2, WarpKernel::kBest}) {
    if (!WarpKernelAvailable(kernel)) continue;
    WarpSums sums;
    EXPECT_FALSE(
        WarpAndSum(w.view(), {pixels.data(), kWidth, kHeight}, H.data(), h0, &sums, kernel));
  }
}

}  // namespace
}  // namespace varsfm

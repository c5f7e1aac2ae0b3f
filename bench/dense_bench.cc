// PatchMatch's innermost loop (dense/window_warp.h) by kernel: one window of the default size
// (radius 5, step 2: 25 samples) warped into a 800 x 533 source by a perspective homography,
// per call.
#include <array>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "varsfm/dense/window_warp.h"

namespace {

using varsfm::WarpKernel;

void BM_WarpAndSum(benchmark::State& state) {
  const auto kernel = static_cast<WarpKernel>(state.range(0));
  if (!varsfm::WarpKernelAvailable(kernel)) {
    state.SkipWithError("kernel not available on this CPU or build");
    return;
  }
  constexpr int kWidth = 800, kHeight = 533;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> pixels(kWidth * kHeight);
  for (float& p : pixels) p = unit(rng);
  alignas(32) std::array<float, 32> dx{}, dy{}, value{}, weight{};
  int count = 0;
  for (int j = -2; j <= 2; ++j)
    for (int i = -2; i <= 2; ++i, ++count) {
      dx[count] = 2.0f * i, dy[count] = 2.0f * j;
      value[count] = unit(rng), weight[count] = unit(rng);
    }
  const varsfm::WarpWindow window{dx.data(), dy.data(), value.data(), weight.data(), count};
  const varsfm::WarpSource source{pixels.data(), kWidth, kHeight};
  // Centres spread over the image, so the loads miss the cache as PatchMatch's do.
  std::vector<std::array<float, 3>> centres(4096);
  for (auto& c : centres) c = {20 + 760 * unit(rng), 20 + 493 * unit(rng), 1.0f};
  const std::array<float, 9> H = {0.98f, 0.03f, 1e-5f, -0.02f, 1.01f, 2e-5f, 0.0f, 0.0f, 1.0f};
  size_t k = 0;
  for (auto _ : state) {
    varsfm::WarpSums sums;
    benchmark::DoNotOptimize(varsfm::WarpAndSum(
        window, source, H.data(), centres[k++ % centres.size()].data(), &sums, kernel));
    benchmark::DoNotOptimize(sums);
  }
}
BENCHMARK(BM_WarpAndSum)
    ->Arg(static_cast<int>(WarpKernel::kPlain))
    ->Arg(static_cast<int>(WarpKernel::kSse2))
    ->Arg(static_cast<int>(WarpKernel::kAvx2))
    ->ArgName("kernel");

}  // namespace

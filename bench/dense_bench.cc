// PatchMatch's innermost loop (dense/window_warp.h) by kernel: one window of the default size
// (radius 5, step 2: 25 samples) warped into a 800 x 533 source by a perspective homography,
// per call, at random centres or along rows. And fusion's consistency filter and fusion
// (dense/depth_fusion.h) of N exact depth maps of a street, each view checked against every other
// one or against its overlapping views.
#include <algorithm>
#include <array>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>
#include <spdlog/spdlog.h>

#include "varsfm/dense/depth_fusion.h"
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
  // Centres spread over the image (every load misses the cache), or walking along rows two
  // pixels at a time as a PatchMatch half-sweep does (neighbouring windows share cache lines).
  const bool row_walk = state.range(1) != 0;
  std::vector<std::array<float, 3>> centres(4096);
  for (size_t c = 0; c < centres.size(); ++c)
    centres[c] = row_walk ? std::array<float, 3>{20.5f + 2.0f * static_cast<float>(c % 380),
                                                 20.5f + static_cast<float>(c / 380), 1.0f}
                          : std::array<float, 3>{20 + 760 * unit(rng), 20 + 493 * unit(rng), 1.0f};
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
    ->ArgsProduct({{static_cast<int>(WarpKernel::kPlain), static_cast<int>(WarpKernel::kSse2),
                    static_cast<int>(WarpKernel::kAvx2)},
                   {0, 1}})
    ->ArgNames({"kernel", "row_walk"});

// View i of a street: at x = 0.5 i looking along +z at the facade z = 10, 80 x 60 pixels, its
// exact depth map; with `overlapping`, checked against the 50 nearest views (the views that see
// the same stretch of facade, as OverlappingViews finds them from the sparse model).
std::vector<varsfm::FusionView> StreetViews(int n, bool overlapping) {
  constexpr int kW = 80, kH = 60;
  std::vector<varsfm::FusionView> views(n);
  for (int i = 0; i < n; ++i) {
    varsfm::FusionView& v = views[i];
    v.image_id = static_cast<varsfm::image_t>(i + 1);
    v.K << 60, 0, kW / 2.0, 0, 60, kH / 2.0, 0, 0, 1;
    v.cam_from_world =
        varsfm::Rigid3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.5 * i, 0, 0));
    v.color = cv::Mat(kH, kW, CV_8UC3, cv::Scalar(10, 20, 30));
    v.map.width = kW, v.map.height = kH;
    v.map.depth.assign(kW * kH, 10.0f);
    v.map.normal.assign(v.map.depth.size(), -Eigen::Vector3f::UnitZ());
    v.map.cost.assign(v.map.depth.size(), 0.3f);
    if (!overlapping || n <= 51) continue;
    const int first = std::clamp(i - 25, 0, n - 51);
    for (int u = first; u < first + 51; ++u)
      if (u != i) v.overlapping.push_back(static_cast<uint32_t>(u));
  }
  return views;
}

void BM_FilterAndFuse(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const bool overlapping = state.range(1) != 0;
  varsfm::DepthFusionOptions options;
  spdlog::set_level(spdlog::level::warn);  // no progress lines among the results
  for (auto _ : state) {
    state.PauseTiming();
    std::vector<varsfm::FusionView> views = StreetViews(n, overlapping);
    state.ResumeTiming();
    varsfm::FilterByGeometricConsistency(&views, options);
    benchmark::DoNotOptimize(varsfm::FuseDepthMaps(views, options));
  }
}
BENCHMARK(BM_FilterAndFuse)
    ->ArgsProduct({{100, 200, 400}, {0, 1}})
    ->ArgNames({"views", "overlapping"})
    ->Unit(benchmark::kMillisecond);

}  // namespace

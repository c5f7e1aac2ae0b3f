// Estimator speed and accuracy on synthetic data (GenerateSyntheticScene):
//   F RANSAC on ~2000 matches with ~50 % outliers: varsfm (MSAC and inlier-count scoring) and
//   OpenCV's cv::findFundamentalMat (FM_RANSAC, USAC_MAGSAC) at the same threshold;
//   resection (EstimateProjectionMatrix) from 1000 2D-3D matches with 30 % outliers.
// Counters: recall / precision of the inlier mask against the ground-truth outlier flags, and
// the RMS Sampson distance of the true inliers' exact projections to the estimated F.
#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>
#include <opencv2/calib3d.hpp>

#include "varsfm/estimators/projection_estimator.h"
#include "varsfm/estimators/two_view_estimators.h"
#include "varsfm/geometry/fundamental.h"
#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm {
namespace {

struct FData {
  std::vector<Eigen::Vector2d> x1, x2, t1, t2;  // observed and exact pixels
  std::vector<char> outlier;
};

const FData& Data() {
  static const FData data = [] {
    SyntheticOptions o;
    o.num_images = 3;
    o.num_points = 4000;
    o.focal_start = 900;
    o.focal_end = 1600;
    o.noise_sigma = 0.5;
    o.outlier_ratio = 0.3;  // per observation: ~51 % of matches have an outlier end
    const SyntheticScene s = GenerateSyntheticScene(o);
    FData d;
    for (const auto& a : s.observations[0]) {
      for (const auto& b : s.observations[2]) {
        if (a.point_id != b.point_id) continue;
        d.x1.push_back(a.pixel);
        d.x2.push_back(b.pixel);
        d.t1.push_back(a.true_pixel);
        d.t2.push_back(b.true_pixel);
        d.outlier.push_back(a.outlier || b.outlier);
      }
      if (d.x1.size() == 2000) break;
    }
    return d;
  }();
  return data;
}

void Report(benchmark::State& state, const Eigen::Matrix3d& F, const std::vector<char>& mask) {
  const FData& d = Data();
  int tp = 0, fp = 0, fn = 0, n = 0;
  double sq = 0;
  for (size_t i = 0; i < d.x1.size(); ++i) {
    tp += mask[i] && !d.outlier[i];
    fp += mask[i] && d.outlier[i];
    fn += !mask[i] && !d.outlier[i];
    if (!d.outlier[i]) {
      sq += SampsonErrorSquared(F, d.t1[i], d.t2[i]);
      ++n;
    }
  }
  state.counters["matches"] = static_cast<double>(d.x1.size());
  state.counters["recall"] = tp / double(tp + fn);
  state.counters["precision"] = tp / double(tp + fp);
  state.counters["rms_true_px"] = std::sqrt(sq / n);
}

void BM_FundamentalVarsfm(benchmark::State& state) {
  const FData& d = Data();
  RansacOptions options;
  options.max_error = 1.5;
  options.msac_score = state.range(0) == 1;
  RansacReport<Eigen::Matrix3d> report;
  for (auto _ : state) {
    report = EstimateFundamentalMatrix(d.x1, d.x2, options);
    benchmark::DoNotOptimize(report.model);
  }
  state.counters["iterations"] = report.iterations;
  Report(state, report.model, report.inlier_mask);
}
BENCHMARK(BM_FundamentalVarsfm)->Arg(1)->Arg(0)->ArgName("msac")->Unit(benchmark::kMillisecond);

void BM_FundamentalOpenCV(benchmark::State& state) {
  const FData& d = Data();
  std::vector<cv::Point2f> p1, p2;
  for (size_t i = 0; i < d.x1.size(); ++i) {
    p1.emplace_back(d.x1[i].x(), d.x1[i].y());
    p2.emplace_back(d.x2[i].x(), d.x2[i].y());
  }
  const int method = static_cast<int>(state.range(0));
  cv::Mat F, mask;
  for (auto _ : state) {
    // OpenCV's threshold is on the point-to-epipolar-line distance (FM_RANSAC) or the
    // Sampson error (USAC); the same 1.5 px is used.
    F = cv::findFundamentalMat(p1, p2, method, 1.5, 0.9999, mask);
    benchmark::DoNotOptimize(F.data);
  }
  Eigen::Matrix3d Fe = Eigen::Matrix3d::Zero();
  std::vector<char> m(d.x1.size(), 0);
  if (F.rows == 3 && F.cols == 3) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) Fe(r, c) = F.at<double>(r, c);
    for (size_t i = 0; i < m.size(); ++i) m[i] = mask.at<uchar>(static_cast<int>(i)) != 0;
  }
  Report(state, Fe, m);
}
BENCHMARK(BM_FundamentalOpenCV)
    ->Arg(cv::FM_RANSAC)
    ->Arg(cv::USAC_MAGSAC)
    ->ArgName("method")
    ->Unit(benchmark::kMillisecond);

void BM_Resection(benchmark::State& state) {
  SyntheticOptions o;
  o.num_images = 2;
  o.num_points = 1600;
  o.focal_start = 1200;
  o.noise_sigma = 0.5;
  o.outlier_ratio = 0.3;
  const SyntheticScene s = GenerateSyntheticScene(o);
  std::vector<Eigen::Vector2d> x;
  std::vector<Eigen::Vector3d> X;
  std::vector<char> outlier;
  for (const auto& obs : s.observations[1]) {
    if (x.size() == 1000) break;
    x.push_back(obs.pixel);
    X.push_back(s.points[obs.point_id]);
    outlier.push_back(obs.outlier);
  }
  RansacOptions options;
  options.max_error = 2.0;
  RansacReport<Matrix34d> report;
  for (auto _ : state) {
    report = EstimateProjectionMatrix(x, X, options);
    benchmark::DoNotOptimize(report.model);
  }
  int tp = 0, fp = 0, fn = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    tp += report.inlier_mask[i] && !outlier[i];
    fp += report.inlier_mask[i] && outlier[i];
    fn += !report.inlier_mask[i] && !outlier[i];
  }
  state.counters["matches"] = static_cast<double>(x.size());
  state.counters["recall"] = tp / double(tp + fn);
  state.counters["precision"] = tp / double(tp + fp);
  state.counters["iterations"] = report.iterations;
}
BENCHMARK(BM_Resection)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace varsfm

BENCHMARK_MAIN();

// Feature extraction of one 12 MP phone photo (4032x3024), stage by stage: JPEG decoding,
// the downscale to SiftOptions::max_image_size, and ExtractSift (OpenCV's scale space,
// extrema, orientations, descriptors, RootSIFT). The photo is a view of the project's
// rendered scene (synthetic/rendered_scene.h) encoded as a JPEG of quality 95 in memory, or
// the JPEG named by the environment variable VARSFM_BENCH_PHOTO. A rendered view has less fine
// detail than a real photo: the `features` counter says how many it gives.
//   build/bench/sift_bench --benchmark_filter=Extract
// Times are per photo on the threads OpenCV uses (cv::getNumThreads); `--benchmark_*` flags
// as usual. The whole extract stage (two photos in flight) is timed by bench/sift_speed.sh.
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <vector>

#include <benchmark/benchmark.h>
#include <opencv2/imgproc.hpp>

#include "varsfm/feature/sift.h"
#include "varsfm/image/jpeg_codec.h"
#include "varsfm/synthetic/rendered_scene.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

const std::vector<uint8_t>& PhotoJpeg() {
  static const std::vector<uint8_t> jpeg = [] {
    std::vector<uint8_t> data;
    if (const char* path = std::getenv("VARSFM_BENCH_PHOTO")) {
      std::ifstream file(path, std::ios::binary);
      data.assign(std::istreambuf_iterator<char>(file), {});
      if (data.empty()) Fail("cannot read {}", path);
      return data;
    }
    RenderedSceneOptions options;
    options.num_images = 2;  // the renderer's minimum; the first view is used
    options.width = 4032;
    options.height = 3024;
    // The demo's field of view (640 px focal length for 800 px wide images).
    options.focal_start = 0.8 * options.width;
    options.supersampling = 1;
    const RenderedScene scene = RenderSyntheticScene(options);
    if (!EncodeJpeg(scene.images[0], 95, &data)) Fail("cannot encode the rendered view");
    return data;
  }();
  return jpeg;
}

cv::Mat DecodedPhoto() {
  const std::vector<uint8_t>& jpeg = PhotoJpeg();
  std::optional<cv::Mat> gray = DecodeJpeg(jpeg.data(), jpeg.size(), ColorMode::kGray);
  if (!gray || gray->empty()) Fail("cannot decode the photo");
  return *gray;
}

void BM_DecodeJpegGray(benchmark::State& state) {
  const std::vector<uint8_t>& jpeg = PhotoJpeg();
  for (auto _ : state) {
    benchmark::DoNotOptimize(DecodeJpeg(jpeg.data(), jpeg.size(), ColorMode::kGray));
  }
}
BENCHMARK(BM_DecodeJpegGray)->Unit(benchmark::kMillisecond);

void BM_DownscaleToSiftSize(benchmark::State& state) {
  const cv::Mat gray = DecodedPhoto();
  const double scale =
      static_cast<double>(SiftOptions().max_image_size) / std::max(gray.cols, gray.rows);
  for (auto _ : state) {
    cv::Mat small;
    cv::resize(gray, small, cv::Size(), scale, scale, cv::INTER_AREA);
    benchmark::DoNotOptimize(small.data);
  }
}
BENCHMARK(BM_DownscaleToSiftSize)->Unit(benchmark::kMillisecond);

void BM_ExtractSift(benchmark::State& state) {
  const cv::Mat gray = DecodedPhoto();
  const SiftOptions options;
  size_t features = 0;
  for (auto _ : state) {
    const ImageFeatures extracted = ExtractSift(gray, options);
    features = extracted.keypoints.size();
  }
  state.counters["features"] = static_cast<double>(features);
  state.counters["width"] = gray.cols;
}
BENCHMARK(BM_ExtractSift)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace varsfm

#include "varsfm/dense/patchmatch.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <tbb/parallel_for.h>

#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/random.h"

namespace varsfm {
namespace {

constexpr float kMaxCost = 2.0f;  // 1 - NCC of anti-correlated windows; also "no view"
constexpr int kMaxSources = 16;
constexpr int kMaxSamples = 15 * 15;

// A few random numbers per pixel and sweep: SplitMix64 from a seed derived from (seed, sweep,
// pixel), so draws do not depend on which thread updates which pixel or in what order.
class PixelRandom {
 public:
  explicit PixelRandom(uint64_t seed) : state_(seed) {}
  float Uniform() {  // [0, 1)
    state_ = DeriveSeed(state_, 0);
    return static_cast<float>(state_ >> 40) * (1.0f / 16777216.0f);
  }

 private:
  uint64_t state_;
};

struct Hypothesis {
  float depth = 0;
  Eigen::Vector3f normal = -Eigen::Vector3f::UnitZ();
};

// The source view's homography for a plane n^T X = c of the reference frame is
// H = K_s (R + t n^T / c) K_r^-1 = A + b (K_r^-T n)^T / c (Hartley & Zisserman eq. 13.2).
struct SourceGeometry {
  Eigen::Matrix3f A;  // K_s R K_r^-1
  Eigen::Vector3f b;  // K_s t
  const float* pixels = nullptr;
  int width = 0, height = 0;
};

// The reference window of one pixel: sample offsets, intensities and bilateral weights, with the
// weighted mean and variance of the intensities (they do not depend on the hypothesis).
struct ReferenceWindow {
  int count = 0;
  std::array<float, kMaxSamples> dx, dy, value, weight;
  float weight_sum = 0, mean = 0, variance = 0;
};

float Sample(const SourceGeometry& s, float x, float y) {
  // Pixel centres at (i + 0.5, j + 0.5); clamped to the border.
  x = std::clamp(x - 0.5f, 0.0f, s.width - 1.001f);
  y = std::clamp(y - 0.5f, 0.0f, s.height - 1.001f);
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const float fx = x - x0, fy = y - y0;
  const float* r0 = s.pixels + static_cast<size_t>(y0) * s.width + x0;
  const float* r1 = r0 + s.width;
  return (r0[0] + fx * (r0[1] - r0[0])) * (1 - fy) + (r1[0] + fx * (r1[1] - r1[0])) * fy;
}

class DepthMapEstimator {
 public:
  DepthMapEstimator(const std::vector<PatchMatchView>& views, uint32_t reference,
                    const std::vector<uint32_t>& sources, const PatchMatchInit& init,
                    const PatchMatchOptions& options, uint64_t seed)
      : options_(options), init_(init), seed_(seed) {
    const PatchMatchView& ref = views[reference];
    ref_.pixels = ref.gray.ptr<float>();
    ref_.width = ref.gray.cols;
    ref_.height = ref.gray.rows;
    K_inv_ = ref.K.inverse().cast<float>();
    for (uint32_t s : sources) {
      const PatchMatchView& view = views[s];
      const Rigid3d source_from_ref = view.cam_from_world * ref.cam_from_world.Inverse();
      SourceGeometry g;
      g.A = (view.K * source_from_ref.R() * ref.K.inverse()).cast<float>();
      g.b = (view.K * source_from_ref.translation).cast<float>();
      g.pixels = view.gray.ptr<float>();
      g.width = view.gray.cols;
      g.height = view.gray.rows;
      sources_.push_back(g);
    }
    map_.width = ref_.width;
    map_.height = ref_.height;
    const size_t n = static_cast<size_t>(map_.width) * map_.height;
    map_.depth.assign(n, 0);
    map_.normal.assign(n, -Eigen::Vector3f::UnitZ());
    map_.cost.assign(n, kMaxCost);
    flat_.assign(n, 0);
  }

  DepthMap Run() {
    ForEachRow([&](int y) {
      for (int x = 0; x < map_.width; ++x) Initialise(x, y);
    });
    for (int iteration = 0; iteration < options_.num_iterations; ++iteration)
      for (int colour = 0; colour < 2; ++colour)
        ForEachRow([&](int y) {
          for (int x = (y + colour) % 2; x < map_.width; x += 2) Update(x, y, iteration, colour);
        });
    for (size_t i = 0; i < map_.depth.size(); ++i)
      if (flat_[i] || map_.cost[i] > options_.max_cost) map_.depth[i] = 0;
    return std::move(map_);
  }

 private:
  template <typename F>
  void ForEachRow(F&& row) {
    tbb::parallel_for(0, map_.height, [&](int y) { row(y); });
  }

  Eigen::Vector3f Ray(int x, int y) const {
    return K_inv_ * Eigen::Vector3f(x + 0.5f, y + 0.5f, 1.0f);
  }

  void BuildWindow(int x, int y, ReferenceWindow* w) const {
    const int step = options_.window_step;
    const int k = options_.window_radius / step;
    const float centre = ref_.pixels[map_.Index(x, y)];
    const float color_factor =
        -0.5f / static_cast<float>(options_.sigma_color * options_.sigma_color);
    const float space_factor =
        -0.5f / static_cast<float>(options_.sigma_spatial * options_.sigma_spatial);
    w->count = 0;
    double sum_w = 0, sum_v = 0, sum_vv = 0;
    for (int j = -k; j <= k; ++j)
      for (int i = -k; i <= k; ++i) {
        const float dx = static_cast<float>(i * step), dy = static_cast<float>(j * step);
        const float v = Sample(ref_, x + 0.5f + dx, y + 0.5f + dy);
        const float weight = std::exp(color_factor * (v - centre) * (v - centre) +
                                      space_factor * (dx * dx + dy * dy));
        const int c = w->count++;
        w->dx[c] = dx, w->dy[c] = dy, w->value[c] = v, w->weight[c] = weight;
        sum_w += weight, sum_v += weight * v, sum_vv += weight * v * v;
      }
    w->weight_sum = static_cast<float>(sum_w);
    w->mean = static_cast<float>(sum_v / sum_w);
    w->variance = static_cast<float>(sum_vv / sum_w - (sum_v / sum_w) * (sum_v / sum_w));
  }

  // 1 - bilateral-weighted NCC of the window against its warp into source s (Schoenberger et al.
  // 2016, eq. 9); kMaxCost when the centre falls behind the source or outside its image.
  float ViewCost(const ReferenceWindow& w, const SourceGeometry& s, const Eigen::Vector3f& m,
                 float inv_c, float px, float py) const {
    const Eigen::Matrix3f H = s.A + s.b * (m.transpose() * inv_c);
    const Eigen::Vector3f h0 = H * Eigen::Vector3f(px, py, 1.0f);
    if (h0.z() <= 1e-6f) return kMaxCost;
    const float cx = h0.x() / h0.z(), cy = h0.y() / h0.z();
    if (cx < 0 || cy < 0 || cx >= s.width || cy >= s.height) return kMaxCost;
    float sum_s = 0, sum_ss = 0, sum_rs = 0;
    for (int i = 0; i < w.count; ++i) {
      const Eigen::Vector3f h = h0 + H.col(0) * w.dx[i] + H.col(1) * w.dy[i];
      if (h.z() <= 1e-6f) return kMaxCost;
      const float v = Sample(s, h.x() / h.z(), h.y() / h.z());
      const float wv = w.weight[i] * v;
      sum_s += wv, sum_ss += wv * v, sum_rs += wv * w.value[i];
    }
    const float mean_s = sum_s / w.weight_sum;
    const float var_s = sum_ss / w.weight_sum - mean_s * mean_s;
    if (var_s < options_.min_ncc_variance) return kMaxCost;
    const float cov = sum_rs / w.weight_sum - w.mean * mean_s;
    const float ncc = cov / std::sqrt(w.variance * var_s);
    return std::clamp(1.0f - ncc, 0.0f, kMaxCost);
  }

  // The mean of the `num_best_views` lowest view costs of a hypothesis at pixel (x, y).
  float Cost(const ReferenceWindow& w, int x, int y, const Hypothesis& h) const {
    const Eigen::Vector3f ray = Ray(x, y);
    const float c = h.depth * h.normal.dot(ray);  // n^T X of the plane through the pixel's point
    if (!(std::abs(c) > 1e-12f)) return kMaxCost;
    const Eigen::Vector3f m = K_inv_.transpose() * h.normal;
    std::array<float, kMaxSources> costs;
    const int n = static_cast<int>(sources_.size());
    for (int s = 0; s < n; ++s)
      costs[s] = ViewCost(w, sources_[s], m, 1.0f / c, x + 0.5f, y + 0.5f);
    const int best = std::min(options_.num_best_views, n);
    std::partial_sort(costs.begin(), costs.begin() + best, costs.begin() + n);
    float sum = 0;
    for (int i = 0; i < best; ++i) sum += costs[i];
    return sum / static_cast<float>(best);
  }

  // A normal facing the camera: flipped when it looks along the viewing ray.
  static Eigen::Vector3f FacingCamera(Eigen::Vector3f n, const Eigen::Vector3f& ray) {
    if (n.dot(ray) > 0) n = -n;
    return n;
  }

  Eigen::Vector3f RandomNormal(PixelRandom& random, const Eigen::Vector3f& ray) const {
    const float z = 2 * random.Uniform() - 1;
    const float phi = 2 * std::numbers::pi_v<float> * random.Uniform();
    const float r = std::sqrt(std::max(0.0f, 1 - z * z));
    return FacingCamera({r * std::cos(phi), r * std::sin(phi), z}, ray);
  }

  // Uniform in inverse depth: equal steps of disparity across the range.
  float RandomDepth(PixelRandom& random) const {
    const float a = 1.0f / init_.max_depth, b = 1.0f / init_.min_depth;
    return 1.0f / (a + (b - a) * random.Uniform());
  }

  uint64_t PixelSeed(size_t index, int sweep) const {
    return DeriveSeed(DeriveSeed(seed_, static_cast<uint64_t>(sweep)), index);
  }

  void Initialise(int x, int y) {
    const size_t i = map_.Index(x, y);
    const Eigen::Vector3f ray = Ray(x, y);
    PixelRandom random(PixelSeed(i, 0));
    Hypothesis h;
    if (!init_.prior.depth.empty() && init_.prior.depth[i] > 0) {
      h.depth = init_.prior.depth[i];
      const Eigen::Vector3f& n = init_.prior.normal[i];
      h.normal = n.squaredNorm() > 0.5f ? FacingCamera(n, ray) : -ray.normalized();
    } else {
      h.depth = RandomDepth(random);
      h.normal = RandomNormal(random, ray);
    }
    ReferenceWindow w;
    BuildWindow(x, y, &w);
    flat_[i] = w.variance < options_.min_ncc_variance;
    map_.depth[i] = h.depth;
    map_.normal[i] = h.normal;
    map_.cost[i] = flat_[i] ? kMaxCost : Cost(w, x, y, h);
  }

  void Update(int x, int y, int iteration, int colour) {
    const size_t i = map_.Index(x, y);
    if (flat_[i]) return;
    ReferenceWindow w;
    BuildWindow(x, y, &w);
    const Eigen::Vector3f ray = Ray(x, y);
    Hypothesis best{map_.depth[i], map_.normal[i]};
    float best_cost = map_.cost[i];
    const auto consider = [&](const Hypothesis& h) {
      if (!(h.depth >= init_.min_depth && h.depth <= init_.max_depth)) return;
      const float cost = Cost(w, x, y, h);
      if (cost < best_cost) best_cost = cost, best = h;
    };
    // Propagation: the planes of the other colour's pixels at odd offsets (Gipuma's pattern,
    // near and far neighbours along the axes), each intersected with this pixel's ray.
    static constexpr std::array<std::array<int, 2>, 8> kOffsets = {
        {{-1, 0}, {1, 0}, {0, -1}, {0, 1}, {-5, 0}, {5, 0}, {0, -5}, {0, 5}}};
    std::array<float, 8> tried{};
    int num_tried = 0;
    for (const auto& [ox, oy] : kOffsets) {
      const int nx = x + ox, ny = y + oy;
      if (nx < 0 || ny < 0 || nx >= map_.width || ny >= map_.height) continue;
      const size_t j = map_.Index(nx, ny);
      if (flat_[j]) continue;
      const Eigen::Vector3f& n = map_.normal[j];
      const float denominator = n.dot(ray);
      if (denominator > -1e-3f) continue;  // plane seen edge-on from this pixel
      Hypothesis h{map_.depth[j] * n.dot(Ray(nx, ny)) / denominator, n};
      if (h.depth == best.depth && h.normal == best.normal) continue;
      if (std::find(tried.begin(), tried.begin() + num_tried, h.depth) != tried.begin() + num_tried)
        continue;
      tried[num_tried++] = h.depth;
      consider(h);
    }
    // Refinement: a random hypothesis, then the current one with its depth and its normal
    // perturbed by a range that shrinks with the iterations.
    PixelRandom random(PixelSeed(i, 1 + 2 * iteration + colour));
    const float scale = 0.5f * std::pow(0.5f, static_cast<float>(iteration));
    consider({RandomDepth(random), RandomNormal(random, ray)});
    const float depth_step = scale * 0.1f * best.depth;
    consider({best.depth + depth_step * (2 * random.Uniform() - 1), best.normal});
    const Eigen::Vector3f perturbation(2 * random.Uniform() - 1, 2 * random.Uniform() - 1,
                                       2 * random.Uniform() - 1);
    consider({best.depth, FacingCamera((best.normal + scale * perturbation).normalized(), ray)});
    map_.depth[i] = best.depth;
    map_.normal[i] = best.normal;
    map_.cost[i] = best_cost;
  }

  const PatchMatchOptions& options_;
  const PatchMatchInit& init_;
  uint64_t seed_;
  SourceGeometry ref_;
  Eigen::Matrix3f K_inv_;
  std::vector<SourceGeometry> sources_;
  DepthMap map_;
  std::vector<uint8_t> flat_;
};

}  // namespace

DepthMap EstimateDepthMap(const std::vector<PatchMatchView>& views, uint32_t reference,
                          const std::vector<uint32_t>& sources, const PatchMatchInit& init,
                          const PatchMatchOptions& options, uint64_t seed) {
  const PatchMatchView& ref = views.at(reference);
  if (ref.gray.type() != CV_32F || ref.gray.cols < 2 || ref.gray.rows < 2)
    Fail("patchmatch: view {} is not a float image of at least 2x2 pixels", reference);
  if (sources.empty() || sources.size() > static_cast<size_t>(kMaxSources))
    Fail("patchmatch: view {} has {} source views (1 to {})", reference, sources.size(),
         kMaxSources);
  for (uint32_t s : sources)
    if (views.at(s).gray.type() != CV_32F || views[s].gray.cols < 2 || views[s].gray.rows < 2)
      Fail("patchmatch: source view {} is not a float image of at least 2x2 pixels", s);
  if (!(init.min_depth > 0 && init.max_depth > init.min_depth))
    Fail("patchmatch: depth range [{}, {}] of view {} is empty", init.min_depth, init.max_depth,
         reference);
  if (!init.prior.depth.empty() &&
      (init.prior.width != ref.gray.cols || init.prior.height != ref.gray.rows))
    Fail("patchmatch: prior depth map of view {} has another size", reference);
  return DepthMapEstimator(views, reference, sources, init, options, seed).Run();
}

void PatchMatchOptions::Check() const {
  CheckInRange("patchmatch window_step", window_step, 1, 7);
  CheckInRange("patchmatch window_radius", window_radius, window_step, 7 * window_step);
  CheckGreaterThan("patchmatch sigma_color", sigma_color, 0);
  CheckGreaterThan("patchmatch sigma_spatial", sigma_spatial, 0);
  CheckInRange("--dense-iterations", num_iterations, 0, 50);
  CheckInRange("patchmatch num_best_views", num_best_views, 1, kMaxSources);
  CheckInRange("patchmatch max_cost", max_cost, 0.0, 2.0);
  CheckAtLeast("patchmatch min_ncc_variance", min_ncc_variance, 0);
}

}  // namespace varsfm

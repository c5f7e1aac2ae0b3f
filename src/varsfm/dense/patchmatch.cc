#include "varsfm/dense/patchmatch.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <tbb/parallel_for.h>
#include <opencv2/imgproc.hpp>

#include "varsfm/dense/window_warp.h"
#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/random.h"

namespace varsfm {
namespace {

constexpr float kMaxCost = 2.0f;     // 1 - NCC of anti-correlated windows; also no match
constexpr float kOutOfView = -1.0f;  // ViewCost: the window's centre is not in the source
constexpr int kMaxSources = 16;
constexpr int kMaxSamples = 15 * 15;
constexpr int kMinLevelSize = 32;  // px, the shorter side of the coarsest pyramid level

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
  // The geometric pass: the source's depth map, and the way back into the reference,
  // K_r X_r = d A_back (u, v, 1)^T - b_back for the source pixel (u, v) at depth d.
  const DepthMap* map = nullptr;
  Eigen::Matrix3f A_back;  // K_r R^T K_s^-1
  Eigen::Vector3f b_back;  // K_r R^T t
};

// The reference window of one pixel: sample offsets, intensities and bilateral weights, with the
// weighted mean and variance of the intensities (they do not depend on the hypothesis).
struct ReferenceWindow {
  int count = 0;
  // Padded to whole groups of kWarpLanes with zeros (window_warp.h).
  static constexpr int kPadded = (kMaxSamples + kWarpLanes - 1) / kWarpLanes * kWarpLanes;
  alignas(32) std::array<float, kPadded> dx, dy, value, weight;
  float weight_sum = 0, mean = 0, variance = 0;
};

// M (x, y, 1)^T, summed as Eigen's coefficient-based product sums a row, but inlined: GCC left
// Eigen's product a call in the per-view cost.
[[gnu::always_inline]] inline Eigen::Vector3f TimesPoint(const Eigen::Matrix3f& M, float x,
                                                         float y) {
  return {M(0, 0) * x + (M(0, 1) * y + M(0, 2)), M(1, 0) * x + (M(1, 1) * y + M(1, 2)),
          M(2, 0) * x + (M(2, 1) * y + M(2, 2))};
}

class DepthMapEstimator {
 public:
  // `upsampled` (null, or the reference's size): the planes of the next coarser level, or of the
  // photometric pass, a starting hypothesis beside the prior. `source_maps` (null, or one per
  // source): the sources' depth maps, which add the geometric term to the cost. init.planar (if
  // not empty) adds the planar prior's term.
  DepthMapEstimator(const std::vector<PatchMatchView>& views, uint32_t reference,
                    const std::vector<uint32_t>& sources, const PatchMatchInit& init,
                    const DepthMap* upsampled, const std::vector<const DepthMap*>* source_maps,
                    const PatchMatchOptions& options, uint64_t seed, int num_iterations)
      : options_(options),
        init_(init),
        upsampled_(upsampled),
        planar_(init.planar.depth.empty() ? nullptr : &init.planar),
        seed_(seed),
        geometric_(source_maps != nullptr),
        planar_term_(planar_ != nullptr),
        num_iterations_(num_iterations) {
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
      if (source_maps) {
        g.map = (*source_maps)[sources_.size()];
        const Rigid3d ref_from_source = source_from_ref.Inverse();
        g.A_back = (ref.K * ref_from_source.R() * view.K.inverse()).cast<float>();
        g.b_back = (-ref.K * ref_from_source.translation).cast<float>();
      }
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

  // `drop_uncertain`: depths above max_cost are dropped (the finest level); a coarser level keeps
  // every hypothesis to start the next from.
  DepthMap Run(bool drop_uncertain) {
    ForEachRow([&](int y) {
      for (int x = 0; x < map_.width; ++x) Initialise(x, y);
    });
    for (int iteration = 0; iteration < num_iterations_; ++iteration)
      for (int colour = 0; colour < 2; ++colour)
        ForEachRow([&](int y) {
          for (int x = (y + colour) % 2; x < map_.width; x += 2) Update(x, y, iteration, colour);
        });
    if ((geometric_ || planar_term_) && drop_uncertain) {
      // The depths are kept or dropped by their photometric cost alone, as after the first pass;
      // the geometric and planar terms only chose among the hypotheses.
      geometric_ = false;
      planar_term_ = false;
      ForEachRow([&](int y) {
        for (int x = 0; x < map_.width; ++x) {
          const size_t i = map_.Index(x, y);
          if (flat_[i]) continue;
          ReferenceWindow w;
          BuildWindow(x, y, &w);
          map_.cost[i] = Cost(w, x, y, {map_.depth[i], map_.normal[i]});
        }
      });
    }
    for (size_t i = 0; i < map_.depth.size(); ++i) {
      if (AgreesWithPlanarPrior(i)) continue;
      if (flat_[i] || (drop_uncertain && map_.cost[i] > options_.max_cost)) map_.depth[i] = 0;
    }
    return std::move(map_);
  }

 private:
  template <typename F>
  void ForEachRow(F&& row) {
    tbb::parallel_for(0, map_.height, [&](int y) { row(y); });
  }

  Eigen::Vector3f Ray(int x, int y) const { return TimesPoint(K_inv_, x + 0.5f, y + 0.5f); }

  void BuildWindow(int x, int y, ReferenceWindow* w) const {
    const int step = options_.window_step;
    const int k = options_.window_radius / step;
    const float centre = ref_.pixels[map_.Index(x, y)];
    const WarpSource reference{ref_.pixels, ref_.width, ref_.height};
    const float color_factor =
        -0.5f / static_cast<float>(options_.sigma_color * options_.sigma_color);
    const float space_factor =
        -0.5f / static_cast<float>(options_.sigma_spatial * options_.sigma_spatial);
    w->count = 0;
    double sum_w = 0, sum_v = 0, sum_vv = 0;
    for (int j = -k; j <= k; ++j)
      for (int i = -k; i <= k; ++i) {
        const float dx = static_cast<float>(i * step), dy = static_cast<float>(j * step);
        const float v = SampleBilinear(reference, x + 0.5f + dx, y + 0.5f + dy);
        const float weight = std::exp(color_factor * (v - centre) * (v - centre) +
                                      space_factor * (dx * dx + dy * dy));
        const int c = w->count++;
        w->dx[c] = dx, w->dy[c] = dy, w->value[c] = v, w->weight[c] = weight;
        sum_w += weight, sum_v += weight * v, sum_vv += weight * v * v;
      }
    for (int c = w->count; c < ReferenceWindow::kPadded; ++c)
      w->dx[c] = w->dy[c] = w->value[c] = w->weight[c] = 0;
    w->weight_sum = static_cast<float>(sum_w);
    w->mean = static_cast<float>(sum_v / sum_w);
    w->variance = static_cast<float>(sum_vv / sum_w - (sum_v / sum_w) * (sum_v / sum_w));
  }

  // The pixel's prior plane as a hypothesis; false where it has none.
  bool PlanarHypothesis(size_t i, Hypothesis* h) const {
    if (!planar_ || !(planar_->depth[i] > 0)) return false;
    *h = {planar_->depth[i], planar_->normal[i]};
    return true;
  }

  bool AgreesWithPlanarPrior(size_t i) const {
    if (!planar_ || !(planar_->depth[i] > 0) || !(map_.depth[i] > 0)) return false;
    if (flat_[i] && !options_.planar_fill_flat) return false;
    const float tolerance = 2 * static_cast<float>(options_.planar_depth_sigma) * planar_->depth[i];
    return std::abs(map_.depth[i] - planar_->depth[i]) <= tolerance;
  }

  // Xu & Tao 2020's planar prior as a cost (PatchMatchOptions::planar_weight).
  float PlanarCost(size_t i, const Hypothesis& h) const {
    const float prior_depth = planar_->depth[i];
    if (!(prior_depth > 0)) return 0;
    const float e_d =
        (h.depth - prior_depth) / (static_cast<float>(options_.planar_depth_sigma) * prior_depth);
    const float angle = std::acos(std::clamp(h.normal.dot(planar_->normal[i]), -1.0f, 1.0f));
    const float e_n =
        angle / static_cast<float>(options_.planar_normal_sigma_deg * std::numbers::pi / 180.0);
    return static_cast<float>(options_.planar_weight) *
           (1 - std::exp(-0.5f * (e_d * e_d + e_n * e_n)));
  }

  // 1 - bilateral-weighted NCC of the window against its warp into source s (Schoenberger et al.
  // 2016, eq. 9); kOutOfView when the centre falls behind the source or outside its image,
  // kMaxCost when a window sample falls behind it or the warped window is flat.
  float ViewCost(const ReferenceWindow& w, const SourceGeometry& s, const Eigen::Vector3f& m,
                 float inv_c, float px, float py) const {
    const Eigen::Matrix3f H = s.A + s.b * (m.transpose() * inv_c);
    const Eigen::Vector3f h0 = TimesPoint(H, px, py);
    if (h0.z() <= 1e-6f) return kOutOfView;
    const float cx = h0.x() / h0.z(), cy = h0.y() / h0.z();
    if (cx < 0 || cy < 0 || cx >= s.width || cy >= s.height) return kOutOfView;
    WarpSums sums;
    const WarpWindow window{w.dx.data(), w.dy.data(), w.value.data(), w.weight.data(), w.count};
    if (!WarpAndSum(window, {s.pixels, s.width, s.height}, H.data(), h0.data(), &sums))
      return kMaxCost;
    const float mean_s = sums.s / w.weight_sum;
    const float var_s = sums.ss / w.weight_sum - mean_s * mean_s;
    if (var_s < options_.min_ncc_variance) return kMaxCost;
    const float cov = sums.rs / w.weight_sum - w.mean * mean_s;
    const float ncc = cov / std::sqrt(w.variance * var_s);
    return std::clamp(1.0f - ncc, 0.0f, kMaxCost);
  }

  // The geometric term of Schoenberger et al. 2016 (section 4.2, eq. 11): the forward-backward
  // reprojection error, in pixels, of the pixel's point through the source's depth map, capped
  // and weighted. A source pixel without a confident depth counts as the cap.
  float GeometricCost(const SourceGeometry& s, float depth, float px, float py) const {
    const float cap = static_cast<float>(options_.geometric_max_error);
    const float weight = static_cast<float>(options_.geometric_weight);
    const Eigen::Vector3f q = depth * TimesPoint(s.A, px, py) + s.b;
    if (!s.map || q.z() <= 1e-6f) return weight * cap;
    const float qx = q.x() / q.z(), qy = q.y() / q.z();
    if (!(qx >= 0 && qy >= 0 && qx < s.width && qy < s.height)) return weight * cap;
    const size_t j = s.map->Index(static_cast<int>(qx), static_cast<int>(qy));
    const float d = s.map->depth[j];
    if (d <= 0 || s.map->cost[j] > options_.max_cost) return weight * cap;
    const Eigen::Vector3f back = d * TimesPoint(s.A_back, qx, qy) - s.b_back;
    if (back.z() <= 1e-6f) return weight * cap;
    const float error = std::hypot(back.x() / back.z() - px, back.y() / back.z() - py);
    return weight * std::min(error, cap);
  }

  // The mean of the `num_best_views` lowest view costs of a hypothesis at pixel (x, y).
  float Cost(const ReferenceWindow& w, int x, int y, const Hypothesis& h) const {
    const Eigen::Vector3f ray = Ray(x, y);
    const float c = h.depth * h.normal.dot(ray);  // n^T X of the plane through the pixel's point
    if (!(std::abs(c) > 1e-12f)) return kMaxCost;
    const Eigen::Vector3f m = K_inv_.transpose() * h.normal;
    std::array<float, kMaxSources> costs;
    const int n = static_cast<int>(sources_.size());
    int in_view = 0;
    for (int s = 0; s < n; ++s) {
      float view_cost = ViewCost(w, sources_[s], m, 1.0f / c, x + 0.5f, y + 0.5f);
      if (view_cost == kOutOfView) {
        if (options_.missing_view_penalty < 0)
          view_cost = kMaxCost;  // counted as a failed match
        else
          continue;
      }
      if (geometric_) view_cost += GeometricCost(sources_[s], h.depth, x + 0.5f, y + 0.5f);
      costs[in_view++] = view_cost;
    }
    // Sources the pixel's point falls outside of carry no evidence: the mean is over those that
    // see it, plus missing_view_penalty for each of the num_best_views it lacks.
    const int wanted = std::min(options_.num_best_views, n);
    const int best = std::min(wanted, in_view);
    if (best == 0) return kMaxCost;
    std::partial_sort(costs.begin(), costs.begin() + best, costs.begin() + in_view);
    float sum = 0;
    for (int i = 0; i < best; ++i) sum += costs[i];
    float cost = sum / static_cast<float>(best);
    if (best < wanted)
      cost = std::min(kMaxCost,
                      cost + static_cast<float>(options_.missing_view_penalty) * (wanted - best));
    return planar_term_ ? cost + PlanarCost(map_.Index(x, y), h) : cost;
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
    ReferenceWindow w;
    BuildWindow(x, y, &w);
    flat_[i] = w.variance < options_.min_ncc_variance;
    // The lower-cost of the prior's and the coarser level's hypotheses, a random one without.
    Hypothesis best;
    float best_cost = kMaxCost;
    bool have = false;
    const auto consider = [&](const Hypothesis& h) {
      const float cost = flat_[i] ? kMaxCost : Cost(w, x, y, h);
      if (!have || cost < best_cost) best = h, best_cost = cost, have = true;
    };
    const auto prior_normal = [&](const Eigen::Vector3f& n) {
      return n.squaredNorm() > 0.5f ? FacingCamera(n, ray) : Eigen::Vector3f(-ray.normalized());
    };
    if (!init_.prior.depth.empty() && init_.prior.depth[i] > 0)
      consider({init_.prior.depth[i], prior_normal(init_.prior.normal[i])});
    if (upsampled_ && upsampled_->depth[i] > 0)
      consider({upsampled_->depth[i], prior_normal(upsampled_->normal[i])});
    // A flat pixel takes its prior plane (its cost cannot choose); others weigh it in.
    if (Hypothesis planar; PlanarHypothesis(i, &planar)) {
      if (flat_[i]) have = false;
      consider(planar);
    }
    if (!have) {
      PixelRandom random(PixelSeed(i, 0));
      const float depth = RandomDepth(random);
      consider({depth, RandomNormal(random, ray)});
    }
    map_.depth[i] = best.depth;
    map_.normal[i] = best.normal;
    map_.cost[i] = best_cost;
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
    // The prior plane, which the depth range does not bound (it comes from confirmed depths).
    if (Hypothesis planar; PlanarHypothesis(i, &planar) &&
                           !(planar.depth == best.depth && planar.normal == best.normal)) {
      const float cost = Cost(w, x, y, planar);
      if (cost < best_cost) best_cost = cost, best = planar;
    }
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
  const DepthMap* upsampled_;
  const DepthMap* planar_;
  uint64_t seed_;
  bool geometric_;
  bool planar_term_;
  int num_iterations_;
  SourceGeometry ref_;
  Eigen::Matrix3f K_inv_;
  std::vector<SourceGeometry> sources_;
  DepthMap map_;
  std::vector<uint8_t> flat_;
};

// Half the size (rounded up) by area averaging. OpenCV's resize maps pixel centres onto pixel
// centres, so in the coordinates used here (centres at i + 0.5) u' = s u and K scales with s.
PatchMatchView HalfSize(const PatchMatchView& view) {
  PatchMatchView half;
  const cv::Size size((view.gray.cols + 1) / 2, (view.gray.rows + 1) / 2);
  cv::resize(view.gray, half.gray, size, 0, 0, cv::INTER_AREA);
  const Eigen::Vector3d scale(static_cast<double>(size.width) / view.gray.cols,
                              static_cast<double>(size.height) / view.gray.rows, 1.0);
  half.K = scale.asDiagonal() * view.K;
  half.cam_from_world = view.cam_from_world;
  return half;
}

// The prior at another resolution: each depth moves to the pixel its pixel's centre falls in
// (depth along the optical axis does not change with K's scale), the nearest where several do.
DepthMap ResizePrior(const DepthMap& prior, int width, int height) {
  DepthMap out;
  out.width = width;
  out.height = height;
  out.depth.assign(static_cast<size_t>(width) * height, 0);
  out.normal.assign(out.depth.size(), Eigen::Vector3f::Zero());
  const float sx = static_cast<float>(width) / prior.width;
  const float sy = static_cast<float>(height) / prior.height;
  for (int y = 0; y < prior.height; ++y)
    for (int x = 0; x < prior.width; ++x) {
      const float d = prior.depth[prior.Index(x, y)];
      if (d <= 0) continue;
      const int u = std::min(static_cast<int>(sx * (x + 0.5f)), width - 1);
      const int v = std::min(static_cast<int>(sy * (y + 0.5f)), height - 1);
      const size_t j = out.Index(u, v);
      if (out.depth[j] > 0 && out.depth[j] <= d) continue;
      out.depth[j] = d;
      out.normal[j] = prior.normal[prior.Index(x, y)];
    }
  return out;
}

// The coarse level's planes at the fine level's pixels: each fine pixel takes the plane of the
// coarse pixel its centre falls in, intersected with its own ray (so a slanted plane keeps its
// slope rather than becoming steps).
DepthMap UpsamplePlanes(const DepthMap& coarse, const Eigen::Matrix3d& K_coarse, int width,
                        int height, const Eigen::Matrix3d& K_fine) {
  DepthMap out;
  out.width = width;
  out.height = height;
  out.depth.assign(static_cast<size_t>(width) * height, 0);
  out.normal.assign(out.depth.size(), Eigen::Vector3f::Zero());
  const Eigen::Matrix3f coarse_inv = K_coarse.inverse().cast<float>();
  const Eigen::Matrix3f fine_inv = K_fine.inverse().cast<float>();
  const float sx = static_cast<float>(coarse.width) / width;
  const float sy = static_cast<float>(coarse.height) / height;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const int u = std::min(static_cast<int>(sx * (x + 0.5f)), coarse.width - 1);
      const int v = std::min(static_cast<int>(sy * (y + 0.5f)), coarse.height - 1);
      const size_t j = coarse.Index(u, v);
      const float d = coarse.depth[j];
      if (d <= 0) continue;
      const Eigen::Vector3f& n = coarse.normal[j];
      const float along_fine = n.dot(fine_inv * Eigen::Vector3f(x + 0.5f, y + 0.5f, 1.0f));
      const float along_coarse = n.dot(coarse_inv * Eigen::Vector3f(u + 0.5f, v + 0.5f, 1.0f));
      const float depth = along_fine < -1e-3f ? d * along_coarse / along_fine : d;
      out.depth[out.Index(x, y)] = depth > 0 ? depth : d;
      out.normal[out.Index(x, y)] = n;
    }
  return out;
}

// Coarse to fine: with `levels` > 1 (and room for a half-size level) the depth map is first
// estimated at half the size, where the same window covers four times the area, so planes
// converge on weak texture; its planes then start this level beside the prior (as multi-scale
// PatchMatch does: Xu & Tao, "Multi-Scale Geometric Consistency Guided Multi-View Stereo", CVPR
// 2019, without the geometric term).
DepthMap EstimateLevels(const std::vector<PatchMatchView>& views, uint32_t reference,
                        const std::vector<uint32_t>& sources, const PatchMatchInit& init,
                        const PatchMatchOptions& options, uint64_t seed, int levels, bool finest) {
  const PatchMatchView& ref = views[reference];
  DepthMap upsampled;
  if (levels > 1 && std::min(ref.gray.cols, ref.gray.rows) >= 2 * kMinLevelSize) {
    std::vector<PatchMatchView> half(views.size());
    half[reference] = HalfSize(ref);
    for (uint32_t s : sources) half[s] = HalfSize(views[s]);
    PatchMatchInit coarse_init;
    coarse_init.min_depth = init.min_depth;
    coarse_init.max_depth = init.max_depth;
    if (!init.prior.depth.empty())
      coarse_init.prior =
          ResizePrior(init.prior, half[reference].gray.cols, half[reference].gray.rows);
    const DepthMap coarse =
        EstimateLevels(half, reference, sources, coarse_init, options,
                       DeriveSeed(seed, static_cast<uint64_t>(levels)), levels - 1, false);
    upsampled = UpsamplePlanes(coarse, half[reference].K, ref.gray.cols, ref.gray.rows, ref.K);
  }
  const DepthMap* coarser = upsampled.depth.empty() ? nullptr : &upsampled;
  const int iterations = coarser && options.num_fine_iterations > 0 ? options.num_fine_iterations
                                                                    : options.num_iterations;
  return DepthMapEstimator(views, reference, sources, init, coarser, nullptr, options, seed,
                           iterations)
      .Run(finest);
}

void CheckInputs(const std::vector<PatchMatchView>& views, uint32_t reference,
                 const std::vector<uint32_t>& sources, const PatchMatchInit& init) {
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
  if (!init.planar.depth.empty() &&
      (init.planar.width != ref.gray.cols || init.planar.height != ref.gray.rows))
    Fail("patchmatch: planar prior of view {} has another size", reference);
}

}  // namespace

DepthMap EstimateDepthMap(const std::vector<PatchMatchView>& views, uint32_t reference,
                          const std::vector<uint32_t>& sources, const PatchMatchInit& init,
                          const PatchMatchOptions& options, uint64_t seed, bool drop_uncertain) {
  CheckInputs(views, reference, sources, init);
  return EstimateLevels(views, reference, sources, init, options, seed, options.num_levels,
                        drop_uncertain);
}

DepthMap RefineDepthMapGeometrically(const std::vector<PatchMatchView>& views, uint32_t reference,
                                     const std::vector<uint32_t>& sources,
                                     const std::vector<const DepthMap*>& source_maps,
                                     const DepthMap& start, const PatchMatchInit& init,
                                     const PatchMatchOptions& options, uint64_t seed) {
  if (source_maps.size() != sources.size())
    Fail("patchmatch: {} source depth maps for {} source views of view {}", source_maps.size(),
         sources.size(), reference);
  return RefineDepthMap(views, reference, sources, source_maps, start, init, options, seed,
                        options.num_geometric_iterations);
}

DepthMap RefineDepthMap(const std::vector<PatchMatchView>& views, uint32_t reference,
                        const std::vector<uint32_t>& sources,
                        const std::vector<const DepthMap*>& source_maps, const DepthMap& start,
                        const PatchMatchInit& init, const PatchMatchOptions& options, uint64_t seed,
                        int num_iterations, bool drop_uncertain) {
  CheckInputs(views, reference, sources, init);
  const PatchMatchView& ref = views[reference];
  if (start.width != ref.gray.cols || start.height != ref.gray.rows)
    Fail("patchmatch: starting depth map of view {} has another size", reference);
  if (!source_maps.empty() && source_maps.size() != sources.size())
    Fail("patchmatch: {} source depth maps for {} source views of view {}", source_maps.size(),
         sources.size(), reference);
  for (size_t k = 0; k < source_maps.size(); ++k)
    if (source_maps[k] && (source_maps[k]->width != views[sources[k]].gray.cols ||
                           source_maps[k]->height != views[sources[k]].gray.rows))
      Fail("patchmatch: depth map of source view {} has another size", sources[k]);
  return DepthMapEstimator(views, reference, sources, init, &start,
                           source_maps.empty() ? nullptr : &source_maps, options, seed,
                           num_iterations)
      .Run(drop_uncertain);
}

void PatchMatchOptions::Check() const {
  CheckInRange("--dense-window-step", window_step, 1, 7);
  CheckInRange("--dense-window-radius", window_radius, window_step, 7 * window_step);
  CheckPositive("--dense-sigma-color", sigma_color);
  CheckPositive("--dense-sigma-spatial", sigma_spatial);
  CheckInRange("--dense-iterations", num_iterations, 0, 50);
  CheckInRange("--dense-levels", num_levels, 1, 4);
  CheckInRange("--dense-fine-iterations", num_fine_iterations, 0, 50);
  CheckInRange("--dense-geometric-iterations", num_geometric_iterations, 0, 50);
  CheckNonNegative("patchmatch geometric_weight", geometric_weight);
  CheckPositive("patchmatch geometric_max_error", geometric_max_error);
  CheckNonNegative("patchmatch planar_weight", planar_weight);
  CheckPositive("patchmatch planar_depth_sigma", planar_depth_sigma);
  CheckPositive("patchmatch planar_normal_sigma_deg", planar_normal_sigma_deg);
  CheckInRange("--dense-best-views", num_best_views, 1, kMaxSources);
  CheckInRange("--dense-missing-view-penalty", missing_view_penalty, -1.0, 2.0);
  CheckInRange("--dense-max-cost", max_cost, 0.0, 2.0);
  CheckNonNegative("patchmatch min_ncc_variance", min_ncc_variance);
}

void DepthMap::MoveToScratch(const std::filesystem::path& folder) {
  ScratchLayout layout;
  layout.Add(depth.size() * sizeof(float), alignof(float));
  layout.Add(normal.size() * sizeof(Eigen::Vector3f), alignof(Eigen::Vector3f));
  layout.Add(cost.size() * sizeof(float), alignof(float));
  const std::shared_ptr<ScratchMemory> memory = ScratchMemory::Create(folder, layout.bytes);
  depth.MoveTo(memory, layout.offsets[0]);
  normal.MoveTo(memory, layout.offsets[1]);
  cost.MoveTo(memory, layout.offsets[2]);
}

}  // namespace varsfm

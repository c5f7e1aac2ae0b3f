#include "varsfm/texture/photo_consistency.h"

#include <array>
#include <atomic>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

// The mode reached by mean shift from `start` with a Gaussian kernel of the given bandwidth, and
// the kernel density there.
Eigen::Vector3f ShiftToMode(const std::vector<Eigen::Vector3f>& colours, Eigen::Vector3f start,
                            double bandwidth, double* density) {
  const double inv = 1.0 / (2 * bandwidth * bandwidth);
  for (int iter = 0; iter < 20; ++iter) {
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    double weights = 0;
    for (const Eigen::Vector3f& c : colours) {
      const double w = std::exp(-(c - start).squaredNorm() * inv);
      sum += static_cast<float>(w) * c;
      weights += w;
    }
    const Eigen::Vector3f next = sum / static_cast<float>(weights);
    const bool done = (next - start).squaredNorm() < 1e-4f;
    start = next;
    if (done) break;
  }
  *density = 0;
  for (const Eigen::Vector3f& c : colours) *density += std::exp(-(c - start).squaredNorm() * inv);
  return start;
}

}  // namespace

size_t RejectInconsistentViews(const std::vector<Eigen::Vector3f>& gains,
                               const std::vector<std::array<int, 3>>& neighbours,
                               const PhotoConsistencyOptions& options, FaceObservations* obs) {
  if (!options.enabled) return 0;
  std::vector<char> rejected_here(obs->quality.size(), 0);
  std::atomic<size_t> rejected = 0;
  const float reject_sq =
      static_cast<float>(std::pow(options.reject_distance * options.bandwidth, 2));
  // Faces are independent and each writes only its own entries: parallel, and deterministic.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, obs->num_faces, 4096), [&](const auto& range) {
    std::vector<size_t> entries;  // of the face's candidate views, in view order
    std::vector<Eigen::Vector3f> colours;
    for (size_t f = range.begin(); f < range.end(); ++f) {
      entries.clear();
      colours.clear();
      for (size_t k = obs->begin[f]; k < obs->begin[f + 1]; ++k) {
        if (obs->quality[k] <= 0) continue;
        entries.push_back(k);
        colours.push_back(obs->colour[k].cwiseProduct(gains[obs->view[k]]));
      }
      if (entries.size() < 3) continue;  // no majority to side with
      Eigen::Vector3f mode = Eigen::Vector3f::Zero();
      double best_density = -1;
      for (const Eigen::Vector3f& c : colours) {
        double density;
        const Eigen::Vector3f m = ShiftToMode(colours, c, options.bandwidth, &density);
        if (density > best_density + 1e-9) {
          best_density = density;
          mode = m;
        }
      }
      size_t inliers = 0;
      for (const Eigen::Vector3f& c : colours) inliers += (c - mode).squaredNorm() <= reject_sq;
      if (2 * inliers <= colours.size()) continue;
      for (size_t i = 0; i < entries.size(); ++i)
        obs->deviation[entries[i]] = (colours[i] - mode).norm();
      for (size_t i = 0; i < entries.size(); ++i) {
        if ((colours[i] - mode).squaredNorm() > reject_sq) {
          obs->quality[entries[i]] = 0;
          rejected_here[entries[i]] = 1;
          ++rejected;
        }
      }
    }
  });
  // An occluder's edge covers the faces around the rejected ones partly: their mean colour
  // passes, but their texture would show a fringe of the occluder. Rejected too, for the faces
  // that keep another candidate.
  size_t ring = 0;
  for (size_t f = 0; f < obs->num_faces; ++f) {
    for (size_t k = obs->begin[f]; k < obs->begin[f + 1]; ++k) {
      if (!rejected_here[k]) continue;
      const uint32_t v = obs->view[k];
      for (const int g : neighbours[f]) {
        if (g < 0) continue;
        const size_t kg = obs->Find(v, g);
        if (kg == FaceObservations::kNone || obs->quality[kg] <= 0 || rejected_here[kg]) continue;
        size_t others = 0;
        for (size_t u = obs->begin[g]; u < obs->begin[g + 1]; ++u)
          others += u != kg && obs->quality[u] > 0;
        if (others == 0) continue;
        obs->quality[kg] = 0;
        ++ring;
      }
    }
  }
  return rejected + ring;
}

void PhotoConsistencyOptions::Check() const {
  CheckPositive("photo_consistency.bandwidth", bandwidth);
  CheckPositive("photo_consistency.reject_distance", reject_distance);
}

}  // namespace varsfm

#include "varsfm/dense/match_propagation.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "varsfm/dense/zncc.h"
#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

// The paper's texture test (section 3.3): confidence s(x) = max over the 4-neighbours D of
// |I(x + D) - I(x)| above t, and a window that is not flat (so ZNCC is defined).
std::vector<uint8_t> TextureMask(const ZnccImage& image, double min_gradient) {
  std::vector<uint8_t> textured(image.size(), 0);
  for (int y = image.radius(); y < image.height() - image.radius(); ++y)
    for (int x = image.radius(); x < image.width() - image.radius(); ++x) {
      const int c = image.At(x, y);
      const int s = std::max({std::abs(image.At(x - 1, y) - c), std::abs(image.At(x + 1, y) - c),
                              std::abs(image.At(x, y - 1) - c), std::abs(image.At(x, y + 1) - c)});
      const size_t i = image.Index(x, y);
      textured[i] = !image.Flat(i) && s > min_gradient;
    }
  return textured;
}

// A parent's disparity (x2 - x1), packed; kNoDisparity: none tried yet.
constexpr uint32_t kNoDisparity = UINT32_MAX;
uint32_t PackDisparity(int dx, int dy) {
  return (static_cast<uint32_t>(dx + 32768) << 16) | static_cast<uint32_t>(dy + 32768);
}

struct Candidate {
  float zncc;
  int x1, y1, x2, y2;
};

// The paper's best-first list of candidate matches (section 3.2) as a bucket queue over
// [min_zncc, 1] with 4096 buckets: O(1) push and pop instead of a binary heap, whose
// sift-downs over millions of entries are cache misses that took half the propagation time.
// Within a bucket (ZNCCs closer than 5e-5 for z = 0.8) the last pushed comes first, so the
// order is still deterministic and best-first up to a difference that does not matter.
class CandidateQueue {
 public:
  explicit CandidateQueue(float min_zncc)
      : min_(min_zncc),
        scale_(min_zncc < 1.f ? kBuckets / (1.f - min_zncc) : 0.f),
        buckets_(kBuckets + 1) {}
  void Push(const Candidate& c) {
    const int b = std::clamp(static_cast<int>((c.zncc - min_) * scale_), 0, kBuckets);
    buckets_[b].push_back(c);
    top_ = std::max(top_, b);
    ++size_;
  }
  bool Empty() const { return size_ == 0; }
  Candidate Pop() {  // requires !Empty()
    while (buckets_[top_].empty()) --top_;
    const Candidate c = buckets_[top_].back();
    buckets_[top_].pop_back();
    --size_;
    return c;
  }

 private:
  static constexpr int kBuckets = 4096;
  float min_, scale_;
  std::vector<std::vector<Candidate>> buckets_;
  int top_ = 0;
  size_t size_ = 0;
};

// Sub-pixel offset of a ZNCC peak from three samples (parabola through them), in [-0.5, 0.5].
float ParabolaPeak(float left, float centre, float right) {
  const float denom = left - 2 * centre + right;
  if (left < -0.5f || right < -0.5f || denom >= 0) return 0.f;
  return std::clamp(0.5f * (left - right) / denom, -0.5f, 0.5f);
}

}  // namespace

std::vector<QuasiDenseMatch> PropagateMatches(const cv::Mat& gray1, const cv::Mat& gray2,
                                              const std::vector<SeedMatch>& seeds,
                                              const PropagationOptions& options,
                                              const std::optional<Eigen::Matrix3d>& F) {
  const ZnccImage s1(gray1, options.window_radius, options.min_window_std);
  const ZnccImage s2(gray2, options.window_radius, options.min_window_std);
  const std::vector<uint8_t> textured1 = TextureMask(s1, options.min_gradient);
  const std::vector<uint8_t> textured2 = TextureMask(s2, options.min_gradient);
  std::vector<uint8_t> matched1(s1.size(), 0), matched2(s2.size(), 0);
  // The parent disparity a pixel of image 1 was last tried with. A second parent with the same
  // disparity proposes the same 3x3 candidates, whose ZNCCs are already known (and the best of
  // them queued), so it is skipped: most neighbours of a smooth surface share their parents'
  // integer disparity, and this removes most of the ZNCC evaluations of section 3.2's growth.
  std::vector<uint32_t> tried(s1.size(), kNoDisparity);
  const float min_zncc = static_cast<float>(options.min_zncc);

  // Epipolar distance of pixel centre (x2, y2) to the line l = F (x1, y1, 1), normalised.
  const auto epipolar_ok = [&](const Eigen::Vector3d& line, int x2, int y2) {
    return std::abs(line.x() * (x2 + 0.5) + line.y() * (y2 + 0.5) + line.z()) <=
           options.max_epipolar_distance;
  };
  const auto line_of = [&](int x1, int y1) -> Eigen::Vector3d {
    Eigen::Vector3d l = (*F) * Eigen::Vector3d(x1 + 0.5, y1 + 0.5, 1.0);
    const double n = l.head<2>().norm();
    return n > 0 ? Eigen::Vector3d(l / n) : Eigen::Vector3d(0, 0, 1e30);
  };

  CandidateQueue queue(min_zncc);
  for (const SeedMatch& seed : seeds) {
    const int x1 = static_cast<int>(std::floor(seed.x1.x())),
              y1 = static_cast<int>(std::floor(seed.x1.y()));
    const int x2 = static_cast<int>(std::floor(seed.x2.x())),
              y2 = static_cast<int>(std::floor(seed.x2.y()));
    if (!s1.Inside(x1, y1) || !s2.Inside(x2, y2)) continue;
    if (F && !epipolar_ok(line_of(x1, y1), x2, y2)) continue;
    const float z = ZnccWindow(s1, x1, y1).Score(s2, x2, y2);
    if (z >= min_zncc) queue.Push({z, x1, y1, x2, y2});
  }

  std::vector<QuasiDenseMatch> matches;
  const int r = 2;  // neighbourhood N(x): the 5x5 pixels around an accepted match (paper 3.2)
  while (!queue.Empty()) {
    const Candidate c = queue.Pop();
    const size_t i1 = s1.Index(c.x1, c.y1), i2 = s2.Index(c.x2, c.y2);
    if (matched1[i1] || matched2[i2]) continue;  // uniqueness: first (best) match wins
    matched1[i1] = matched2[i2] = 1;
    QuasiDenseMatch m;
    m.x1 = Eigen::Vector2f(c.x1 + 0.5f, c.y1 + 0.5f);
    m.x2 = Eigen::Vector2f(c.x2 + 0.5f, c.y2 + 0.5f);
    m.zncc = c.zncc;
    if (options.subpixel) {
      // Uniqueness can hold a match one pixel off its ZNCC peak where the disparity field
      // compresses (two pixels of image 1 on one of image 2), so the position reported is the
      // peak's: climb to the local ZNCC maximum (ignoring uniqueness), then fit a parabola per
      // axis through it and its neighbours.
      const ZnccWindow w1(s1, c.x1, c.y1);
      const auto z_at = [&](int x, int y) { return s2.Inside(x, y) ? w1.Score(s2, x, y) : -1.f; };
      int px = c.x2, py = c.y2;
      float pz = c.zncc;
      float around[3][3];  // ZNCC of the 8 neighbours of the last sweep's centre
      bool at_peak = false;
      for (int step = 0; step < 2 && !at_peak; ++step) {
        int bx = px, by = py;
        float bz = pz;
        for (int ey = -1; ey <= 1; ++ey)
          for (int ex = -1; ex <= 1; ++ex) {
            const float z = (ex || ey) ? z_at(px + ex, py + ey) : -2.f;
            around[ey + 1][ex + 1] = z;
            if (z > bz) bx = px + ex, by = py + ey, bz = z;
          }
        at_peak = bx == px && by == py;
        px = bx, py = by, pz = bz;
      }
      // The parabolas' samples: from the last sweep when it was centred on the peak (the
      // common case), else computed.
      const auto z_near = [&](int ex, int ey) {
        return at_peak ? around[ey + 1][ex + 1] : z_at(px + ex, py + ey);
      };
      m.x2 = Eigen::Vector2f(px + 0.5f + ParabolaPeak(z_near(-1, 0), pz, z_near(1, 0)),
                             py + 0.5f + ParabolaPeak(z_near(0, -1), pz, z_near(0, 1)));
    }
    matches.push_back(m);
    if (options.max_matches > 0 && matches.size() >= options.max_matches) break;

    for (int dy = -r; dy <= r; ++dy) {
      for (int dx = -r; dx <= r; ++dx) {
        const int u1 = c.x1 + dx, v1 = c.y1 + dy;
        if ((dx == 0 && dy == 0) || !s1.Inside(u1, v1)) continue;
        const size_t j1 = s1.Index(u1, v1);
        if (matched1[j1] || !textured1[j1]) continue;
        const uint32_t disparity = PackDisparity(c.x2 - c.x1, c.y2 - c.y1);
        if (tried[j1] == disparity) continue;
        tried[j1] = disparity;
        const ZnccWindow w1(s1, u1, v1);
        Eigen::Vector3d line = Eigen::Vector3d::Zero();
        if (F) line = line_of(u1, v1);
        // Disparity gradient limit: the neighbour's disparity differs by at most 1 px per axis
        // from the parent's (the paper's ||(u' - u) - (x' - x)||_inf <= 1).
        Candidate best{-2.f, u1, v1, 0, 0};
        for (int ey = -1; ey <= 1; ++ey) {
          for (int ex = -1; ex <= 1; ++ex) {
            const int u2 = c.x2 + dx + ex, v2 = c.y2 + dy + ey;
            if (!s2.Inside(u2, v2)) continue;
            const size_t j2 = s2.Index(u2, v2);
            if (matched2[j2] || !textured2[j2]) continue;
            if (F && !epipolar_ok(line, u2, v2)) continue;
            const float z = w1.Score(s2, u2, v2);
            if (z > best.zncc) best.zncc = z, best.x2 = u2, best.y2 = v2;
          }
        }
        if (best.zncc >= min_zncc) queue.Push(best);
      }
    }
  }
  return matches;
}

void PropagationOptions::Check() const {
  CheckAtLeast("window_radius", window_radius, 1);
  CheckInRange("--min-zncc", min_zncc, -1, 1);
  CheckNonNegative("min_gradient", min_gradient);
  CheckNonNegative("min_window_std", min_window_std);
  CheckPositive("max_epipolar_distance", max_epipolar_distance);
}

}  // namespace varsfm

#include "varsfm/dense/match_propagation.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <tuple>

#include <opencv2/imgproc.hpp>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// Per-image data for fast ZNCC: intensities plus the window mean and 1 / std of every pixel,
// from integral images (so each ZNCC costs one cross-correlation sum only), and the texture
// mask of the paper's confidence test.
struct WindowStats {
  int width = 0, height = 0, radius = 0;
  std::vector<float> intensity, mean, inv_std;  // inv_std 0: window untextured or off-image
  std::vector<uint8_t> textured;

  WindowStats(const cv::Mat& gray, const PropagationOptions& options) {
    if (gray.empty() || gray.type() != CV_8UC1)
      Fail("match propagation: images must be 8-bit gray");
    width = gray.cols, height = gray.rows, radius = options.window_radius;
    const size_t n = static_cast<size_t>(width) * height;
    intensity.resize(n), mean.assign(n, 0.f), inv_std.assign(n, 0.f), textured.assign(n, 0);
    for (int y = 0; y < height; ++y) {
      const uint8_t* row = gray.ptr<uint8_t>(y);
      for (int x = 0; x < width; ++x) intensity[Index(x, y)] = row[x];
    }
    cv::Mat sum, sqsum;
    cv::integral(gray, sum, sqsum, CV_64F, CV_64F);
    const int r = radius;
    const double area = (2.0 * r + 1) * (2.0 * r + 1);
    const double min_var = options.min_window_std * options.min_window_std;
    for (int y = r; y < height - r; ++y) {
      for (int x = r; x < width - r; ++x) {
        const auto box = [&](const cv::Mat& s) {
          return s.at<double>(y + r + 1, x + r + 1) - s.at<double>(y - r, x + r + 1) -
                 s.at<double>(y + r + 1, x - r) + s.at<double>(y - r, x - r);
        };
        const double m = box(sum) / area;
        const double var = box(sqsum) / area - m * m;
        const size_t i = Index(x, y);
        mean[i] = static_cast<float>(m);
        if (var > min_var) inv_std[i] = static_cast<float>(1.0 / std::sqrt(var));
        // Paper section 3.3: s(x) = max over the 4-neighbours of |I(x + D) - I(x)| > t.
        const float c = intensity[i];
        const float s =
            std::max({std::abs(intensity[i - 1] - c), std::abs(intensity[i + 1] - c),
                      std::abs(intensity[i - width] - c), std::abs(intensity[i + width] - c)});
        textured[i] = inv_std[i] > 0 && s > options.min_gradient;
      }
    }
  }
  size_t Index(int x, int y) const { return static_cast<size_t>(y) * width + x; }
  bool Inside(int x, int y) const {
    return x >= radius && y >= radius && x < width - radius && y < height - radius;
  }
};

float Zncc(const WindowStats& a, int x1, int y1, const WindowStats& b, int x2, int y2) {
  const size_t i1 = a.Index(x1, y1), i2 = b.Index(x2, y2);
  if (a.inv_std[i1] == 0 || b.inv_std[i2] == 0) return -1.f;
  const int r = a.radius;
  float cross = 0;
  for (int dy = -r; dy <= r; ++dy) {
    const float* p = &a.intensity[a.Index(x1 - r, y1 + dy)];
    const float* q = &b.intensity[b.Index(x2 - r, y2 + dy)];
    for (int dx = 0; dx <= 2 * r; ++dx) cross += p[dx] * q[dx];
  }
  const float area = static_cast<float>((2 * r + 1) * (2 * r + 1));
  return (cross / area - a.mean[i1] * b.mean[i2]) * a.inv_std[i1] * b.inv_std[i2];
}

struct Candidate {
  float zncc;
  int x1, y1, x2, y2;
  // Best ZNCC first; ties broken by position so the order never depends on the heap layout.
  bool operator<(const Candidate& o) const {
    if (zncc != o.zncc) return zncc < o.zncc;
    return std::tie(o.y1, o.x1, o.y2, o.x2) < std::tie(y1, x1, y2, x2);
  }
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
  const WindowStats s1(gray1, options), s2(gray2, options);
  std::vector<uint8_t> matched1(s1.intensity.size(), 0), matched2(s2.intensity.size(), 0);
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

  std::priority_queue<Candidate> heap;
  for (const SeedMatch& seed : seeds) {
    const int x1 = static_cast<int>(std::floor(seed.x1.x())),
              y1 = static_cast<int>(std::floor(seed.x1.y()));
    const int x2 = static_cast<int>(std::floor(seed.x2.x())),
              y2 = static_cast<int>(std::floor(seed.x2.y()));
    if (!s1.Inside(x1, y1) || !s2.Inside(x2, y2)) continue;
    if (F && !epipolar_ok(line_of(x1, y1), x2, y2)) continue;
    const float z = Zncc(s1, x1, y1, s2, x2, y2);
    if (z >= min_zncc) heap.push({z, x1, y1, x2, y2});
  }

  std::vector<QuasiDenseMatch> matches;
  const int r = 2;  // neighbourhood N(x): the 5x5 pixels around an accepted match (paper 3.2)
  while (!heap.empty()) {
    const Candidate c = heap.top();
    heap.pop();
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
      const auto z_at = [&](int x, int y) {
        return s2.Inside(x, y) ? Zncc(s1, c.x1, c.y1, s2, x, y) : -1.f;
      };
      int px = c.x2, py = c.y2;
      float pz = c.zncc;
      for (int step = 0; step < 2; ++step) {
        int bx = px, by = py;
        float bz = pz;
        for (int ey = -1; ey <= 1; ++ey)
          for (int ex = -1; ex <= 1; ++ex) {
            const float z = (ex || ey) ? z_at(px + ex, py + ey) : -2.f;
            if (z > bz) bx = px + ex, by = py + ey, bz = z;
          }
        if (bx == px && by == py) break;
        px = bx, py = by, pz = bz;
      }
      m.x2 = Eigen::Vector2f(px + 0.5f + ParabolaPeak(z_at(px - 1, py), pz, z_at(px + 1, py)),
                             py + 0.5f + ParabolaPeak(z_at(px, py - 1), pz, z_at(px, py + 1)));
    }
    matches.push_back(m);
    if (options.max_matches > 0 && matches.size() >= options.max_matches) break;

    for (int dy = -r; dy <= r; ++dy) {
      for (int dx = -r; dx <= r; ++dx) {
        const int u1 = c.x1 + dx, v1 = c.y1 + dy;
        if ((dx == 0 && dy == 0) || !s1.Inside(u1, v1)) continue;
        const size_t j1 = s1.Index(u1, v1);
        if (matched1[j1] || !s1.textured[j1]) continue;
        Eigen::Vector3d line;
        if (F) line = line_of(u1, v1);
        // Disparity gradient limit: the neighbour's disparity differs by at most 1 px per axis
        // from the parent's (the paper's ||(u' - u) - (x' - x)||_inf <= 1).
        Candidate best{-2.f, u1, v1, 0, 0};
        for (int ey = -1; ey <= 1; ++ey) {
          for (int ex = -1; ex <= 1; ++ex) {
            const int u2 = c.x2 + dx + ex, v2 = c.y2 + dy + ey;
            if (!s2.Inside(u2, v2)) continue;
            const size_t j2 = s2.Index(u2, v2);
            if (matched2[j2] || !s2.textured[j2]) continue;
            if (F && !epipolar_ok(line, u2, v2)) continue;
            const float z = Zncc(s1, u1, v1, s2, u2, v2);
            if (z > best.zncc) best.zncc = z, best.x2 = u2, best.y2 = v2;
          }
        }
        if (best.zncc >= min_zncc) heap.push(best);
      }
    }
  }
  return matches;
}

}  // namespace varsfm

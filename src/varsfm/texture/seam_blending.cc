#include "varsfm/texture/seam_blending.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include <tbb/parallel_for.h>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

#include "varsfm/texture/atlas_sample.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

// One side of a seam: an edge of a face of `chart` (atlas pixels p0 -> p1 on `page`) and the
// same edge in the chart across it (q0 -> q1 on `other_page`).
struct SeamSide {
  int chart = -1;
  int page = 0;
  int other_page = 0;
  Eigen::Vector2d p0, p1, q0, q1;
};

Eigen::Vector2d AtlasPixel(const TexturedMesh& mesh, int face, int corner) {
  const cv::Mat& page = mesh.pages[mesh.face_page[face]];
  const Eigen::Vector2f& uv = mesh.texcoords[mesh.face_texcoords[face][corner]];
  return Eigen::Vector2d(uv.x() * page.cols, uv.y() * page.rows);
}

std::vector<SeamSide> FindSeamSides(const std::vector<std::array<int, 3>>& neighbours,
                                    const std::vector<int>& labels,
                                    const std::vector<int>& chart_of_face,
                                    const TexturedMesh& mesh) {
  std::vector<SeamSide> sides;
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    if (chart_of_face[f] < 0 || labels[f] < 0) continue;
    for (int k = 0; k < 3; ++k) {
      const int g = neighbours[f][k];
      if (g < 0 || chart_of_face[g] < 0 || labels[g] < 0 || labels[g] == labels[f]) continue;
      const int a = mesh.faces[f][k], b = mesh.faces[f][(k + 1) % 3];
      int ga = -1, gb = -1;
      for (int j = 0; j < 3; ++j) {
        if (mesh.faces[g][j] == a) ga = j;
        if (mesh.faces[g][j] == b) gb = j;
      }
      if (ga < 0 || gb < 0) continue;
      sides.push_back({chart_of_face[f], mesh.face_page[f], mesh.face_page[g],
                       AtlasPixel(mesh, static_cast<int>(f), k),
                       AtlasPixel(mesh, static_cast<int>(f), (k + 1) % 3), AtlasPixel(mesh, g, ga),
                       AtlasPixel(mesh, g, gb)});
    }
  }
  return sides;
}

// Per page: every texel's distance to the nearest seam side of its own chart (up to the strip
// width; +inf beyond) and, for texels within one texel of it, half the colour gap there.
struct SeamField {
  cv::Mat distance;  // CV_32FC1
  cv::Mat half_gap;  // CV_32FC3
};

// The rows [first, last] of the page that a side's strip may reach.
std::pair<int, int> SideRows(const SeamSide& s, int rows, double width) {
  return {std::max(0, static_cast<int>(std::floor(std::min(s.p0.y(), s.p1.y()) - width))),
          std::min(rows - 1, static_cast<int>(std::max(s.p0.y(), s.p1.y()) + width))};
}

// Marks the side's strip in rows [row_begin, row_end) of the page.
void MarkSeamSide(const SeamSide& s, const TexturedMesh& mesh, const cv::Mat& owner, double width,
                  int row_begin, int row_end, SeamField* field) {
  const Eigen::Vector2d d = s.p1 - s.p0;
  const double length2 = std::max(d.squaredNorm(), 1e-12);
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min(s.p0.x(), s.p1.x()) - width)));
  const int x1 = std::min(owner.cols - 1, static_cast<int>(std::max(s.p0.x(), s.p1.x()) + width));
  const auto [y0, y1] = SideRows(s, owner.rows, width);
  for (int y = std::max(y0, row_begin); y <= std::min(y1, row_end - 1); ++y) {
    const int* who = owner.ptr<int>(y);
    float* dist = field->distance.ptr<float>(y);
    cv::Vec3f* gap = field->half_gap.ptr<cv::Vec3f>(y);
    for (int x = x0; x <= x1; ++x) {
      if (who[x] != s.chart) continue;
      const Eigen::Vector2d q(x + 0.5, y + 0.5);
      const double t = std::clamp((q - s.p0).dot(d) / length2, 0.0, 1.0);
      const double e = (q - s.p0 - t * d).norm();
      if (e >= dist[x]) continue;
      dist[x] = static_cast<float>(e);
      if (e > 1) continue;
      const Eigen::Vector2d p = s.p0 + t * d, o = s.q0 + t * (s.q1 - s.q0);
      gap[x] = 0.5f * (SampleAtlas(mesh.pages[s.other_page], o.x(), o.y()) -
                       SampleAtlas(mesh.pages[s.page], p.x(), p.y()));
    }
  }
}

// Solves Laplace(d) = 0 on the page's strip texels (1 < distance < width) and adds d to them,
// the half gap to the seam texels (distance <= 1).
void SolveStrip(const SeamField& field, const cv::Mat& owner, double width, cv::Mat* page) {
  const int w = page->cols, h = page->rows;
  cv::Mat index(h, w, CV_32SC1, cv::Scalar::all(-1));
  std::vector<cv::Point> unknowns;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float dist = field.distance.at<float>(y, x);
      if (dist > 1 && dist < width) {
        index.at<int>(y, x) = static_cast<int>(unknowns.size());
        unknowns.emplace_back(x, y);
      }
    }
  Eigen::MatrixXd solution;
  if (!unknowns.empty()) {
    const int n = static_cast<int>(unknowns.size());
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 3);
    const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
    for (int i = 0; i < n; ++i) {
      const cv::Point p = unknowns[i];
      const int chart = owner.at<int>(p);
      // A vanishing ridge keeps a strip cut off from every seam (it cannot be) solvable.
      double diagonal = 1e-9;
      for (int k = 0; k < 4; ++k) {
        const cv::Point q(p.x + dx[k], p.y + dy[k]);
        if (q.x < 0 || q.y < 0 || q.x >= w || q.y >= h || owner.at<int>(q) != chart) continue;
        diagonal += 1;
        const int j = index.at<int>(q);
        if (j >= 0) {
          triplets.emplace_back(i, j, -1.0);
        } else if (field.distance.at<float>(q) <= 1) {
          const cv::Vec3f& g = field.half_gap.at<cv::Vec3f>(q);
          rhs.row(i) += Eigen::Vector3d(g[0], g[1], g[2]).transpose();
        }
      }
      triplets.emplace_back(i, i, diagonal);
    }
    Eigen::SparseMatrix<double> laplacian(n, n);
    laplacian.setFromTriplets(triplets.begin(), triplets.end());
    // Conjugate gradients: the strip is a few texels wide, so its Laplacian is well conditioned
    // (about strip_width^2) and a few dozen iterations reach the tolerance (1e-4 of the gaps:
    // far below a grey level), with less memory than factorising it.
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> solver;
    solver.setTolerance(1e-4);
    solver.compute(laplacian);
    if (solver.info() == Eigen::Success) solution = solver.solve(rhs);
  }
  for (int y = 0; y < h; ++y) {
    cv::Vec3b* texel = page->ptr<cv::Vec3b>(y);
    for (int x = 0; x < w; ++x) {
      const float dist = field.distance.at<float>(y, x);
      cv::Vec3f change(0, 0, 0);
      if (dist <= 1) {
        change = field.half_gap.at<cv::Vec3f>(y, x);
      } else if (dist < width && solution.size() > 0) {
        const Eigen::Vector3d s = solution.row(index.at<int>(y, x));
        change =
            cv::Vec3f(static_cast<float>(s[0]), static_cast<float>(s[1]), static_cast<float>(s[2]));
      } else {
        continue;
      }
      for (int c = 0; c < 3; ++c) texel[x][c] = cv::saturate_cast<uchar>(texel[x][c] + change[c]);
    }
  }
}

}  // namespace

void BlendSeams(const std::vector<std::array<int, 3>>& neighbours, const std::vector<int>& labels,
                const std::vector<int>& chart_of_face, const std::vector<cv::Mat>& owner,
                const SeamBlendingOptions& options, TexturedMesh* mesh) {
  if (!options.enabled) return;
  const double width = options.strip_width;
  const std::vector<SeamSide> sides = FindSeamSides(neighbours, labels, chart_of_face, *mesh);
  // All gaps are read before any page changes: both sides of a seam see the other's colour.
  std::vector<SeamField> fields(mesh->pages.size());
  for (size_t p = 0; p < fields.size(); ++p) {
    const cv::Size size = mesh->pages[p].size();
    fields[p].distance =
        cv::Mat(size, CV_32FC1, cv::Scalar::all(std::numeric_limits<float>::infinity()));
    fields[p].half_gap = cv::Mat(size, CV_32FC3, cv::Scalar::all(0));
  }
  // A texel takes the nearest of the sides of its chart, the first of equally near ones: the
  // sides are marked in their order, band of rows by band of rows in parallel (each band's
  // texels see the same sides in the same order as one pass would show them).
  constexpr int kBandRows = 32;
  for (size_t p = 0; p < fields.size(); ++p) {
    const int rows = mesh->pages[p].rows;
    const int num_bands = (rows + kBandRows - 1) / kBandRows;
    std::vector<std::vector<uint32_t>> sides_of_band(num_bands);
    for (uint32_t i = 0; i < sides.size(); ++i) {
      if (sides[i].page != static_cast<int>(p)) continue;
      const auto [first, last] = SideRows(sides[i], rows, width);
      if (first > last) continue;  // off the page
      for (int b = first / kBandRows; b <= last / kBandRows; ++b) sides_of_band[b].push_back(i);
    }
    tbb::parallel_for(0, num_bands, [&](int b) {
      for (const uint32_t i : sides_of_band[b])
        MarkSeamSide(sides[i], *mesh, owner[p], width, b * kBandRows,
                     std::min(rows, (b + 1) * kBandRows), &fields[p]);
    });
  }
  for (size_t p = 0; p < fields.size(); ++p)
    SolveStrip(fields[p], owner[p], width, &mesh->pages[p]);
}

void SeamBlendingOptions::Check() const { CheckInRange("seam.strip_width", strip_width, 2, 256); }

}  // namespace varsfm

#include "varsfm/eval/surface_score.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/statistics.h"

namespace varsfm {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Triangles = std::vector<Kernel::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Kernel::Point_3 ToPoint(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }

// Share of `distances` at most `tolerance`.
double ShareWithin(const std::vector<double>& distances, double tolerance) {
  if (distances.empty()) return 0;
  const auto within =
      std::count_if(distances.begin(), distances.end(), [&](double d) { return d <= tolerance; });
  return static_cast<double>(within) / static_cast<double>(distances.size());
}

}  // namespace

struct MeshDistance::Tree {
  Triangles triangles;  // the tree refers to these
  varsfm::Tree tree;
};

MeshDistance::MeshDistance(const TriangleMesh& mesh) : tree_(std::make_unique<Tree>()) {
  if (mesh.faces.empty()) Fail("a surface to measure against has no faces");
  for (const Eigen::Vector3i& f : mesh.faces) {
    const Kernel::Triangle_3 t(ToPoint(mesh.vertices[f[0]]), ToPoint(mesh.vertices[f[1]]),
                               ToPoint(mesh.vertices[f[2]]));
    if (!t.is_degenerate()) tree_->triangles.push_back(t);
  }
  if (tree_->triangles.empty()) Fail("a surface to measure against has only degenerate faces");
  tree_->tree.insert(tree_->triangles.begin(), tree_->triangles.end());
  tree_->tree.accelerate_distance_queries();
}

MeshDistance::~MeshDistance() = default;

double MeshDistance::operator()(const Eigen::Vector3d& point) const {
  return std::sqrt(tree_->tree.squared_distance(ToPoint(point)));
}

bool MeshDistance::Blocks(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double margin) const {
  const Eigen::Vector3d d = b - a;
  const double length = d.norm();
  if (length <= 2 * margin) return false;
  const Eigen::Vector3d u = d / length;
  return tree_->tree.do_intersect(
      Kernel::Segment_3(ToPoint(a + margin * u), ToPoint(b - margin * u)));
}

std::vector<Eigen::Vector3d> SampleSurface(const TriangleMesh& mesh, double spacing,
                                           uint64_t seed) {
  if (!(spacing > 0)) Fail("surface sampling: the spacing must be positive, not {}", spacing);
  Rng rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> samples;
  for (const Eigen::Vector3i& f : mesh.faces) {
    const Eigen::Vector3d &a = mesh.vertices[f[0]], &b = mesh.vertices[f[1]],
                          &c = mesh.vertices[f[2]];
    const double expected = 0.5 * (b - a).cross(c - a).norm() / (spacing * spacing);
    const double whole = std::floor(expected);
    const int count = static_cast<int>(whole) + (unit(rng) < expected - whole ? 1 : 0);
    for (int k = 0; k < count; ++k) {
      // Uniform on the triangle (Osada et al. 2002, Eq. 1).
      const double r1 = std::sqrt(unit(rng)), r2 = unit(rng);
      samples.push_back((1 - r1) * a + r1 * (1 - r2) * b + r1 * r2 * c);
    }
  }
  return samples;
}

void SurfaceScoreOptions::Check() const {
  CheckPositive("tolerance", tolerance);
  CheckNonNegative("sample_spacing", sample_spacing);
}

SurfaceScore ScoreSurface(const TriangleMesh& reconstruction, const TriangleMesh& truth,
                          const SurfaceScoreOptions& options,
                          const std::function<bool(const Eigen::Vector3d&)>& observed) {
  options.Check();
  const double spacing =
      options.sample_spacing > 0 ? options.sample_spacing : options.tolerance / 4;
  const MeshDistance to_truth(truth), to_reconstruction(reconstruction);
  std::vector<double> accuracy, completeness;
  for (const Eigen::Vector3d& p : SampleSurface(reconstruction, spacing, options.seed))
    accuracy.push_back(to_truth(p));
  for (const Eigen::Vector3d& p : SampleSurface(truth, spacing, options.seed + 1))
    if (!observed || observed(p)) completeness.push_back(to_reconstruction(p));
  SurfaceScore score;
  score.reconstruction_samples = accuracy.size();
  score.truth_samples = completeness.size();
  score.accuracy = ShareWithin(accuracy, options.tolerance);
  score.completeness = ShareWithin(completeness, options.tolerance);
  const double sum = score.accuracy + score.completeness;
  score.fscore = sum > 0 ? 2 * score.accuracy * score.completeness / sum : 0;
  score.median_accuracy_distance = Median(std::move(accuracy));
  score.median_completeness_distance = Median(std::move(completeness));
  return score;
}

std::function<bool(const Eigen::Vector3d&)> SeenByCameras(const TriangleMesh& truth,
                                                          const std::vector<Camera>& cameras,
                                                          const std::vector<Rigid3d>& poses,
                                                          int min_views) {
  if (cameras.size() != poses.size())
    Fail("{} cameras with {} poses", cameras.size(), poses.size());
  auto occluder = std::make_shared<MeshDistance>(truth);
  Eigen::Vector3d lo = truth.vertices.front(), hi = lo;
  for (const Eigen::Vector3d& v : truth.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const double margin = 1e-6 * (hi - lo).norm();  // the point's own face does not hide it
  return [=](const Eigen::Vector3d& point) {
    int views = 0;
    for (size_t i = 0; i < cameras.size() && views < min_views; ++i) {
      const Eigen::Vector3d in_camera = poses[i] * point;
      if (in_camera.z() <= 0) continue;
      const Eigen::Vector2d pixel = cameras[i].Project(in_camera);
      if (pixel.x() < 0 || pixel.y() < 0 || pixel.x() >= cameras[i].width ||
          pixel.y() >= cameras[i].height)
        continue;
      if (!occluder->Blocks(poses[i].Center(), point, margin)) ++views;
    }
    return views >= min_views;
  };
}

}  // namespace varsfm

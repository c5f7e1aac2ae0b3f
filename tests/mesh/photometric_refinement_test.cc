// Photometric refinement on the rendered synthetic scene, whose surface is known exactly: a mesh
// of its faces pushed off them along their normals must come back.
#include "varsfm/mesh/photometric_refinement.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <Eigen/Geometry>

#include "varsfm/synthetic/rendered_scene.h"
#include "varsfm/synthetic/rendered_truth.h"

namespace varsfm {
namespace {

// Each quad of the scene as an n x n grid of counter-clockwise triangles (seen from the side
// u x v points to); `quad_of` gets each vertex's quad.
TriangleMesh GridOfQuads(const std::vector<SurfaceQuad>& quads, int n,
                         std::vector<size_t>* quad_of) {
  TriangleMesh mesh;
  for (size_t q = 0; q < quads.size(); ++q) {
    const int first = static_cast<int>(mesh.vertices.size());
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        mesh.vertices.push_back(quads[q].origin + quads[q].u * i / n + quads[q].v * j / n);
        quad_of->push_back(q);
      }
    const auto id = [&](int i, int j) { return first + j * (n + 1) + i; };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        mesh.faces.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
        mesh.faces.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
      }
  }
  return mesh;
}

Eigen::Vector3d QuadNormal(const SurfaceQuad& quad) { return quad.u.cross(quad.v).normalized(); }

// Whether at least three of the scene's views see `point` of `quad` unoccluded, from within 45
// degrees of its normal: where a vertex's views measure its depth well.
bool SeenWell(const RenderedScene& scene, const SurfaceQuad& quad, const Eigen::Vector3d& point) {
  int views = 0;
  for (size_t v = 0; v < scene.images.size(); ++v) {
    const Eigen::Vector3d in_camera = scene.poses[v] * point;
    if (in_camera.z() <= 0) continue;
    const Eigen::Vector2d pixel = scene.cameras[v].Project(in_camera);
    if (pixel.x() < 0 || pixel.y() < 0 || pixel.x() >= scene.images[v].cols ||
        pixel.y() >= scene.images[v].rows)
      continue;
    const Eigen::Vector3d centre = scene.poses[v].Center();
    const double distance = (point - centre).norm();
    const Eigen::Vector3d ray = (point - centre) / distance;
    if (std::abs(ray.dot(QuadNormal(quad))) >= std::cos(M_PI / 4) &&
        NearestHit(scene.surface, centre, ray) > distance * (1 - 1e-6))
      ++views;
  }
  return views >= 3;
}

// Mean |distance| of the vertices from their quads' planes, over the vertices `counted`.
double MeanPlaneDistance(const TriangleMesh& mesh, const std::vector<SurfaceQuad>& quads,
                         const std::vector<size_t>& quad_of, const std::vector<bool>& counted) {
  double sum = 0;
  size_t count = 0;
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!counted[i]) continue;
    const SurfaceQuad& quad = quads[quad_of[i]];
    sum += std::abs((mesh.vertices[i] - quad.origin).dot(QuadNormal(quad)));
    ++count;
  }
  return sum / static_cast<double>(count);
}

std::vector<RefinementView> ViewsOf(const RenderedScene& scene) {
  std::vector<RefinementView> views;
  for (size_t i = 0; i < scene.images.size(); ++i)
    views.push_back(RefinementViewOf(scene.images[i], {scene.cameras[i], scene.poses[i]}));
  return views;
}

class PhotometricRefinementTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    RenderedSceneOptions options;
    options.num_images = 6;
    options.zoom = 1.2;
    scene_ = new RenderedScene(RenderSyntheticScene(options));
  }
  static void TearDownTestSuite() { delete scene_; }
  // Per vertex of a GridOfQuads mesh: SeenWell.
  static std::vector<bool> SeenWellMask(const TriangleMesh& mesh,
                                        const std::vector<size_t>& quad_of) {
    std::vector<bool> seen(mesh.vertices.size());
    for (size_t i = 0; i < seen.size(); ++i)
      seen[i] = SeenWell(*scene_, scene_->surface[quad_of[i]], mesh.vertices[i]);
    return seen;
  }
  static RenderedScene* scene_;
};
RenderedScene* PhotometricRefinementTest::scene_ = nullptr;

TEST_F(PhotometricRefinementTest, BringsVerticesPushedOffTheSurfaceBack) {
  std::vector<size_t> quad_of;
  TriangleMesh mesh = GridOfQuads(scene_->surface, 40, &quad_of);
  const std::vector<bool> seen = SeenWellMask(mesh, quad_of);
  // A smooth bump field along each quad's normal, up to 1 cm (1 to 2 pixels at the scene's
  // depths), as a surface that the cut and the smoothing left a little off.
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const SurfaceQuad& quad = scene_->surface[quad_of[i]];
    const Eigen::Vector3d p = mesh.vertices[i] - quad.origin;
    const double s = p.dot(quad.u) / quad.u.squaredNorm(), t = p.dot(quad.v) / quad.v.squaredNorm();
    mesh.vertices[i] += 0.01 * std::sin(3 * s + 1) * std::cos(2 * t) * QuadNormal(quad);
  }
  const double before = MeanPlaneDistance(mesh, scene_->surface, quad_of, seen);
  PhotometricRefinementOptions options;
  options.iterations = 3;
  const PhotometricRefinementStats stats = RefinePhotometrically(ViewsOf(*scene_), options, &mesh);
  const double after = MeanPlaneDistance(mesh, scene_->surface, quad_of, seen);
  const size_t num_seen = std::count(seen.begin(), seen.end(), true);
  EXPECT_GT(stats.measured_vertices, num_seen / 3);
  EXPECT_LT(after, 0.6 * before) << "before " << before << ", after " << after;
}

TEST_F(PhotometricRefinementTest, LeavesTheTrueSurfaceWhereItIs) {
  std::vector<size_t> quad_of;
  TriangleMesh mesh = GridOfQuads(scene_->surface, 40, &quad_of);
  const std::vector<bool> seen = SeenWellMask(mesh, quad_of);
  PhotometricRefinementOptions options;
  options.iterations = 3;
  RefinePhotometrically(ViewsOf(*scene_), options, &mesh);
  // A third of a pixel at the boxes' depth (the search's noise), well below the 3.5 mm of the
  // bumps of the test above.
  EXPECT_LT(MeanPlaneDistance(mesh, scene_->surface, quad_of, seen), 0.0015);
}

TEST_F(PhotometricRefinementTest, NoIterationsOrOneViewChangeNothing) {
  std::vector<size_t> quad_of;
  const TriangleMesh mesh = GridOfQuads(scene_->surface, 10, &quad_of);
  TriangleMesh refined = mesh;
  PhotometricRefinementOptions options;
  options.iterations = 0;
  RefinePhotometrically(ViewsOf(*scene_), options, &refined);
  EXPECT_EQ(refined.vertices, mesh.vertices);
  options.iterations = 2;
  RefinePhotometrically({ViewsOf(*scene_)[0]}, options, &refined);
  EXPECT_EQ(refined.vertices, mesh.vertices);
}

// The views are searched in parallel batches: one thread and all give the same vertices, with
// every view given twice (more views than a batch, and ties between equally frontal views).
TEST_F(PhotometricRefinementTest, SameVerticesWhateverTheThreadCount) {
  std::vector<size_t> quad_of;
  TriangleMesh mesh = GridOfQuads(scene_->surface, 20, &quad_of);
  for (size_t i = 0; i < mesh.vertices.size(); ++i)
    mesh.vertices[i] +=
        0.005 * std::sin(0.1 * static_cast<double>(i)) * QuadNormal(scene_->surface[quad_of[i]]);
  std::vector<RefinementView> views = ViewsOf(*scene_);
  const std::vector<RefinementView> again = views;
  views.insert(views.end(), again.begin(), again.end());
  PhotometricRefinementOptions options;
  TriangleMesh one_thread = mesh, all_threads = mesh;
  tbb::task_arena(1).execute([&] { RefinePhotometrically(views, options, &one_thread); });
  const PhotometricRefinementStats stats = RefinePhotometrically(views, options, &all_threads);
  EXPECT_GT(stats.measured_vertices, 0u);
  EXPECT_NE(all_threads.vertices, mesh.vertices);
  EXPECT_EQ(one_thread.vertices, all_threads.vertices);
}

TEST(PhotometricRefinementOptions, CheckRejectsBadValues) {
  PhotometricRefinementOptions options;
  EXPECT_NO_THROW(options.Check());
  options.iterations = -1;
  EXPECT_ANY_THROW(options.Check());
  options = {};
  options.max_views = 1;
  EXPECT_ANY_THROW(options.Check());
  options = {};
  options.step = 0;
  EXPECT_ANY_THROW(options.Check());
}

}  // namespace
}  // namespace varsfm

// Long faces on a scene with exact truth: a plane of small triangles seen by a camera, with a
// hole spanned by long faces (a weakly textured patch the cut closed) and a flap of long faces
// from its edge out to a far point (a membrane across space).
#include "varsfm/mesh/long_faces.h"

#include <gtest/gtest.h>

namespace varsfm {
namespace {

constexpr int kCells = 40;  // the plane: kCells x kCells cells of 0.1 at z = 5
constexpr int kHole = 10;   // the hole in the middle: kHole x kHole cells
constexpr double kCell = 0.1;

int GridVertex(int i, int j) { return j * (kCells + 1) + i; }

struct Scene {
  TriangleMesh mesh;
  size_t plane_faces = 0, hole_faces = 0, flap_faces = 0;
};

// `patch_z`: the depth of the hole's fan; off the plane's 5 it is a patch of its own (its own
// vertices) floating in front of the hole.
Scene PlaneWithHoleAndFlap(double patch_z = 5.0) {
  Scene scene;
  TriangleMesh& mesh = scene.mesh;
  for (int j = 0; j <= kCells; ++j)
    for (int i = 0; i <= kCells; ++i)
      mesh.vertices.emplace_back(-2 + i * kCell, -2 + j * kCell, 5.0);
  const int lo = (kCells - kHole) / 2, hi = lo + kHole;
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      if (i >= lo && i < hi && j >= lo && j < hi) continue;
      mesh.faces.emplace_back(GridVertex(i, j), GridVertex(i + 1, j), GridVertex(i + 1, j + 1));
      mesh.faces.emplace_back(GridVertex(i, j), GridVertex(i + 1, j + 1), GridVertex(i, j + 1));
      scene.plane_faces += 2;
    }
  // The hole: a fan from its centre to every edge of its boundary.
  const int centre = static_cast<int>(mesh.vertices.size());
  mesh.vertices.emplace_back(0, 0, patch_z);
  std::vector<int> loop;
  for (int i = lo; i < hi; ++i) loop.push_back(GridVertex(i, lo));
  for (int j = lo; j < hi; ++j) loop.push_back(GridVertex(hi, j));
  for (int i = hi; i > lo; --i) loop.push_back(GridVertex(i, hi));
  for (int j = hi; j > lo; --j) loop.push_back(GridVertex(lo, j));
  if (patch_z != 5.0) {
    for (int& v : loop) {
      const Eigen::Vector3d p = mesh.vertices[v];
      v = static_cast<int>(mesh.vertices.size());
      mesh.vertices.emplace_back(p.x(), p.y(), patch_z);
    }
  }
  for (size_t k = 0; k < loop.size(); ++k) {
    mesh.faces.emplace_back(centre, loop[k], loop[(k + 1) % loop.size()]);
    ++scene.hole_faces;
  }
  // The flap: from the plane's right edge to a point far to the right, beyond the view.
  const int far = static_cast<int>(mesh.vertices.size());
  mesh.vertices.emplace_back(6, 0, 5.0);
  for (int j = 0; j < kCells; ++j) {
    mesh.faces.emplace_back(GridVertex(kCells, j), far, GridVertex(kCells, j + 1));
    ++scene.flap_faces;
  }
  return scene;
}

// A camera at the origin looking down +z, seeing x and y in [-2.5, 2.5] at z = 5.
PosedCamera FrontView() { return {Camera::FromFocal(400, 400, 400.0), Rigid3d()}; }

LongFaceOptions Options() {
  LongFaceOptions options;
  options.max_edge_factor = 3;  // the fan's spokes are 0.5-0.7 long against cells of 0.1
  options.keep_enclosed = true;
  return options;
}

TEST(LongFaces, TheHoleTheViewSeesEnclosedStaysTheFlapToTheOpenGoes) {
  Scene scene = PlaneWithHoleAndFlap();
  const TriangleMesh before = scene.mesh;
  const LongFaceStats stats = RemoveLongFaces(Options(), {FrontView()}, &scene.mesh);
  EXPECT_EQ(stats.long_faces, scene.hole_faces + scene.flap_faces);
  EXPECT_EQ(stats.kept, scene.hole_faces);
  ASSERT_EQ(scene.mesh.faces.size(), scene.plane_faces + scene.hole_faces);
  // The faces keep their order: the plane's, then the hole's.
  for (size_t f = 0; f < scene.mesh.faces.size(); ++f)
    EXPECT_EQ(scene.mesh.faces[f], before.faces[f]) << f;
}

TEST(LongFaces, WithoutViewsOrWhenAskedEveryLongFaceGoes) {
  Scene scene = PlaneWithHoleAndFlap();
  EXPECT_EQ(RemoveLongFaces(Options(), {}, &scene.mesh).kept, 0u);
  EXPECT_EQ(scene.mesh.faces.size(), scene.plane_faces);

  scene = PlaneWithHoleAndFlap();
  LongFaceOptions options = Options();
  options.keep_enclosed = false;
  EXPECT_EQ(RemoveLongFaces(options, {FrontView()}, &scene.mesh).kept, 0u);
  EXPECT_EQ(scene.mesh.faces.size(), scene.plane_faces);
}

// A patch in front of a farther surface fills no hole of it: the plane seen around it lies
// behind it.
TEST(LongFaces, APatchFloatingInFrontOfTheSurfaceGoes) {
  Scene scene = PlaneWithHoleAndFlap(3.0);
  const LongFaceStats stats = RemoveLongFaces(Options(), {FrontView()}, &scene.mesh);
  EXPECT_EQ(stats.kept, 0u);
  EXPECT_EQ(scene.mesh.faces.size(), scene.plane_faces);
}

// A second view that sees the hole's faces reach the open (here, from beside the plane, where
// the image's edge cuts them) outvotes the view that sees them enclosed.
TEST(LongFaces, OneViewSeeingTheFacesReachTheOpenRemovesThem) {
  Scene scene = PlaneWithHoleAndFlap();
  PosedCamera zoomed = FrontView();
  zoomed.camera = Camera::FromFocal(400, 400, 2400.0);  // sees x, y in [-0.42, 0.42] only
  const LongFaceStats stats = RemoveLongFaces(Options(), {FrontView(), zoomed}, &scene.mesh);
  EXPECT_EQ(stats.kept, 0u);
}

TEST(LongFaceOptions, BadValuesAreRefused) {
  LongFaceOptions options;
  options.Check();
  options.max_edge_factor = -1;
  EXPECT_ANY_THROW(options.Check());
  options = {};
  options.max_depth_ratio = 0.5;
  EXPECT_ANY_THROW(options.Check());
  options = {};
  options.min_enclosed_fraction = 1.5;
  EXPECT_ANY_THROW(options.Check());
  options = {};
  options.raster_size = 0;
  EXPECT_ANY_THROW(options.Check());
}

}  // namespace
}  // namespace varsfm

// The surface score on shapes whose accuracy and completeness are known in closed form.
#include "varsfm/eval/surface_score.h"

#include <gtest/gtest.h>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// The square [x0, x1] x [0, 1] at height z, two triangles.
TriangleMesh Square(double x0, double x1, double z) {
  TriangleMesh mesh;
  mesh.vertices = {{x0, 0, z}, {x1, 0, z}, {x1, 1, z}, {x0, 1, z}};
  mesh.faces = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

TEST(SurfaceScore, ShiftWithinAndBeyondTheTolerance) {
  const TriangleMesh truth = Square(0, 1, 0);
  SurfaceScoreOptions options;
  options.tolerance = 0.01;
  const SurfaceScore near = ScoreSurface(Square(0, 1, 0.009), truth, options);
  EXPECT_EQ(near.accuracy, 1.0);
  EXPECT_EQ(near.completeness, 1.0);
  EXPECT_EQ(near.fscore, 1.0);
  EXPECT_NEAR(near.median_accuracy_distance, 0.009, 1e-12);
  const SurfaceScore far = ScoreSurface(Square(0, 1, 0.011), truth, options);
  EXPECT_EQ(far.accuracy, 0.0);
  EXPECT_EQ(far.completeness, 0.0);
  EXPECT_EQ(far.fscore, 0.0);
}

TEST(SurfaceScore, HalfTheSurfaceIsHalfComplete) {
  // The left half reconstructed exactly: accuracy 1, completeness 1/2 (+ the tolerance band
  // beyond the cut: 0.01 of the width), F = 2 * 1 * 0.51 / 1.51.
  SurfaceScoreOptions options;
  options.tolerance = 0.01;
  const SurfaceScore half = ScoreSurface(Square(0, 0.5, 0), Square(0, 1, 0), options);
  EXPECT_EQ(half.accuracy, 1.0);
  EXPECT_NEAR(half.completeness, 0.51, 0.01);
  EXPECT_NEAR(half.fscore, 2 * 0.51 / 1.51, 0.01);
  EXPECT_GT(half.truth_samples, 10000u);  // one sample per (tolerance / 4)^2
  // Surface beyond the truth is inaccurate: the truth's left half against the whole square.
  const SurfaceScore extra = ScoreSurface(Square(0, 1, 0), Square(0, 0.5, 0), options);
  EXPECT_NEAR(extra.accuracy, 0.51, 0.01);
  EXPECT_EQ(extra.completeness, 1.0);
}

TEST(SurfaceScore, SamplesAreEvenAndDeterministic) {
  const TriangleMesh square = Square(0, 2, 0);  // area 2
  const auto a = SampleSurface(square, 0.01, 7);
  EXPECT_NEAR(static_cast<double>(a.size()), 2 / (0.01 * 0.01), 2.0);
  double left = 0;
  for (const auto& p : a) left += p.x() < 1;
  EXPECT_NEAR(left / a.size(), 0.5, 0.01);
  EXPECT_EQ(a, SampleSurface(square, 0.01, 7));
}

TEST(SurfaceScore, OnlyObservedTruthCountsForCompleteness) {
  // A unit square at z = 0 seen by one camera at z = -2 looking along +z, with a smaller square
  // in front of its left half: the hidden part is not held against the reconstruction.
  TriangleMesh truth = Square(0, 1, 0);
  const TriangleMesh blocker = Square(-1, 0.5, -1);
  const int base = static_cast<int>(truth.vertices.size());
  for (const auto& v : blocker.vertices) truth.vertices.push_back(v);
  for (const auto& f : blocker.faces) truth.faces.push_back(f + Eigen::Vector3i::Constant(base));
  Camera camera = Camera::FromFocal(1000, 1000, 400);
  const Rigid3d pose(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.5, -0.5, 2));
  const auto seen = SeenByCameras(truth, {camera}, {pose}, 1);
  EXPECT_TRUE(seen({0.9, 0.5, 0}));
  EXPECT_FALSE(seen({0.1, 0.5, 0}));  // behind the blocker
  EXPECT_TRUE(seen({0.1, 0.5, -1}));  // the blocker itself
  EXPECT_FALSE(seen({50, 0.5, 0}));   // outside the image
  SurfaceScoreOptions options;
  options.tolerance = 0.01;
  // Only the right half of the back square reconstructed, and the blocker: complete where seen.
  TriangleMesh reconstruction = Square(0.5, 1, 0);
  for (const auto& v : blocker.vertices) reconstruction.vertices.push_back(v);
  for (const auto& f : blocker.faces)
    reconstruction.faces.push_back(f + Eigen::Vector3i::Constant(4));
  const SurfaceScore score = ScoreSurface(reconstruction, truth, options, seen);
  EXPECT_GT(score.completeness, 0.99);
  EXPECT_EQ(score.accuracy, 1.0);
}

TEST(SurfaceScore, RefusesEmptyMeshesAndBadOptions) {
  SurfaceScoreOptions options;
  options.tolerance = 0.01;
  EXPECT_THROW(ScoreSurface(TriangleMesh{}, Square(0, 1, 0), options), Error);
  options.tolerance = 0;
  EXPECT_THROW(ScoreSurface(Square(0, 1, 0), Square(0, 1, 0), options), Error);
}

}  // namespace
}  // namespace varsfm

#include "varsfm/scene/reconstruction.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "support/synthetic_reconstruction.h"
#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm {
namespace {

using testing::ReconstructionFromSynthetic;

TEST(Reconstruction, ExactSceneHasZeroErrorAndConsistentLinks) {
  SyntheticOptions o;
  o.num_images = 5;
  o.num_points = 300;
  const SyntheticScene scene = GenerateSyntheticScene(o);
  Reconstruction rec = ReconstructionFromSynthetic(scene);
  EXPECT_EQ(rec.NumRegisteredImages(), 5u);
  EXPECT_GT(rec.points3D().size(), 200u);
  EXPECT_LT(rec.RmsReprojectionError(), 1e-9);
  EXPECT_GT(rec.MeanTrackLength(), 2.0);
  for (const auto& [id, point] : rec.points3D())
    for (const auto& el : point.track)
      EXPECT_EQ(rec.image(el.image_id).points2D[el.point2D_idx].point3D_id, id);
}

// A point added without a colour is grey, never whatever the memory held: an uninitialised
// colour made `map` without its photos write different points3D.bin bytes from run to run
// (seen under AddressSanitizer, whose heap differs between runs).
TEST(Reconstruction, PointAddedWithoutColourIsGrey) {
  SyntheticOptions o;
  o.num_images = 3;
  o.num_points = 100;
  Reconstruction rec = ReconstructionFromSynthetic(GenerateSyntheticScene(o));
  ASSERT_FALSE(rec.points3D().empty());
  for (const auto& [id, point] : rec.points3D()) EXPECT_EQ(point.color, kUncolouredPoint) << id;
  const Eigen::Matrix<uint8_t, 3, 1> red(255, 0, 0);
  const TrackElement a = rec.point3D(rec.points3D().begin()->first).track[0];
  const TrackElement b = rec.point3D(rec.points3D().begin()->first).track[1];
  rec.DeletePoint3D(rec.points3D().begin()->first);
  EXPECT_EQ(rec.point3D(rec.AddPoint3D(Eigen::Vector3d::Zero(), {a, b}, red)).color, red);
}

TEST(Reconstruction, FilteringRemovesOnlyBadObservations) {
  SyntheticOptions o;
  o.num_images = 4;
  o.num_points = 200;
  Reconstruction rec = ReconstructionFromSynthetic(GenerateSyntheticScene(o));
  const size_t before = rec.NumObservations();
  // Corrupt one observation by 10 px.
  const point3D_t id = rec.points3D().begin()->first;
  const TrackElement el = rec.point3D(id).track.front();
  rec.image(el.image_id).points2D[el.point2D_idx].xy += Eigen::Vector2d(10, 0);
  EXPECT_EQ(rec.FilterObservationsWithLargeError(4.0), 1u);
  EXPECT_FALSE(rec.image(el.image_id).points2D[el.point2D_idx].HasPoint3D());
  EXPECT_EQ(rec.NumObservations(), before - (rec.ExistsPoint3D(id) ? 1 : 2));
  // Every ray of the orbit subtends > 1 degree, far fewer than 60.
  EXPECT_EQ(rec.FilterPointsWithSmallTriangulationAngle(1.0), 0u);
  EXPECT_GT(rec.FilterPointsWithSmallTriangulationAngle(60.0), 0u);
}

TEST(Reconstruction, TwoViewFilterRemovesOnlyBadTwoViewPoints) {
  SyntheticOptions o;
  o.num_images = 4;
  o.num_points = 200;
  Reconstruction rec = ReconstructionFromSynthetic(GenerateSyntheticScene(o));
  // Three points cut down to two views, two points left with more; one of each pair corrupted
  // by 3 px in one observation.
  std::vector<point3D_t> ids;
  for (const auto& [id, point] : rec.points3D())
    if (point.track.size() >= 4) ids.push_back(id);
  ASSERT_GE(ids.size(), 5u);
  for (int k = 0; k < 3; ++k) {
    while (rec.point3D(ids[k]).track.size() > 2) {
      const TrackElement el = rec.point3D(ids[k]).track.back();
      rec.DeleteObservation(el.image_id, el.point2D_idx);
    }
  }
  const auto corrupt = [&](point3D_t id) {
    const TrackElement el = rec.point3D(id).track.front();
    rec.image(el.image_id).points2D[el.point2D_idx].xy += Eigen::Vector2d(0, 3);
  };
  corrupt(ids[0]);  // two views, 3 px: removed
  corrupt(ids[3]);  // four views, 3 px: kept (other filters judge it)
  const size_t points = rec.points3D().size();
  EXPECT_EQ(rec.FilterTwoViewPointsWithLargeError(2.0), 1u);
  EXPECT_FALSE(rec.ExistsPoint3D(ids[0]));
  EXPECT_TRUE(rec.ExistsPoint3D(ids[1]) && rec.ExistsPoint3D(ids[2]) && rec.ExistsPoint3D(ids[3]));
  EXPECT_EQ(rec.points3D().size(), points - 1);
  EXPECT_EQ(rec.FilterTwoViewPointsWithLargeError(4.0), 0u);
}

// The same model with every image id times `factor` (ids far apart, as a model merged from
// several workspaces could have them).
Reconstruction WithSparseImageIds(const Reconstruction& rec, image_t factor) {
  Reconstruction out;
  for (const auto& [id, camera] : rec.cameras()) out.AddCamera(camera);
  for (const auto& [id, image] : rec.images()) {
    Image copy = image;
    copy.image_id = id * factor;
    for (Point2D& p : copy.points2D) p.point3D_id = kInvalidPoint3DId;
    out.AddImage(copy);
    if (image.registered) out.RegisterImage(copy.image_id);
  }
  for (const auto& [id, point] : rec.points3D()) {
    std::vector<TrackElement> track = point.track;
    for (TrackElement& el : track) el.image_id *= factor;
    out.AddPoint3D(point.xyz, track);
  }
  return out;
}

// The filters judge the points in parallel and edit the model in point order; the error
// statistics sum per-observation errors computed in parallel. Checked against the plain
// one-observation-at-a-time definitions, bit for bit, with dense and with sparse image ids,
// on enough points for several parallel chunks and a fifth of the observations corrupted.
TEST(Reconstruction, ParallelFiltersAndErrorsMatchTheSerialDefinitions) {
  SyntheticOptions o;
  o.num_images = 6;
  o.num_points = 3000;
  const Reconstruction dense = ReconstructionFromSynthetic(GenerateSyntheticScene(o));
  for (const image_t factor : {1u, 1000u}) {
    Reconstruction rec = WithSparseImageIds(dense, factor);
    size_t k = 0;
    for (const auto& [id, point] : rec.points3D())
      for (const TrackElement& el : point.track)
        if (++k % 5 == 0)
          rec.image(el.image_id).points2D[el.point2D_idx].xy +=
              Eigen::Vector2d(static_cast<double>(k % 13), 3.0);
    double sum_sq = 0, sum = 0, sum_of_point_sums = 0;
    size_t n = 0;
    for (const auto& [id, point] : rec.points3D()) {
      double point_sum = 0;
      for (const TrackElement& el : point.track) {
        const double e = rec.SquaredReprojectionError(el, point.xyz);
        sum_sq += e, sum += std::sqrt(e), point_sum += std::sqrt(e), ++n;
      }
      sum_of_point_sums += point_sum;
    }
    EXPECT_EQ(rec.RmsReprojectionError(), std::sqrt(sum_sq / n));
    EXPECT_EQ(rec.MeanReprojectionError(), sum / n);
    EXPECT_EQ(rec.UpdatePointErrors(), sum_of_point_sums / n);
    for (const auto& [id, point] : rec.points3D()) EXPECT_GE(point.error, 0.0) << id;

    // A window of two images: only their points are judged.
    const std::vector<image_t> window = {2 * factor, 5 * factor};
    Reconstruction expected = rec;
    size_t expected_removed = 0;
    std::vector<point3D_t> judged;
    for (const image_t id : window)
      for (const Point2D& p : rec.image(id).points2D)
        if (p.HasPoint3D()) judged.push_back(p.point3D_id);
    std::sort(judged.begin(), judged.end());
    judged.erase(std::unique(judged.begin(), judged.end()), judged.end());
    for (const point3D_t id : judged) {
      const Point3D point = expected.point3D(id);
      for (const TrackElement& el : point.track) {
        if (!expected.ExistsPoint3D(id)) break;
        if (expected.SquaredReprojectionError(el, point.xyz) <= 4.0 * 4.0) continue;
        expected.DeleteObservation(el.image_id, el.point2D_idx);
        ++expected_removed;
      }
    }
    const size_t removed = rec.FilterObservationsWithLargeError(4.0, window);
    EXPECT_GT(removed, 100u);
    EXPECT_EQ(removed, expected_removed);
    ASSERT_EQ(rec.points3D().size(), expected.points3D().size());
    for (const auto& [id, point] : expected.points3D()) {
      ASSERT_TRUE(rec.ExistsPoint3D(id)) << id;
      ASSERT_EQ(rec.point3D(id).track.size(), point.track.size()) << id;
    }
    const size_t before = rec.points3D().size();
    EXPECT_GT(rec.FilterPointsWithSmallTriangulationAngle(60.0, window), 0u);
    EXPECT_LT(rec.points3D().size(), before);
    for (const image_t id : window)
      for (const Point2D& p : rec.image(id).points2D) {
        if (!p.HasPoint3D()) continue;
        const Point3D& point = rec.point3D(p.point3D_id);
        double max_angle = 0;
        for (const TrackElement& a : point.track)
          for (const TrackElement& b : point.track) {
            const Eigen::Vector3d ra = (point.xyz - rec.image(a.image_id).Center()).normalized();
            const Eigen::Vector3d rb = (point.xyz - rec.image(b.image_id).Center()).normalized();
            max_angle = std::max(max_angle, std::acos(std::clamp(ra.dot(rb), -1.0, 1.0)));
          }
        EXPECT_GE(max_angle * 180 / std::numbers::pi, 60.0) << p.point3D_id;
      }
  }
}

TEST(Reconstruction, DeRegisterRemovesObservationsAndShortTracks) {
  SyntheticOptions o;
  o.num_images = 3;
  o.num_points = 100;
  Reconstruction rec = ReconstructionFromSynthetic(GenerateSyntheticScene(o));
  rec.DeRegisterImage(1);
  rec.DeRegisterImage(2);
  EXPECT_EQ(rec.points3D().size(), 0u);  // one image left: no track of length 2
  EXPECT_EQ(rec.NumRegisteredImages(), 1u);
}

}  // namespace
}  // namespace varsfm

// View selection as a labelling problem: alpha-expansion against brute force (and its early
// stop), exposure gains recovered exactly, an occluder in one photo rejected by the
// photo-consistency check, and a photo with a look of its own (haze) given fewer faces by the
// consensus term.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include <opencv2/imgproc.hpp>

#include "plane_scene.h"
#include "support/test_data.h"
#include "varsfm/texture/alpha_expansion.h"
#include "varsfm/texture/exposure_gain.h"
#include "varsfm/texture/face_observations.h"
#include "varsfm/texture/render.h"
#include "varsfm/texture/texture_mapping.h"
#include "varsfm/texture/view_selection.h"

namespace varsfm {
namespace {

// A side x side grid of nodes, every label a candidate with a random cost.
PottsProblem RandomGridProblem(int side, int num_labels, double potts, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> cost(0, 1);
  PottsProblem p;
  p.num_labels = num_labels;
  p.potts = potts;
  for (int n = 0; n < side * side; ++n) {
    for (int l = 0; l < num_labels; ++l) {
      p.candidate_labels.push_back(l);
      p.candidate_costs.push_back(cost(rng));
    }
    p.offsets.push_back(p.candidate_labels.size());
    const int x = n % side, y = n / side;
    p.neighbours.push_back(
        {x + 1 < side ? n + 1 : -1, y + 1 < side ? n + side : -1, x > 0 ? n - 1 : -1});
  }
  return p;
}

double BruteForceMinimum(const PottsProblem& p) {
  const size_t n = p.num_nodes();
  std::vector<int> labels(n, 0);
  double best = 1e300;
  while (true) {
    best = std::min(best, PottsEnergy(p, labels));
    size_t i = 0;
    while (i < n && ++labels[i] == p.num_labels) labels[i++] = 0;
    if (i == n) return best;
  }
}

TEST(AlphaExpansion, TwoLabelsReachTheGlobalMinimum) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const PottsProblem p = RandomGridProblem(4, 2, 0.3, seed);
    std::vector<int> labels(p.num_nodes(), 0);
    ExpandLabels(p, 5, &labels, 1e-6);
    EXPECT_NEAR(PottsEnergy(p, labels), BruteForceMinimum(p), 1e-6) << seed;
  }
}

TEST(AlphaExpansion, ThreeLabelsWithinTheFactorTwoBound) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const PottsProblem p = RandomGridProblem(3, 3, 0.4, seed);
    std::vector<int> labels(p.num_nodes(), 0);
    const double start = PottsEnergy(p, labels);
    ExpandLabels(p, 5, &labels, 1e-6);
    const double optimum = BruteForceMinimum(p);
    EXPECT_LE(PottsEnergy(p, labels), 2 * optimum + 1e-9) << seed;
    EXPECT_LE(PottsEnergy(p, labels), start) << seed;
  }
}

// Each cycle runs only when the one before lowered the energy by more than the tolerance: a
// tolerance of 1 stops after the first cycle, and the result is then the one-cycle result.
TEST(AlphaExpansion, ToleranceEndsTheCyclesEarly) {
  const PottsProblem p = RandomGridProblem(12, 4, 0.2, 7);
  std::vector<int> one_cycle(p.num_nodes(), 0), stopped(p.num_nodes(), 0),
      converged(p.num_nodes(), 0);
  ExpandLabels(p, 1, &one_cycle, 1e-6);
  ExpandLabels(p, 10, &stopped, 1.0);
  ExpandLabels(p, 10, &converged, 1e-6);
  // The problem needs more than one cycle, so a tolerance that were ignored would show.
  ASSERT_NE(converged, one_cycle);
  EXPECT_EQ(stopped, one_cycle);
  EXPECT_LE(PottsEnergy(p, converged), PottsEnergy(p, stopped));
}

TEST(AlphaExpansion, NodesKeepTheirCandidates) {
  PottsProblem p = RandomGridProblem(3, 1, 10.0, 1);  // label 0 everywhere ...
  p.num_labels = 2;
  p.candidate_labels[4] = 1;  // ... but the centre may only take label 1
  std::vector<int> labels(p.num_nodes(), 0);
  labels[4] = 1;
  ExpandLabels(p, 5, &labels, 1e-6);
  EXPECT_EQ(labels[4], 1);
  for (int n : {0, 1, 2, 3, 5, 6, 7, 8}) EXPECT_EQ(labels[n], 0) << n;
}

// Face 0 seen by views 0 and 2, face 1 by view 1 only: a view's entry or none.
TEST(FaceObservations, FindsAViewsEntryOfAFaceOrNone) {
  FaceObservations obs;
  obs.num_faces = 2;
  obs.num_views = 3;
  obs.begin = {0, 2, 3};
  obs.view = {0, 2, 1};
  obs.quality = {1.0f, 2.0f, 3.0f};
  obs.colour = {{1, 1, 1}, {2, 2, 2}, {3, 3, 3}};
  EXPECT_EQ(obs.Find(2, 0), 1u);
  EXPECT_EQ(obs.Find(1, 1), 2u);
  EXPECT_EQ(obs.Find(1, 0), FaceObservations::kNone);
  EXPECT_EQ(obs.Find(0, 1), FaceObservations::kNone);
  EXPECT_EQ(obs.Quality(1, 0), 0.0f);
  EXPECT_EQ(obs.Quality(2, 0), 2.0f);
  EXPECT_EQ(obs.Colour(0, 1), Eigen::Vector3f::Zero());
}

TEST(ExposureGain, RecoversTheRatioOfExposures) {
  // Three views of one face set; view 1 exposed at 0.5 and view 2 at 1.5 times view 0, per
  // channel differently for view 2 (white balance).
  // Every view sees every face: face f's entries are 3f (view 0) to 3f + 2 (view 2).
  FaceObservations obs;
  obs.num_faces = 200;
  obs.num_views = 3;
  for (size_t f = 0; f <= obs.num_faces; ++f) obs.begin.push_back(3 * f);
  for (size_t f = 0; f < obs.num_faces; ++f) obs.view.insert(obs.view.end(), {0, 1, 2});
  obs.quality.assign(600, 1.0f);
  obs.colour.resize(600);
  const Eigen::Vector3f exposure[3] = {{1, 1, 1}, {0.5f, 0.5f, 0.5f}, {1.5f, 1.4f, 1.3f}};
  for (size_t f = 0; f < obs.num_faces; ++f) {
    const Eigen::Vector3f c(40.0f + f % 50, 60.0f + f % 30, 50.0f + f % 70);
    for (int v = 0; v < 3; ++v) obs.colour[3 * f + v] = c.cwiseProduct(exposure[v]);
  }
  ASSERT_EQ(obs.Find(2, 7), 23u);
  ASSERT_EQ(obs.Colour(1, 7), obs.colour[22]);
  // A face is seen by an occluder in view 1 in a minority of faces: the median ignores it.
  for (size_t f = 0; f < 30; ++f) obs.colour[3 * f + 1] = {200, 10, 10};
  const std::vector<Eigen::Vector3f> gains = EstimateExposureGains(obs);
  for (int v = 1; v < 3; ++v)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(gains[v][k] * exposure[v][k], gains[0][k] * exposure[0][k], 1e-3) << v << k;
  // Geometric mean 1.
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(gains[0][k] * gains[1][k] * gains[2][k], 1.0, 1e-3);
}

// Three views of the plane; the middle one is nearest and frontal (the best for every face it
// sees) but a red disc hides the plane around the origin in its photo: an occluder the mesh
// does not have.
struct OccludedPlane {
  TriangleMesh mesh = testing::PlaneMesh();
  std::vector<PosedCamera> views = {testing::PlaneView({-0.8, 0, -2.5}, {0, 0, 0}),
                                    testing::PlaneView({0, 0, -2.0}, {0, 0, 0}),
                                    testing::PlaneView({0.8, 0, -2.5}, {0, 0, 0})};
  std::vector<cv::Mat> photos;
  OccludedPlane() {
    for (const PosedCamera& v : views) photos.push_back(testing::PhotographPlane(v, 1.0));
    cv::circle(photos[1], cv::Point(100, 100), 25, cv::Scalar(0, 0, 255), cv::FILLED);
  }
  // Faces whose centroid is within `radius` of the origin.
  std::vector<size_t> FacesNearOrigin(double radius) const {
    std::vector<size_t> out;
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
      const Eigen::Vector3d c = (mesh.vertices[mesh.faces[f][0]] + mesh.vertices[mesh.faces[f][1]] +
                                 mesh.vertices[mesh.faces[f][2]]) /
                                3;
      if (c.norm() < radius) out.push_back(f);
    }
    return out;
  }
};

TEST(ViewSelection, AnOccluderInOnePhotoIsRejected) {
  const OccludedPlane scene;
  const auto load = [&](size_t v) { return scene.photos[v]; };
  // The disc covers 25 px around the image centre, at depth 2: radius 25 / 150 x 2 = 0.33.
  const std::vector<size_t> hidden = scene.FacesNearOrigin(0.25);
  ASSERT_GT(hidden.size(), 10u);
  ViewSelectionOptions without;
  without.consistency.enabled = false;
  const ViewSelection naive =
      SelectViews(scene.mesh.vertices, scene.mesh.faces, scene.views, load, without);
  size_t naive_on_occluder = 0;
  for (const size_t f : hidden) naive_on_occluder += naive.labels[f] == 1;
  EXPECT_GT(naive_on_occluder, hidden.size() / 2) << "the test needs view 1 to be the best";

  const ViewSelection checked =
      SelectViews(scene.mesh.vertices, scene.mesh.faces, scene.views, load);
  EXPECT_GT(checked.num_rejected_observations, hidden.size() / 2);
  for (const size_t f : hidden) EXPECT_NE(checked.labels[f], 1) << f;
  // Away from the disc the middle view still textures the plane.
  size_t middle = 0;
  for (const int label : checked.labels) middle += label == 1;
  EXPECT_GT(middle, scene.mesh.faces.size() / 4);

  // Rendered from the middle camera, the textured plane shows the plane, not the disc.
  const TexturedMesh textured = TextureMesh(scene.mesh, scene.views, load);
  const Rendering r =
      RenderTexturedMesh(textured, scene.views[1].camera, scene.views[1].cam_from_world);
  const cv::Vec3b centre = r.image.at<cv::Vec3b>(100, 100);
  const Eigen::Vector3f truth = testing::PlaneColour(0, 0);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(centre[k], truth[k], 12) << k;
}

// Four views of the plane; the nearest, frontal one (the best for every face by quality) is
// hazy: half the contrast plus a veil of 60 grey levels, as a photo taken against the sun. No
// exposure gain undoes an offset, so its colours stay off the other three views' consensus;
// with the consensus term it textures fewer faces and a new view of the plane renders nearer
// the truth.
TEST(ViewSelection, TheConsensusTermPrefersPhotosThatLookLikeTheOthers) {
  const TriangleMesh mesh = testing::PlaneMesh();
  const std::vector<PosedCamera> views = {
      testing::PlaneView({-0.8, 0, -2.5}, {0, 0, 0}), testing::PlaneView({0, 0, -2.0}, {0, 0, 0}),
      testing::PlaneView({0.8, 0, -2.5}, {0, 0, 0}), testing::PlaneView({0, 0.8, -2.5}, {0, 0, 0})};
  std::vector<cv::Mat> photos;
  for (const PosedCamera& v : views) photos.push_back(testing::PhotographPlane(v, 1.0));
  const cv::Mat off_plane = photos[1] == 0;
  photos[1].convertTo(photos[1], -1, 0.5, 60);
  photos[1].setTo(cv::Scalar::all(0), off_plane);
  const auto load = [&](size_t v) { return photos[v]; };

  TextureMappingOptions plain, consensus;  // the default weight: 2
  plain.selection.consensus_weight = 0.0;
  const auto faces_of_hazy_view = [&](const TextureMappingOptions& options) {
    const ViewSelection s = SelectViews(mesh.vertices, mesh.faces, views, load, options.selection);
    return std::count(s.labels.begin(), s.labels.end(), 1);
  };
  const auto plain_faces = faces_of_hazy_view(plain);
  EXPECT_GT(plain_faces, static_cast<long>(mesh.faces.size() / 4))
      << "the test needs the hazy view to be the best";
  EXPECT_LT(2 * faces_of_hazy_view(consensus), plain_faces);

  // A view none of the photos was taken from, against the plane's true colours.
  const PosedCamera novel = testing::PlaneView({0, -0.8, -2.5}, {0, 0, 0});
  const cv::Mat truth = testing::PhotographPlane(novel, 1.0);
  const auto mean_error = [&](const TextureMappingOptions& options) {
    const Rendering r = RenderTexturedMesh(TextureMesh(mesh, views, load, options), novel.camera,
                                           novel.cam_from_world);
    cv::Mat diff;
    cv::absdiff(r.image, truth, diff);
    const cv::Scalar sum = cv::sum(diff);
    return (sum[0] + sum[1] + sum[2]) / (3.0 * cv::countNonZero(r.mask));
  };
  const double plain_error = mean_error(plain), consensus_error = mean_error(consensus);
  EXPECT_LT(consensus_error, 0.75 * plain_error) << plain_error << " " << consensus_error;
}

TEST(FaceObservations, EachFaceKeepsItsBestViewsInViewOrder) {
  // 40 photos of the plane from distances in a shuffled order (two batches of views): with a cap
  // of 4 each face keeps exactly the 4 of its uncapped observations of highest quality (ties: the
  // earlier view), in view order, with the same figures.
  const TriangleMesh mesh = testing::PlaneMesh(0.25);
  std::vector<PosedCamera> views;
  std::vector<cv::Mat> photos;
  for (int i = 0; i < 40; ++i) {
    const double z = 2.0 + 0.1 * ((i * 17) % 40);
    views.push_back(testing::PlaneView({0.05 * (i % 3), 0.05 * (i % 2), z}, {0, 0, 0}));
    photos.push_back(testing::PhotographPlane(views.back(), 1.0));
  }
  const auto load = [&](size_t v) { return photos[v]; };
  FaceObservationOptions options;
  options.max_views_per_face = 64;
  const FaceObservations all = ObserveFaces(mesh.vertices, mesh.faces, views, load, options);
  options.max_views_per_face = 4;
  const FaceObservations capped = ObserveFaces(mesh.vertices, mesh.faces, views, load, options);
  ASSERT_EQ(capped.num_faces, all.num_faces);
  EXPECT_EQ(capped.coverage, all.coverage);
  size_t faces_over_cap = 0;
  for (size_t f = 0; f < all.num_faces; ++f) {
    std::vector<size_t> entries;
    for (size_t k = all.begin[f]; k < all.begin[f + 1]; ++k) entries.push_back(k);
    faces_over_cap += entries.size() > 4;
    std::stable_sort(entries.begin(), entries.end(),
                     [&](size_t a, size_t b) { return all.quality[a] > all.quality[b]; });
    entries.resize(std::min<size_t>(entries.size(), 4));
    std::sort(entries.begin(), entries.end());  // view order
    ASSERT_EQ(capped.begin[f + 1] - capped.begin[f], entries.size());
    for (size_t k = 0; k < entries.size(); ++k) {
      const size_t c = capped.begin[f] + k;
      EXPECT_EQ(capped.view[c], all.view[entries[k]]);
      EXPECT_EQ(capped.quality[c], all.quality[entries[k]]);
      EXPECT_EQ(capped.colour[c], all.colour[entries[k]]);
    }
  }
  EXPECT_GT(faces_over_cap, all.num_faces / 2);
}

// The small photos in scratch memory (FaceObservationOptions::scratch_folder) texture the mesh
// bit for bit as on the heap, and leave nothing in the folder.
TEST(FaceObservations, SmallPhotosInScratchMemoryGiveTheSameTexture) {
  const TriangleMesh mesh = testing::PlaneMesh(0.25);
  std::vector<PosedCamera> views;
  std::vector<cv::Mat> photos;
  for (int i = 0; i < 6; ++i) {
    views.push_back(testing::PlaneView({0.3 * (i - 2.5), 0.1 * (i % 2), 2.5}, {0, 0, 0}));
    photos.push_back(testing::PhotographPlane(views.back(), 0.8 + 0.08 * i));
  }
  const auto load = [&](size_t v) { return photos[v]; };
  testing::TempDir scratch("texture_scratch");
  TextureMappingOptions heap_options, scratch_options;
  scratch_options.selection.observation.scratch_folder = scratch.path();
  const TexturedMesh heap = TextureMesh(mesh, views, load, heap_options);
  const TexturedMesh mapped = TextureMesh(mesh, views, load, scratch_options);
  ASSERT_EQ(heap.pages.size(), mapped.pages.size());
  for (size_t p = 0; p < heap.pages.size(); ++p)
    EXPECT_EQ(cv::norm(heap.pages[p], mapped.pages[p], cv::NORM_INF), 0) << p;
  EXPECT_EQ(heap.texcoords, mapped.texcoords);
  EXPECT_EQ(heap.face_texcoords, mapped.face_texcoords);
  EXPECT_EQ(std::filesystem::directory_iterator(scratch.path()),
            std::filesystem::directory_iterator());
}

}  // namespace
}  // namespace varsfm

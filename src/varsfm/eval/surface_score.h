#pragma once
// A reconstructed surface against the true one, as the ETH3D (Schops et al., CVPR 2017) and
// Tanks and Temples (Knapitsch et al., SIGGRAPH 2017) benchmarks score meshes: both surfaces are
// sampled evenly; accuracy is the share of the reconstruction's samples within a tolerance of
// the true surface, completeness the share of the true surface's samples within the tolerance of
// the reconstruction, and the F-score their harmonic mean. Distances are exact point-to-triangle
// distances (CGAL's AABB tree), not distances between the two sample sets.
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "varsfm/camera/camera.h"
#include "varsfm/geometry/rigid3.h"
#include "varsfm/scene/triangle_mesh.h"
#include "varsfm/util/random.h"

namespace varsfm {

// Exact distance to a triangle mesh and segment tests against it.
class MeshDistance {
 public:
  explicit MeshDistance(const TriangleMesh& mesh);  // throws varsfm::Error without faces
  ~MeshDistance();
  MeshDistance(const MeshDistance&) = delete;
  MeshDistance& operator=(const MeshDistance&) = delete;
  double operator()(const Eigen::Vector3d& point) const;
  // Whether the open segment a -> b (its ends shortened by `margin`) meets the mesh.
  bool Blocks(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double margin) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

// Points spread over the mesh's faces at about one per spacing^2 of area (each face gets its
// area / spacing^2 samples, the fraction drawn at random), uniform within each face.
// Deterministic for a seed.
std::vector<Eigen::Vector3d> SampleSurface(const TriangleMesh& mesh, double spacing,
                                           uint64_t seed = kDefaultSeed);

struct SurfaceScoreOptions {
  double tolerance = 0;       // absolute (ETH3D and T&T: a fixed share of the scene's size)
  double sample_spacing = 0;  // between samples on both surfaces; 0: tolerance / 4
  uint64_t seed = kDefaultSeed;
  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct SurfaceScore {
  size_t reconstruction_samples = 0;
  size_t truth_samples = 0;  // those counted (observed)
  double accuracy = 0;       // share of reconstruction samples within tolerance of the truth
  double completeness = 0;   // share of observed truth samples within tolerance of the mesh
  double fscore = 0;         // 2 a c / (a + c)
  double median_accuracy_distance = 0;
  double median_completeness_distance = 0;
};

// `observed` (optional) keeps the truth samples that count for completeness: the parts of the
// true surface no camera saw cannot be reconstructed, and ETH3D likewise scores completeness
// only where its laser scan saw. Throws varsfm::Error when either mesh has no faces.
SurfaceScore ScoreSurface(const TriangleMesh& reconstruction, const TriangleMesh& truth,
                          const SurfaceScoreOptions& options,
                          const std::function<bool(const Eigen::Vector3d&)>& observed = {});

// True for a point of `truth` inside the image of at least `min_views` of the cameras and not
// hidden from them by `truth` itself.
std::function<bool(const Eigen::Vector3d&)> SeenByCameras(const TriangleMesh& truth,
                                                          const std::vector<Camera>& cameras,
                                                          const std::vector<Rigid3d>& poses,
                                                          int min_views);

}  // namespace varsfm

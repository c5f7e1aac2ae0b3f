#pragma once
// Registration of a new image to the model (section 4.3 of El Hazzat et al.): 2D-3D
// correspondences through the tracks of every registered image (Algorithm 2, generalised), a
// RANSAC + DLT projection matrix decomposed into K, R, t, and non-linear refinement of the pose
// and of the intrinsics the policy frees; beyond the paper, a PnP hypothesis with a neighbour's
// intrinsics competes with it (a nearly planar set of points makes the DLT ill-posed), and the
// first photo of a size that fits poorly with a centred principal point gets its own.
#include <cstdint>
#include <vector>

#include "varsfm/scene/reconstruction.h"
#include "varsfm/sfm/correspondence_graph.h"
#include "varsfm/sfm/intrinsics_policy.h"

namespace varsfm {

struct ImageRegistrationOptions {
  // n0 of the paper: the DLT needs six 2D-3D correspondences.
  int min_correspondences = 6;
  // Fewer inliers of the chosen pose and camera, or fewer than min_inlier_ratio of the image's
  // 2D-3D correspondences: the image is left for later.
  int min_inliers = 15;
  double min_inlier_ratio = 0.0;
  // Beyond the paper: when no candidate reaches min_inliers, the mapper tries them once more
  // accepting relaxed_min_inliers (still >= n0) where they are at least relaxed_min_inlier_ratio
  // of the image's correspondences, then goes on as before. A part of the capture tied to the
  // model by a few matches (small photos, a gap in the walk) then joins it rather than making a
  // model of its own (bench/results/2026-12-05-s21-relaxed-registration.md). 0: no second try.
  int relaxed_min_inliers = 10;
  double relaxed_min_inlier_ratio = 0.6;
  // RANSAC's inlier threshold, and the largest error of an observation the new image adds.
  double max_error_px = 4.0;
  // A hypothesis is refined on the correspondences within this factor of max_error_px: RANSAC's
  // minimal-sample pose is rough, so a tighter gate would drop the points that refine it.
  double refinement_gate_factor = 4.0;
  // PnP hypothesis (LO-RANSAC around P3P): its iteration cap and confidence. 1000 iterations
  // reach 99.99 % confidence down to an inlier ratio of about 0.2 for 3-point samples.
  int pnp_max_iterations = 1000;
  double pnp_confidence = 0.9999;
  // The registered focal length must lie within these factors of the larger image side (about
  // 170 to 5 deg of horizontal field of view): outside it the pose is a degenerate fit.
  double min_focal_factor = 0.2;
  double max_focal_factor = 10.0;
  // The DLT's K starts the refinement only when it is physically plausible for the image: focal
  // length within these factors of the larger side, aspect within [min, max], skew below this
  // fraction of f, principal point within this fraction of the larger side of the centre. Else
  // the DLT's pose starts from the neighbour's intrinsics.
  double dlt_min_focal_factor = 0.3;
  double dlt_max_focal_factor = 5.0;
  double dlt_min_aspect = 0.8;
  double dlt_max_aspect = 1.25;
  double dlt_max_skew_fraction = 0.1;
  double dlt_max_principal_point_offset = 0.3;
  // The first image of its size is refined once more with its principal point free (a photo
  // cropped off-centre); that pose and camera are taken when their truncated squared error is at
  // most max_cost_ratio of the centred one's (0: never) and the principal point lies at least
  // min_offset x the larger side from the centre.
  double free_principal_point_max_cost_ratio = 0.5;
  double free_principal_point_min_offset = 0.1;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value

  // These options with the relaxed thresholds in place of min_inliers and min_inlier_ratio.
  ImageRegistrationOptions Relaxed() const {
    ImageRegistrationOptions relaxed = *this;
    relaxed.min_inliers = relaxed_min_inliers;
    relaxed.min_inlier_ratio = relaxed_min_inlier_ratio;
    relaxed.relaxed_min_inliers = 0;
    return relaxed;
  }
};

// A 2D point of an unregistered image and the 3D point its tracks lead to.
struct Correspondence2D3D {
  point2D_t point2D_idx;
  point3D_t point3D_id;
};

// Through the tracks of every registered image (Algorithm 2 of the paper, generalised): for each
// 2D point of `image_id`, the first registered match that has a 3D point.
std::vector<Correspondence2D3D> FindCorrespondences2D3D(const CorrespondenceGraph& graph,
                                                        const Reconstruction& rec,
                                                        image_t image_id);

// Registers `image_id` (unregistered, its camera at its initial values) into `rec`: on success
// the image has its pose, its camera (unless a registered image shares it) its intrinsics, and
// its inlier 2D points join the 3D points. `registration_order` lists the registered images,
// the last one most recent (its camera starts the refinement when no registered image shares
// more points). `seed` is the mapper's: each image's RANSACs derive theirs from it.
bool RegisterImage(const CorrespondenceGraph& graph, const ImageRegistrationOptions& options,
                   const IntrinsicsPolicy& intrinsics,
                   const std::vector<image_t>& registration_order, uint64_t seed, image_t image_id,
                   Reconstruction* rec);

}  // namespace varsfm

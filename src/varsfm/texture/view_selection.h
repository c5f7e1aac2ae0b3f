#pragma once
// Which image textures each face, as a labelling problem (Lempitsky & Ivanov, "Seamless
// mosaicing of image-based texture maps", CVPR 2007; Waechter, Moehrle & Goesele, "Let there be
// color!", ECCV 2014): a data term per face and view from the view's quality of the face
// (face_observations.h: unoccluded, well inside the image, gradient magnitude integrated over
// its projection), views that disagree with the others' colour removed first
// (photo_consistency.h, after the exposure gains of exposure_gain.h) and the others' distance
// from the consensus colour added to the data term (a soft form of that check), and a Potts
// smoothness term over edge-adjacent faces so that faces group into charts of one image and few
// seams cross the model; minimised by alpha-expansion (alpha_expansion.h).
#include <array>
#include <functional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "varsfm/texture/exposure_gain.h"
#include "varsfm/texture/face_observations.h"
#include "varsfm/texture/photo_consistency.h"

namespace varsfm {

struct ViewSelectionOptions {
  FaceObservationOptions observation;
  ExposureGainOptions exposure;
  PhotoConsistencyOptions consistency;
  // Potts weight per pair of adjacent faces with different images, in units of the data term
  // (1 - quality / best quality of the face, so 0 for a face's best view).
  double smoothness = 1.0;
  // Weight of the consensus term added to the data term: a view's distance from the consensus
  // colour of the face (photo_consistency.h, after the exposure gains), over the rejection
  // distance and capped at 1. Photos with a look of their own (haze or flare from the sun, a
  // sheen on a slate roof, shade), which the exposure gains cannot undo and the rejection leaves
  // in, then texture fewer faces, so the model looks like most photos and renders new views
  // better (Waechter et al.'s rejection made soft; weights 0 / 2 / 4 measured in
  // bench/results/2026-12-03-texture-consensus.md).
  double consensus_weight = 2.0;
  int max_expansion_cycles = 4;
  // Alpha-expansion stops after a cycle that lowers the energy by at most this fraction: the
  // first cycle takes nearly all of the decrease, and each later one costs as much time as the
  // first for a handful of faces (bench/results/2026-12-03-dense-800.md).
  double expansion_tolerance = 1e-2;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct ViewSelection {
  std::vector<int> labels;  // per face: index into the views, or -1 when no view sees it
  size_t num_visible_faces = 0;
  size_t num_rejected_observations = 0;  // (view, face) pairs removed by photo-consistency
  size_t num_changed_by_smoothing = 0;   // faces not textured from their best view
  std::vector<double> coverage;          // per view: the fraction of its pixels the mesh covers
  std::vector<Eigen::Vector3f> gains;    // per view: BGR exposure gain
  std::vector<cv::Mat> small_photos;     // per view: CV_32FC3, small_scale x the photo
  std::vector<double> small_scale;
  std::vector<std::array<int, 3>> neighbours;  // per face: FaceNeighbours, for the later steps
};

// `load_image(v)` returns view v's photo (BGR, 8-bit, the camera's size); it may be called from
// several threads at once. Throws varsfm::Error for a photo of another size.
ViewSelection SelectViews(const std::vector<Eigen::Vector3d>& vertices,
                          const std::vector<Eigen::Vector3i>& faces,
                          const std::vector<PosedCamera>& views,
                          const std::function<cv::Mat(size_t)>& load_image,
                          const ViewSelectionOptions& options = {});

}  // namespace varsfm

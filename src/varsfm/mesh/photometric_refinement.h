#pragma once
// Photometric refinement of a surface: every vertex moves along its normal to where the photos
// that see it agree best. The surface's vertices lie on fused depth-map points, which the cut and
// the smoothing leave a fraction of a pixel to a few pixels off the surface the photos show; a
// held-out view rendered from other views' texture then shows their parallax as blur and
// doubled edges.
//
// Per vertex, a small square patch on its tangent plane, one pixel of its most frontal view (the
// reference) per sample, is moved along the normal through a few offsets; at each the patch is
// projected into the reference and the other views that see the vertex, and the offset with the
// highest mean zero-mean NCC between the reference's samples and each other view's wins -- the
// normal-direction search with which PMVS refines its patches (Furukawa & Ponce, "Accurate,
// dense, and robust multiview stereopsis", PAMI 2010, sec. 3.1.1), here on the mesh's own normals.
// Each vertex then moves by the mean, over itself and its neighbours, of the medians of their
// own and their neighbours' winning offsets (the smoothness term of the variational refinement
// of Vu, Labatut, Pons & Keriven, PAMI 2012, in its simplest form, robust to a neighbour matched
// wrongly), so that the surface moves as a surface and a vertex no view measures follows its
// neighbours. Visibility comes from the mesh
// itself: a z-buffer per view (geometry/rasterizer.h), drawn again at each iteration. Each
// iteration halves the offsets' step: the first reaches a few pixels, the next refine.
#include <cstddef>
#include <vector>

#include <opencv2/core.hpp>

#include "varsfm/geometry/posed_camera.h"
#include "varsfm/scene/triangle_mesh.h"

namespace varsfm {

struct PhotometricRefinementOptions {
  int iterations = 2;  // 0: no refinement
  // Offsets tried on each side of the vertex, `step` x the size of a reference pixel at the
  // vertex apart at the first iteration, half that at the second, ... (the best one refined
  // between its neighbours by a parabola).
  int offsets = 3;
  double step = 1.0;
  int window_radius = 2;  // the patch: (2 r + 1)^2 samples one reference pixel apart
  // The reference and up to max_views - 1 other views, the most frontal; a vertex fewer than
  // min_views see is not measured (with one other view a wrong offset matches as well as the
  // right one more often).
  int max_views = 4;
  int min_views = 3;
  // The winning offset's mean NCC must reach this, and beat the vertex's own place by
  // min_ncc_gain, for the vertex to be measured; others only follow their neighbours.
  double min_ncc = 0.7;
  double min_ncc_gain = 0.02;
  double min_cos_angle = 0.3;     // between the normal and the direction to a view's centre
  double depth_tolerance = 0.01;  // relative: a vertex is seen where the z-buffer is this near

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// A registered view of the surface: intensities in [0, 1] (CV_32F, one channel) and its camera
// at that image's size.
struct RefinementView {
  cv::Mat gray;
  PosedCamera camera;
};

// The view of `photo` (8-bit, BGR or gray) taken from `camera` (at the photo's size).
RefinementView RefinementViewOf(const cv::Mat& photo, const PosedCamera& camera);

struct PhotometricRefinementStats {
  size_t measured_vertices = 0;  // at the last iteration: vertices whose offset was measured
  double mean_offset = 0;  // mean |applied offset| over all vertices and iterations, scene units
};

// Moves mesh->vertices (faces and colours unchanged). Deterministic whatever the thread count.
PhotometricRefinementStats RefinePhotometrically(const std::vector<RefinementView>& views,
                                                 const PhotometricRefinementOptions& options,
                                                 TriangleMesh* mesh);

}  // namespace varsfm

#pragma once
// Which image textures each face. The data term follows Lempitsky & Ivanov ("Seamless mosaicing
// of image-based texture maps", CVPR 2007) and Waechter, Moehrle & Goesele ("Let there be
// color!", ECCV 2014): a face may take an image that sees it unoccluded (depth test against the
// mesh rendered into the view), and prefers the one where it covers the most pixels, which
// rewards both resolution (near, zoomed-in cameras) and frontal views (area ~ cos(angle) / d^2).
// A Potts smoothness term over edge-adjacent faces, minimised by iterated conditional modes,
// groups faces into charts of one image, so fewer seams cross the model.
#include <vector>

#include <Eigen/Core>

#include "varsfm/camera/camera.h"
#include "varsfm/geometry/rigid3.h"

namespace varsfm {

struct TextureView {
  Camera camera;
  Rigid3d cam_from_world;
};

struct ViewSelectionOptions {
  // Visibility rasters are at most this many pixels on their longer side (speed; faces are
  // tested at their corners and centroid, so faces smaller than a raster pixel still are).
  int max_raster_size = 1000;
  // A face is occluded when the raster is nearer than its centroid or one of its corners by more
  // than this fraction of the depth.
  double depth_tolerance = 0.01;
  // Faces seen at more than acos(min_cos_angle) from their normal are not textured from the view.
  double min_cos_angle = 0.15;
  // Vertices should project this far inside the image so the chart's pixels all exist.
  double border_px = 2.0;
  // Score factor for a face only partly inside the image (its centroid must be inside).
  double partial_face_weight = 0.05;
  // Potts weight, in units of the data term (1 - score / best score of the face).
  double smoothness = 0.3;
  int smoothing_iterations = 6;
  int num_threads = 0;  // 0: all cores

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct ViewSelection {
  std::vector<int> labels;  // per face: index into the views, or -1 when no view sees it
  size_t num_visible_faces = 0;
  size_t num_changed_by_smoothing = 0;
  std::vector<double> coverage;  // per view: the fraction of its pixels the mesh covers
};

ViewSelection SelectViews(const std::vector<Eigen::Vector3d>& vertices,
                          const std::vector<Eigen::Vector3i>& faces,
                          const std::vector<TextureView>& views,
                          const ViewSelectionOptions& options = {});

}  // namespace varsfm

#pragma once
// Texturing a mesh from the registered photos: per-face image choice (view_selection.h), charts
// of connected faces with the same image (texture_charts.h), the photo texels each chart's faces
// cover plus a gutter packed by shape into an atlas (atlas.h), texture coordinates from projecting
// the vertices through the full camera model (distortion included), so colours come straight from
// the photo's pixels with no resampling. Inside a face the photo is mapped affinely between its
// corners' distorted positions: exact at the corners, and off by (distortion curvature x face
// size^2), a small fraction of a pixel for the faces of a reconstructed mesh. Faces no photo sees
// take their vertex colour (or grey) from a palette block of the atlas.
#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "varsfm/scene/textured_mesh.h"
#include "varsfm/scene/triangle_mesh.h"
#include "varsfm/texture/colour_levelling.h"
#include "varsfm/texture/seam_blending.h"
#include "varsfm/texture/view_selection.h"

namespace varsfm {

struct TextureMappingOptions {
  ViewSelectionOptions selection;
  ColourLevellingOptions levelling;
  SeamBlendingOptions seams;
  // Photo pixels kept around each chart's faces (the gutter) so bilinear lookups (and the first
  // mip-map levels of viewers) at a chart's edge read the photo, not a neighbouring chart or
  // the background: this is what hides seams. Bilinear lookups need 1.
  int padding = 2;
  // Texels of chart colour bled into the empty atlas around charts, for viewers' mip-maps
  // (atlas_fill.h); 0: leave the background black.
  int bleed_rings = 8;
  // Charts are cut along a grid of this many photo pixels (texture_charts.h: CutChart) so that
  // long or ring-shaped charts pack densely; smaller squares add gutter texels along the cuts.
  int chart_tile = 256;
  int max_page_size = 8192;
  // Photos larger than this (longer side, px) are textured from a copy of this size, which
  // bounds the atlas and the glb of a model from high-resolution photos; 0: full resolution.
  int max_image_size = 0;
  cv::Vec3b unseen_color = {128, 128, 128};  // BGR, for unseen faces of a mesh without colours
  // Texturing fails when the mesh covers less than this fraction of the photos' pixels on
  // average: such a mesh is not the surface the photos show (a collapsed or misplaced mesh),
  // and its textured model would be empty in every view.
  double min_mean_coverage = 0.01;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct TextureMappingStats {
  size_t num_faces = 0;
  size_t num_textured_faces = 0;
  size_t num_rejected_observations = 0;  // (view, face) pairs failing photo-consistency
  size_t num_charts = 0;  // pieces packed into the atlas (charts cut along the tile grid)
  size_t num_pages = 0;
  size_t atlas_pixels = 0;
  size_t chart_texels = 0;   // atlas texels the charts hold: their faces' and their gutters
  double face_texels = 0;    // atlas texels inside textured faces (the rest is gutter and waste)
  double mean_coverage = 0;  // the mean over the views of the fraction of pixels the mesh covers
  double seconds_selection = 0;
  double seconds_levelling = 0;
  double seconds_atlas = 0;  // packing, copying, seam blending
};

// `load_image(v)` returns view v's photo (BGR, 8-bit, the camera's size). Throws varsfm::Error
// for an empty mesh, no views, a mesh covering less than min_mean_coverage of the photos, or a
// photo whose size differs from its camera.
TexturedMesh TextureMesh(const TriangleMesh& mesh, const std::vector<PosedCamera>& views,
                         const std::function<cv::Mat(size_t)>& load_image,
                         const TextureMappingOptions& options = {},
                         TextureMappingStats* stats = nullptr);

}  // namespace varsfm

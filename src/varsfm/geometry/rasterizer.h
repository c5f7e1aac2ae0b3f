#pragma once
// Software triangle rasterisation with a z-buffer: which face is nearest at every pixel of a
// view. Used for visibility when choosing a face's image (texture) and for rendering a textured
// mesh from a registered camera (render).
//
// Vertices are projected through the full camera model, distortion included, and triangles are
// filled with straight edges in the (distorted) image: exact without distortion and within a
// fraction of a pixel for the small triangles of a reconstructed mesh. Attributes are then
// computed per pixel by intersecting the pixel's undistorted viewing ray with the face's plane
// (FaceBarycentrics), which is perspective-correct whatever the triangle size.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "varsfm/camera/camera.h"
#include "varsfm/geometry/rigid3.h"

namespace varsfm {

// A vertex seen by a view: pixel position (at the raster's scale) and camera-space depth;
// depth <= 0 marks a vertex that cannot be drawn: behind (or too close to) the camera, or so far
// outside the view that the distortion model is no longer valid there.
struct ProjectedVertex {
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  double depth = 0;
};

// Projects every vertex; `scale` shrinks the image (raster of scale x width by scale x height;
// with the top-left-corner pixel convention a pixel position scales by the same factor).
std::vector<ProjectedVertex> ProjectVertices(const std::vector<Eigen::Vector3d>& vertices,
                                             const Camera& camera, const Rigid3d& cam_from_world,
                                             double scale = 1.0);
// The same into `out`, whose storage is reused: a caller projecting a large mesh into view after
// view then touches no fresh memory.
void ProjectVertices(const std::vector<Eigen::Vector3d>& vertices, const Camera& camera,
                     const Rigid3d& cam_from_world, double scale,
                     std::vector<ProjectedVertex>* out);

struct FaceRaster {
  int width = 0;
  int height = 0;
  std::vector<float> depth;   // camera-space depth of the nearest face; +inf where none
  std::vector<int32_t> face;  // index of the nearest face; -1 where none

  int32_t FaceAt(int x, int y) const { return face[static_cast<size_t>(y) * width + x]; }
  float DepthAt(int x, int y) const { return depth[static_cast<size_t>(y) * width + x]; }
};

// Fills the faces in, sampling at pixel centres (x + 0.5, y + 0.5) with a top-left fill rule so
// that a pixel on an edge shared by two faces belongs to exactly one. Depth is interpolated as
// 1/z, linear in the image for a pinhole camera. Faces with a vertex of depth <= 0 are skipped.
// Both windings are drawn (no back-face culling): meshes from Poisson or advancing front are not
// always consistently oriented.
FaceRaster RasterizeFaces(const std::vector<ProjectedVertex>& projected,
                          const std::vector<Eigen::Vector3i>& faces, int width, int height);

// Barycentric coordinates of the point where the ray through normalised image point `ray`
// (x/z, y/z, camera frame) meets the plane of triangle (a, b, c) given in camera coordinates.
// Returns false when the ray is parallel to the plane.
bool FaceBarycentrics(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                      const Eigen::Vector2d& ray, Eigen::Vector3d* barycentric);

}  // namespace varsfm

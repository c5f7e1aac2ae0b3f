#pragma once
// A triangle mesh whose faces carry texture coordinates into one or more atlas pages: what
// `varsfm texture` produces and `varsfm render` draws. Texture coordinates follow glTF: (0, 0)
// is the top-left corner of the page, (1, 1) the bottom-right (OBJ's v axis is flipped on write).
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace varsfm {

struct TexturedMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> faces;           // vertex indices, counter-clockwise from outside
  std::vector<Eigen::Vector2f> texcoords;       // (u, v) in [0, 1], glTF orientation
  std::vector<Eigen::Vector3i> face_texcoords;  // texcoord indices, one triple per face
  std::vector<int> face_page;                   // atlas page of each face
  std::vector<cv::Mat> pages;                   // BGR 8-bit atlas images
};

}  // namespace varsfm

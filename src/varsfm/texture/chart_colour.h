#pragma once
// A chart's texels as they go into the atlas: the photo's pixels times the photo's exposure gain
// (exposure_gain.h) plus the additive correction of the global levelling (colour_levelling.h),
// interpolated linearly over each face from its corners (Waechter et al. 2014, sec. 4.1).
// Texels of the padding around the faces take the correction of the nearest face (barycentric
// coordinates clamped to it), so bilinear lookups at a chart's edge read corrected colour too.
#include <array>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace varsfm {

// `chart` (CV_8UC3, in place): the chart's rectangle of the photo. `face_pixels`: the corners
// of each of its faces in the rectangle's pixel coordinates (top-left-corner convention);
// `face_corrections`: the BGR correction at those corners. Texels farther than `reach` from
// every face get the gain only.
void CorrectChartColours(const std::vector<std::array<Eigen::Vector2d, 3>>& face_pixels,
                         const std::vector<std::array<Eigen::Vector3f, 3>>& face_corrections,
                         const Eigen::Vector3f& gain, double reach, cv::Mat* chart);

}  // namespace varsfm

#pragma once
// RootSIFT (Arandjelovic & Zisserman, "Three things everyone should know to improve object
// retrieval", CVPR 2012): comparing square roots of L1-normalised SIFT descriptors with the
// Euclidean distance equals comparing the originals with the Hellinger kernel, which matches
// better. Stored as uint8 exactly as COLMAP stores its descriptors, so workspaces interoperate.
#include <opencv2/core.hpp>

#include "varsfm/feature/types.h"

namespace varsfm {

// `descriptors`: one SIFT descriptor per row, CV_32F, non-negative. Each row is L1-normalised,
// square-rooted (its L2 norm is then 1) and quantised as COLMAP does: min(255, round(512 x)).
FeatureDescriptors RootSiftDescriptors(const cv::Mat& descriptors);

}  // namespace varsfm

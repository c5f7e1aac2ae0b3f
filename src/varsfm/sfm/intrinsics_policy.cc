#include "varsfm/sfm/intrinsics_policy.h"

#include "varsfm/util/option_check.h"

namespace varsfm {

void IntrinsicsPolicy::Check() const {
  if (sharing != IntrinsicsSharing::kPerImage && sharing != IntrinsicsSharing::kShared &&
      sharing != IntrinsicsSharing::kFocalPerImage)
    FailOption("--intrinsics", "per-image, focal-per-image or shared", static_cast<int>(sharing));
  if (!(zoom_band_focal_ratio == 0.0 || zoom_band_focal_ratio > 1.0))
    FailOption("--zoom-band", "0 or above 1", zoom_band_focal_ratio);
}

std::vector<int> IntrinsicsPolicy::SharedPerSize() const {
  if (sharing == IntrinsicsSharing::kFocalPerImage)
    return {Camera::kAspect, Camera::kSkew, Camera::kU0, Camera::kV0, Camera::kK1, Camera::kK2};
  if (share_principal_point && !refine_principal_point) return {Camera::kU0, Camera::kV0};
  return {};
}

IntrinsicsOptions IntrinsicsPolicy::ForAdjustment(bool whole_model) const {
  IntrinsicsOptions in;
  in.refine_focal = true;
  in.refine_aspect = refine_aspect;
  in.refine_skew = refine_skew;
  in.refine_principal_point = refine_principal_point;
  in.refine_k1 = refine_distortion;
  in.refine_k2 = refine_distortion;
  in.shared_per_size = SharedPerSize();
  in.max_shared_focal_ratio = zoom_band_focal_ratio;
  if (share_principal_point && !refine_principal_point) in.refine_principal_point = whole_model;
  if (!whole_model)
    for (const int i : in.shared_per_size) {
      if (i == Camera::kAspect) in.refine_aspect = false;
      if (i == Camera::kSkew) in.refine_skew = false;
      if (i == Camera::kU0) in.refine_principal_point = false;
      if (i == Camera::kK1) in.refine_k1 = false;
      if (i == Camera::kK2) in.refine_k2 = false;
    }
  return in;
}

IntrinsicsOptions IntrinsicsPolicy::ForRegistration(bool camera_registered) const {
  IntrinsicsOptions in;
  if (camera_registered) {
    in.refine_focal = false;
    in.refine_aspect = in.refine_skew = in.refine_principal_point = false;
    in.shared_per_size.clear();
  } else {
    in = ForAdjustment(/*whole_model=*/false);
  }
  in.refine_k1 = in.refine_k2 = false;
  return in;
}

}  // namespace varsfm

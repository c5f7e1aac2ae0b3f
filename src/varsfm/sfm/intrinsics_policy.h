#pragma once
// The intrinsics policy: which camera parameters the mapper estimates for each image, which once
// per image size, and which it holds at their initial values (principal point at the image
// centre, aspect 1, skew 0). One type from the command line (--intrinsics, --refine-*) down to
// the bundle adjustments, whose IntrinsicsOptions (ba/bundle_adjuster.h) it makes.
#include <vector>

#include "varsfm/ba/bundle_adjuster.h"
#include "varsfm/util/enum_names.h"

namespace varsfm {

// Which images share which intrinsics.
enum class IntrinsicsSharing {
  kPerImage,       // every image its own camera (the paper; default)
  kShared,         // one camera for all images of a size (a fixed-zoom capture): the workspace's
                   // images point at one camera per size when they are loaded (pipeline/map.cc)
  kFocalPerImage,  // focal length per image; aspect, skew, principal point and k1, k2 one set
                   // per image size (a zoom lens on one body), estimated in the global adjustments
};

// The names `--intrinsics` takes.
inline constexpr EnumName<IntrinsicsSharing> kIntrinsicsSharingNames[] = {
    {IntrinsicsSharing::kPerImage, "per-image"},
    {IntrinsicsSharing::kFocalPerImage, "focal-per-image"},
    {IntrinsicsSharing::kShared, "shared"}};

struct IntrinsicsPolicy {
  IntrinsicsSharing sharing = IntrinsicsSharing::kPerImage;
  // The paper refines every intrinsic per image; on real sequences holding the principal point,
  // aspect and skew is more accurate (docs/mapper.md). The focal length is always estimated.
  bool refine_principal_point = false;
  // One principal point per image size (and zoom band, below), estimated in the global
  // adjustments from all its images; new images start from it. One image cannot separate its
  // principal point from its rotation, but the images of one physical camera share it and many
  // views pin it down.
  bool share_principal_point = true;
  bool refine_aspect = false;
  bool refine_skew = false;
  bool refine_distortion = true;  // k1, k2
  // What is estimated once per image size is shared only by the images of a zoom band: focal
  // lengths within this ratio (IntrinsicsOptions::max_shared_focal_ratio; 0: one band per size).
  // Above the few percent by which refocusing changes the focal length.
  double zoom_band_focal_ratio = 1.1;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value

  // The parameters (Camera::Param indices) estimated once per image size.
  std::vector<int> SharedPerSize() const;
  // What a bundle adjustment refines. Parameters shared per image size are estimated in the
  // adjustments of the whole model (`whole_model`: two-view and global; a size needs
  // IntrinsicsOptions::min_images_to_share images to form a group, so the two-view one holds
  // them) and held at their current values in local ones, so that every camera of a size keeps
  // the same values.
  IntrinsicsOptions ForAdjustment(bool whole_model) const;
  // What the refinement of a new image's pose refines with it: nothing when its camera is one
  // a registered image already uses (`camera_registered`), else what a local adjustment
  // refines less k1, k2 (a single image's few points do not determine the distortion; the
  // adjustments do).
  IntrinsicsOptions ForRegistration(bool camera_registered) const;
};

}  // namespace varsfm

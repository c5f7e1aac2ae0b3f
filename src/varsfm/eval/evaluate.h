#pragma once
// Accuracy of a reconstruction against ground-truth cameras (Strecha's benchmark protocol):
// images are matched by name, the estimated camera centres are aligned onto the true ones by a
// similarity, then per image the centre error (ground-truth units, metres), the rotation error,
// and the intrinsics errors (focal %, aspect, principal point px) are measured.
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "varsfm/eval/alignment.h"
#include "varsfm/eval/ground_truth.h"
#include "varsfm/scene/reconstruction.h"

namespace varsfm {

struct EvaluationOptions {
  AlignmentOptions alignment;  // inlier_threshold > 0 makes the alignment robust (RANSAC)

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct ErrorStats {
  size_t count = 0;
  double mean = std::numeric_limits<double>::quiet_NaN();
  double median = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();
  static ErrorStats Of(std::vector<double> values);
};

struct ImageEvaluation {
  std::string name;
  bool registered = false;  // in the model under this name (or file name) and registered
  // The remaining fields are NaN when not registered; centre/rotation also when not aligned.
  double center_error = std::numeric_limits<double>::quiet_NaN();         // GT units
  double rotation_error_deg = std::numeric_limits<double>::quiet_NaN();   // angle of R_est R_gt^T
  double focal_error_percent = std::numeric_limits<double>::quiet_NaN();  // 100 |f - f_gt| / f_gt
  double aspect_error = std::numeric_limits<double>::quiet_NaN();         // |e - e_gt|
  double principal_point_error_px = std::numeric_limits<double>::quiet_NaN();
  // The intrinsics errors above are measured: registered, and the model's image is the true one
  // resized (not cropped: the aspect ratio agrees).
  bool intrinsics_compared = false;
  bool alignment_inlier = false;
};

struct EvaluationReport {
  size_t num_gt_images = 0;
  size_t num_registered = 0;    // ground-truth images registered in the model
  size_t num_model_images = 0;  // registered images in the model (some may lack ground truth)
  bool aligned = false;         // false with fewer than 3 registered images (or collinear centres)
  Sim3d alignment;              // gt ~ alignment * estimated
  size_t num_alignment_inliers = 0;
  ErrorStats center_error, rotation_error_deg, focal_error_percent, aspect_error,
      principal_point_error_px;
  size_t num_points3D = 0;
  size_t num_observations = 0;
  double rms_reprojection_error_px = 0.0;
  std::vector<ImageEvaluation> images;  // one per ground-truth image, in name order
};

// Estimated intrinsics are compared at the ground truth's image size: if the model's camera has
// a different width, its focal length and principal point are scaled by width_gt / width. An
// image whose aspect ratio differs from the ground truth's (cropped) has no intrinsics errors.
EvaluationReport EvaluateAgainstGroundTruth(const Reconstruction& reconstruction,
                                            const GroundTruth& ground_truth,
                                            const EvaluationOptions& options = {});

nlohmann::json ToJson(const EvaluationReport& report);     // NaN becomes null
std::string FormatReport(const EvaluationReport& report);  // a readable table

}  // namespace varsfm

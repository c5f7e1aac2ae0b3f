#include "varsfm/eval/evaluate.h"
#include "varsfm/util/option_check.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>

#include <nlohmann/json.hpp>

namespace varsfm {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Registered model images by name, and by file name alone so "images/0000.jpg" matches the
// ground truth's "0000.jpg" (COLMAP keeps the path relative to its image folder).
class NameIndex {
 public:
  explicit NameIndex(const Reconstruction& rec) {
    std::map<std::string, int> basename_count, stem_count;
    for (const auto& [id, image] : rec.images()) {
      if (!image.registered) continue;
      by_name_[image.name] = id;
      const std::filesystem::path path(image.name);
      by_basename_[path.filename().string()] = id;
      ++basename_count[path.filename().string()];
      by_stem_[path.stem().string()] = id;
      ++stem_count[path.stem().string()];
    }
    // Ambiguous: only more exact names match.
    for (const auto& [base, count] : basename_count)
      if (count > 1) by_basename_.erase(base);
    for (const auto& [stem, count] : stem_count)
      if (count > 1) by_stem_.erase(stem);
  }
  // The registered image of ground-truth camera `name`: by name, else by file name (photos in
  // subfolders), else by file name without extension (photos converted to another format:
  // an iPhone's IMG_0001.HEIC against ground truth made for IMG_0001.jpg).
  const Image* Find(const Reconstruction& rec, const std::string& name) const {
    const std::filesystem::path path(name);
    for (const auto& [index, key] :
         {std::pair{&by_name_, name}, std::pair{&by_basename_, path.filename().string()},
          std::pair{&by_stem_, path.stem().string()}})
      if (const auto it = index->find(key); it != index->end()) return &rec.image(it->second);
    return nullptr;
  }

 private:
  std::map<std::string, image_t> by_name_, by_basename_, by_stem_;
};

double RotationAngleDeg(const Eigen::Matrix3d& R) {
  const double c = std::clamp((R.trace() - 1.0) / 2.0, -1.0, 1.0);
  // acos loses precision near 0; use the sine part too (|axis| = 2 sin(angle)).
  const Eigen::Vector3d axis(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  return std::atan2(0.5 * axis.norm(), c) * 180.0 / std::numbers::pi;
}

// Whether the estimated camera's image is the true one's, resized: the two scales agree within
// the rounding of a pixel on the smaller side. A cropped photo's intrinsics have another origin
// and field of view, and comparing them would report its crop as error.
bool SameFrame(const Camera& estimated, const Camera& truth) {
  if (estimated.width <= 0 || estimated.height <= 0) return false;
  const double sx = static_cast<double>(truth.width) / estimated.width;
  const double sy = static_cast<double>(truth.height) / estimated.height;
  return std::abs(sx - sy) <= 1.5 * sx / std::min(estimated.width, estimated.height);
}

void CompareIntrinsics(const Camera& estimated, const Camera& truth, ImageEvaluation* e) {
  if (!SameFrame(estimated, truth)) return;
  e->intrinsics_compared = true;
  const double s = static_cast<double>(truth.width) / estimated.width;
  const double f = s * estimated.focal(), f_gt = truth.focal();
  e->focal_error_percent = 100.0 * std::abs(f - f_gt) / f_gt;
  e->aspect_error = std::abs(estimated.params[Camera::kAspect] - truth.params[Camera::kAspect]);
  const Eigen::Vector2d pp(estimated.params[Camera::kU0], estimated.params[Camera::kV0]);
  const Eigen::Vector2d pp_gt(truth.params[Camera::kU0], truth.params[Camera::kV0]);
  e->principal_point_error_px = (s * pp - pp_gt).norm();
}

nlohmann::json Number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

nlohmann::json StatsJson(const ErrorStats& s) {
  return {{"count", s.count},
          {"mean", Number(s.mean)},
          {"median", Number(s.median)},
          {"max", Number(s.max)}};
}

std::string Cell(double v, int precision) {
  return std::isfinite(v) ? fmt::format("{:.{}f}", v, precision) : "-";
}

}  // namespace

ErrorStats ErrorStats::Of(std::vector<double> values) {
  std::erase_if(values, [](double v) { return !std::isfinite(v); });
  ErrorStats s;
  s.count = values.size();
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  double sum = 0;
  for (double v : values) sum += v;
  s.mean = sum / values.size();
  const size_t mid = values.size() / 2;
  s.median = values.size() % 2 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
  s.max = values.back();
  return s;
}

EvaluationReport EvaluateAgainstGroundTruth(const Reconstruction& rec, const GroundTruth& gt,
                                            const EvaluationOptions& options) {
  EvaluationReport report;
  report.num_gt_images = gt.cameras.size();
  report.num_model_images = rec.NumRegisteredImages();
  report.num_points3D = rec.points3D().size();
  report.num_observations = rec.NumObservations();
  report.rms_reprojection_error_px = rec.RmsReprojectionError();

  const NameIndex index(rec);
  std::vector<const Image*> matched;  // parallel to report.images
  std::vector<Eigen::Vector3d> estimated_centers, true_centers;
  std::vector<size_t> aligned_rows;  // rows of report.images entering the alignment
  for (const auto& [name, truth] : gt.cameras) {
    ImageEvaluation e;
    e.name = name;
    const Image* image = index.Find(rec, name);
    e.registered = image != nullptr;
    if (image) {
      CompareIntrinsics(rec.camera(image->camera_id), truth.camera, &e);
      estimated_centers.push_back(image->Center());
      true_centers.push_back(truth.Center());
      aligned_rows.push_back(report.images.size());
      ++report.num_registered;
    }
    matched.push_back(image);
    report.images.push_back(e);
  }

  const AlignmentResult alignment =
      AlignSimilarity(estimated_centers, true_centers, options.alignment);
  report.aligned = alignment.success;
  if (alignment.success) {
    report.alignment = alignment.sim;
    report.num_alignment_inliers = alignment.num_inliers;
    for (size_t k = 0; k < aligned_rows.size(); ++k) {
      ImageEvaluation& e = report.images[aligned_rows[k]];
      const Image& image = *matched[aligned_rows[k]];
      const GroundTruthCamera& truth = gt.cameras.at(e.name);
      e.alignment_inlier = alignment.inliers[k];
      e.center_error = (alignment.sim * estimated_centers[k] - true_centers[k]).norm();
      // x_gt = s A x_est + t, so the estimated camera's rotation in the GT frame is R_est A^T.
      const Eigen::Matrix3d R_aligned =
          image.cam_from_world.R() * alignment.sim.rotation.transpose();
      e.rotation_error_deg = RotationAngleDeg(R_aligned * truth.cam_from_world.R().transpose());
    }
  }

  auto collect = [&](double ImageEvaluation::*field) {
    std::vector<double> v;
    for (const auto& e : report.images) v.push_back(e.*field);
    return ErrorStats::Of(v);
  };
  report.center_error = collect(&ImageEvaluation::center_error);
  report.rotation_error_deg = collect(&ImageEvaluation::rotation_error_deg);
  report.focal_error_percent = collect(&ImageEvaluation::focal_error_percent);
  report.aspect_error = collect(&ImageEvaluation::aspect_error);
  report.principal_point_error_px = collect(&ImageEvaluation::principal_point_error_px);
  return report;
}

nlohmann::json ToJson(const EvaluationReport& r) {
  nlohmann::json j;
  j["num_gt_images"] = r.num_gt_images;
  j["num_registered"] = r.num_registered;
  j["num_model_images"] = r.num_model_images;
  j["aligned"] = r.aligned;
  if (r.aligned) {
    // Eigen types are not JSON-serialisable: plain arrays, rotation row by row.
    nlohmann::json rows = nlohmann::json::array();
    for (int i = 0; i < 3; ++i)
      rows.push_back(
          {r.alignment.rotation(i, 0), r.alignment.rotation(i, 1), r.alignment.rotation(i, 2)});
    j["alignment"] = {
        {"scale", r.alignment.scale},
        {"rotation", rows},
        {"translation",
         {r.alignment.translation.x(), r.alignment.translation.y(), r.alignment.translation.z()}},
        {"num_inliers", r.num_alignment_inliers}};
  }
  j["center_error_m"] = StatsJson(r.center_error);
  j["rotation_error_deg"] = StatsJson(r.rotation_error_deg);
  j["focal_error_percent"] = StatsJson(r.focal_error_percent);
  j["aspect_error"] = StatsJson(r.aspect_error);
  j["principal_point_error_px"] = StatsJson(r.principal_point_error_px);
  j["num_points3D"] = r.num_points3D;
  j["num_observations"] = r.num_observations;
  j["rms_reprojection_error_px"] = r.rms_reprojection_error_px;
  nlohmann::json images = nlohmann::json::array();
  for (const auto& e : r.images)
    images.push_back({{"name", e.name},
                      {"registered", e.registered},
                      {"intrinsics_compared", e.intrinsics_compared},
                      {"alignment_inlier", e.alignment_inlier},
                      {"center_error_m", Number(e.center_error)},
                      {"rotation_error_deg", Number(e.rotation_error_deg)},
                      {"focal_error_percent", Number(e.focal_error_percent)},
                      {"aspect_error", Number(e.aspect_error)},
                      {"principal_point_error_px", Number(e.principal_point_error_px)}});
  j["images"] = images;
  return j;
}

std::string FormatReport(const EvaluationReport& r) {
  std::string out;
  auto line = [&](const std::string& s) { out += s + '\n'; };
  line(fmt::format("registered: {} / {} ground-truth images ({} registered in the model)",
                   r.num_registered, r.num_gt_images, r.num_model_images));
  if (r.aligned)
    line(fmt::format("alignment: similarity on {} camera centres, scale {:.6g}, {} inliers",
                     r.num_registered, r.alignment.scale, r.num_alignment_inliers));
  else
    line("alignment: not possible (needs 3 registered images with non-collinear centres)");
  line(fmt::format("sparse model: {} points, {} observations, RMS reprojection error {:.3f} px",
                   r.num_points3D, r.num_observations, r.rms_reprojection_error_px));
  line("");
  line(fmt::format("{:<26}{:>12}{:>12}{:>12}", "error", "mean", "median", "max"));
  auto row = [&](const char* label, const ErrorStats& s, int precision) {
    line(fmt::format("{:<26}{:>12}{:>12}{:>12}", label, Cell(s.mean, precision),
                     Cell(s.median, precision), Cell(s.max, precision)));
  };
  row("camera centre (GT units)", r.center_error, 4);
  row("rotation (deg)", r.rotation_error_deg, 3);
  row("focal length (%)", r.focal_error_percent, 3);
  row("aspect ratio", r.aspect_error, 5);
  row("principal point (px)", r.principal_point_error_px, 2);
  const auto cropped = std::count_if(
      r.images.begin(), r.images.end(),
      [](const ImageEvaluation& e) { return e.registered && !e.intrinsics_compared; });
  if (cropped > 0)
    line(
        fmt::format("intrinsics of {} image(s) not compared: their aspect ratio differs from the "
                    "ground truth's (a cropped photo)",
                    cropped));
  line("");
  line(fmt::format("{:<24}{:>12}{:>10}{:>10}{:>10}{:>10}", "image", "centre", "rot deg", "focal %",
                   "pp px", "inlier"));
  for (const auto& e : r.images)
    line(fmt::format("{:<24}{:>12}{:>10}{:>10}{:>10}{:>10}", e.name,
                     e.registered ? Cell(e.center_error, 4) : "unregistered",
                     Cell(e.rotation_error_deg, 3), Cell(e.focal_error_percent, 3),
                     Cell(e.principal_point_error_px, 2),
                     e.registered && r.aligned ? (e.alignment_inlier ? "yes" : "no") : "-"));
  return out;
}

void EvaluationOptions::Check() const { alignment.Check(); }

}  // namespace varsfm

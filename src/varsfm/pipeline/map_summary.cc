#include "varsfm/pipeline/map_summary.h"

#include <map>
#include <string>

namespace varsfm {
namespace {

nlohmann::json ImageSummaryJson(const Reconstruction& rec, const Image& image) {
  nlohmann::json im;
  im["image_id"] = image.image_id;
  im["name"] = image.name;
  im["registered"] = image.registered;
  if (image.registered) {
    const Camera& c = rec.camera(image.camera_id);
    im["camera_id"] = image.camera_id;
    im["focal_px"] = c.focal();
    im["aspect"] = c.params[Camera::kAspect];
    im["skew"] = c.params[Camera::kSkew];
    im["principal_point"] = {c.params[Camera::kU0], c.params[Camera::kV0]};
    im["k1"] = c.params[Camera::kK1];
    im["k2"] = c.params[Camera::kK2];
    im["num_points3D"] = image.NumPoints3D();
    const Eigen::Vector3d center = image.Center();
    im["center"] = {center.x(), center.y(), center.z()};
  }
  return im;
}

}  // namespace

nlohmann::json ReconstructionSummaryJson(const Reconstruction& rec) {
  nlohmann::json j;
  j["images_total"] = rec.images().size();
  j["images_registered"] = rec.NumRegisteredImages();
  j["points3D"] = rec.points3D().size();
  j["observations"] = rec.NumObservations();
  j["mean_track_length"] = rec.MeanTrackLength();
  j["rms_reprojection_error_px"] = rec.RmsReprojectionError();
  j["mean_reprojection_error_px"] = rec.MeanReprojectionError();
  nlohmann::json images = nlohmann::json::array();
  for (const auto& [id, image] : rec.images()) images.push_back(ImageSummaryJson(rec, image));
  j["images"] = images;
  return j;
}

nlohmann::json MapSummaryJson(const std::vector<MapperModel>& models,
                              const std::vector<UnmodelledImage>& unmodelled) {
  nlohmann::json j = ReconstructionSummaryJson(models.front().reconstruction);
  // Every image, from the model it is in; "registered" stays "in model 0".
  std::map<image_t, nlohmann::json> images;
  nlohmann::json model_list = nlohmann::json::array();
  for (size_t k = 0; k < models.size(); ++k) {
    const Reconstruction& rec = models[k].reconstruction;
    nlohmann::json names = nlohmann::json::array();
    for (const auto& [id, image] : rec.images()) {
      if (!image.registered) {
        if (!images.count(id)) images[id] = ImageSummaryJson(rec, image);
        continue;
      }
      images[id] = ImageSummaryJson(rec, image);
      images[id]["registered"] = k == 0;
      images[id]["model"] = k;
      names.push_back(image.name);
    }
    const MapperSummary& s = models[k].summary;
    model_list.push_back({{"path", "sparse/" + std::to_string(k)},
                          {"images_registered", rec.NumRegisteredImages()},
                          {"points3D", rec.points3D().size()},
                          {"observations", rec.NumObservations()},
                          {"rms_reprojection_error_px", rec.RmsReprojectionError()},
                          {"initial_pair", {s.initial_image_id1, s.initial_image_id2}},
                          {"seconds_mapping", models[k].seconds},
                          {"images", names}});
  }
  nlohmann::json none = nlohmann::json::array();
  for (const UnmodelledImage& u : unmodelled) {
    images[u.image_id]["model"] = nullptr;
    images[u.image_id]["reason"] = u.reason;
    none.push_back(
        {{"image_id", u.image_id}, {"name", images[u.image_id]["name"]}, {"reason", u.reason}});
  }
  j["images_total"] = images.size();
  j["images"] = nlohmann::json::array();
  for (auto& [id, im] : images) j["images"].push_back(std::move(im));
  j["models"] = model_list;
  j["images_in_no_model"] = none;
  return j;
}

}  // namespace varsfm

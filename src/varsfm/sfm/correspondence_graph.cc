#include "varsfm/sfm/correspondence_graph.h"

#include <algorithm>

#include "varsfm/util/error.h"

namespace varsfm {

void CorrespondenceGraph::AddImage(image_t image_id, size_t num_points2D) {
  images_[image_id].correspondences.resize(num_points2D);
}

void CorrespondenceGraph::AddImagePair(image_t id1, image_t id2, const FeatureMatches& matches,
                                       const std::optional<Eigen::Matrix3d>& F) {
  if (id1 == id2) return;
  if (F) fundamentals_[{std::min(id1, id2), std::max(id1, id2)}] = id1 < id2 ? *F : F->transpose();
  auto& c1 = images_.at(id1).correspondences;
  auto& c2 = images_.at(id2).correspondences;
  size_t added = 0;
  for (const FeatureMatch& m : matches) {
    if (m.point2D_idx1 >= c1.size() || m.point2D_idx2 >= c2.size()) continue;
    c1[m.point2D_idx1].push_back({id2, m.point2D_idx2});
    c2[m.point2D_idx2].push_back({id1, m.point2D_idx1});
    ++added;
  }
  pair_counts_[{std::min(id1, id2), std::max(id1, id2)}] += added;
  if (added == 0) return;
  for (const auto& [from, to] : {std::pair{id1, id2}, std::pair{id2, id1}}) {
    auto& neighbors = images_.at(from).neighbors;
    const auto it = std::lower_bound(neighbors.begin(), neighbors.end(), to);
    if (it == neighbors.end() || *it != to) neighbors.insert(it, to);
  }
}

std::vector<image_t> CorrespondenceGraph::ImageIds() const {
  std::vector<image_t> ids;
  for (const auto& [id, entry] : images_) ids.push_back(id);
  return ids;
}

size_t CorrespondenceGraph::NumObservedPoints2D(image_t image_id) const {
  const auto& c = images_.at(image_id).correspondences;
  return std::count_if(c.begin(), c.end(), [](const auto& v) { return !v.empty(); });
}

std::optional<Eigen::Matrix3d> CorrespondenceGraph::FundamentalMatrix(image_t id1,
                                                                      image_t id2) const {
  const auto it = fundamentals_.find({std::min(id1, id2), std::max(id1, id2)});
  if (it == fundamentals_.end()) return std::nullopt;
  return id1 < id2 ? it->second : Eigen::Matrix3d(it->second.transpose());
}

FeatureMatches CorrespondenceGraph::MatchesBetween(image_t id1, image_t id2) const {
  FeatureMatches matches;
  const auto& c1 = images_.at(id1).correspondences;
  for (point2D_t idx = 0; idx < c1.size(); ++idx)
    for (const auto& corr : c1[idx])
      if (corr.image_id == id2) matches.push_back({idx, corr.point2D_idx});
  return matches;
}

}  // namespace varsfm

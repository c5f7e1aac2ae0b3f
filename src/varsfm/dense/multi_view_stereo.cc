#include "varsfm/dense/multi_view_stereo.h"

#include <algorithm>
#include <atomic>
#include <map>
#include <set>

#include <tbb/parallel_for.h>

#include "varsfm/dense/undistorted_view.h"
#include "varsfm/image/scratch_image.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/progress.h"
#include "varsfm/util/scratch_memory.h"
#include "varsfm/util/timer.h"

namespace varsfm {
namespace {

struct LoadedView {
  UndistortedView image;
  PatchMatchView patchmatch;
};

// Writes the depth (and, when given, the camera-frame normal) of each point into the pixel it
// projects to, where it is nearer than what the pixel holds.
void SplatPoints(const std::vector<Eigen::Vector3d>& points,
                 const std::vector<Eigen::Vector3d>* normals, const Eigen::Matrix3d& K,
                 const Rigid3d& cam_from_world, DepthMap* map) {
  const Eigen::Matrix3d R = cam_from_world.R();
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d camera = cam_from_world * points[i];
    if (camera.z() <= 0) continue;
    const Eigen::Vector2d x = (K * camera).hnormalized();
    if (!(x.x() >= 0 && x.y() >= 0 && x.x() < map->width && x.y() < map->height)) continue;
    const size_t j = map->Index(static_cast<int>(x.x()), static_cast<int>(x.y()));
    const float depth = static_cast<float>(camera.z());
    if (map->depth[j] > 0 && map->depth[j] <= depth) continue;
    map->depth[j] = depth;
    map->normal[j] =
        normals ? Eigen::Vector3f((R * (*normals)[i]).cast<float>()) : Eigen::Vector3f::Zero();
  }
}

// The starting depths of a view: the sparse points it observes, then the prior cloud's points
// where nearer.
DepthMap PriorDepths(const Reconstruction& rec, image_t image_id, const LoadedView& view,
                     const PointCloud* prior) {
  DepthMap map;
  map.width = view.patchmatch.gray.cols;
  map.height = view.patchmatch.gray.rows;
  map.depth.assign(static_cast<size_t>(map.width) * map.height, 0);
  map.normal.assign(map.depth.size(), Eigen::Vector3f::Zero());
  std::vector<Eigen::Vector3d> sparse;
  for (const Point2D& p : rec.image(image_id).points2D)
    if (p.HasPoint3D() && rec.ExistsPoint3D(p.point3D_id))
      sparse.push_back(rec.point3D(p.point3D_id).xyz);
  const Rigid3d& pose = view.patchmatch.cam_from_world;
  SplatPoints(sparse, nullptr, view.patchmatch.K, pose, &map);
  if (prior)
    SplatPoints(prior->points, prior->HasNormals() ? &prior->normals : nullptr, view.patchmatch.K,
                pose, &map);
  return map;
}

// Drops the depths where a covering point projects at or in front of them (5 % slack): those
// pixels are already on the surface the covering cloud stands for. A covering point behind the
// depth map's surface is occluded there and leaves the pixel to PatchMatch.
void LeaveCovered(const PointCloud& covered, FusionView* view) {
  DepthMap nearest;
  nearest.width = view->map.width;
  nearest.height = view->map.height;
  nearest.depth.assign(view->map.depth.size(), 0);
  nearest.normal.assign(view->map.depth.size(), Eigen::Vector3f::Zero());
  SplatPoints(covered.points, nullptr, view->K, view->cam_from_world, &nearest);
  ScratchArray<float>& depth = view->map.depth;
  const DepthMap& map = view->map;
  std::vector<uint8_t> drop(depth.size(), 0);
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const float d = depth[map.Index(x, y)];
      if (d <= 0) continue;
      // The covering points are sparser than the pixels: a 3x3 neighbourhood.
      for (int dy = -1; dy <= 1 && !drop[map.Index(x, y)]; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= map.width || ny >= map.height) continue;
          const float c = nearest.depth[map.Index(nx, ny)];
          if (c > 0 && c <= 1.05f * d) {
            drop[map.Index(x, y)] = 1;
            break;
          }
        }
    }
  for (size_t i = 0; i < depth.size(); ++i)
    if (drop[i]) depth[i] = 0;
}

// The planar-prior pass (planar_prior.h): the anchors are each view's depths of cost at most
// anchor_max_cost that other views confirm (FilterByGeometricConsistency), so a prior plane spans
// depths that are right, not merely photometrically plausible; every view is then re-estimated
// from its map with its prior planes. Deterministic: all priors are built before any map changes.
void PlanarPriorPass(const std::vector<PatchMatchView>& views,
                     const std::function<uint32_t(size_t)>& view_index,
                     const std::function<std::vector<uint32_t>(size_t)>& sources_of,
                     const std::function<PatchMatchInit(size_t)>& range_of,
                     const MultiViewStereoOptions& options, std::vector<FusionView>* fusion) {
  std::vector<FusionView> anchors = *fusion;
  for (FusionView& v : anchors)
    for (size_t i = 0; i < v.map.depth.size(); ++i)
      if (v.map.cost[i] > options.planar.anchor_max_cost) v.map.depth[i] = 0;
  DepthFusionOptions strict = options.fusion;
  strict.two_view_max_cost = 0;  // an anchor spans a triangle: two confirming views, always
  FilterByGeometricConsistency(&anchors, strict);
  std::vector<DepthMap> refined(fusion->size());
  Progress progress("patchmatch (planar prior)", fusion->size());
  tbb::parallel_for(size_t{0}, fusion->size(), [&](size_t r) {
    PatchMatchInit init = range_of(r);
    init.planar = BuildPlanarPrior(anchors[r].map, anchors[r].K, options.planar);
    refined[r] = RefineDepthMap(views, view_index(r), sources_of(r), {}, (*fusion)[r].map, init,
                                options.patchmatch,
                                DeriveSeed(DeriveSeed(options.seed, (*fusion)[r].image_id), 2),
                                options.planar.num_iterations);
    progress.Tick();
  });
  for (size_t r = 0; r < fusion->size(); ++r) (*fusion)[r].map = std::move(refined[r]);
}

// Moves a finished depth map into scratch memory in `folder` (none: empty); once the folder has
// no more room, the maps stay on the heap, with one warning: the run goes on as it would have
// without scratch memory.
void MoveToScratchWhileThereIsRoom(const std::filesystem::path& folder, std::atomic<bool>* full,
                                   DepthMap* map) {
  if (folder.empty() || full->load()) return;
  try {
    map->MoveToScratch(folder);
  } catch (const Error& e) {
    if (!full->exchange(true)) warn("{}: the depth maps that follow stay in RAM", e.what());
  }
}

size_t CountDepths(const std::vector<FusionView>& views) {
  size_t n = 0;
  for (const FusionView& v : views)
    n += static_cast<size_t>(
        std::count_if(v.map.depth.begin(), v.map.depth.end(), [](float d) { return d > 0; }));
  return n;
}

// The views that get a depth map: those with sources and a depth range (in `ranges`), less the
// redundant ones (reference_views.h). Throws varsfm::Error when no view has sources.
std::vector<image_t> ReferenceViews(const Reconstruction& rec,
                                    const std::map<image_t, std::vector<image_t>>& sources,
                                    const MultiViewStereoOptions& options,
                                    std::map<image_t, DepthRange>* ranges,
                                    MultiViewStereoStats* stats) {
  std::vector<image_t> candidates;
  for (const auto& [id, list] : sources) {
    const DepthRange range = SparseDepthRange(rec, id, options.sources.depth_range_percentile);
    if (range.max_depth > range.min_depth && range.min_depth > 0)
      candidates.push_back(id), (*ranges)[id] = range;
  }
  if (candidates.empty())
    Fail("densify: no registered view shares {} points with another (multi-view stereo)",
         options.sources.min_shared_points);
  std::vector<image_t> references =
      SelectReferenceViews(rec, candidates, options.references, options.fusion.min_fused_views);
  stats->num_redundant_views = candidates.size() - references.size();
  if (stats->num_redundant_views > 0)
    info("multi-view stereo: {} of {} views are redundant with the others: depth maps for {}",
         stats->num_redundant_views, candidates.size(), references.size());
  return references;
}

}  // namespace

void MultiViewStereoInto(const Reconstruction& rec,
                         const std::function<cv::Mat(image_t)>& load_image,
                         const MultiViewStereoOptions& options, const MultiViewStereoInputs& inputs,
                         const FusedPointSink& sink, MultiViewStereoStats* stats) {
  MultiViewStereoStats local;
  MultiViewStereoStats& st = stats ? *stats : local;
  st = {};
  const auto sources = SelectSourceViews(rec, options.sources);
  std::map<image_t, DepthRange> ranges;
  const std::vector<image_t> references = ReferenceViews(rec, sources, options, &ranges, &st);
  std::set<image_t> used(references.begin(), references.end());
  for (image_t id : references) used.insert(sources.at(id).begin(), sources.at(id).end());
  const std::vector<image_t> ids(used.begin(), used.end());
  std::map<image_t, uint32_t> index;
  for (size_t i = 0; i < ids.size(); ++i) index[ids[i]] = static_cast<uint32_t>(i);

  Timer timer;
  std::vector<LoadedView> views(ids.size());
  std::filesystem::path scratch = options.scratch_folder;
  if (!scratch.empty() && !ScratchFolderUsable(scratch, "the views' photos and depth maps"))
    scratch.clear();
  std::atomic<bool> scratch_full = false;
  tbb::parallel_for(size_t{0}, ids.size(), [&](size_t i) {
    LoadedView& v = views[i];
    v.image = UndistortAtMostSize(load_image(ids[i]), rec.CameraOf(ids[i]), options.max_image_size);
    v.image.gray.convertTo(v.patchmatch.gray, CV_32F, 1.0 / 255.0);
    v.image.gray.release();  // PatchMatch reads the floating-point copy
    if (!scratch.empty()) {
      v.image.color = CopyToScratch(v.image.color, scratch);
      v.patchmatch.gray = CopyToScratch(v.patchmatch.gray, scratch);
    }
    v.patchmatch.K = v.image.K;
    v.patchmatch.cam_from_world = rec.image(ids[i]).cam_from_world;
  });
  std::vector<PatchMatchView> patchmatch_views;
  for (const LoadedView& v : views) patchmatch_views.push_back(v.patchmatch);
  st.seconds_undistort = timer.Seconds();
  timer.Restart();

  std::vector<FusionView> fusion(references.size());
  {
    const std::vector<std::vector<uint32_t>> overlapping =
        OverlappingViews(rec, references, options.fusion.max_overlapping_views);
    for (size_t r = 0; r < references.size(); ++r) fusion[r].overlapping = overlapping[r];
  }
  const bool geometric = options.patchmatch.num_geometric_iterations > 0;
  const bool planar = options.planar.num_iterations > 0;
  const auto source_indices = [&](image_t id) {
    std::vector<uint32_t> indices;
    for (image_t s : sources.at(id)) indices.push_back(index.at(s));
    return indices;
  };
  const auto depth_range = [&](image_t id) {
    PatchMatchInit init;
    init.min_depth = static_cast<float>(ranges.at(id).min_depth);
    init.max_depth = static_cast<float>(ranges.at(id).max_depth);
    return init;
  };
  {
    Progress progress("patchmatch", references.size());
    tbb::parallel_for(size_t{0}, references.size(), [&](size_t r) {
      const image_t id = references[r];
      const LoadedView& view = views[index.at(id)];
      PatchMatchInit init = depth_range(id);
      init.prior = PriorDepths(rec, id, view, inputs.prior);
      FusionView& f = fusion[r];
      // A later pass starts from every first-pass hypothesis, the uncertain ones included.
      f.map =
          EstimateDepthMap(patchmatch_views, index.at(id), source_indices(id), init,
                           options.patchmatch, DeriveSeed(options.seed, id), !geometric && !planar);
      f.image_id = id;
      f.K = view.patchmatch.K;
      f.cam_from_world = view.patchmatch.cam_from_world;
      f.color = view.image.color;
      if (!geometric && !planar) MoveToScratchWhileThereIsRoom(scratch, &scratch_full, &f.map);
      progress.Tick();
    });
  }
  if (geometric) {
    // Every view's second pass reads the first-pass maps of its sources, so all of them are kept
    // until every second pass is done (and the result does not depend on the order).
    std::map<image_t, const DepthMap*> first_pass;
    for (const FusionView& f : fusion) first_pass[f.image_id] = &f.map;
    std::vector<DepthMap> refined(references.size());
    Progress progress("patchmatch (geometric)", references.size());
    tbb::parallel_for(size_t{0}, references.size(), [&](size_t r) {
      const image_t id = references[r];
      std::vector<const DepthMap*> source_maps;
      for (image_t s : sources.at(id))
        source_maps.push_back(first_pass.count(s) ? first_pass.at(s) : nullptr);
      refined[r] = RefineDepthMap(patchmatch_views, index.at(id), source_indices(id), source_maps,
                                  fusion[r].map, depth_range(id), options.patchmatch,
                                  DeriveSeed(DeriveSeed(options.seed, id), 1),
                                  options.patchmatch.num_geometric_iterations, !planar);
      progress.Tick();
    });
    for (size_t r = 0; r < references.size(); ++r) fusion[r].map = std::move(refined[r]);
  }
  if (planar)
    PlanarPriorPass(
        patchmatch_views, [&](size_t r) { return index.at(references[r]); },
        [&](size_t r) { return source_indices(references[r]); },
        [&](size_t r) { return depth_range(references[r]); }, options, &fusion);
  if (geometric || planar)
    tbb::parallel_for(size_t{0}, fusion.size(), [&](size_t r) {
      MoveToScratchWhileThereIsRoom(scratch, &scratch_full, &fusion[r].map);
    });
  // The grey images are done with; the reference views' colours live on in `fusion`.
  patchmatch_views.clear();
  views.clear();
  st.num_views = references.size();
  st.num_depths = CountDepths(fusion);
  st.seconds_patchmatch = timer.Seconds();
  timer.Restart();

  std::vector<size_t> beside_background(fusion.size(), 0);
  tbb::parallel_for(size_t{0}, fusion.size(), [&](size_t r) {
    beside_background[r] = ErodeDepthEdges(options.edges, &fusion[r].map);
  });
  for (const size_t n : beside_background) st.num_beside_background += n;
  FilterByGeometricConsistency(&fusion, options.fusion);
  st.num_consistent = CountDepths(fusion);
  if (inputs.covered)
    tbb::parallel_for(size_t{0}, fusion.size(),
                      [&](size_t r) { LeaveCovered(*inputs.covered, &fusion[r]); });
  size_t num_points = 0;
  FuseDepthMaps(fusion, options.fusion, [&](FusedPoint&& p) {
    sink(std::move(p));
    ++num_points;
  });
  st.num_points = num_points;
  st.seconds_fusion = timer.Seconds();
  info(
      "multi-view stereo: {} depth maps, {} depths ({} beside the open background dropped), {} "
      "consistent, {} fused points (undistort {:.1f} s, patchmatch {:.1f} s, fusion {:.1f} s)",
      st.num_views, st.num_depths, st.num_beside_background, st.num_consistent, st.num_points,
      st.seconds_undistort, st.seconds_patchmatch, st.seconds_fusion);
}

PointCloud MultiViewStereo(const Reconstruction& rec,
                           const std::function<cv::Mat(image_t)>& load_image,
                           const MultiViewStereoOptions& options,
                           const MultiViewStereoInputs& inputs, DenseVisibility* visibility,
                           MultiViewStereoStats* stats) {
  PointCloud cloud;
  if (visibility) visibility->clear();
  MultiViewStereoInto(rec, load_image, options, inputs, AppendTo(&cloud, visibility), stats);
  return cloud;
}

void MultiViewStereoOptions::Check() const {
  CheckAtLeast("--dense-max-image-size", max_image_size, 16);
  references.Check();
  sources.Check();
  patchmatch.Check();
  planar.Check();
  edges.Check();
  fusion.Check();
}

}  // namespace varsfm

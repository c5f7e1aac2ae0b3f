#include "varsfm/pipeline/densify.h"

#include <cstdint>
#include <optional>

#include <nlohmann/json.hpp>

#include "varsfm/dense/multi_view_stereo.h"
#include "varsfm/io/model_photo.h"
#include "varsfm/io/ply.h"
#include "varsfm/io/point_cloud_stream.h"
#include "varsfm/io/point_visibility.h"
#include "varsfm/pipeline/output_folder.h"
#include "varsfm/pipeline/scratch_choice.h"
#include "varsfm/pipeline/stage_model.h"
#include "varsfm/scene/holdout.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/even_sample.h"
#include "varsfm/util/log.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/path_lock.h"
#include "varsfm/util/scratch_memory.h"
#include "varsfm/util/timer.h"

namespace varsfm {
namespace {

// The dense points the check against the sparse model measures: evenly spread, a few thousand
// give its medians to a fraction of a per cent. A streamed cloud's even sample holds 20,000 to
// 40,000 of them (util/even_sample.h), all measured; a cloud in memory has every n-th measured,
// 20,000 at most (MeasureAgainstSparse's default).
constexpr size_t kCheckedDensePoints = 20000;

void WriteSummary(const std::filesystem::path& file, const DensifySummary& r, uint64_t seed,
                  double seconds_check) {
  const DensifyStats& st = r.stats;
  const nlohmann::json summary = {
      {"points", r.num_points},
      {"method", NameOf(kDenseMethodNames, r.method)},
      {"seed", seed},
      {"depth_maps", st.mvs.num_views},
      {"redundant_views", st.mvs.num_redundant_views},
      {"depths", st.mvs.num_depths},
      {"depths_beside_open_background", st.mvs.num_beside_background},
      {"consistent_depths", st.mvs.num_consistent},
      {"patchmatch_points", st.mvs.num_points},
      {"pairs", st.num_pairs},
      {"matches", st.num_matches},
      {"triangulated", st.num_triangulated},
      {"seconds",
       {{"undistort", st.seconds_undistort},
        {"propagation", st.seconds_propagation},
        {"fusion", st.seconds_fusion},
        {"normals", st.seconds_normals},
        {"mvs_undistort", st.mvs.seconds_undistort},
        {"patchmatch", st.mvs.seconds_patchmatch},
        {"depth_fusion", st.mvs.seconds_fusion},
        {"check", seconds_check},
        {"total", r.seconds}}},
      // Distances in units of the median camera-to-point depth of the sparse model.
      {"sparse_check",
       {{"checked_points", r.quality.num_checked},
        {"scene_depth", r.quality.scene_depth},
        {"median_distance_to_nearest_sparse_point", r.quality.median_nearest},
        {"median_distance_to_local_sparse_plane", r.quality.median_plane},
        {"fraction_within_1_percent_of_depth", r.quality.fraction_within_1pc}}}};
  WriteJsonAtomically(file, summary);
}

// Why a dense stage can end with no point: PatchMatch keeps a depth only where
// min_consistent_views other views confirm it (one, for a confident depth when two-view depths
// are on), so fewer registered images than that plus one can never give a point; with more, the
// views share too little surface.
std::string EmptyCloudMessage(const Reconstruction& rec, const DenseReconstructionOptions& dense) {
  const size_t registered = rec.NumRegisteredImages();
  if (dense.method != DenseMethod::kPropagation) {
    const DepthFusionOptions& fusion = dense.mvs.fusion;
    const int needed = fusion.FewestConfirmingViews() + 1;
    if (registered < static_cast<size_t>(needed))
      return fmt::format(
          "densify: no dense point: the model has {} registered images, and a depth is kept only "
          "where {} views agree (--dense-min-consistent {}, --dense-two-view-cost {}); add "
          "photos of the scene",
          registered, needed, fusion.min_consistent_views, fusion.two_view_max_cost);
  }
  return fmt::format(
      "densify: no dense point from {} registered images: no depth was confirmed across views "
      "(too little overlap or texture)",
      registered);
}

}  // namespace

void DensifyOptions::Check() const {
  dense.Check();
  CheckHoldout(holdout);
}

DensifySummary RunDensify(const DensifyOptions& options, OptionsCheck check) {
  if (check == OptionsCheck::kByStage) options.Check();
  OutputFolderLock output_lock(options.output);
  Timer timer;
  if (!options.workspace.empty() && !std::filesystem::exists(options.workspace))
    Fail("workspace {} does not exist", options.workspace.string());
  const Reconstruction rec =
      ReadStageModel("densify", options.sparse, options.image_dir, options.holdout, 2);

  const auto load = [&](image_t id) { return ReadModelPhoto(rec, id, options.image_dir); };
  DensifySummary result;
  result.method = options.dense.method;
  DenseReconstructionOptions dense = options.dense;
  dense.mvs.scratch_folder = ScratchFolderFor(
      options.output,
      ViewBytes(rec, dense.mvs.max_image_size, MultiViewStereoOptions::kViewBytesPerPixel),
      "densify: the views' photos and depth maps");
  // PatchMatch's points go to scratch files on the output's disk as fusion makes them, so the
  // cloud is never whole in memory (a thousand photos at 800 px make tens of millions of points);
  // the other methods' clouds are made in memory.
  std::optional<PointCloudStream> stream;
  EvenSample<Eigen::Vector3d> checked(kCheckedDensePoints);
  PointCloud cloud;
  PointVisibility visibility;
  if (StreamsPoints(dense.method)) {
    stream.emplace(NearestExistingFolder(options.output));
    DensifyInto(rec, load, dense, &result.stats, [&](FusedPoint&& p) {
      stream->Add(p.position, p.normal, p.color, p.seen_by);
      checked.Add(p.position);
    });
    result.num_points = stream->size();
  } else {
    cloud = Densify(rec, load, dense, &result.stats, &visibility);
    result.num_points = cloud.points.size();
  }
  // Checked before anything is written, so that a failed run leaves no empty dense.ply for the
  // mesh stage to pick up.
  if (result.num_points == 0) Fail("{}", EmptyCloudMessage(rec, options.dense));
  output_lock.CreateAndLock();
  RemoveOutputsAfter(options.output, ChainStage::kDensify);
  WriteOutputsTogether(options.output, ChainStage::kDensify, [&] {
    if (stream) {
      std::move(*stream).Write(options.output / "dense.ply", options.output / "dense.ply.vis");
      return;
    }
    WritePly(options.output / "dense.ply", cloud);
    WritePointVisibility(options.output / "dense.ply.vis", visibility);
  });
  Timer check_timer;
  result.quality = stream ? MeasureAgainstSparse(checked.items(), rec, 8, 2 * kCheckedDensePoints)
                          : MeasureAgainstSparse(cloud.points, rec);
  const double seconds_check = check_timer.Seconds();
  result.seconds = timer.Seconds();
  info(
      "densify: median distance to the nearest sparse point {:.4f}, to the local sparse plane "
      "{:.4f} (x median scene depth {:.3g}; {:.1f} % within 1 %)",
      result.quality.median_nearest, result.quality.median_plane, result.quality.scene_depth,
      100 * result.quality.fraction_within_1pc);
  WriteSummary(options.output / "dense_summary.json", result, options.dense.mvs.seed,
               seconds_check);
  info("densify: wrote {} points to {} in {:.1f} s", result.num_points,
       (options.output / "dense.ply").string(), result.seconds);
  return result;
}

}  // namespace varsfm

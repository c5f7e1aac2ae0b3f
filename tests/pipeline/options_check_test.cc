// Every stage's options Check(): the defaults pass, and a bad value of any kind (out of range,
// NaN, infinite) fails with one line that starts with the option's name.
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/bad_option_values.h"
#include "varsfm/pipeline/demo.h"
#include "varsfm/pipeline/evaluate.h"
#include "varsfm/pipeline/export.h"
#include "varsfm/pipeline/render.h"
#include "varsfm/pipeline/report.h"
#include "varsfm/pipeline/run.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

using testing::BadValue;
using testing::ExpectRejected;
using testing::kInf;
using testing::kNan;

// Each bad value, applied alone to `valid`, makes Check() throw OptionError naming its option.
template <typename Options>
void ExpectEachRejected(const Options& valid, const std::vector<BadValue<Options>>& bad_values) {
  ASSERT_NO_THROW(valid.Check());
  for (const BadValue<Options>& bad : bad_values) {
    Options options = valid;
    bad.spoil(options);
    const std::string message = ExpectRejected([&] { options.Check(); }, bad.option);
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(OptionsCheck, Extract) {
  ExpectEachRejected<ExtractOptions>(
      {}, {{"--max-features", [](auto& o) { o.sift.max_features = 0; }},
           {"--max-image-size", [](auto& o) { o.sift.max_image_size = -1; }},
           {"--contrast-threshold", [](auto& o) { o.sift.contrast_threshold = kNan; }},
           {"--contrast-threshold", [](auto& o) { o.sift.contrast_threshold = 0; }},
           {"edge_threshold", [](auto& o) { o.sift.edge_threshold = kInf; }},
           {"--max-frames", [](auto& o) { o.keyframes.max_frames = -1; }},
           {"blur_ratio", [](auto& o) { o.keyframes.blur_ratio = kNan; }},
           {"min_tracked", [](auto& o) { o.keyframes.min_tracked = 1.5; }},
           {"jpeg_quality", [](auto& o) { o.keyframes.jpeg_quality = 101; }},
           {"--threads", [](auto& o) { o.threads = -3; }},
           {"--memory-mb", [](auto& o) { o.memory_mb = size_t{1} << 44; }}});
}

TEST(OptionsCheck, Match) {
  ExpectEachRejected<MatchOptions>(
      {}, {{"--ratio", [](auto& o) { o.matching.max_ratio = kNan; }},
           {"--ratio", [](auto& o) { o.matching.max_ratio = 0; }},
           {"--ratio", [](auto& o) { o.matching.max_ratio = 1.5; }},
           {"max_distance", [](auto& o) { o.matching.max_distance = -kInf; }},
           {"--overlap", [](auto& o) { o.overlap = 0; }},
           {"--max-error", [](auto& o) { o.verification.max_error = kInf; }},
           {"--homography-max-error", [](auto& o) { o.verification.homography_max_error = 0; }},
           {"--min-inliers", [](auto& o) { o.verification.min_num_inliers = 0; }},
           {"confidence", [](auto& o) { o.verification.confidence = kNan; }},
           {"max_H_inlier_ratio", [](auto& o) { o.verification.max_H_inlier_ratio = -0.1; }},
           {"--threads", [](auto& o) { o.num_threads = -3; }}});
}

TEST(OptionsCheck, Map) {
  ExpectEachRejected<MapOptions>(
      {},
      {{"--local-ba-images", [](auto& o) { o.mapper.adjustment.local_ba_images = 0; }},
       {"--local-ba-max-track",
        [](auto& o) { o.mapper.adjustment.local_ba_max_track_length = -1; }},
       {"--global-ba-images", [](auto& o) { o.mapper.adjustment.first_global_ba_images = -1; }},
       {"--global-ba-growth", [](auto& o) { o.mapper.adjustment.global_ba_growth = 0.5; }},
       {"--global-ba-growth", [](auto& o) { o.mapper.adjustment.global_ba_growth = kNan; }},
       {"--global-ba-tolerance",
        [](auto& o) { o.mapper.adjustment.global_ba_function_tolerance = kNan; }},
       {"--growth-ba-tolerance",
        [](auto& o) { o.mapper.adjustment.growth_ba_function_tolerance = 0; }},
       {"--degenerate-init-global-ba",
        [](auto& o) { o.mapper.adjustment.degenerate_init_global_ba_images = -2; }},
       {"--min-correspondences", [](auto& o) { o.mapper.registration.min_correspondences = 5; }},
       {"--threads", [](auto& o) { o.mapper.num_threads = -3; }},
       {"init_min_median_angle_deg", [](auto& o) { o.mapper.init_min_median_angle_deg = kInf; }},
       {"min_matches_fraction", [](auto& o) { o.mapper.initial_pair.min_matches_fraction = kNan; }},
       {"registration_max_error_px", [](auto& o) { o.mapper.registration.max_error_px = kNan; }},
       {"min_pair_inliers", [](auto& o) { o.min_pair_inliers = 0; }}});
  MapOptions never;
  never.mapper.adjustment.global_ba_growth = 0;  // "never" is allowed
  EXPECT_NO_THROW(never.Check());
}

TEST(OptionsCheck, Densify) {
  ExpectEachRejected<DensifyOptions>(
      {},
      {{"--partners", [](auto& o) { o.dense.max_partners = 0; }},
       {"--partners", [](auto& o) { o.dense.max_partners = 11; }},
       {"--min-zncc", [](auto& o) { o.dense.propagation.min_zncc = kNan; }},
       {"--min-zncc", [](auto& o) { o.dense.propagation.min_zncc = 1.5; }},
       {"--max-image-size", [](auto& o) { o.dense.max_image_size = 0; }},
       {"--threads", [](auto& o) { o.dense.num_threads = -1; }},
       {"max_pair_angle_deg", [](auto& o) { o.dense.max_pair_angle_deg = 1; }},
       {"fusion_depth_tolerance", [](auto& o) { o.dense.fusion_depth_tolerance = kNan; }},
       {"max_epipolar_distance", [](auto& o) { o.dense.propagation.max_epipolar_distance = kInf; }},
       // PatchMatch's options (DenseReconstructionOptions::mvs), each algorithm's in turn.
       {"--dense-max-image-size", [](auto& o) { o.dense.mvs.max_image_size = 8; }},
       {"--dense-redundant-fraction",
        [](auto& o) { o.dense.mvs.references.redundant_fraction = kNan; }},
       {"--dense-redundant-fraction",
        [](auto& o) { o.dense.mvs.references.redundant_fraction = 1.5; }},
       {"--dense-redundant-other-views",
        [](auto& o) { o.dense.mvs.references.min_other_views = 1; }},
       {"--dense-redundant-max-angle",
        [](auto& o) { o.dense.mvs.references.max_view_angle_deg = 181; }},
       {"--dense-redundant-max-uncovered",
        [](auto& o) { o.dense.mvs.references.max_uncovered_fraction = kNan; }},
       {"--dense-source-views", [](auto& o) { o.dense.mvs.sources.num_source_views = 0; }},
       {"--dense-redundant-weight",
        [](auto& o) { o.dense.mvs.sources.redundant_point_weight = 1.5; }},
       {"--dense-redundant-weight",
        [](auto& o) { o.dense.mvs.sources.redundant_point_weight = kNan; }},
       {"source view covered_views", [](auto& o) { o.dense.mvs.sources.covered_views = 0; }},
       {"--dense-depth-range-percentile",
        [](auto& o) { o.dense.mvs.sources.depth_range_percentile = kNan; }},
       {"--dense-iterations", [](auto& o) { o.dense.mvs.patchmatch.num_iterations = -1; }},
       {"--dense-sigma-color", [](auto& o) { o.dense.mvs.patchmatch.sigma_color = kInf; }},
       {"--dense-sigma-spatial", [](auto& o) { o.dense.mvs.patchmatch.sigma_spatial = 0; }},
       {"--dense-window-step", [](auto& o) { o.dense.mvs.patchmatch.window_step = 8; }},
       {"--dense-window-radius", [](auto& o) { o.dense.mvs.patchmatch.window_radius = 1; }},
       {"--dense-missing-view-penalty",
        [](auto& o) { o.dense.mvs.patchmatch.missing_view_penalty = kNan; }},
       {"--dense-max-cost", [](auto& o) { o.dense.mvs.patchmatch.max_cost = -0.1; }},
       {"--dense-missing-view-penalty",
        [](auto& o) { o.dense.mvs.patchmatch.missing_view_penalty = 3; }},
       {"planar prior anchor_cell", [](auto& o) { o.dense.mvs.planar.anchor_cell = 0; }},
       {"fusion max_depth_difference",
        [](auto& o) { o.dense.mvs.fusion.max_depth_difference = kNan; }},
       {"--dense-min-views", [](auto& o) { o.dense.mvs.fusion.min_fused_views = 0; }},
       {"--dense-min-views", [](auto& o) { o.dense.mvs.fusion.min_fused_views = 52; }},
       {"fusion max_overlapping_views",
        [](auto& o) { o.dense.mvs.fusion.max_overlapping_views = 0; }},
       {"--dense-two-view-cost", [](auto& o) { o.dense.mvs.fusion.two_view_max_cost = 3; }}});
}

TEST(OptionsCheck, Mesh) {
  ExpectEachRejected<MeshOptions>(
      {}, {{"--holdout", [](auto& o) { o.holdout = 1; }},
           {"--max-points", [](auto& o) { o.surface.max_points = 0; }},
           {"--trim", [](auto& o) { o.surface.trim_factor = kNan; }},
           {"--trim", [](auto& o) { o.surface.trim_factor = -1; }},
           {"cell_spacing", [](auto& o) { o.surface.cell_spacing = kInf; }},
           {"--max-depth", [](auto& o) { o.surface.max_depth = 17; }},
           {"--threads", [](auto& o) { o.surface.num_threads = 0; }},
           {"--merge-spacing", [](auto& o) { o.surface.delaunay.merge_spacing = 0; }},
           {"--sigma", [](auto& o) { o.surface.delaunay.sigma = kNan; }},
           {"--min-component", [](auto& o) { o.surface.delaunay.min_component_fraction = 2; }},
           {"--smoothing", [](auto& o) { o.surface.delaunay.smoothing_iterations = -1; }},
           {"--max-faces", [](auto& o) { o.surface.decimation.max_faces = 2; }},
           {"--photometric-refinement", [](auto& o) { o.refinement.iterations = -1; }},
           {"--photometric-refinement", [](auto& o) { o.refinement.iterations = 11; }},
           {"--refinement-max-image-size", [](auto& o) { o.refinement_max_image_size = 10; }},
           {"quality.max_relative_distance",
            [](auto& o) { o.surface.quality.max_relative_distance = 0; }},
           {"quality.max_relative_distance",
            [](auto& o) { o.surface.quality.max_relative_distance = kNan; }},
           {"quality.min_faces_per_point",
            [](auto& o) { o.surface.quality.min_faces_per_point = 1.5; }}});
}

TEST(OptionsCheck, Texture) {
  ExpectEachRejected<TextureOptions>(
      {},
      {{"--smoothness", [](auto& o) { o.texture.selection.smoothness = kNan; }},
       {"--consensus-weight", [](auto& o) { o.texture.selection.consensus_weight = -1; }},
       {"--depth-tolerance", [](auto& o) { o.texture.selection.observation.depth_tolerance = 2; }},
       {"--min-cos", [](auto& o) { o.texture.selection.observation.min_cos_angle = -0.1; }},
       {"--padding", [](auto& o) { o.texture.padding = 65; }},
       {"--threads", [](auto& o) { o.texture.selection.observation.num_threads = -1; }},
       {"border_px", [](auto& o) { o.texture.selection.observation.border_px = kInf; }},
       {"photo_consistency.bandwidth",
        [](auto& o) { o.texture.selection.consistency.bandwidth = 0; }},
       {"exposure.min_shared_faces",
        [](auto& o) { o.texture.selection.exposure.min_shared_faces = 0; }},
       {"exposure.min_level", [](auto& o) { o.texture.selection.exposure.min_level = 0; }},
       {"exposure.max_level", [](auto& o) { o.texture.selection.exposure.max_level = 4; }},
       {"exposure.max_level",
        [](auto& o) { o.texture.selection.exposure.max_level = static_cast<float>(kNan); }},
       {"exposure.max_gain", [](auto& o) { o.texture.selection.exposure.max_gain = 0.5; }},
       {"exposure.max_gain", [](auto& o) { o.texture.selection.exposure.max_gain = kInf; }},
       {"levelling.ridge", [](auto& o) { o.texture.levelling.ridge = kNan; }},
       {"levelling.direct_max_unknowns",
        [](auto& o) { o.texture.levelling.direct_max_unknowns = -1; }},
       {"levelling.iterative_tolerance",
        [](auto& o) { o.texture.levelling.iterative_tolerance = 0; }},
       {"max_views_per_face",
        [](auto& o) { o.texture.selection.observation.max_views_per_face = 0; }},
       {"seam.strip_width", [](auto& o) { o.texture.seams.strip_width = 1; }},
       {"max_page_size", [](auto& o) { o.texture.max_page_size = 0; }}});
}

TEST(OptionsCheck, Render) {
  RenderOptions valid;
  valid.camera = "IMG_0001.jpg";
  valid.output = "view.png";
  ExpectEachRejected<RenderOptions>(valid, {{"--camera", [](auto& o) { o.camera.clear(); }},
                                            {"--output", [](auto& o) { o.output.clear(); }}});
}

TEST(OptionsCheck, Evaluate) {
  EvaluateOptions valid;
  valid.gt_dir = "gt";
  ExpectEachRejected<EvaluateOptions>(
      valid,
      {{"--inlier-threshold", [](auto& o) { o.evaluation.alignment.inlier_threshold = kNan; }},
       {"--inlier-threshold", [](auto& o) { o.evaluation.alignment.inlier_threshold = -1; }},
       {"max_trials", [](auto& o) { o.evaluation.alignment.max_trials = 0; }}});
  EvaluateOptions nothing;  // neither --gt nor --render
  EXPECT_THROW(nothing.Check(), OptionError);
  EvaluateOptions render_without_photos;
  render_without_photos.render = true;
  EXPECT_THROW(render_without_photos.Check(), OptionError);
}

// `run` checks every stage's options before the first one starts.
TEST(OptionsCheck, Run) {
  ExpectEachRejected<RunOptions>(
      {}, {{"--max-features", [](auto& o) { o.extract.sift.max_features = -1; }},
           {"--ratio", [](auto& o) { o.match.matching.max_ratio = kNan; }},
           {"--global-ba-tolerance",
            [](auto& o) { o.map.mapper.adjustment.global_ba_function_tolerance = -1; }},
           {"--min-zncc", [](auto& o) { o.dense.propagation.min_zncc = kInf; }},
           {"--trim", [](auto& o) { o.surface.trim_factor = kNan; }},
           {"--smoothness", [](auto& o) { o.texture.selection.smoothness = -kInf; }},
           {"exposure.max_gain", [](auto& o) { o.texture.selection.exposure.max_gain = kNan; }},
           {"--holdout", [](auto& o) { o.holdout = -1; }},
           // The report's, before the first stage rather than as a warning at the end.
           {"--max-points", [](auto& o) { o.report.data.max_view_points = 0; }},
           {"model.jpeg_quality", [](auto& o) { o.report.data.model.jpeg_quality = 0; }}});
}

TEST(OptionsCheck, Demo) {
  ExpectEachRejected<DemoOptions>(
      {}, {{"--images", [](auto& o) { o.scene.num_images = 2; }},
           {"--images", [](auto& o) { o.scene.num_images = 201; }},
           {"zoom", [](auto& o) { o.scene.zoom = kNan; }},
           {"k1", [](auto& o) { o.scene.k1 = kInf; }},
           {"--threads", [](auto& o) { o.run.map.mapper.num_threads = -1; }}});
}

TEST(OptionsCheck, Report) {
  ExpectEachRejected<ReportOptions>(
      {.output = "OUT"},
      {{"output", [](auto& o) { o.output.clear(); }},
       {"--max-points", [](auto& o) { o.data.max_view_points = 0; }},
       {"--thumbnail-width", [](auto& o) { o.data.thumbnail_width = 8; }},
       {"--thumbnail-width", [](auto& o) { o.data.thumbnail_width = 2048; }},
       {"thumbnail_quality", [](auto& o) { o.data.thumbnail_quality = 0; }},
       {"model.max_faces", [](auto& o) { o.data.model.max_faces = 0; }},
       {"model.max_texture_size", [](auto& o) { o.data.model.max_texture_size = 0; }},
       {"model.jpeg_quality", [](auto& o) { o.data.model.jpeg_quality = 101; }}});
}

// Export checks that its folders exist too: the valid options name this test's working folder
// as the model and a folder that is not there as the output.
TEST(OptionsCheck, Export) {
  ExpectEachRejected<ExportOptions>(
      {.model = ".", .output = "varsfm-options-check-export-not-created"},
      {{"model", [](auto& o) { o.model.clear(); }}, {"output", [](auto& o) { o.output.clear(); }}});
}

}  // namespace
}  // namespace varsfm

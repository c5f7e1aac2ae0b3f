// varsfm command-line tool: a thin layer over the library. Each subcommand parses its options
// into the options struct of one function of src/varsfm/pipeline and calls it; that function
// validates them (the struct's Check()) before any work. Every failure is one line on stderr:
// exit code 2 for a usage error (CLI11's parse errors, a bad option value), 1 for any other.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "varsfm/pipeline/demo.h"
#include "varsfm/pipeline/densify.h"
#include "varsfm/pipeline/evaluate.h"
#include "varsfm/pipeline/export.h"
#include "varsfm/pipeline/extract.h"
#include "varsfm/pipeline/map.h"
#include "varsfm/pipeline/match.h"
#include "varsfm/pipeline/mesh.h"
#include "varsfm/pipeline/render.h"
#include "varsfm/pipeline/report.h"
#include "varsfm/pipeline/run.h"
#include "varsfm/pipeline/texture.h"
#include "varsfm/util/enum_names.h"
#include "varsfm/util/error.h"
#include "varsfm/util/heap_policy.h"
#include "varsfm/util/log.h"
#include "varsfm/util/option_check.h"

namespace {

// One help text for extract's and run's option: a location's second orientation is a feature of
// its own (as in COLMAP), so the count of features may exceed the number.
constexpr const char* kMaxFeaturesHelp =
    "strongest keypoint locations kept (a location with two orientations gives two features)";

// extract's --memory-mb and run's --extract-memory-mb.
constexpr const char* kExtractMemoryHelp =
    "SIFT scale spaces in memory at once stay within this (MB; about 1.6 GB a 6-megapixel "
    "photo): fewer photos are extracted at once where one per thread would not fit, a photo "
    "larger than the first waits for room (0: half the machine's or the container's memory)";

// texture's and run's.
constexpr const char* kTextureMaxImageSizeHelp =
    "photos larger than this (longer side, px) are textured from a copy of this size, which "
    "bounds the atlas and the glb (0: full resolution)";

constexpr const char* kKeepEnclosedLongFacesHelp =
    "keep the long faces that fill a hole the views see enclosed by the surface (closes holes "
    "in weakly textured objects; their texture is poor)";

constexpr const char* kMaxHoleEdgesHelp =
    "close boundary loops of at most this many edges (0: none)";

constexpr const char* kHoleFairingHelp =
    "refine the faces that close a hole to the surface's density and fair them, so they "
    "continue a curved surface's shape (true/false)";

constexpr const char* kPhotometricRefinementHelp =
    "move the surface's vertices along their normals to where the photos agree best, this many "
    "times (0: none)";

constexpr int kUsageError = 2;

// The names an option takes for the values of an enum.
template <typename T>
using Choices = std::vector<std::pair<std::string, T>>;

template <typename T>
std::string ChoiceNames(const Choices<T>& choices) {
  std::string names;
  for (size_t i = 0; i < choices.size(); ++i) {
    if (i > 0) names += i + 1 == choices.size() ? " or " : ", ";
    names += choices[i].first;
  }
  return names;
}

// The value `text` names (case-insensitive); a CLI11 parse error (one line) for any other text.
template <typename T>
T Choose(const std::string& flag, const Choices<T>& choices, std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  for (const auto& [name, value] : choices)
    if (name == text) return value;
  throw CLI::ValidationError(flag, fmt::format("expected {}, got {}", ChoiceNames(choices), text));
}

// The choices of an enum's name table (util/enum_names.h), in its order.
template <typename T, size_t N>
Choices<T> ChoicesOf(const varsfm::EnumName<T> (&names)[N]) {
  Choices<T> choices;
  for (const auto& [value, name] : names) choices.emplace_back(name, value);
  return choices;
}

// An option that takes one of `choices` into `*target`; the help shows the current value.
template <typename T>
CLI::Option* AddChoice(CLI::App* cmd, const std::string& flag, T* target, Choices<T> choices,
                       const std::string& description) {
  std::string current;
  for (const auto& [name, value] : choices)
    if (value == *target) current = name;
  CLI::Option* option = cmd->add_option_function<std::string>(
      flag, [=](const std::string& text) { *target = Choose(flag, choices, text); },
      fmt::format("{}: {}", ChoiceNames(choices), description));
  return option->default_str(current);
}

// Unsigned options: CLI11 would wrap "-1" around to the largest value, and clamp a number too
// large for `T` to the largest without a word.
template <typename T>
CLI::Validator UnsignedRange() {
  return CLI::Validator(
      [](std::string& text) {
        T value{};
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
        return ec == std::errc() && end == text.data() + text.size()
                   ? std::string()
                   : fmt::format("expected an integer from 0 to {}, got {}",
                                 std::numeric_limits<T>::max(), text);
      },
      "");
}

// An option whose help shows its default value; an unsigned one refuses what does not fit it.
template <typename T>
CLI::Option* AddWithDefault(CLI::App* cmd, const std::string& flag, T& value,
                            const std::string& description) {
  CLI::Option* option = cmd->add_option(flag, value, description)->capture_default_str();
  if constexpr (std::is_unsigned_v<T> && !std::is_same_v<T, bool>)
    option->check(UnsignedRange<T>());
  return option;
}

// The dense method and its multi-view stereo settings (densify and run).
void AddDenseMethodOptions(CLI::App* cmd, varsfm::DenseReconstructionOptions* dense) {
  AddChoice(cmd, "--dense-method", &dense->method, ChoicesOf(varsfm::kDenseMethodNames),
            "match propagation, PatchMatch depth maps, PatchMatch started from propagation, "
            "propagation filled by PatchMatch, or both");
  AddWithDefault(cmd, "--dense-max-image-size", dense->mvs.max_image_size,
                 "PatchMatch depth map size (longer side, px)");
  AddWithDefault(cmd, "--dense-redundant-fraction", dense->mvs.references.redundant_fraction,
                 "a view gets no depth map (it stays a source and texture view) when this share "
                 "of its sparse points is seen by --dense-redundant-other-views other depth-map "
                 "views each (0 to 1; 0: every view gets one)");
  AddWithDefault(cmd, "--dense-redundant-other-views", dense->mvs.references.min_other_views,
                 "see --dense-redundant-fraction (2 to 1000)");
  AddWithDefault(cmd, "--dense-redundant-max-uncovered",
                 dense->mvs.references.max_uncovered_fraction,
                 "a view is redundant only when at most this share of its sparse points would "
                 "be left with fewer depth-map views than a fused point needs (0 to 1)");
  AddWithDefault(cmd, "--dense-redundant-max-angle", dense->mvs.references.max_view_angle_deg,
                 "other views count for a sparse point when they see it within this angle (deg) "
                 "of the view's own ray (0 to 180)");
  AddWithDefault(cmd, "--dense-source-views", dense->mvs.sources.num_source_views,
                 "PatchMatch source views per depth map (1 to 16)");
  AddWithDefault(cmd, "--dense-redundant-weight", dense->mvs.sources.redundant_point_weight,
                 "source views chosen one at a time: a sparse point two chosen sources see counts "
                 "this much for the next (0 to 1; 1: ranked by score alone)");
  AddWithDefault(cmd, "--dense-coverage-source", dense->mvs.sources.coverage_source,
                 "one more source view: the one seeing most of the sparse points no chosen "
                 "source sees, however short its baseline (true/false)");
  AddWithDefault(
      cmd, "--dense-missing-view-penalty", dense->mvs.patchmatch.missing_view_penalty,
      "a source the pixel's point falls outside of is left out of PatchMatch's cost, "
      "which pays this for each of its --dense-best-views it lacks (-1 to 2; < 0: counted "
      "as a failed match; no effect with --dense-best-views 1)");
  AddWithDefault(cmd, "--dense-best-views", dense->mvs.patchmatch.num_best_views,
                 "PatchMatch's cost is the mean of this many lowest source view costs (1 to 16; "
                 "1: a surface one source sees hidden does not lose to wrong planes)");
  AddWithDefault(cmd, "--dense-max-cost", dense->mvs.patchmatch.max_cost,
                 "PatchMatch depths of a higher cost (1 - NCC, 0 to 2) are dropped");
  AddWithDefault(cmd, "--dense-window-radius", dense->mvs.patchmatch.window_radius,
                 "PatchMatch's NCC window reaches this many pixels from its centre");
  AddWithDefault(cmd, "--dense-window-step", dense->mvs.patchmatch.window_step,
                 "PatchMatch's NCC window takes every this-many-th pixel (1 to 7)");
  AddWithDefault(cmd, "--dense-sigma-color", dense->mvs.patchmatch.sigma_color,
                 "PatchMatch's bilateral NCC weights: intensity difference (0 to 1) of half weight "
                 "at about 1.2 x this");
  AddWithDefault(cmd, "--dense-sigma-spatial", dense->mvs.patchmatch.sigma_spatial,
                 "PatchMatch's bilateral NCC weights: pixel distance from the window's centre of "
                 "about 1.2 x this has half weight");
  AddWithDefault(cmd, "--dense-min-texture", dense->mvs.patchmatch.min_ncc_variance,
                 "PatchMatch gives no depth to a pixel whose bilateral-weighted window has a "
                 "lower intensity variance (intensities 0 to 1)");
  AddWithDefault(cmd, "--dense-iterations", dense->mvs.patchmatch.num_iterations,
                 "PatchMatch iterations (red and black sweeps; at the coarsest level when "
                 "--dense-levels > 1)");
  AddWithDefault(cmd, "--dense-levels", dense->mvs.patchmatch.num_levels,
                 "PatchMatch coarse-to-fine levels (1: the depth-map size only)");
  AddWithDefault(cmd, "--dense-fine-iterations", dense->mvs.patchmatch.num_fine_iterations,
                 "PatchMatch iterations at each level started from a coarser one's planes "
                 "(--dense-levels > 1; 0: --dense-iterations)");
  AddWithDefault(cmd, "--dense-depth-range-percentile", dense->mvs.sources.depth_range_percentile,
                 "PatchMatch depth range: this percentile of a view's sparse depths to 100 minus "
                 "it, widened by a quarter (0: every sparse point)");
  AddWithDefault(cmd, "--dense-geometric-iterations",
                 dense->mvs.patchmatch.num_geometric_iterations,
                 "PatchMatch geometric-consistency pass iterations (0: none)");
  AddWithDefault(cmd, "--dense-planar-iterations", dense->mvs.planar.num_iterations,
                 "PatchMatch planar-prior pass iterations (0: none)");
  AddWithDefault(cmd, "--dense-planar-fill-flat", dense->mvs.patchmatch.planar_fill_flat,
                 "planar prior: flat windows take their prior plane (true/false)");
  AddWithDefault(
      cmd, "--dense-edge-erosion", dense->mvs.edges.erosion_px,
      "PatchMatch depths within this many pixels of the open background (no depth, reaching "
      "the image's border or covering 1 % of it: the sky past a roofline) are dropped before "
      "fusion, against foreground fattening (0 to 16; 0: none)");
  AddWithDefault(cmd, "--dense-min-consistent", dense->mvs.fusion.min_consistent_views,
                 "other views that must confirm a PatchMatch depth (geometric consistency)");
  AddWithDefault(cmd, "--dense-two-view-cost", dense->mvs.fusion.two_view_max_cost,
                 "PatchMatch depths of at most this cost need one confirming view and fuse with "
                 "two (0: none)");
  AddWithDefault(cmd, "--dense-min-views", dense->mvs.fusion.min_fused_views,
                 "views a fused PatchMatch point needs");
}

// The sparse model and its photos of the stages that read both (densify and texture).
void AddModelAndPhotosOptions(CLI::App* cmd, std::filesystem::path* sparse,
                              std::filesystem::path* image_dir) {
  cmd->add_option("--sparse", *sparse,
                  "COLMAP model folder, or its parent holding 0/, 1/, ... (model 0)")
      ->required();
  cmd->add_option("--images", *image_dir, "image folder")->required();
}

// The held-out views a stage leaves out (densify and texture; scene/holdout.h).
void AddHoldoutOption(CLI::App* cmd, int* holdout) {
  cmd->add_option("--holdout", *holdout,
                  "leave every N-th registered image (by name) out (0: none)");
}

void AddLogLevelOption(CLI::App* app) {
  static const Choices<spdlog::level::level_enum> kLevels = ChoicesOf(varsfm::kLogLevelNames);
  app->add_option_function<std::string>(
      "--log-level",
      [](const std::string& text) { spdlog::set_level(Choose("--log-level", kLevels, text)); },
      fmt::format("{} (before or after the subcommand)", ChoiceNames(kLevels)));
  app->add_flag_callback(
      "-q,--quiet", [] { spdlog::set_level(spdlog::level::warn); },
      "warnings and errors only, no progress (--log-level warn)");
}

// Mapper options shared by `map` and `run`.
void AddMapperOptions(CLI::App* cmd, varsfm::MapOptions* map) {
  auto& m = map->mapper;
  auto& a = m.adjustment;
  auto& in = m.intrinsics;
  AddWithDefault(cmd, "--local-ba-images", a.local_ba_images, "m0: images in each local BA");
  AddWithDefault(cmd, "--local-ba-max-track", a.local_ba_max_track_length,
                 "points seen by more images are held constant in local BAs (0: none)");
  AddWithDefault(cmd, "--global-ba-images", a.first_global_ba_images,
                 "M0: images registered before the first global BA (0: after every image)");
  AddWithDefault(cmd, "--global-ba-growth", a.global_ba_growth,
                 "further global BA when the model grew by this factor (0: never)");
  AddWithDefault(cmd, "--global-ba-tolerance", a.global_ba_function_tolerance,
                 "global BAs stop when an iteration lowers the cost by less than this fraction");
  AddWithDefault(cmd, "--growth-ba-tolerance", a.growth_ba_function_tolerance,
                 "the same for the global BAs as the model grows (--global-ba-growth)");
  AddWithDefault(cmd, "--two-view-filter", a.final_two_view_filter_factor,
                 "after the final BA, points of two views above this x the RMS error are removed "
                 "and the model adjusted again (0: no)");
  AddWithDefault(cmd, "--growth-ba-max-track", a.growth_ba_max_point_observations,
                 "observations per point in the global BAs as the model grows (0: all)");
  AddWithDefault(cmd, "--growth-ba-subset-images", a.growth_ba_subset_min_images,
                 "registered images from which --growth-ba-max-track applies");
  AddWithDefault(cmd, "--global-ba-iterative-images", a.global_ba_iterative_min_images,
                 "global BAs of this many images solve by conjugate gradients (0: never)");
  AddWithDefault(cmd, "--global-ba-cg-tolerance", a.global_ba_cg_tolerance,
                 "their relative residual at which conjugate gradients stop");
  AddWithDefault(cmd, "--global-ba-cg-iterations", a.global_ba_cg_max_iterations,
                 "their most conjugate-gradient iterations per step");
  AddChoice(cmd, "--global-ba-trust-region", &a.global_ba_trust_region,
            ChoicesOf(varsfm::kTrustRegionNames),
            "global BAs' steps, Powell's dogleg or Levenberg-Marquardt");
  AddWithDefault(cmd, "--degenerate-init-global-ba", a.degenerate_init_global_ba_images,
                 "after a degenerate initial pair, a global BA when this many images are in "
                 "(0: none)");
  cmd->add_flag("!--no-degenerate-focal-search", m.degenerate_init_focal_search,
                "keep the prior focal length of a degenerate initial pair (default: the one a "
                "third view fits best)");
  cmd->add_flag("!--no-final-global-ba", a.final_global_ba,
                "skip the global BA at the end (with --global-ba-images above the image count, "
                "--global-ba-growth 0 and --degenerate-init-global-ba 0: local BA only)");
  AddWithDefault(cmd, "--min-correspondences", m.registration.min_correspondences,
                 "n0: 2D-3D needed (>= 6)");
  cmd->add_flag("--refine-principal-point", in.refine_principal_point,
                "estimate the principal point per image (default: held at the centre)");
  cmd->add_flag("!--no-shared-principal-point", in.share_principal_point,
                "hold every principal point at its image centre (default: one principal point "
                "per image size and zoom band, estimated in the global adjustments)");
  AddWithDefault(cmd, "--zoom-band", in.zoom_band_focal_ratio,
                 "what is estimated per image size is shared by the photos whose focal lengths "
                 "are within this ratio (a zoom setting; 0: all photos of the size)");
  cmd->add_flag("--refine-aspect", in.refine_aspect, "estimate the aspect ratio per image");
  cmd->add_flag("--refine-skew", in.refine_skew, "estimate the skew per image");
  cmd->add_flag("!--no-distortion", in.refine_distortion, "hold k1 = k2 = 0");
  cmd->add_flag("--sequential-order", m.sequential_order,
                "register images in sequence order (video, numbered photos)");
  AddWithDefault(cmd, "--seed", m.seed, "random seed");
  AddWithDefault(
      cmd, "--threads", m.num_threads,
      "bundle adjustment threads (0: all cores; the native solver's result does not depend "
      "on it, Ceres' is reproducible with 1 only)");
  AddChoice(cmd, "--ba-solver", &m.ba_solver, ChoicesOf(varsfm::kBundleAdjustmentSolverNames),
            "bundle adjustment solver: by size, varsfm's dense Schur LM, Ceres only by size, or "
            "one of Ceres' (Schur complement each)");
  AddChoice(cmd, "--intrinsics", &in.sharing, ChoicesOf(varsfm::kIntrinsicsSharingNames),
            "every image its own camera, the focal length per image and the rest one set per "
            "image size, or one camera (per image size)");
}

// extract: photos or a video's keyframes -> cameras, images and SIFT features.
void AddExtractCommand(CLI::App* app) {
  auto options = std::make_shared<varsfm::ExtractOptions>();
  CLI::App* cmd = app->add_subcommand("extract", "SIFT features of images or video keyframes");
  cmd->add_option("--workspace", options->workspace, "workspace database (created if absent)")
      ->required();
  CLI::Option_group* input = cmd->add_option_group("input", "exactly one of --images, --video");
  input->add_option("--images", options->image_dir, "image folder (searched recursively)");
  input->add_option("--video", options->video,
                    "video; keyframes go to <workspace>_frames/<video name>/");
  input->require_option(1);
  AddWithDefault(cmd, "--max-features", options->sift.max_features, kMaxFeaturesHelp);
  AddWithDefault(cmd, "--max-image-size", options->sift.max_image_size,
                 "larger images are downscaled for extraction");
  AddWithDefault(cmd, "--contrast-threshold", options->sift.contrast_threshold,
                 "SIFT contrast threshold (OpenCV's; lower: more, weaker features)");
  AddWithDefault(
      cmd, "--max-frames", options->keyframes.max_frames,
      "at most this many video keyframes, subsampled evenly (0: as many as the motion needs)");
  AddWithDefault(cmd, "--threads", options->threads, "worker threads (0: all cores)");
  AddWithDefault(cmd, "--memory-mb", options->memory_mb, kExtractMemoryHelp);
  cmd->callback([options] { varsfm::RunExtraction(*options); });
}

// match: features -> raw matches and verified two-view geometries of image pairs.
void AddMatchCommand(CLI::App* app) {
  auto options = std::make_shared<varsfm::MatchOptions>();
  CLI::App* cmd = app->add_subcommand("match", "match features of image pairs and verify them");
  cmd->add_option("--workspace", options->workspace, "workspace database")->required();
  AddChoice(cmd, "--strategy", &options->strategy, ChoicesOf(varsfm::kMatchStrategyNames),
            fmt::format("every pair, each image with its next --overlap, its top "
                        "--retrieval-neighbors by a vocabulary tree, or retrieval above {} images",
                        varsfm::kAutoRetrievalImages));
  AddWithDefault(cmd, "--overlap", options->overlap, "sequential: each image with its next N");
  AddWithDefault(cmd, "--loop-interval", options->loop_interval,
                 "sequential: every Nth image also with its retrieved images (loop closure; 0: "
                 "none)");
  AddWithDefault(cmd, "--retrieval-neighbors", options->retrieval.num_neighbors,
                 "retrieval: each image with its top K retrieved images");
  AddWithDefault(cmd, "--query-expansion", options->retrieval.query_expansion,
                 "retrieval: best M images averaged into a second query (0: none)");
  AddChoice(cmd, "--retrieval-scoring", &options->retrieval.scoring,
            ChoicesOf(varsfm::kRetrievalScoringNames), "distance of the TF-IDF vectors");
  cmd->add_option("--vocabulary", options->vocabulary_file,
                  "vocabulary tree file: read if it exists, else trained and saved there");
  AddWithDefault(cmd, "--vocabulary-branching", options->vocabulary.branching,
                 "vocabulary tree: clusters per node");
  AddWithDefault(cmd, "--vocabulary-depth", options->vocabulary.depth, "vocabulary tree: levels");
  AddWithDefault(cmd, "--vocabulary-sample", options->vocabulary_sample,
                 "vocabulary tree: descriptors to train on");
  AddWithDefault(cmd, "--ratio", options->matching.max_ratio,
                 "Lowe's ratio test on descriptor angles");
  AddWithDefault(cmd, "--max-error", options->verification.max_error,
                 "RANSAC inlier threshold of the fundamental matrix (px, Sampson distance)");
  AddWithDefault(cmd, "--homography-max-error", options->verification.homography_max_error,
                 "RANSAC inlier threshold of the homography (px, transfer error)");
  AddWithDefault(cmd, "--min-inliers", options->verification.min_num_inliers,
                 "fewer inliers: the pair is not verified");
  AddChoice(cmd, "--ransac", &options->verification.method, ChoicesOf(varsfm::kRansacMethodNames),
            "robust estimator of F and H, the project's RANSAC with MSAC scoring: without local "
            "optimisation, or with iterated least squares (LO-RANSAC) or graph cuts (GC-RANSAC)");
  AddWithDefault(cmd, "--gc-neighbours", options->verification.mean_neighbours,
                 "gc-ransac: mean neighbours of a match in its neighbourhood graph");
  AddWithDefault(cmd, "--gc-coherence", options->verification.spatial_coherence,
                 "gc-ransac: weight of equal labels among neighbours (0 to 1)");
  cmd->add_flag("!--no-degensac", options->verification.degeneracy_recovery,
                "no DEGENSAC (plane-and-parallax recovery of F from samples on a dominant plane)");
  AddWithDefault(cmd, "--threads", options->num_threads, "worker threads (0: all cores)");
  AddWithDefault(cmd, "--commit-interval", options->commit_interval,
                 "seconds between commits: the most work a kill loses");
  AddWithDefault(cmd, "--seed", options->seed, "random seed");
  cmd->callback([options] { varsfm::RunMatching(*options); });
}

// map: features and verified matches -> sparse model (Algorithm 1) and its exports.
void AddMapCommand(CLI::App* app) {
  auto options = std::make_shared<varsfm::MapOptions>();
  CLI::App* cmd = app->add_subcommand("map", "incremental reconstruction from a workspace");
  cmd->add_option("--workspace", options->workspace, "workspace database")->required();
  cmd->add_option("--output", options->output, "output folder")->required();
  cmd->add_option("--images", options->image_dir, "image folder (for point colours)");
  AddMapperOptions(cmd, options.get());
  cmd->callback([options] { varsfm::RunMapping(*options); });
}

// run: photos or a video -> model, every stage with its defaults.
void AddRunCommand(CLI::App* app) {
  auto options = std::make_shared<varsfm::RunOptions>();
  CLI::App* cmd =
      app->add_subcommand("run", "the whole chain: extract, match, map, densify, mesh, texture");
  cmd->add_option("input", options->input, "folder of photos, or a video file")->required();
  cmd->add_option("output", options->output, "output folder")->required();
  AddChoice(cmd, "--matching", &options->matching, ChoicesOf(varsfm::kMatchStrategyNames),
            fmt::format("auto: sequential for a video, retrieval above {} images, else "
                        "exhaustive",
                        varsfm::kAutoRetrievalImages));
  AddWithDefault(cmd, "--max-features", options->extract.sift.max_features, kMaxFeaturesHelp);
  AddWithDefault(cmd, "--extract-memory-mb", options->extract.memory_mb, kExtractMemoryHelp);
  AddChoice(cmd, "--until", &options->until, ChoicesOf(varsfm::kRunStageNames),
            "the last stage run");
  AddDenseMethodOptions(cmd, &options->dense);
  AddWithDefault(cmd, "--holdout", options->holdout,
                 "keep every N-th registered image (by name) out of densify and texture, then "
                 "score the model on those views (PSNR, SSIM, coverage); 0: none");
  AddChoice(cmd, "--surface", &options->surface.method, ChoicesOf(varsfm::kSurfaceMethodNames),
            "mesh stage: visibility-based Delaunay graph cut, screened Poisson, or advancing "
            "front");
  AddWithDefault(cmd, "--max-faces", options->surface.decimation.max_faces,
                 "mesh stage: decimate to at most this many faces (0: keep all)");
  cmd->add_flag("--keep-enclosed-long-faces", options->surface.delaunay.long_faces.keep_enclosed,
                std::string("mesh stage (delaunay): ") + kKeepEnclosedLongFacesHelp);
  AddWithDefault(cmd, "--max-hole-edges", options->surface.delaunay.hole_filling.max_edges,
                 std::string("mesh stage (delaunay): ") + kMaxHoleEdgesHelp);
  AddWithDefault(cmd, "--hole-fairing", options->surface.delaunay.hole_filling.refine_and_fair,
                 std::string("mesh stage (delaunay): ") + kHoleFairingHelp);
  AddWithDefault(cmd, "--photometric-refinement", options->refinement.iterations,
                 std::string("mesh stage: ") + kPhotometricRefinementHelp);
  AddWithDefault(cmd, "--texture-max-image-size", options->texture.max_image_size,
                 std::string("texture stage: ") + kTextureMaxImageSizeHelp);
  AddMapperOptions(cmd, &options->map);
  cmd->get_option("--seed")->description(
      "random seed of every stage (matching, mapping, multi-view stereo)");
  cmd->callback([options] { varsfm::RunAll(*options); });
}

// evaluate: a COLMAP model against Strecha ground-truth cameras, and/or its renderings.
void AddEvaluateCommand(CLI::App* app) {
  auto options = std::make_shared<varsfm::EvaluateOptions>();
  CLI::App* cmd = app->add_subcommand(
      "evaluate", "accuracy against ground truth (--gt) and/or render vs. photo (--render)");
  cmd->add_option(
         "model", options->model_dir,
         "COLMAP model folder (text or binary), or its parent holding 0/, 1/, ... (model 0)")
      ->required();
  cmd->add_option("--gt", options->gt_dir, "folder of Strecha NAME.camera files");
  cmd->add_flag("--render", options->render,
                "render the textured model from every registered camera: PSNR and coverage");
  cmd->add_option("--textured", options->textured,
                  "--render: model.obj or its folder (default OUT/textured for OUT/sparse[/0])");
  cmd->add_option("--images", options->image_dir, "--render: the photos");
  cmd->add_option("--render-dir", options->render_dir, "--render: also write the renderings here");
  cmd->add_option("--json", options->json_path, "also write the report as JSON");
  cmd->add_option("--holdout", options->holdout,
                  "--render: every N-th image by name was held out (run --holdout N): report "
                  "those views apart");
  AddWithDefault(cmd, "--inlier-threshold", options->evaluation.alignment.inlier_threshold,
                 "robust alignment: centres farther than this (GT units) are outliers "
                 "(0: least squares over all)");
  cmd->callback([options] { std::fputs(varsfm::RunEvaluateCommand(*options).c_str(), stdout); });
}

// demo: a rendered synthetic scene with a zooming camera, reconstructed and evaluated.
void AddDemoCommand(CLI::App* app) {
  auto options = std::make_shared<varsfm::DemoOptions>();
  CLI::App* cmd =
      app->add_subcommand("demo", "reconstruct a built-in synthetic scene and score it");
  cmd->add_option("--output", options->output, "output folder")->required();
  AddWithDefault(cmd, "--images", options->scene.num_images, "images to render (3 to 200)");
  AddWithDefault(cmd, "--seed", options->scene.seed, "scene seed");
  AddChoice(cmd, "--until", &options->run.until, ChoicesOf(varsfm::kRunStageNames),
            "the last stage run");
  cmd->callback([options] { varsfm::RunDemo(*options); });
}

// densify: sparse model + photos -> dense coloured point cloud by match propagation.
void AddDensifyCommand(CLI::App* app) {
  auto options = std::make_shared<varsfm::DensifyOptions>();
  CLI::App* cmd = app->add_subcommand(
      "densify", "dense point cloud by match propagation and/or PatchMatch depth maps");
  cmd->add_option("--workspace", options->workspace, "workspace database (optional)");
  AddModelAndPhotosOptions(cmd, &options->sparse, &options->image_dir);
  cmd->add_option("--output", options->output, "output folder (dense.ply)")->required();
  AddWithDefault(cmd, "--max-image-size", options->dense.max_image_size, "matching image size");
  AddWithDefault(cmd, "--partners", options->dense.max_partners, "partners per image (1 to 10)");
  AddWithDefault(cmd, "--min-zncc", options->dense.propagation.min_zncc,
                 "ZNCC threshold (-1 to 1)");
  AddHoldoutOption(cmd, &options->holdout);
  AddWithDefault(cmd, "--threads", options->dense.num_threads, "threads (0: all cores)");
  AddDenseMethodOptions(cmd, &options->dense);
  AddWithDefault(cmd, "--seed", options->dense.mvs.seed, "random seed (PatchMatch)");
  cmd->callback([options] { varsfm::RunDensify(*options); });
}

// mesh: dense oriented point cloud -> surface mesh with vertex colours (mesh.ply).
void AddMeshCommand(CLI::App* app) {
  auto options = std::make_shared<varsfm::MeshOptions>();
  CLI::App* cmd = app->add_subcommand("mesh", "surface mesh from a dense point cloud");
  cmd->add_option("--input", options->input, "point cloud PLY (dense.ply)")->required();
  cmd->add_option("--output", options->output, "output folder (mesh.ply)")->required();
  cmd->add_option("--sparse", options->sparse,
                  "delaunay: the sparse model whose cameras see the points of INPUT.vis "
                  "(default: INPUT's folder/sparse)");
  AddWithDefault(cmd, "--holdout", options->holdout,
                 "delaunay: every N-th registered image (by name) does not judge the long faces, "
                 "as densify --holdout N left it out (0: none)");
  AddChoice(cmd, "--method", &options->surface.method, ChoicesOf(varsfm::kSurfaceMethodNames),
            "visibility-based Delaunay graph cut, screened Poisson, or advancing front");
  AddWithDefault(cmd, "--max-depth", options->surface.max_depth,
                 "screened Poisson: largest octree depth (the depth follows the cloud)");
  AddWithDefault(cmd, "--threads", options->surface.num_threads,
                 "screened Poisson threads (the mesh is reproducible for a fixed count)");
  AddWithDefault(cmd, "--max-points", options->surface.max_points,
                 "afront: downsample above this many points");
  AddWithDefault(cmd, "--max-read-points", options->max_read_points,
                 "read a larger cloud merged per voxel to this many points (0: as many as half "
                 "of 3/4 of the machine's or the container's memory holds, ~256 bytes each)");
  AddWithDefault(cmd, "--trim", options->surface.trim_factor,
                 "Poisson: drop faces farther than this x point spacing from the data (0: keep)");
  varsfm::DelaunaySurfaceOptions& delaunay = options->surface.delaunay;
  AddWithDefault(cmd, "--merge-spacing", delaunay.merge_spacing,
                 "delaunay: merge points within this x the cloud's average spacing");
  AddWithDefault(
      cmd, "--max-merged-points", delaunay.max_merged_points,
      "delaunay: merge more coarsely where merge-spacing leaves more points than this "
      "(0: as many as 3/4 of the machine's or the container's memory holds, ~1.5 KB each)");
  AddWithDefault(cmd, "--max-edge-factor", delaunay.long_faces.max_edge_factor,
                 "delaunay: drop faces with an edge above this x the median edge (0: keep)");
  cmd->add_flag("--keep-enclosed-long-faces", delaunay.long_faces.keep_enclosed,
                std::string("delaunay: ") + kKeepEnclosedLongFacesHelp);
  AddWithDefault(cmd, "--max-hole-edges", delaunay.hole_filling.max_edges,
                 std::string("delaunay: ") + kMaxHoleEdgesHelp);
  AddWithDefault(cmd, "--hole-fairing", delaunay.hole_filling.refine_and_fair,
                 std::string("delaunay: ") + kHoleFairingHelp);
  AddWithDefault(cmd, "--smoothing", delaunay.smoothing_iterations,
                 "delaunay: Taubin smoothing passes (0: vertices stay on the data)");
  AddWithDefault(cmd, "--max-faces", options->surface.decimation.max_faces,
                 "decimate to at most this many faces (quadric edge collapse; 0: keep all)");
  AddWithDefault(cmd, "--photometric-refinement", options->refinement.iterations,
                 std::string(kPhotometricRefinementHelp) + " (with --images)");
  cmd->add_option("--images", options->image_dir,
                  "the photos' folder, for the photometric refinement (none without it)");
  AddWithDefault(cmd, "--refinement-max-image-size", options->refinement_max_image_size,
                 "photometric refinement: the photos' longer side, in pixels, at most");
  cmd->callback([options] { varsfm::RunMesh(*options); });
}

// texture: mesh + sparse model + photos -> textured OBJ (atlas PNG) and binary glTF.
void AddTextureCommand(CLI::App* app) {
  auto options = std::make_shared<varsfm::TextureOptions>();
  varsfm::TextureMappingOptions& t = options->texture;
  CLI::App* cmd = app->add_subcommand("texture", "texture a mesh from the registered photos");
  cmd->add_option("--mesh", options->mesh, "mesh PLY (mesh.ply)")->required();
  AddModelAndPhotosOptions(cmd, &options->sparse, &options->image_dir);
  cmd->add_option("--output", options->output, "output folder (textured/, model.glb)")->required();
  AddWithDefault(cmd, "--smoothness", t.selection.smoothness,
                 "Potts weight grouping faces into charts (0: best image per face)");
  AddWithDefault(cmd, "--consensus-weight", t.selection.consensus_weight,
                 "data term: weight of a view's colour distance from the other views' consensus");
  AddWithDefault(cmd, "--depth-tolerance", t.selection.observation.depth_tolerance,
                 "visibility: a face is occluded when the mesh is nearer by this fraction");
  AddWithDefault(cmd, "--min-cos", t.selection.observation.min_cos_angle,
                 "faces seen more obliquely than acos(this) are not textured from a view");
  cmd->add_flag("!--no-photo-consistency", t.selection.consistency.enabled,
                "keep views whose colour of a face disagrees with the other views'");
  AddWithDefault(cmd, "--consistency-bandwidth", t.selection.consistency.bandwidth,
                 "photo-consistency: mean-shift bandwidth in grey levels");
  cmd->add_flag("!--no-exposure-gain", t.selection.exposure.enabled, "no per-photo exposure gains");
  cmd->add_flag("!--no-levelling", t.levelling.enabled, "no colour levelling across seams");
  AddWithDefault(cmd, "--padding", t.padding, "photo pixels kept around each chart (0 to 64)");
  AddWithDefault(cmd, "--max-image-size", t.max_image_size, kTextureMaxImageSizeHelp);
  AddHoldoutOption(cmd, &options->holdout);
  AddWithDefault(cmd, "--threads", t.selection.observation.num_threads, "threads (0: all cores)");
  cmd->callback([options] { varsfm::RunTexture(*options); });
}

// render: the textured model seen from a registered camera (software rasteriser).
void AddRenderCommand(CLI::App* app) {
  auto options = std::make_shared<varsfm::RenderOptions>();
  CLI::App* cmd =
      app->add_subcommand("render", "render the textured model from a registered camera");
  cmd->add_option("--model", options->model, "output folder of texture (OUT)")->required();
  cmd->add_option("--camera", options->camera, "image name in the sparse model")->required();
  cmd->add_option("--output", options->output, "image file to write (PNG)")->required();
  cmd->add_option("--sparse", options->sparse, "COLMAP model folder (default OUT/sparse: model 0)");
  cmd->add_option("--textured", options->textured,
                  "model.obj or its folder (default OUT/textured)");
  cmd->add_flag("--mask", options->write_mask, "also write NAME_mask.png (255: mesh covers)");
  cmd->add_option("--panel", options->panel_image_dir,
                  "the photos' folder: write photo | rendering | shaded mesh side by side");
  cmd->callback([options] { varsfm::RunRender(*options); });
}

// report: OUT/report.html, one offline page showing what a run made (run writes it too).
void AddReportCommand(CLI::App* app) {
  auto options = std::make_shared<varsfm::ReportOptions>();
  CLI::App* cmd = app->add_subcommand("report", "write OUT/report.html from a run's outputs");
  cmd->add_option("output", options->output, "output folder of run (or map)")->required();
  cmd->add_option("--images", options->data.image_dir,
                  "the photos, for thumbnails (default: where the run read them)");
  cmd->add_option("--three-js", options->three_js_dir,
                  "three.js folder (default: $VARSFM_THREE_JS_DIR, else Debian's libjs-three)");
  AddWithDefault(cmd, "--max-points", options->data.max_view_points, "points shown in the 3D view");
  AddWithDefault(cmd, "--thumbnail-width", options->data.thumbnail_width,
                 "thumbnail width (px, 16 to 1024)");
  cmd->add_flag("!--no-model", options->data.embed_model,
                "leave OUT/model.glb out of the page (smaller file, no textured model)");
  cmd->callback([options] { varsfm::RunReport(*options); });
}

// export: the model and photos in the layout of 3D Gaussian Splatting or nerfstudio.
void AddExportCommand(CLI::App* app) {
  auto options = std::make_shared<varsfm::ExportOptions>();
  CLI::App* cmd = app->add_subcommand(
      "export", "write the model for 3D Gaussian Splatting (3dgs) or nerfstudio");
  AddChoice(cmd, "--format", &options->format, ChoicesOf(varsfm::kExportFormatNames),
            "the layout written");
  cmd->add_option("model", options->model, "output folder of run/map, or a COLMAP model folder")
      ->required();
  cmd->add_option("output", options->output, "folder to create")->required();
  cmd->add_option("--images", options->image_dir,
                  "the photos (default: where the run that made the model read them)");
  cmd->add_flag("!--keep-principal-point", options->centre_principal_point,
                "3dgs: keep each photo's principal point where it is and every pixel (for "
                "trainers that read cx, cy) instead of cutting the photo around it");
  cmd->callback([options] { varsfm::RunExport(*options); });
}

// CLI11's parse errors as one line (its default adds "Run with --help for more information.").
std::string OneLineFailure(const CLI::App*, const CLI::Error& e) {
  std::string message = e.what();
  std::replace(message.begin(), message.end(), '\n', ' ');
  return fmt::format("varsfm: error: {}\n", message);
}

}  // namespace

int main(int argc, char** argv) {
  varsfm::KeepFreedMemoryForReuse();
  spdlog::set_level(spdlog::level::info);
  spdlog::set_pattern("[%H:%M:%S] %^%l%$ %v");
  CLI::App app{"varsfm: structure from motion for cameras with varying intrinsics"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "varsfm 0.1.0");
  app.failure_message(OneLineFailure);
  // `varsfm run IN OUT --quiet` as well as `varsfm --quiet run IN OUT`: a subcommand passes the
  // options it does not know to the main command. Set before the subcommands, which inherit it.
  app.fallthrough();
  AddLogLevelOption(&app);
  AddExtractCommand(&app);
  AddMatchCommand(&app);
  AddMapCommand(&app);
  AddRunCommand(&app);
  AddEvaluateCommand(&app);
  AddDemoCommand(&app);
  AddDensifyCommand(&app);
  AddMeshCommand(&app);
  AddTextureCommand(&app);
  AddRenderCommand(&app);
  AddReportCommand(&app);
  AddExportCommand(&app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // --help and --version print and exit 0
    return code == 0 ? 0 : kUsageError;
  } catch (const varsfm::OptionError& e) {
    std::fprintf(stderr, "varsfm: error: %s\n", e.what());
    return kUsageError;
  } catch (const varsfm::Error& e) {
    std::fprintf(stderr, "varsfm: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "varsfm: unexpected error: %s\n", e.what());
    return 1;
  }
  return 0;
}

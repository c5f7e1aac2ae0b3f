// varsfm command-line tool: a thin layer over the library. Each subcommand parses its options
// and calls one function of src/varsfm/pipeline; a varsfm::Error becomes one line on stderr and
// exit code 1, a usage error exit code 2 (CLI11's own codes for parse errors).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <string>

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
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"

namespace {

void SetLogLevel(const std::string& level) {
  spdlog::set_level(spdlog::level::from_str(level));
  spdlog::set_pattern("[%H:%M:%S] %^%l%$ %v");
}

// Mapper options shared by `map` and `run`.
void AddMapperOptions(CLI::App* cmd, varsfm::MapOptions* map) {
  auto& m = map->mapper;
  cmd->add_option("--local-ba-images", m.local_ba_images, "m0: images in each local BA")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--local-ba-max-track", m.local_ba_max_track_length,
                  "points seen by more images are held constant in local BAs (0: none)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--global-ba-images", m.first_global_ba_images,
                  "M0: images registered before the first global BA (0: after every image)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--global-ba-growth", m.global_ba_growth,
                  "further global BA when the model grew by this factor (0: never)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--global-ba-tolerance", m.global_ba_function_tolerance,
                  "global BAs stop when an iteration lowers the cost by less than this fraction")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--growth-ba-tolerance", m.growth_ba_function_tolerance,
                  "the same for the global BAs as the model grows (--global-ba-growth)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  static const std::map<std::string, varsfm::BundleAdjustmentOptions::TrustRegion> kRegions = {
      {"dogleg", varsfm::BundleAdjustmentOptions::TrustRegion::kDogleg},
      {"lm", varsfm::BundleAdjustmentOptions::TrustRegion::kLevenbergMarquardt}};
  cmd->add_option("--global-ba-trust-region", m.global_ba_trust_region,
                  "global BAs' steps: dogleg (Powell's) | lm (Levenberg-Marquardt)")
      ->transform(CLI::CheckedTransformer(kRegions, CLI::ignore_case))
      ->capture_default_str();
  cmd->add_option("--degenerate-init-global-ba", m.degenerate_init_global_ba_images,
                  "after a degenerate initial pair, a global BA when this many images are in "
                  "(0: none)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("!--no-degenerate-focal-search", m.degenerate_init_focal_search,
                "keep the prior focal length of a degenerate initial pair (default: the one a "
                "third view fits best)");
  cmd->add_flag("!--no-final-global-ba", m.final_global_ba,
                "skip the global BA at the end (with --global-ba-images above the image count, "
                "--global-ba-growth 0 and --degenerate-init-global-ba 0: local BA only)");
  cmd->add_option("--min-correspondences", m.min_correspondences, "n0: 2D-3D needed (>= 6)")
      ->capture_default_str()
      ->check(CLI::Range(6, 1000000));
  cmd->add_flag("--refine-principal-point", m.refine_principal_point,
                "estimate the principal point per image (default: held at the centre)");
  cmd->add_flag("!--no-shared-principal-point", m.share_principal_point,
                "hold every principal point at its image centre (default: one principal point "
                "per image size, estimated in the global adjustments)");
  cmd->add_flag("--refine-aspect", m.refine_aspect, "estimate the aspect ratio per image");
  cmd->add_flag("--refine-skew", m.refine_skew, "estimate the skew per image");
  cmd->add_flag("!--no-distortion", m.refine_distortion, "hold k1 = k2 = 0");
  cmd->add_flag("--sequential-order", m.sequential_order,
                "register images in sequence order (video, numbered photos)");
  cmd->add_option("--seed", m.seed, "random seed")->capture_default_str();
  cmd->add_option(
         "--threads", m.num_threads,
         "bundle adjustment threads (0: all cores; the native solver's result does not depend "
         "on it, Ceres' is reproducible with 1 only)")
      ->capture_default_str();
  using Solver = varsfm::BundleAdjustmentOptions::Solver;
  static const std::map<std::string, Solver> kSolvers = {
      {"auto", Solver::kAuto},
      {"native", Solver::kNativeDenseSchur},
      {"ceres", Solver::kCeresAuto},
      {"dense", Solver::kDenseSchur},
      {"sparse", Solver::kSparseSchurSuiteSparse},
      {"sparse-eigen", Solver::kSparseSchurEigen},
      {"iterative", Solver::kIterativeSchur}};
  cmd->add_option("--ba-solver", m.ba_solver,
                  "bundle adjustment solver: auto (by size) | native (varsfm's dense Schur LM) | "
                  "ceres (Ceres only, by size) | dense | sparse | sparse-eigen | iterative "
                  "(Ceres, Schur complement each)")
      ->transform(CLI::CheckedTransformer(kSolvers, CLI::ignore_case));
  static const std::map<std::string, varsfm::IntrinsicsSharing> kSharing = {
      {"per-image", varsfm::IntrinsicsSharing::kPerImage},
      {"shared", varsfm::IntrinsicsSharing::kShared},
      {"focal-per-image", varsfm::IntrinsicsSharing::kFocalPerImage}};
  cmd->add_option("--intrinsics", map->sharing,
                  "per-image (default) | focal-per-image (the rest one set per image size) | "
                  "shared (one camera)")
      ->transform(CLI::CheckedTransformer(kSharing, CLI::ignore_case));
}

}  // namespace

int main(int argc, char** argv) {
  SetLogLevel("info");
  CLI::App app{"varsfm: structure from motion for cameras with varying intrinsics"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "varsfm 0.1.0");
  app.add_option_function<std::string>("--log-level", SetLogLevel,
                                       "trace|debug|info|warn|error|off (before the subcommand)");

  // ---- Subcommands: each registers its options and a callback into the pipeline. ----

  // extract: photos or a video's keyframes -> cameras, images and SIFT features.
  varsfm::ExtractOptions extract;
  {
    CLI::App* cmd = app.add_subcommand("extract", "SIFT features of images or video keyframes");
    cmd->add_option("--workspace", extract.workspace, "workspace database (created if absent)")
        ->required();
    CLI::Option_group* input = cmd->add_option_group("input", "exactly one of --images, --video");
    input->add_option("--images", extract.image_dir, "image folder (searched recursively)");
    input->add_option("--video", extract.video,
                      "video; keyframes go to <workspace>_frames/<video name>/");
    input->require_option(1);
    cmd->add_option("--max-features", extract.sift.max_features, "strongest features kept")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--max-image-size", extract.sift.max_image_size,
                    "larger images are downscaled for extraction")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--contrast-threshold", extract.sift.contrast_threshold,
                    "SIFT contrast threshold (OpenCV's; lower: more, weaker features)")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--max-frames", extract.keyframes.max_frames, "video keyframe cap (0: none)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--threads", extract.threads, "worker threads (0: all cores)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    cmd->callback([&extract] { varsfm::RunExtraction(extract); });
  }

  // match: features -> raw matches and verified two-view geometries of image pairs.
  varsfm::MatchOptions match;
  {
    CLI::App* cmd = app.add_subcommand("match", "match features of image pairs and verify them");
    cmd->add_option("--workspace", match.workspace, "workspace database")->required();
    cmd->add_option("--strategy", match.strategy, "exhaustive | sequential")
        ->capture_default_str()
        ->check(CLI::IsMember({"exhaustive", "sequential"}));
    cmd->add_option("--overlap", match.overlap, "sequential: each image with its next N")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--ratio", match.matching.max_ratio, "Lowe's ratio test on descriptor angles")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_option("--max-error", match.verification.max_error, "RANSAC inlier threshold (px)")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--min-inliers", match.verification.min_num_inliers,
                    "fewer inliers: the pair is not verified")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--threads", match.num_threads, "worker threads (0: all cores)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--commit-interval", match.commit_interval,
                    "seconds between commits: the most work a kill loses")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--seed", match.seed, "random seed")->capture_default_str();
    cmd->callback([&match] { varsfm::RunMatching(match); });
  }

  // map: features and verified matches -> sparse model (Algorithm 1) and its exports.
  varsfm::MapOptions map;
  {
    CLI::App* cmd = app.add_subcommand("map", "incremental reconstruction from a workspace");
    cmd->add_option("--workspace", map.workspace, "workspace database")->required();
    cmd->add_option("--output", map.output, "output folder")->required();
    cmd->add_option("--images", map.image_dir, "image folder (for point colours)");
    AddMapperOptions(cmd, &map);
    cmd->callback([&map] { varsfm::RunMapping(map); });
  }

  // run: photos or a video -> model, every stage with its defaults.
  varsfm::RunOptions run;
  {
    CLI::App* cmd =
        app.add_subcommand("run", "the whole chain: extract, match, map, densify, mesh, texture");
    cmd->add_option("input", run.input, "folder of photos, or a video file")->required();
    cmd->add_option("output", run.output, "output folder")->required();
    cmd->add_option("--matching", run.matching, "auto|exhaustive|sequential")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "exhaustive", "sequential"}));
    cmd->add_option("--max-features", run.extract.sift.max_features, "strongest features kept")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--until", run.until, "last stage: sparse | dense | mesh | texture")
        ->capture_default_str()
        ->check(CLI::IsMember({"sparse", "dense", "mesh", "texture"}));
    cmd->add_option("--holdout", run.holdout,
                    "keep every N-th registered image (by name) out of densify and texture, then "
                    "score the model on those views (PSNR, SSIM, coverage); 0: none")
        ->capture_default_str();
    AddMapperOptions(cmd, &run.map);
    cmd->callback([&run] { varsfm::RunAll(run); });
  }

  // evaluate: a COLMAP model against Strecha ground-truth cameras.
  varsfm::EvaluateCommandOptions evaluate;
  {
    CLI::App* cmd = app.add_subcommand(
        "evaluate", "accuracy against ground truth (--gt) and/or render vs. photo (--render)");
    cmd->add_option(
           "model", evaluate.model_dir,
           "COLMAP model folder (text or binary), or its parent holding 0/, 1/, ... (model 0)")
        ->required();
    cmd->add_option("--gt", evaluate.gt_dir, "folder of Strecha NAME.camera files");
    cmd->add_flag("--render", evaluate.render,
                  "render the textured model from every registered camera: PSNR and coverage");
    cmd->add_option("--textured", evaluate.textured,
                    "--render: model.obj or its folder (default OUT/textured for OUT/sparse[/0])");
    cmd->add_option("--images", evaluate.image_dir, "--render: the photos");
    cmd->add_option("--render-dir", evaluate.render_dir,
                    "--render: also write the renderings here");
    cmd->add_option("--json", evaluate.json_path, "also write the report as JSON");
    cmd->add_option("--holdout", evaluate.holdout,
                    "--render: every N-th image by name was held out (run --holdout N): report "
                    "those views apart");
    cmd->add_option("--inlier-threshold", evaluate.evaluation.alignment.inlier_threshold,
                    "robust alignment: centres farther than this (GT units) are outliers "
                    "(0: least squares over all)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    cmd->callback(
        [&evaluate] { std::fputs(varsfm::RunEvaluateCommand(evaluate).c_str(), stdout); });
  }

  // demo: a rendered synthetic scene with a zooming camera, reconstructed and evaluated.
  varsfm::DemoOptions demo;
  {
    CLI::App* cmd =
        app.add_subcommand("demo", "reconstruct a built-in synthetic scene and score it");
    cmd->add_option("--output", demo.output, "output folder")->required();
    cmd->add_option("--images", demo.scene.num_images, "images to render")
        ->capture_default_str()
        ->check(CLI::Range(3, 200));
    cmd->add_option("--seed", demo.scene.seed, "scene seed")->capture_default_str();
    cmd->add_option("--until", demo.run.until, "last stage: sparse | dense | mesh | texture")
        ->capture_default_str()
        ->check(CLI::IsMember({"sparse", "dense", "mesh", "texture"}));
    cmd->callback([&demo] { varsfm::RunDemo(demo); });
  }

  // densify: sparse model + photos -> dense coloured point cloud by match propagation.
  varsfm::DensifyCommandOptions densify;
  {
    CLI::App* cmd = app.add_subcommand("densify", "quasi-dense point cloud by match propagation");
    cmd->add_option("--workspace", densify.workspace, "workspace database (optional)");
    cmd->add_option("--sparse", densify.sparse,
                    "COLMAP model folder, or its parent holding 0/, 1/, ... (model 0)")
        ->required();
    cmd->add_option("--images", densify.image_dir, "image folder")->required();
    cmd->add_option("--output", densify.output, "output folder (dense.ply)")->required();
    cmd->add_option("--max-image-size", densify.dense.max_image_size, "matching image size")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--partners", densify.dense.max_partners, "partners per image")
        ->capture_default_str()
        ->check(CLI::Range(1, 10));
    cmd->add_option("--min-zncc", densify.dense.propagation.min_zncc, "ZNCC threshold")
        ->capture_default_str()
        ->check(CLI::Range(-1.0, 1.0));
    cmd->add_option("--holdout", densify.holdout,
                    "leave every N-th registered image (by name) out (0: none)");
    cmd->add_option("--threads", densify.dense.num_threads, "threads (0: all cores)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    cmd->callback([&densify] { varsfm::RunDensify(densify); });
  }

  // mesh: dense oriented point cloud -> surface mesh with vertex colours (mesh.ply).
  varsfm::MeshCommandOptions mesh;
  {
    CLI::App* cmd = app.add_subcommand("mesh", "surface mesh from a dense point cloud");
    cmd->add_option("--input", mesh.input, "point cloud PLY (dense.ply)")->required();
    cmd->add_option("--output", mesh.output, "output folder (mesh.ply)")->required();
    cmd->add_option_function<std::string>(
           "--method",
           [&mesh](const std::string& m) { mesh.surface.method = varsfm::ParseSurfaceMethod(m); },
           "poisson (screened, default) | afront")
        ->check(CLI::IsMember({"poisson", "afront"}));
    cmd->add_option("--max-depth", mesh.surface.max_depth,
                    "screened Poisson: largest octree depth (the depth follows the cloud)")
        ->capture_default_str()
        ->check(CLI::Range(1, 16));
    cmd->add_option("--threads", mesh.surface.num_threads,
                    "screened Poisson threads (the mesh is reproducible for a fixed count)")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--max-points", mesh.surface.max_points,
                    "afront: downsample above this many points")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--trim", mesh.surface.trim_factor,
                    "Poisson: drop faces farther than this x point spacing from the data (0: keep)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    cmd->callback([&mesh] { varsfm::RunMesh(mesh); });
  }

  // texture: mesh + sparse model + photos -> textured OBJ (atlas PNG) and binary glTF.
  varsfm::TextureCommandOptions texture;
  {
    CLI::App* cmd = app.add_subcommand("texture", "texture a mesh from the registered photos");
    cmd->add_option("--mesh", texture.mesh, "mesh PLY (mesh.ply)")->required();
    cmd->add_option("--sparse", texture.sparse,
                    "COLMAP model folder, or its parent holding 0/, 1/, ... (model 0)")
        ->required();
    cmd->add_option("--images", texture.image_dir, "image folder")->required();
    cmd->add_option("--output", texture.output, "output folder (textured/, model.glb)")->required();
    cmd->add_option("--smoothness", texture.texture.selection.smoothness,
                    "Potts weight grouping faces into charts (0: best image per face)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--depth-tolerance", texture.texture.selection.depth_tolerance,
                    "visibility: a face is occluded when the mesh is nearer by this fraction")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_option("--min-cos", texture.texture.selection.min_cos_angle,
                    "faces seen more obliquely than acos(this) are not textured from a view")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_option("--padding", texture.texture.padding, "photo pixels kept around each chart")
        ->capture_default_str()
        ->check(CLI::Range(0, 64));
    cmd->add_option("--holdout", texture.holdout,
                    "leave every N-th registered image (by name) out (0: none)");
    cmd->add_option("--threads", texture.texture.selection.num_threads, "threads (0: all cores)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    cmd->callback([&texture] { varsfm::RunTexture(texture); });
  }

  // render: the textured model seen from a registered camera (software rasteriser).
  varsfm::RenderCommandOptions render;
  {
    CLI::App* cmd =
        app.add_subcommand("render", "render the textured model from a registered camera");
    cmd->add_option("--model", render.model, "output folder of texture (OUT)")->required();
    cmd->add_option("--camera", render.camera, "image name in the sparse model")->required();
    cmd->add_option("--output", render.output, "image file to write (PNG)")->required();
    cmd->add_option("--sparse", render.sparse, "COLMAP model folder (default OUT/sparse: model 0)");
    cmd->add_option("--textured", render.textured,
                    "model.obj or its folder (default OUT/textured)");
    cmd->add_flag("--mask", render.write_mask, "also write NAME_mask.png (255: mesh covers)");
    cmd->add_option("--panel", render.panel_image_dir,
                    "the photos' folder: write photo | rendering | shaded mesh side by side");
    cmd->callback([&render] { varsfm::RunRender(render); });
  }

  // report: OUT/report.html, one offline page showing what a run made (run writes it too).
  varsfm::ReportOptions report;
  {
    CLI::App* cmd = app.add_subcommand("report", "write OUT/report.html from a run's outputs");
    cmd->add_option("output", report.output, "output folder of run (or map)")->required();
    cmd->add_option("--images", report.data.image_dir,
                    "the photos, for thumbnails (default: where the run read them)");
    cmd->add_option("--three-js", report.three_js_dir,
                    "three.js folder (default: $VARSFM_THREE_JS_DIR, else Debian's libjs-three)");
    cmd->add_option("--max-points", report.data.max_view_points, "points shown in the 3D view")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--thumbnail-width", report.data.thumbnail_width, "thumbnail width (px)")
        ->capture_default_str()
        ->check(CLI::Range(16, 1024));
    cmd->add_flag("!--no-model", report.data.embed_model,
                  "leave OUT/model.glb out of the page (smaller file, no textured model)");
    cmd->callback([&report] { varsfm::RunReport(report); });
  }

  // export: the model and photos in the layout of 3D Gaussian Splatting or nerfstudio.
  varsfm::ExportOptions export_options;
  std::string export_format = "3dgs";
  {
    CLI::App* cmd = app.add_subcommand(
        "export", "write the model for 3D Gaussian Splatting (3dgs) or nerfstudio");
    cmd->add_option("--format", export_format, "3dgs | nerfstudio")->capture_default_str();
    cmd->add_option("model", export_options.model,
                    "output folder of run/map, or a COLMAP model folder")
        ->required();
    cmd->add_option("output", export_options.output, "folder to create")->required();
    cmd->add_option("--images", export_options.image_dir,
                    "the photos (default: where the run that made the model read them)");
    cmd->callback([&export_options, &export_format] {
      export_options.format = varsfm::ParseExportFormat(export_format);
      varsfm::RunExport(export_options);
    });
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const varsfm::Error& e) {
    std::fprintf(stderr, "varsfm: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "varsfm: unexpected error: %s\n", e.what());
    return 1;
  }
  return 0;
}

// The surface stage scored against exact truth (issue 18's geometric check): the project's
// rendered scene (synthetic/rendered_scene.h) with its true cameras, densified, meshed by each
// surface method, and scored by eval/surface_score.h at a tolerance of 0.5 % of the extent of
// the true surface that two or more views see.
//   surface_fscore [--images 12] [--width 800] [--height 600] [--tolerance 0.005]
//                  [--dense patchmatch|propagation|seeded|fill|seeded-fill]
//                  [--edge-factors 8,0,...]
//                  [--hole-edges 100,0,...] [--hole-fairing 0,1] [--smoothing 10,0,...]
//                  [--planar-iterations 0] [--source-views 4]
//                  [--coverage-source true]
//                  [--redundant-weight 0.03] [--redundant-fraction 0.8]
//                  [--redundant-other-views 5] [--redundant-max-uncovered 0.05]
//                  [--redundant-max-angle 15]
//                  [--missing-view-penalty 0] [--max-cost 0.6]
//                  [--best-views 1] [--fusion-reprojection 1] [--fusion-depth 0.01]
//                  [--two-view-cost 0.1] [--window-radius 5] [--window-step 2]
//                  [--levels 2] [--fine-iterations 2]
//                  [--edge-erosion 4]
//                  [--seed 42] [--write-cloud FILE] [--write-samples FILE]
// --edge-factors: one Delaunay row per max_edge_factor (delaunay_surface.h; 0 keeps every face),
// --hole-edges: for each, one per hole_filling.max_edges (hole_filling.h; 0 fills none);
// --hole-fairing: for each of those, one per hole_filling.refine_and_fair (1: on);
// --smoothing: for each of those, one per smoothing_iterations (Taubin passes).
// --planar-iterations: the planar-prior pass (dense/planar_prior.h; 0, the default: none).
// --source-views, --coverage-source, --redundant-weight: the source views (dense/source_views.h);
// --redundant-fraction, --redundant-other-views, --redundant-max-uncovered, --redundant-max-angle:
// which views get a depth map (dense/reference_views.h; fraction 0: every view);
// --missing-view-penalty, --max-cost, --best-views, --window-radius, --window-step, --levels,
// --fine-iterations: PatchMatch's (patchmatch.h);
// --fusion-reprojection, --fusion-depth, --two-view-cost: fusion's (depth_fusion.h);
// --edge-erosion: the depths dropped beside the open background before fusion (depth_edges.h);
// --seed: the scene's seed (RenderedSceneOptions).
// Prints one markdown table row per method: faces, accuracy, completeness, F-score, seconds;
// each Delaunay row is followed by its surface after the photometric refinement
// (mesh/photometric_refinement.h, `mesh`'s default).
#include <cstdio>
#include <exception>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "varsfm/dense/densify.h"
#include "varsfm/eval/surface_score.h"
#include "varsfm/io/ply.h"
#include "varsfm/mesh/photometric_refinement.h"
#include "varsfm/mesh/point_grid.h"
#include "varsfm/mesh/surface.h"
#include "varsfm/mesh/surface_input.h"
#include "varsfm/synthetic/rendered_truth.h"
#include "varsfm/util/timer.h"

namespace {

// The command line: the scene, the dense and surface settings, and what to write.
struct Arguments {
  varsfm::RenderedSceneOptions options;  // the demo's scene: 800 x 600, zooming x1.6
  double tolerance = 0.005;
  varsfm::DenseReconstructionOptions dense;  // PatchMatch, the default
  std::vector<double> edge_factors = {varsfm::DelaunaySurfaceOptions().long_faces.max_edge_factor};
  std::string cloud_file;  // --write-cloud: the dense cloud as PLY, camera centres beside it
  std::vector<double> hole_edges = {
      static_cast<double>(varsfm::DelaunaySurfaceOptions().hole_filling.max_edges)};
  std::vector<double> hole_fairing = {  // 0 or 1 each
      varsfm::DelaunaySurfaceOptions().hole_filling.refine_and_fair ? 1.0 : 0.0};
  std::vector<double> smoothing = {
      static_cast<double>(varsfm::DelaunaySurfaceOptions().smoothing_iterations)};
  // --write-samples: every observed sample of the true surface, one line each: x y z, the face,
  // how many views see it, whether a dense point is within the tolerance, its distance to the
  // last mesh -- to map where completeness is lost.
  std::string samples_file;
};

Arguments ParseArguments(int argc, char** argv) {
  Arguments a;
  auto& [options, tolerance, dense, edge_factors, cloud_file, hole_edges, hole_fairing, smoothing,
         samples_file] = a;
  const auto parse_list = [](const std::string& text) {
    std::vector<double> values;
    std::stringstream list(text);
    for (std::string item; std::getline(list, item, ',');) values.push_back(std::stod(item));
    return values;
  };
  using Setter = std::function<void(const std::string&)>;
  const auto integer = [](int* target) -> Setter {
    return [target](const std::string& text) { *target = std::stoi(text); };
  };
  const auto real = [](double* target) -> Setter {
    return [target](const std::string& text) { *target = std::stod(text); };
  };
  varsfm::PatchMatchOptions& patchmatch = dense.mvs.patchmatch;
  varsfm::DepthFusionOptions& fusion = dense.mvs.fusion;
  const std::map<std::string, Setter> setters = {
      {"--images", integer(&options.num_images)},
      {"--width", integer(&options.width)},
      {"--height", integer(&options.height)},
      {"--seed", [&](const std::string& text) { options.seed = std::stoull(text); }},
      {"--tolerance", real(&tolerance)},
      {"--dense",
       [&](const std::string& text) {
         dense.method = varsfm::ValueOf(varsfm::kDenseMethodNames, text, "--dense method");
       }},
      {"--planar-iterations", integer(&dense.mvs.planar.num_iterations)},
      {"--redundant-weight", real(&dense.mvs.sources.redundant_point_weight)},
      {"--redundant-fraction", real(&dense.mvs.references.redundant_fraction)},
      {"--redundant-other-views", integer(&dense.mvs.references.min_other_views)},
      {"--redundant-max-uncovered", real(&dense.mvs.references.max_uncovered_fraction)},
      {"--redundant-max-angle", real(&dense.mvs.references.max_view_angle_deg)},
      {"--source-views", integer(&dense.mvs.sources.num_source_views)},
      {"--coverage-source",
       [&](const std::string& text) { dense.mvs.sources.coverage_source = text == "true"; }},
      {"--missing-view-penalty", real(&patchmatch.missing_view_penalty)},
      {"--best-views", integer(&patchmatch.num_best_views)},
      {"--max-cost", real(&patchmatch.max_cost)},
      {"--window-radius", integer(&patchmatch.window_radius)},
      {"--window-step", integer(&patchmatch.window_step)},
      {"--levels", integer(&patchmatch.num_levels)},
      {"--fine-iterations", integer(&patchmatch.num_fine_iterations)},
      {"--sigma-color", real(&patchmatch.sigma_color)},
      {"--fusion-reprojection", real(&fusion.max_reprojection_error)},
      {"--fusion-depth", real(&fusion.max_depth_difference)},
      {"--two-view-cost", real(&fusion.two_view_max_cost)},
      {"--edge-erosion", integer(&dense.mvs.edges.erosion_px)},
      {"--write-cloud", [&](const std::string& text) { cloud_file = text; }},
      {"--write-samples", [&](const std::string& text) { samples_file = text; }},
      {"--edge-factors", [&](const std::string& text) { edge_factors = parse_list(text); }},
      {"--hole-edges", [&](const std::string& text) { hole_edges = parse_list(text); }},
      {"--hole-fairing", [&](const std::string& text) { hole_fairing = parse_list(text); }},
      {"--smoothing", [&](const std::string& text) { smoothing = parse_list(text); }},
  };
  for (int i = 1; i < argc; i += 2) {
    const auto setter = setters.find(argv[i]);
    if (setter == setters.end())
      throw std::runtime_error(std::string("unknown option ") + argv[i] +
                               " (the options are listed at the top of bench/surface_fscore.cc)");
    if (i + 1 == argc) throw std::runtime_error(std::string(argv[i]) + " needs a value");
    setter->second(argv[i + 1]);
  }
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    auto [options, tolerance, dense, edge_factors, cloud_file, hole_edges, hole_fairing, smoothing,
          samples_file] = ParseArguments(argc, argv);
    options.focal_start = 0.8 * options.width;  // the demo's field of view at any width
    const varsfm::RenderedScene scene = varsfm::RenderSyntheticScene(options);
    const varsfm::Reconstruction rec = varsfm::SparseModelFromRenderedScene(scene);
    varsfm::Timer timer;
    varsfm::DenseVisibility visibility;
    varsfm::PointCloud cloud = varsfm::Densify(
        rec, [&](varsfm::image_t id) { return scene.images[id - 1]; }, dense, nullptr, &visibility);
    // The cameras that saw each point, which the Delaunay cut needs, as `mesh` attaches them
    // from dense.ply.vis (propagation's cloud carries them already).
    if (!cloud.HasVisibility()) varsfm::AttachVisibility(visibility, rec, &cloud);
    std::printf("%d views %dx%d, %s: %zu dense points in %.1f s\n", options.num_images,
                options.width, options.height,
                std::string(varsfm::NameOf(varsfm::kDenseMethodNames, dense.method)).c_str(),
                cloud.points.size(), timer.Seconds());
    if (!cloud_file.empty()) {
      varsfm::WritePly(cloud_file, cloud);
      std::ofstream centres(cloud_file + ".cameras.txt");
      for (size_t k = 0; k < scene.poses.size(); ++k)
        centres << scene.poses[k].Center().transpose() << '\n';
    }
    const varsfm::TriangleMesh truth = varsfm::SurfaceMesh(scene.surface);
    const auto seen = varsfm::SeenByCameras(truth, scene.cameras, scene.poses, 2);
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (const Eigen::Vector3d& p : varsfm::SampleSurface(truth, 0.05))
      if (seen(p)) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    varsfm::SurfaceScoreOptions score_options;
    score_options.tolerance = tolerance * (hi - lo).norm();
    score_options.sample_spacing = score_options.tolerance / 4;  // the per-face areas use it
    std::printf("extent %.3f, tolerance %.4f\n\n", (hi - lo).norm(), score_options.tolerance);
    std::printf("| surface | faces | accuracy | completeness | F-score | median distances | s |\n");
    std::printf("|---|---|---|---|---|---|---|\n");
    std::vector<std::pair<std::string, varsfm::SurfaceOptions>> variants(1);
    variants[0].first = "poisson";
    variants[0].second.method = varsfm::SurfaceMethod::kScreenedPoisson;
    for (double factor : edge_factors)
      for (double holes : hole_edges)
        for (double fair : hole_fairing)
          for (double passes : smoothing) {
            varsfm::SurfaceOptions& surface = variants.emplace_back().second;
            variants.back().first = "delaunay, edge factor " + std::to_string(factor).substr(0, 4) +
                                    ", holes up to " + std::to_string(static_cast<int>(holes)) +
                                    " edges" + (fair != 0 ? ", faired" : "") + ", " +
                                    std::to_string(static_cast<int>(passes)) + " smoothing passes";
            surface.method = varsfm::SurfaceMethod::kDelaunay;
            surface.delaunay.long_faces.max_edge_factor = factor;
            surface.delaunay.hole_filling.max_edges = static_cast<int>(holes);
            surface.delaunay.hole_filling.refine_and_fair = fair != 0;
            surface.delaunay.smoothing_iterations = static_cast<int>(passes);
            surface.Check();  // ReconstructSurface expects checked options
          }
    // Before it, the first Delaunay variant with the long faces in enclosed holes kept.
    if (variants.size() > 1) {
      auto kept = variants[1];
      kept.first += ", enclosed long faces kept";
      kept.second.delaunay.long_faces.keep_enclosed = true;
      variants.insert(variants.begin() + 1, kept);
    }
    // The true cameras judge the long faces (mesh/long_faces.h), as the sparse model's do.
    std::vector<varsfm::PosedCamera> views;
    for (size_t k = 0; k < scene.poses.size(); ++k)
      views.push_back({scene.cameras[k], scene.poses[k]});
    // The photos, for the photometric refinement that `mesh` runs after the surface.
    std::vector<varsfm::RefinementView> photos;
    for (size_t k = 0; k < scene.images.size(); ++k)
      photos.push_back(varsfm::RefinementViewOf(scene.images[k], views[k]));
    const varsfm::PhotometricRefinementOptions refinement;
    varsfm::TriangleMesh last_mesh;
    const auto score_row = [&](const std::string& name, const varsfm::TriangleMesh& mesh,
                               double seconds) {
      const varsfm::SurfaceScore s = varsfm::ScoreSurface(mesh, truth, score_options, seen);
      std::printf("| %s | %zu | %.3f | %.3f | %.3f | %.4f / %.4f | %.1f |\n", name.c_str(),
                  mesh.faces.size(), s.accuracy, s.completeness, s.fscore,
                  s.median_accuracy_distance, s.median_completeness_distance, seconds);
    };
    for (const auto& [name, surface] : variants) {
      timer.Restart();
      varsfm::TriangleMesh mesh = varsfm::ReconstructSurface(cloud, surface, nullptr, views);
      score_row(name, mesh, timer.Seconds());
      if (surface.method == varsfm::SurfaceMethod::kDelaunay) {
        timer.Restart();
        varsfm::RefinePhotometrically(photos, refinement, &mesh);
        score_row(name + ", then refined from the photos", mesh, timer.Seconds());
      }
      last_mesh = mesh;
    }
    // Where completeness is lost: each face of the scene (a quad of the room or a box) scored
    // alone against the last variant's mesh.
    std::printf("\nCompleteness per face of the scene (%s%s):\n\n", variants.back().first.c_str(),
                variants.back().second.method == varsfm::SurfaceMethod::kDelaunay
                    ? ", then refined from the photos"
                    : "");
    // Beside it, the dense points' own completeness (a point within the tolerance of the face's
    // sample): what the surface could have covered, so a loss is told apart as depth or surface.
    // And both on the part three or more views see, as fusion asks (DepthFusionOptions).
    const varsfm::PointGrid grid(cloud.points, score_options.tolerance);
    const auto seen3 = varsfm::SeenByCameras(truth, scene.cameras, scene.poses, 3);
    const auto seen4 = varsfm::SeenByCameras(truth, scene.cameras, scene.poses, 4);
    const varsfm::MeshDistance mesh_distance(last_mesh);
    std::ofstream samples;
    if (!samples_file.empty()) samples.open(samples_file);
    std::printf(
        "| face | centre | normal | observed area | completeness | points' completeness | area "
        "3+ views see | points' completeness there |\n|---|---|---|---|---|---|---|---|\n");
    for (size_t q = 0; q < scene.surface.size(); ++q) {
      const varsfm::SurfaceQuad& quad = scene.surface[q];
      const varsfm::TriangleMesh face = varsfm::SurfaceMesh({quad});
      const varsfm::SurfaceScore s = varsfm::ScoreSurface(last_mesh, face, score_options, seen);
      if (s.truth_samples == 0) continue;
      const Eigen::Vector3d c = quad.origin + 0.5 * (quad.u + quad.v);
      const Eigen::Vector3d n = quad.u.cross(quad.v).normalized();
      const double spacing = score_options.sample_spacing;
      size_t observed = 0, near_point = 0, observed3 = 0, near_point3 = 0;
      for (const Eigen::Vector3d& p : varsfm::SampleSurface(face, spacing, score_options.seed)) {
        if (!seen(p)) continue;
        const bool three = seen3(p);
        // The grid's cell is the tolerance: a point within one cell is within the tolerance.
        const bool near = grid.NearestWithinCell(p).has_value();
        observed += 1, observed3 += three, near_point += near, near_point3 += three && near;
        if (samples.is_open())
          samples << p.x() << ' ' << p.y() << ' ' << p.z() << ' ' << q << ' '
                  << (three ? (seen4(p) ? 4 : 3) : 2) << ' ' << near << ' ' << mesh_distance(p)
                  << '\n';
      }
      const auto share = [](size_t part, size_t whole) {
        return whole ? static_cast<double>(part) / whole : 0.0;
      };
      std::printf(
          "| %zu | (%.2f, %.2f, %.2f) | (%.2f, %.2f, %.2f) | %.2f | %.3f | %.3f | %.2f | %.3f |\n",
          q, c.x(), c.y(), c.z(), n.x(), n.y(), n.z(), s.truth_samples * spacing * spacing,
          s.completeness, share(near_point, observed), observed3 * spacing * spacing,
          share(near_point3, observed3));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "surface_fscore: %s\n", e.what());
    return 1;
  }
  return 0;
}

// Renders a long synthetic sequence for bench/scale: the project's textured scene
// (synthetic/rendered_scene.h) filmed along an orbit by a zooming camera, written as
// OUT/images/image_NNNN.png with Strecha ground truth in OUT/gt/.
//   render_sequence OUT NUM_IMAGES [WIDTH HEIGHT ARC_DEGREES ZOOM SEED]
// Defaults: 320 x 240, a 60 degree arc, zoom x1.6 over the sequence, the default seed.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>

#include "varsfm/synthetic/rendered_scene.h"

int main(int argc, char** argv) {
  if (argc < 3 || argc > 8) {
    std::fprintf(stderr,
                 "usage: %s OUT NUM_IMAGES [WIDTH HEIGHT ARC_DEGREES ZOOM SEED]\n", argv[0]);
    return 2;
  }
  try {
    const std::filesystem::path out = argv[1];
    varsfm::RenderedSceneOptions options;
    options.num_images = std::stoi(argv[2]);
    options.width = argc > 3 ? std::stoi(argv[3]) : 320;
    options.height = argc > 4 ? std::stoi(argv[4]) : 240;
    options.arc_degrees = argc > 5 ? std::stod(argv[5]) : 60.0;
    options.zoom = argc > 6 ? std::stod(argv[6]) : 1.6;
    if (argc > 7) options.seed = std::stoull(argv[7]);
    // The demo's 640 px focal length is for 800 px wide images: keep the same field of view.
    options.focal_start = 0.8 * options.width;
    varsfm::WriteRenderedScene(varsfm::RenderSyntheticScene(options), out / "images", out / "gt");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "render_sequence: %s\n", e.what());
    return 1;
  }
  return 0;
}

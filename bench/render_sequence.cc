// Renders a long synthetic sequence for bench/scale: the project's textured scene
// (synthetic/rendered_scene.h) filmed by a zooming camera, written as OUT/images/image_NNNN.png
// with Strecha ground truth in OUT/gt/.
//   render_sequence OUT NUM_IMAGES [--width 320] [--height 240] [--zoom 1.6] [--seed S]
//                   [--path orbit|street|street-and-back|photos] [--arc 60] [--step 0.1]
//                   [--jpeg QUALITY] [--supersampling 2]
// orbit: around the room corner over --arc degrees for the whole sequence (zoom x1 -> x--zoom);
// street: along a facade, --step metres per image (zoom in and out every 100 images), so that
// every point stays in view for a bounded number of images however long the sequence;
// street-and-back: along the facade for half the images and back to the start (a loop);
// photos: an unordered collection of the street (--step x NUM_IMAGES metres long) from random
// positions and directions, focal length x1 .. x--zoom at random per photo.
// --jpeg: the images are written as image_NNNN.jpg of that quality instead (as phone photos,
// for bench/sift_speed.sh).
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>

#include "varsfm/image/image_file.h"
#include "varsfm/synthetic/rendered_scene.h"

namespace {

int Usage(const char* argv0) {
  std::fprintf(stderr,
               "usage: %s OUT NUM_IMAGES [--width W] [--height H] [--zoom Z] [--seed S] "
               "[--path orbit|street|street-and-back|photos] [--arc DEGREES] [--step METRES] "
               "[--jpeg QUALITY] [--supersampling N]\n",
               argv0);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3 || argc % 2 == 0) return Usage(argv[0]);
  try {
    const std::filesystem::path out = argv[1];
    varsfm::RenderedSceneOptions options;
    options.num_images = std::stoi(argv[2]);
    options.width = 320;
    options.height = 240;
    options.arc_degrees = 60.0;
    int jpeg_quality = 0;  // 0: PNG
    for (int i = 3; i + 1 < argc; i += 2) {
      const std::string flag = argv[i], value = argv[i + 1];
      if (flag == "--width")
        options.width = std::stoi(value);
      else if (flag == "--height")
        options.height = std::stoi(value);
      else if (flag == "--zoom")
        options.zoom = std::stod(value);
      else if (flag == "--seed")
        options.seed = std::stoull(value);
      else if (flag == "--arc")
        options.arc_degrees = std::stod(value);
      else if (flag == "--jpeg")
        jpeg_quality = std::stoi(value);
      else if (flag == "--supersampling")
        options.supersampling = std::stoi(value);
      else if (flag == "--step")
        options.street_step = std::stod(value);
      else if (flag == "--path" && value == "orbit")
        options.path = varsfm::CameraPath::kOrbit;
      else if (flag == "--path" && value == "street")
        options.path = varsfm::CameraPath::kStreet;
      else if (flag == "--path" && value == "street-and-back")
        options.path = varsfm::CameraPath::kStreetAndBack;
      else if (flag == "--path" && value == "photos")
        options.path = varsfm::CameraPath::kPhotos;
      else
        return Usage(argv[0]);
    }
    // The demo's 640 px focal length is for 800 px wide images: keep the same field of view.
    options.focal_start = 0.8 * options.width;
    const varsfm::RenderedScene scene = varsfm::RenderSyntheticScene(options);
    varsfm::WriteRenderedScene(scene, out / "images", out / "gt");
    if (jpeg_quality > 0) {
      for (const auto& entry : std::filesystem::directory_iterator(out / "images")) {
        if (entry.path().extension() != ".png") continue;
        const cv::Mat pixels = varsfm::ReadImagePixels(entry.path());
        std::filesystem::path jpeg = entry.path();
        varsfm::WriteImage(jpeg.replace_extension(".jpg"), pixels, {.jpeg_quality = jpeg_quality});
        std::filesystem::remove(entry.path());
        // The ground truth is named after the image (NAME.camera).
        const std::filesystem::path gt =
            out / "gt" / (entry.path().filename().string() + ".camera");
        std::filesystem::rename(gt, out / "gt" / (jpeg.filename().string() + ".camera"));
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "render_sequence: %s\n", e.what());
    return 1;
  }
  return 0;
}

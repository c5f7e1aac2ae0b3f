#include "varsfm/synthetic/rendered_scene.h"

#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "varsfm/image/image_file.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

// A textured rectangle: origin + s * u + t * v for s, t in [0, 1].
struct TexturedQuad {
  Eigen::Vector3d origin, u, v;
  cv::Mat texture;  // CV_32FC3, BGR in [0, 255]
};

// Texture with structure at several scales: smooth colour noise plus random discs and
// rectangles, so that every part of a face has distinctive SIFT keypoints.
cv::Mat MakeTexture(int size, Rng& rng) {
  cv::Mat texture(size, size, CV_32FC3, cv::Scalar::all(0));
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int octave = 4; octave <= 64; octave *= 2) {
    cv::Mat coarse(octave, octave, CV_32FC3);
    for (int y = 0; y < octave; ++y)
      for (int x = 0; x < octave; ++x)
        coarse.at<cv::Vec3f>(y, x) = cv::Vec3f(unit(rng), unit(rng), unit(rng)) * (200.0f / 5);
    cv::Mat up;
    cv::resize(coarse, up, texture.size(), 0, 0, cv::INTER_CUBIC);
    texture += up;
  }
  cv::Mat shapes(size, size, CV_8UC3, cv::Scalar::all(0));
  for (int i = 0; i < size / 2; ++i) {
    const cv::Point centre(static_cast<int>(unit(rng) * size), static_cast<int>(unit(rng) * size));
    const cv::Scalar colour(255 * unit(rng), 255 * unit(rng), 255 * unit(rng));
    const int radius = 2 + static_cast<int>(std::pow(unit(rng), 2) * size / 24);
    if (i % 3 == 0)
      cv::rectangle(shapes, centre, centre + cv::Point(radius, radius * 2), colour, cv::FILLED);
    else
      cv::circle(shapes, centre, radius, colour, cv::FILLED, cv::LINE_AA);
  }
  cv::Mat shapes_f;
  shapes.convertTo(shapes_f, CV_32FC3);
  cv::Mat mask;
  cv::cvtColor(shapes, mask, cv::COLOR_BGR2GRAY);
  shapes_f.copyTo(texture, mask > 0);
  return texture;
}

// The visible faces of a box [c - half, c + half] standing on the floor (y down, cameras in -z).
void AddBox(const Eigen::Vector3d& c, const Eigen::Vector3d& half, int texture_size, Rng& rng,
            std::vector<TexturedQuad>* quads) {
  const Eigen::Vector3d lo = c - half, hi = c + half;
  const auto add = [&](Eigen::Vector3d o, Eigen::Vector3d u, Eigen::Vector3d v) {
    quads->push_back({o, u, v, MakeTexture(texture_size, rng)});
  };
  add({lo.x(), lo.y(), lo.z()}, {hi.x() - lo.x(), 0, 0}, {0, hi.y() - lo.y(), 0});  // front
  add({lo.x(), lo.y(), lo.z()}, {0, 0, hi.z() - lo.z()}, {0, hi.y() - lo.y(), 0});  // left
  add({hi.x(), lo.y(), lo.z()}, {0, 0, hi.z() - lo.z()}, {0, hi.y() - lo.y(), 0});  // right
  add({lo.x(), lo.y(), lo.z()}, {hi.x() - lo.x(), 0, 0}, {0, 0, hi.z() - lo.z()});  // top
}

std::vector<TexturedQuad> MakeRoomScene(Rng& rng) {
  std::vector<TexturedQuad> quads;
  const auto add = [&](Eigen::Vector3d o, Eigen::Vector3d u, Eigen::Vector3d v) {
    quads.push_back({o, u, v, MakeTexture(512, rng)});
  };
  // World: y points down, the cameras look along +z. Room corner.
  add({-2.5, -1.8, 2.0}, {7.0, 0, 0}, {0, 3.0, 0});   // back wall (z = 2)
  add({-2.5, 1.2, -2.0}, {7.0, 0, 0}, {0, 0, 4.0});   // floor (y = 1.2)
  add({-2.5, -1.8, -2.0}, {0, 0, 4.0}, {0, 3.0, 0});  // left wall (x = -2.5)
  // Two boxes standing on the floor.
  AddBox({-0.6, 0.7, 0.6}, {0.5, 0.5, 0.5}, 512, rng, &quads);
  AddBox({0.9, 0.9, 0.1}, {0.35, 0.3, 0.35}, 512, rng, &quads);
  return quads;
}

// A facade (z = 4) and the ground in front of it from x = x0 to x1, in 3 m segments with a
// box of random size in front of the facade in each; 256-pixel textures (the street is seen
// from farther than the room, and may be long).
std::vector<TexturedQuad> MakeStreetScene(double x0, double x1, Rng& rng) {
  std::vector<TexturedQuad> quads;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  constexpr double kSegment = 3.0;
  for (double x = x0; x < x1; x += kSegment) {
    quads.push_back({{x, -1.8, 4.0}, {kSegment, 0, 0}, {0, 3.0, 0}, MakeTexture(256, rng)});
    quads.push_back({{x, 1.2, 0.5}, {kSegment, 0, 0}, {0, 0, 3.5}, MakeTexture(256, rng)});
    const Eigen::Vector3d half(0.3 + 0.4 * unit(rng), 0.2 + 0.4 * unit(rng), 0.3 + 0.3 * unit(rng));
    AddBox({x + kSegment * (0.25 + 0.5 * unit(rng)), 1.2 - half.y(), 3.0 - half.z()}, half, 256,
           rng, &quads);
  }
  return quads;
}

// The quads a camera at `centre` may see: all of them for the room; for the street those
// within 12 m along it (the visible stretch is a few metres wide).
std::vector<TexturedQuad> QuadsNear(const std::vector<TexturedQuad>& quads, CameraPath path,
                                    const Eigen::Vector3d& centre) {
  if (path == CameraPath::kOrbit) return quads;
  std::vector<TexturedQuad> near;
  for (const TexturedQuad& q : quads) {
    const double a = q.origin.x(), b = (q.origin + q.u + q.v).x();
    if (std::max(a, b) > centre.x() - 12.0 && std::min(a, b) < centre.x() + 12.0)
      near.push_back(q);  // shares the texture (cv::Mat is reference-counted)
  }
  return near;
}

cv::Vec3f Bilinear(const cv::Mat& texture, double x, double y) {
  const int x0 = std::min(static_cast<int>(x), texture.cols - 2);
  const int y0 = std::min(static_cast<int>(y), texture.rows - 2);
  const float ax = static_cast<float>(x - x0), ay = static_cast<float>(y - y0);
  const cv::Vec3f* row0 = texture.ptr<cv::Vec3f>(y0);
  const cv::Vec3f* row1 = texture.ptr<cv::Vec3f>(y0 + 1);
  return (1 - ay) * ((1 - ax) * row0[x0] + ax * row0[x0 + 1]) +
         ay * ((1 - ax) * row1[x0] + ax * row1[x0 + 1]);
}

// Colour seen along a ray (nearest quad), black when nothing is hit.
cv::Vec3f Trace(const std::vector<TexturedQuad>& quads, const Eigen::Vector3d& origin,
                const Eigen::Vector3d& dir) {
  double best = std::numeric_limits<double>::infinity();
  cv::Vec3f colour(0, 0, 0);
  for (const auto& q : quads) {
    const Eigen::Vector3d n = q.u.cross(q.v);
    const double denom = n.dot(dir);
    if (std::abs(denom) < 1e-12) continue;
    const double t = n.dot(q.origin - origin) / denom;
    if (t <= 1e-6 || t >= best) continue;
    const Eigen::Vector3d p = origin + t * dir - q.origin;
    const double s = p.dot(q.u) / q.u.squaredNorm(), r = p.dot(q.v) / q.v.squaredNorm();
    if (s < 0 || s > 1 || r < 0 || r > 1) continue;
    best = t;
    colour = Bilinear(q.texture, s * (q.texture.cols - 1), r * (q.texture.rows - 1));
  }
  return colour;
}

// One photo of kPhotos: centre, aimed point and zoom fraction drawn independently of every
// other photo, so that the collection has no order.
struct RandomPhotoView {
  Eigen::Vector3d centre, target;
  double zoom_fraction = 0;
};

RandomPhotoView RandomPhotoViewpoint(double street_length, Rng& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  RandomPhotoView view;
  const double x = street_length * unit(rng);
  // The boxes stand at most 2.2 m in front of the facade (z >= 1.8): cameras stay behind z = 1.
  view.centre = Eigen::Vector3d(x, -0.9 + 1.0 * unit(rng), -1.0 + 2.0 * unit(rng));
  const double yaw = (2.0 * unit(rng) - 1.0) * 35.0 * std::numbers::pi / 180.0;
  const double depth = 4.0 - view.centre.z();
  view.target = Eigen::Vector3d(x + depth * std::tan(yaw), -0.6 + 1.5 * unit(rng), 4.0);
  view.zoom_fraction = unit(rng);
  return view;
}

}  // namespace

RenderedScene RenderSyntheticScene(const RenderedSceneOptions& o, OptionsCheck check) {
  if (check == OptionsCheck::kByStage) o.Check();
  Rng rng(o.seed);
  const bool street = o.path != CameraPath::kOrbit;
  const bool back = o.path == CameraPath::kStreetAndBack;
  const int turn = (o.num_images - 1) / 2;  // kStreetAndBack: the last image going out
  const double street_length = o.street_step * (back ? turn : o.num_images - 1);
  const std::vector<TexturedQuad> all_quads =
      street ? MakeStreetScene(-8.0, street_length + 8.0, rng) : MakeRoomScene(rng);
  RenderedScene scene;
  for (const TexturedQuad& q : all_quads) scene.surface.push_back({q.origin, q.u, q.v});
  std::uniform_real_distribution<double> jitter(-0.15, 0.15);
  for (int i = 0; i < o.num_images; ++i) {
    const double t = static_cast<double>(i) / (o.num_images - 1);
    Eigen::Vector3d centre, target;
    double zoom_fraction = t;
    if (o.path == CameraPath::kPhotos) {
      const RandomPhotoView view = RandomPhotoViewpoint(street_length, rng);
      centre = view.centre;
      target = view.target;
      zoom_fraction = view.zoom_fraction;
    } else if (street) {
      // Walking along the facade about 4 m away, looking at it slightly ahead; the path
      // meanders in height and distance (camera centres on a line would leave the rotation
      // about it out of the evaluation's similarity alignment); the zoom goes in and out with a
      // period of 100 images.
      const bool returning = back && i > turn;
      const double x = (returning ? 2 * turn + 1 - i : i) * o.street_step;
      centre = Eigen::Vector3d(x, -0.4 + 0.3 * std::sin(0.05 * i),
                               0.6 * std::sin(0.031 * i) + (returning ? 1.0 : 0.0));
      target = Eigen::Vector3d(x + (returning ? -0.8 : 0.8) + jitter(rng), 0.3 + jitter(rng), 4.0);
      zoom_fraction = 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * i / 100.0);
    } else {
      const double a = (t - 0.5) * o.arc_degrees * std::numbers::pi / 180.0;
      const double radius = 4.0;
      target = Eigen::Vector3d(0.1 + jitter(rng), 0.2 + jitter(rng), 0.8 + jitter(rng));
      centre = Eigen::Vector3d(radius * std::sin(a), -0.6 - 0.3 * std::sin(2 * a),
                               0.8 - radius * std::cos(a));
    }
    const std::vector<TexturedQuad> quads = QuadsNear(all_quads, o.path, centre);
    Camera camera =
        Camera::FromFocal(o.width, o.height, o.focal_start * (1 + zoom_fraction * (o.zoom - 1)));
    camera.camera_id = static_cast<camera_t>(i + 1);
    camera.params[Camera::kK1] = o.k1;
    const Rigid3d pose = LookAt(centre, target);
    const Eigen::Matrix3d world_from_cam = pose.R().transpose();

    cv::Mat image(o.height, o.width, CV_8UC3);
    const int ss = std::max(1, o.supersampling);
    cv::parallel_for_(cv::Range(0, o.height), [&](const cv::Range& rows) {
      for (int y = rows.start; y < rows.end; ++y) {
        for (int x = 0; x < o.width; ++x) {
          cv::Vec3f sum(0, 0, 0);
          for (int sy = 0; sy < ss; ++sy)
            for (int sx = 0; sx < ss; ++sx) {
              // varsfm pixel convention: pixel (x, y) covers [x, x+1) x [y, y+1).
              const Eigen::Vector2d pixel(x + (sx + 0.5) / ss, y + (sy + 0.5) / ss);
              const Eigen::Vector2d n = camera.ImageToNormalized(pixel);
              sum += Trace(quads, centre, world_from_cam * n.homogeneous());
            }
          sum *= 1.0f / (ss * ss);
          image.at<cv::Vec3b>(y, x) =
              cv::Vec3b(cv::saturate_cast<uchar>(sum[0]), cv::saturate_cast<uchar>(sum[1]),
                        cv::saturate_cast<uchar>(sum[2]));
        }
      }
    });
    scene.images.push_back(image);
    scene.cameras.push_back(camera);
    scene.poses.push_back(pose);
  }
  return scene;
}

void WriteRenderedScene(const RenderedScene& scene, const std::filesystem::path& image_dir,
                        const std::filesystem::path& gt_dir) {
  std::filesystem::create_directories(image_dir);
  std::filesystem::create_directories(gt_dir);
  for (size_t i = 0; i < scene.images.size(); ++i) {
    const std::string name = fmt::format("image_{:04d}.png", i);
    WriteImage(image_dir / name, scene.images[i]);
    const Camera& c = scene.cameras[i];
    Eigen::Matrix3d K = c.K();
    K(0, 2) -= 0.5;  // Strecha's convention: the centre of the top-left pixel is (0, 0)
    K(1, 2) -= 0.5;
    const Eigen::Matrix3d R = scene.poses[i].R().transpose();  // camera-to-world
    const Eigen::Vector3d C = scene.poses[i].Center();
    if (c.HasDistortion())
      Fail("the Strecha layout holds no lens distortion; render with k1 = k2 = 0");
    WriteFileAtomically(gt_dir / (name + ".camera"), [&](std::ostream& out) {
      out.precision(17);
      for (int r = 0; r < 3; ++r) out << K(r, 0) << " " << K(r, 1) << " " << K(r, 2) << "\n";
      out << "0 0 0\n";
      for (int r = 0; r < 3; ++r) out << R(r, 0) << " " << R(r, 1) << " " << R(r, 2) << "\n";
      out << C.x() << " " << C.y() << " " << C.z() << "\n";
      out << c.width << " " << c.height << "\n";
    });
  }
}

void RenderedSceneOptions::Check() const {
  CheckPositive("street_step", street_step);
  CheckAtLeast("--images", num_images, 2);
  CheckAtLeast("width", width, 64);
  CheckAtLeast("height", height, 64);
  CheckPositive("focal_start", focal_start);
  CheckPositive("zoom", zoom);
  CheckFinite("k1", k1);
  CheckFinite("arc_degrees", arc_degrees);
  CheckInRange("supersampling", supersampling, 1, 8);
}

}  // namespace varsfm

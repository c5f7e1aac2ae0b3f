#include "varsfm/io/colmap_model.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "varsfm/camera/colmap_models.h"
#include "varsfm/io/text_line.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/little_endian.h"
#include "varsfm/util/log.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> ColmapModelFileNames(bool binary) {
  if (binary) return {"cameras.bin", "images.bin", "points3D.bin"};
  return {"cameras.txt", "images.txt", "points3D.txt"};
}

// Parameter count of the COLMAP models varsfm can represent; 0 for the others (fisheye, FOV,
// thin prism), whose parameter blocks cannot be skipped without knowing their sizes.
size_t ColmapNumParams(int model_id) {
  switch (model_id) {
    case kColmapSimplePinhole:
      return 3;
    case kColmapPinhole:
    case kColmapSimpleRadial:
      return 4;
    case kColmapRadial:
      return 5;
    case kColmapOpenCV:
      return 8;
    case kColmapFullOpenCV:
      return 12;
    default:
      return 0;
  }
}

// A binary COLMAP file (little-endian whatever the host) being read, with the count of bytes left
// in it, so that a record count read from the file is checked against what the file can hold before
// anything is sized from it (a corrupt count of 2^40 points would otherwise allocate terabytes).
class BinaryFile {
 public:
  explicit BinaryFile(const fs::path& file) : file_(file), in_(file, std::ios::binary) {
    if (!in_) Fail("{}: cannot open", file.string());
    std::error_code ec;
    left_ = fs::file_size(file, ec);
    if (ec) Fail("{}: cannot read its size: {}", file.string(), ec.message());
  }

  template <typename T>
  T Get() {
    char bytes[sizeof(T)];
    if (left_ < sizeof(T) || !in_.read(bytes, sizeof(T)))
      Fail("{}: truncated binary COLMAP file", file_.string());
    left_ -= sizeof(T);
    return GetLittleEndian<T>(bytes);
  }

  // A NUL-terminated string.
  std::string GetString() {
    std::string text;
    if (!std::getline(in_, text, '\0') || left_ < text.size() + 1)
      Fail("{}: truncated image name", file_.string());
    left_ -= text.size() + 1;
    return text;
  }

  // Throws unless `count` records of at least `record_bytes` each fit in the bytes left.
  uint64_t Count(uint64_t count, uint64_t record_bytes, const char* what) {
    if (count > left_ / record_bytes)
      Fail("{}: {} {} cannot fit in the {} bytes left (corrupt count)", file_.string(), count, what,
           left_);
    return count;
  }

 private:
  fs::path file_;
  std::ifstream in_;
  uint64_t left_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Writing.

struct CameraRecord {
  int model_id;
  std::vector<double> params;
};

CameraRecord ToRecord(const Camera& camera, int force_model_id) {
  const int model_id = force_model_id >= 0 ? force_model_id : SmallestColmapModel(camera);
  CameraRecord record{model_id, ToColmapParams(camera, model_id)};
  if (force_model_id >= 0) {
    // A forced model may lack a parameter the camera uses: say so instead of silently losing it.
    const Camera back = CameraFromColmap(model_id, record.params, camera.width, camera.height);
    for (int p = 0; p < Camera::kNumParams; ++p)
      if (p != Camera::kSkew && back.params[p] != camera.params[p]) {
        warn("camera {}: COLMAP model {} cannot hold all its parameters; they are truncated",
             camera.camera_id, ColmapModelName(model_id));
        break;
      }
  }
  return record;
}

std::vector<const Image*> RegisteredImages(const Reconstruction& rec) {
  std::vector<const Image*> images;
  for (const auto& [id, image] : rec.images())
    if (image.registered) images.push_back(&image);
  return images;
}

std::ofstream OpenForWrite(const fs::path& file, bool binary) {
  std::ofstream out(file, binary ? std::ios::binary : std::ios::out);
  if (!out) Fail("{}: cannot open for writing", file.string());
  return out;
}

void CloseChecked(std::ofstream& out, const fs::path& file) {
  out.close();
  if (!out) Fail("{}: write failed (disk full?)", file.string());
}

// Text values use fmt's shortest round-trip form, so reading back gives the same double.
void WriteCamerasText(const Reconstruction& rec, const fs::path& file, int force_model_id) {
  std::ofstream out = OpenForWrite(file, false);
  out << "# Camera list with one line of data per camera:\n"
      << "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
      << fmt::format("# Number of cameras: {}\n", rec.cameras().size());
  for (const auto& [id, camera] : rec.cameras()) {
    const CameraRecord r = ToRecord(camera, force_model_id);
    out << fmt::format("{} {} {} {} {}\n", id, ColmapModelName(r.model_id), camera.width,
                       camera.height, fmt::join(r.params, " "));
  }
  CloseChecked(out, file);
}

void WriteCamerasBinary(const Reconstruction& rec, const fs::path& file, int force_model_id) {
  std::ofstream out = OpenForWrite(file, true);
  PutLittleEndian<uint64_t>(out, rec.cameras().size());
  for (const auto& [id, camera] : rec.cameras()) {
    const CameraRecord r = ToRecord(camera, force_model_id);
    PutLittleEndian<uint32_t>(out, id);
    PutLittleEndian<int32_t>(out, r.model_id);
    PutLittleEndian<uint64_t>(out, static_cast<uint64_t>(camera.width));
    PutLittleEndian<uint64_t>(out, static_cast<uint64_t>(camera.height));
    for (double p : r.params) PutLittleEndian<double>(out, p);
  }
  CloseChecked(out, file);
}

void WriteImagesText(const Reconstruction& rec, const fs::path& file) {
  const auto images = RegisteredImages(rec);
  size_t num_obs = 0;
  for (const Image* image : images) num_obs += image->NumPoints3D();
  std::ofstream out = OpenForWrite(file, false);
  out << "# Image list with two lines of data per image:\n"
      << "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
      << "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
      << fmt::format("# Number of images: {}, mean observations per image: {}\n", images.size(),
                     images.empty() ? 0.0 : static_cast<double>(num_obs) / images.size());
  // Formatted into one buffer per image (fmt::format_to): a temporary string per 2D point made
  // the text model the slowest of the mapper's outputs.
  fmt::memory_buffer buffer;
  for (const Image* image : images) {
    const Eigen::Quaterniond q = image->cam_from_world.rotation.normalized();
    const Eigen::Vector3d& t = image->cam_from_world.translation;
    buffer.clear();
    auto it = std::back_inserter(buffer);
    fmt::format_to(it, "{} {} {} {} {} {} {} {} {} {}\n", image->image_id, q.w(), q.x(), q.y(),
                   q.z(), t.x(), t.y(), t.z(), image->camera_id, image->name);
    for (size_t i = 0; i < image->points2D.size(); ++i) {
      const Point2D& p = image->points2D[i];
      if (i > 0) buffer.push_back(' ');
      if (p.HasPoint3D())
        fmt::format_to(it, "{} {} {}", p.xy.x(), p.xy.y(), p.point3D_id);
      else
        fmt::format_to(it, "{} {} -1", p.xy.x(), p.xy.y());
    }
    buffer.push_back('\n');
    out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  }
  CloseChecked(out, file);
}

void WriteImagesBinary(const Reconstruction& rec, const fs::path& file) {
  const auto images = RegisteredImages(rec);
  std::ofstream out = OpenForWrite(file, true);
  PutLittleEndian<uint64_t>(out, images.size());
  for (const Image* image : images) {
    const Eigen::Quaterniond q = image->cam_from_world.rotation.normalized();
    const Eigen::Vector3d& t = image->cam_from_world.translation;
    PutLittleEndian<uint32_t>(out, image->image_id);
    for (double v : {q.w(), q.x(), q.y(), q.z(), t.x(), t.y(), t.z()})
      PutLittleEndian<double>(out, v);
    PutLittleEndian<uint32_t>(out, image->camera_id);
    out.write(image->name.c_str(), static_cast<std::streamsize>(image->name.size() + 1));
    PutLittleEndian<uint64_t>(out, image->points2D.size());
    for (const Point2D& p : image->points2D) {
      PutLittleEndian<double>(out, p.xy.x());
      PutLittleEndian<double>(out, p.xy.y());
      PutLittleEndian<uint64_t>(
          out, p.point3D_id);  // kInvalidPoint3DId is COLMAP's invalid id, 2^64 - 1
    }
  }
  CloseChecked(out, file);
}

void WritePointsText(const Reconstruction& rec, const fs::path& file) {
  std::ofstream out = OpenForWrite(file, false);
  out << "# 3D point list with one line of data per point:\n"
      << "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
      << fmt::format("# Number of points: {}, mean track length: {}\n", rec.points3D().size(),
                     rec.MeanTrackLength());
  fmt::memory_buffer buffer;
  for (const auto& [id, point] : rec.points3D()) {
    buffer.clear();
    auto it = std::back_inserter(buffer);
    fmt::format_to(it, "{} {} {} {} {} {} {} {}", id, point.xyz.x(), point.xyz.y(), point.xyz.z(),
                   point.color[0], point.color[1], point.color[2], point.error);
    for (const TrackElement& el : point.track)
      fmt::format_to(it, " {} {}", el.image_id, el.point2D_idx);
    buffer.push_back('\n');
    out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  }
  CloseChecked(out, file);
}

void WritePointsBinary(const Reconstruction& rec, const fs::path& file) {
  std::ofstream out = OpenForWrite(file, true);
  PutLittleEndian<uint64_t>(out, rec.points3D().size());
  for (const auto& [id, point] : rec.points3D()) {
    PutLittleEndian<uint64_t>(out, id);
    for (int k = 0; k < 3; ++k) PutLittleEndian<double>(out, point.xyz[k]);
    for (int k = 0; k < 3; ++k) PutLittleEndian<uint8_t>(out, point.color[k]);
    PutLittleEndian<double>(out, point.error);
    PutLittleEndian<uint64_t>(out, point.track.size());
    for (const TrackElement& el : point.track) {
      PutLittleEndian<uint32_t>(out, el.image_id);
      PutLittleEndian<uint32_t>(out, el.point2D_idx);
    }
  }
  CloseChecked(out, file);
}

// ---------------------------------------------------------------------------------------------
// Reading. Points are read last and linked through their tracks (COLMAP's images file repeats
// the links; the tracks are authoritative, and checked against the images).

struct PendingPoint {
  Eigen::Vector3d xyz;
  Eigen::Matrix<uint8_t, 3, 1> color;
  double error;
  std::vector<TrackElement> track;
};

Camera CameraFromRecord(const fs::path& file, camera_t id, int model_id,
                        const std::vector<double>& params, int width, int height) {
  try {
    Camera camera = CameraFromColmap(model_id, params, width, height);
    camera.camera_id = id;
    return camera;
  } catch (const Error& e) {
    Fail("{}: camera {}: {}", file.string(), id, e.what());
  }
}

// Text lines without comments and blank lines, with their line numbers for messages.
class TextLines {
 public:
  explicit TextLines(const fs::path& file) : file_(file), in_(file) {
    if (!in_) Fail("{}: cannot open", file.string());
  }
  // Next data line, to be parsed from `fields`; `keep_blank` returns blank lines too (the
  // POINTS2D line may be empty).
  bool Next(std::istringstream* fields, bool keep_blank = false) {
    while (ReadTextLine(in_, &line_)) {
      ++number_;
      const auto first = line_.find_first_not_of(" \t");
      if ((keep_blank && first == std::string::npos) ||
          (first != std::string::npos && line_[first] != '#')) {
        fields->clear();
        fields->str(line_);
        return true;
      }
    }
    return false;
  }
  [[noreturn]] void Bad(const std::string& what) const {
    Fail("{}:{}: {}", file_.string(), number_, what);
  }

 private:
  fs::path file_;
  std::ifstream in_;
  std::string line_;
  int number_ = 0;
};

void ReadCamerasText(const fs::path& file, Reconstruction* rec) {
  TextLines lines(file);
  std::istringstream s;
  while (lines.Next(&s)) {
    camera_t id;
    std::string model;
    int width, height;
    if (!(s >> id >> model >> width >> height)) lines.Bad("expected CAMERA_ID MODEL WIDTH HEIGHT");
    const int model_id = ColmapModelIdFromName(model);
    if (model_id < 0) lines.Bad(fmt::format("camera model {} is not supported", model));
    std::vector<double> params;
    for (double v; s >> v;) params.push_back(v);
    if (!s.eof()) lines.Bad("bad camera parameter");
    rec->AddCamera(CameraFromRecord(file, id, model_id, params, width, height));
  }
}

void ReadCamerasBinary(const fs::path& file, Reconstruction* rec) {
  BinaryFile in(file);
  const uint64_t n = in.Get<uint64_t>();
  for (uint64_t i = 0; i < n; ++i) {
    const auto id = in.Get<uint32_t>();
    const auto model_id = in.Get<int32_t>();
    const auto width = in.Get<uint64_t>();
    const auto height = in.Get<uint64_t>();
    const size_t num_params = ColmapNumParams(model_id);
    if (num_params == 0)
      Fail("{}: camera {}: COLMAP camera model id {} is not supported", file.string(), id,
           model_id);
    std::vector<double> params(num_params);
    for (double& p : params) p = in.Get<double>();
    rec->AddCamera(CameraFromRecord(file, id, model_id, params, static_cast<int>(width),
                                    static_cast<int>(height)));
  }
}

void AddImageChecked(const fs::path& file, Image image, Reconstruction* rec) {
  if (!rec->ExistsCamera(image.camera_id))
    Fail("{}: image {} refers to camera {}, absent from the cameras file", file.string(),
         image.image_id, image.camera_id);
  if (rec->ExistsImage(image.image_id))
    Fail("{}: image id {} appears twice", file.string(), image.image_id);
  // PoseFrom normalises the quaternion: a zero one stays zero, a non-number stays NaN; either
  // would put the camera nowhere.
  if (!image.cam_from_world.translation.allFinite() ||
      !(std::abs(image.cam_from_world.rotation.norm() - 1.0) < 1e-6))
    Fail("{}: image {} ({}): its pose is not finite (a zero quaternion or a non-number)",
         file.string(), image.image_id, image.name);
  for (const Point2D& point : image.points2D)
    if (!point.xy.allFinite())
      Fail("{}: image {} ({}): a 2D point is not a finite number", file.string(), image.image_id,
           image.name);
  image.registered = true;
  rec->AddImage(std::move(image));
}

Rigid3d PoseFrom(const double* v) {
  return {Eigen::Quaterniond(v[0], v[1], v[2], v[3]).normalized(),
          Eigen::Vector3d(v[4], v[5], v[6])};
}

void ReadImagesText(const fs::path& file, Reconstruction* rec) {
  TextLines lines(file);
  std::istringstream s, p;
  while (lines.Next(&s)) {
    Image image;
    double v[7];
    if (!(s >> image.image_id >> v[0] >> v[1] >> v[2] >> v[3] >> v[4] >> v[5] >> v[6] >>
          image.camera_id))
      lines.Bad("expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME");
    // The name is the rest of the line: COLMAP allows spaces in it.
    std::getline(s >> std::ws, image.name);
    if (image.name.empty()) lines.Bad("image without a name");
    image.cam_from_world = PoseFrom(v);
    if (!lines.Next(&p, /*keep_blank=*/true)) lines.Bad("missing POINTS2D line");
    double x, y;
    int64_t point3D_id;
    while (p >> x >> y >> point3D_id) image.points2D.push_back({Eigen::Vector2d(x, y)});
    if (!(p >> std::ws).eof()) lines.Bad("bad POINTS2D entry (expected X Y POINT3D_ID triples)");
    AddImageChecked(file, std::move(image), rec);
  }
}

void ReadImagesBinary(const fs::path& file, Reconstruction* rec) {
  BinaryFile in(file);
  const uint64_t n = in.Get<uint64_t>();
  for (uint64_t i = 0; i < n; ++i) {
    Image image;
    image.image_id = in.Get<uint32_t>();
    double v[7];
    for (double& x : v) x = in.Get<double>();
    image.cam_from_world = PoseFrom(v);
    image.camera_id = in.Get<uint32_t>();
    image.name = in.GetString();
    // Each 2D point: x, y (double) and a point id (uint64).
    image.points2D.resize(in.Count(in.Get<uint64_t>(), 24, "2D points"));
    for (Point2D& p : image.points2D) {
      p.xy.x() = in.Get<double>();
      p.xy.y() = in.Get<double>();
      in.Get<uint64_t>();  // the link is rebuilt from the tracks
    }
    AddImageChecked(file, std::move(image), rec);
  }
}

std::vector<PendingPoint> ReadPointsText(const fs::path& file) {
  TextLines lines(file);
  std::vector<PendingPoint> points;
  std::istringstream s;
  while (lines.Next(&s)) {
    uint64_t id;
    PendingPoint point;
    int r, g, b;
    if (!(s >> id >> point.xyz.x() >> point.xyz.y() >> point.xyz.z() >> r >> g >> b >> point.error))
      lines.Bad("expected POINT3D_ID X Y Z R G B ERROR");
    point.color = Eigen::Matrix<uint8_t, 3, 1>(r, g, b);
    TrackElement el;
    while (s >> el.image_id >> el.point2D_idx) point.track.push_back(el);
    if (!(s.eof())) lines.Bad("bad track entry (expected IMAGE_ID POINT2D_IDX pairs)");
    points.push_back(std::move(point));
  }
  return points;
}

std::vector<PendingPoint> ReadPointsBinary(const fs::path& file) {
  BinaryFile in(file);
  // Each point: id, x, y, z, r, g, b, error, track length (8 + 24 + 3 + 8 + 8 bytes).
  std::vector<PendingPoint> points(in.Count(in.Get<uint64_t>(), 51, "3D points"));
  for (PendingPoint& point : points) {
    in.Get<uint64_t>();  // ids are reassigned by Reconstruction::AddPoint3D
    for (int k = 0; k < 3; ++k) point.xyz[k] = in.Get<double>();
    for (int k = 0; k < 3; ++k) point.color[k] = in.Get<uint8_t>();
    point.error = in.Get<double>();
    point.track.resize(in.Count(in.Get<uint64_t>(), 8, "track elements"));
    for (TrackElement& el : point.track) {
      el.image_id = in.Get<uint32_t>();
      el.point2D_idx = in.Get<uint32_t>();
    }
  }
  return points;
}

void AddPoints(const fs::path& file, std::vector<PendingPoint> points, Reconstruction* rec) {
  for (PendingPoint& point : points) {
    if (!point.xyz.allFinite())
      Fail("{}: a 3D point's position is not a finite number", file.string());
    for (const TrackElement& el : point.track)
      if (!rec->ExistsImage(el.image_id) ||
          el.point2D_idx >= rec->image(el.image_id).points2D.size())
        Fail("{}: track element ({}, {}) refers to no 2D point of the images file", file.string(),
             el.image_id, el.point2D_idx);
    const point3D_t id = rec->AddPoint3D(point.xyz, std::move(point.track), point.color);
    rec->point3D(id).error = point.error;
  }
}

// Writes into `tmp`, then moves the files into `target` (see the header's atomicity promise).
void WriteAll(const Reconstruction& rec, const fs::path& dir, const ColmapWriteOptions& options) {
  const auto names = ColmapModelFileNames(options.binary);
  if (options.binary) {
    WriteCamerasBinary(rec, dir / names[0], options.force_model_id);
    WriteImagesBinary(rec, dir / names[1]);
    WritePointsBinary(rec, dir / names[2]);
  } else {
    WriteCamerasText(rec, dir / names[0], options.force_model_id);
    WriteImagesText(rec, dir / names[1]);
    WritePointsText(rec, dir / names[2]);
  }
}

}  // namespace

void WriteColmapModel(const Reconstruction& rec, const fs::path& dir,
                      const ColmapWriteOptions& options) {
  WriteFilesAtomically(dir, ColmapModelFileNames(options.binary),
                       [&](const fs::path& tmp) { WriteAll(rec, tmp, options); });
}

fs::path ResolveColmapModelFolder(const fs::path& path) {
  const auto holds_model = [](const fs::path& dir) {
    return fs::is_regular_file(dir / "cameras.bin") || fs::is_regular_file(dir / "cameras.txt");
  };
  if (!holds_model(path) && holds_model(path / "0")) return path / "0";
  return path;
}

Reconstruction ReadColmapModel(const fs::path& path) {
  if (!fs::is_directory(path)) Fail("{}: model folder does not exist", path.string());
  const fs::path dir = ResolveColmapModelFolder(path);
  bool binary = true;
  for (const auto& name : ColmapModelFileNames(true)) binary &= fs::is_regular_file(dir / name);
  const auto names = ColmapModelFileNames(binary);
  for (const auto& name : names)
    if (!fs::is_regular_file(dir / name))
      Fail("{}: no COLMAP model (missing {} or the .bin files)", dir.string(), name);
  Reconstruction rec;
  if (binary) {
    ReadCamerasBinary(dir / names[0], &rec);
    ReadImagesBinary(dir / names[1], &rec);
    AddPoints(dir / names[2], ReadPointsBinary(dir / names[2]), &rec);
  } else {
    ReadCamerasText(dir / names[0], &rec);
    ReadImagesText(dir / names[1], &rec);
    AddPoints(dir / names[2], ReadPointsText(dir / names[2]), &rec);
  }
  debug("read COLMAP {} model {}: {} cameras, {} images, {} points", binary ? "binary" : "text",
        dir.string(), rec.cameras().size(), rec.images().size(), rec.points3D().size());
  return rec;
}

}  // namespace varsfm

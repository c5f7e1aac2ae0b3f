// Writes the seed corpus of every harness (fuzz/corpus/<name>/): tiny valid files made by
// varsfm's own writers where it has one, by hand otherwise (ascii PLY, Strecha cameras, EXIF).
// Run once when a reader's format grows; the output is committed (a few KB per file).
//
// Usage: fuzz_seeds CORPUS_DIR
#include <sqlite3.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <zlib.h>
#include <opencv2/core.hpp>

#include "fuzz_support.h"
#include "varsfm/image/image_file.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/io/database.h"
#include "varsfm/io/mesh_ply.h"
#include "varsfm/io/obj_io.h"
#include "varsfm/io/ply.h"
#include "varsfm/matching/vocabulary_tree_io.h"

namespace {

namespace fs = std::filesystem;
using varsfm::fuzz::JoinParts;
using Bytes = std::vector<uint8_t>;

std::string Slurp(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void Put(const fs::path& file, const std::string& bytes) {
  fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << bytes;
  std::printf("%s: %zu bytes\n", file.c_str(), bytes.size());
}
void Put(const fs::path& file, const Bytes& bytes) {
  Put(file, std::string(bytes.begin(), bytes.end()));
}

// Three cameras (a radial, a pinhole and an OpenCV one), two images, two points: every record
// kind of a COLMAP model.
varsfm::Reconstruction SmallModel() {
  varsfm::Reconstruction rec;
  for (varsfm::camera_t id = 1; id <= 3; ++id) {
    varsfm::Camera camera = varsfm::Camera::FromFocal(64, 48, 50.0 + id);
    camera.camera_id = id;
    if (id == 2) camera.params[varsfm::Camera::kAspect] = 1.1;
    if (id == 3) camera.params[varsfm::Camera::kK2] = 0.01;
    camera.params[varsfm::Camera::kK1] = id == 1 ? -0.05 : 0.0;
    rec.AddCamera(camera);
  }
  for (varsfm::image_t id = 1; id <= 2; ++id) {
    varsfm::Image image;
    image.image_id = id;
    image.camera_id = id;
    image.name = id == 1 ? "a.jpg" : "sub dir/b.jpg";
    image.cam_from_world = varsfm::Rigid3d(Eigen::Quaterniond(1, 0, 0.1 * id, 0).normalized(),
                                           Eigen::Vector3d(0.5 * id, 0, 0));
    image.registered = true;
    for (int k = 0; k < 3; ++k) image.points2D.push_back({Eigen::Vector2d(10.5 + k, 20.25)});
    rec.AddImage(image);
  }
  rec.AddPoint3D(Eigen::Vector3d(0, 0, 5), {{1, 0}, {2, 0}}, {255, 128, 0});
  rec.AddPoint3D(Eigen::Vector3d(1, -1, 6), {{1, 2}, {2, 1}}, {0, 10, 200});
  return rec;
}

void ColmapSeeds(const fs::path& corpus, const fs::path& scratch) {
  const varsfm::Reconstruction rec = SmallModel();
  for (const bool binary : {false, true}) {
    const fs::path dir = scratch / (binary ? "bin" : "txt");
    varsfm::WriteColmapModel(rec, dir, {.binary = binary});
    const char* ext = binary ? ".bin" : ".txt";
    std::vector<std::string> parts;
    for (const char* name : {"cameras", "images", "points3D"})
      parts.push_back(Slurp(dir / (std::string(name) + ext)));
    Put(corpus / (binary ? "colmap_binary" : "colmap_text") / "model", JoinParts(parts));
  }
}

void PlySeeds(const fs::path& corpus, const fs::path& scratch) {
  varsfm::PointCloud cloud;
  cloud.points = {{0, 0, 0}, {1, 2, 3}, {-1.5, 0.25, 1e3}};
  cloud.colors = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}};
  varsfm::WritePly(scratch / "c.ply", cloud);
  Put(corpus / "ply" / "float_colors.ply", Slurp(scratch / "c.ply"));
  cloud.normals = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}};
  cloud.colors.clear();
  varsfm::WritePly(scratch / "c.ply", cloud, {.double_precision = true});
  Put(corpus / "ply" / "double_normals.ply", Slurp(scratch / "c.ply"));
  Put(corpus / "ply" / "ascii.ply",
      std::string("ply\nformat ascii 1.0\ncomment other tools' layout\nelement vertex 2\n"
                  "property float x\nproperty float y\nproperty float z\nproperty uchar red\n"
                  "property uchar green\nproperty uchar blue\nproperty int flags\n"
                  "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                  "0 0 0 255 255 255 1\n1 1 1 0 0 0 2\n3 0 1 1\n"));

  varsfm::TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  mesh.colors = {{10, 20, 30}, {40, 50, 60}, {70, 80, 90}, {100, 110, 120}};
  mesh.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  varsfm::WriteMeshPly(scratch / "m.ply", mesh);
  Put(corpus / "mesh_ply" / "tetrahedron.ply", Slurp(scratch / "m.ply"));
  Put(corpus / "mesh_ply" / "ascii_quad.ply",
      std::string("ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\n"
                  "property double y\nproperty double z\nelement face 1\n"
                  "property list uchar uint vertex_index\nend_header\n"
                  "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n"));
}

void ObjSeeds(const fs::path& corpus, const fs::path& scratch) {
  varsfm::TexturedMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  mesh.faces = {{0, 1, 2}, {1, 3, 2}};
  mesh.texcoords = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  mesh.face_texcoords = {{0, 1, 2}, {1, 3, 2}};
  mesh.face_page = {0, 0};
  mesh.pages = {cv::Mat(4, 4, CV_8UC3, cv::Scalar(1, 2, 3))};
  varsfm::WriteTexturedObj(scratch / "obj", mesh, "model");
  std::string mtl = Slurp(scratch / "obj" / "model.mtl");
  mtl.replace(mtl.find("model_0.png"), std::strlen("model_0.png"), "page.png");
  Put(corpus / "obj" / "quad", JoinParts({Slurp(scratch / "obj" / "model.obj"), mtl}));
  Put(corpus / "obj" / "polygon",
      JoinParts({"mtllib model.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\n"
                 "vt 1 1\nvt 0 1\nvn 0 0 1\nusemtl a\nf 1/1/1 2/2/1 3/3/1 4/4/1\nf -4/-4 -2/-2 "
                 "-1/-1\n",
                 "newmtl a\r\nKd 1 1 1\r\nmap_Kd page.png\r\n"}));
}

// ---- EXIF, built by hand: a TIFF header, IFD0 (orientation, pointer to the Exif IFD), the
// Exif IFD (focal-length tags), then the values that do not fit in an entry.

struct Tag {
  uint16_t tag, type;  // type 3 SHORT, 4 LONG, 5 RATIONAL
  uint32_t a, b = 1;   // the value, or a rational's numerator and denominator
};

Bytes Tiff(bool little, const std::vector<Tag>& ifd0, const std::vector<Tag>& exif_ifd) {
  Bytes out;
  auto put = [&](uint32_t v, int bytes, size_t at = SIZE_MAX) {
    for (int k = 0; k < bytes; ++k) {
      const uint8_t b = static_cast<uint8_t>(v >> (8 * (little ? k : bytes - 1 - k)));
      if (at == SIZE_MAX)
        out.push_back(b);
      else
        out[at + k] = b;
    }
  };
  out = {'E', 'x', 'i', 'f', 0, 0};
  const size_t base = out.size();  // TIFF offsets count from here
  out.push_back(little ? 'I' : 'M');
  out.push_back(little ? 'I' : 'M');
  put(42, 2);
  put(8, 4);
  const size_t ifd0_size = 2 + 12 * (ifd0.size() + 1) + 4, exif_size = 2 + 12 * exif_ifd.size() + 4;
  size_t data_at = 8 + ifd0_size + exif_size;
  std::vector<std::pair<size_t, Tag>> rationals;
  auto write_ifd = [&](std::vector<Tag> tags, bool with_pointer) {
    if (with_pointer) tags.push_back({0x8769, 4, static_cast<uint32_t>(8 + ifd0_size)});
    put(static_cast<uint32_t>(tags.size()), 2);
    for (const Tag& t : tags) {
      put(t.tag, 2);
      put(t.type, 2);
      put(1, 4);
      if (t.type == 3) {
        put(t.a, 2);
        put(0, 2);
      } else if (t.type == 4) {
        put(t.a, 4);
      } else {
        put(static_cast<uint32_t>(data_at), 4);
        rationals.push_back({data_at, t});
        data_at += 8;
      }
    }
    put(0, 4);  // no next IFD
  };
  write_ifd(ifd0, true);
  write_ifd(exif_ifd, false);
  out.resize(base + data_at);
  for (const auto& [at, t] : rationals) {
    put(t.a, 4, base + at);
    put(t.b, 4, base + at + 4);
  }
  return out;
}

// A JPEG with `exif` as its APP1 segment, right after SOI.
Bytes WithExif(Bytes jpeg, const Bytes& exif) {
  Bytes segment = {0xFF, 0xE1, static_cast<uint8_t>((exif.size() + 2) >> 8),
                   static_cast<uint8_t>(exif.size() + 2)};
  segment.insert(segment.end(), exif.begin(), exif.end());
  jpeg.insert(jpeg.begin() + 2, segment.begin(), segment.end());
  return jpeg;
}

// A PNG with the TIFF part of `exif` as an eXIf chunk before IEND.
Bytes WithExifChunk(Bytes png, const Bytes& exif) {
  const Bytes tiff(exif.begin() + 6, exif.end());
  Bytes chunk;
  for (int k = 3; k >= 0; --k) chunk.push_back(static_cast<uint8_t>(tiff.size() >> (8 * k)));
  for (char c : {'e', 'X', 'I', 'f'}) chunk.push_back(static_cast<uint8_t>(c));
  chunk.insert(chunk.end(), tiff.begin(), tiff.end());
  const uLong crc = crc32(0, chunk.data() + 4, static_cast<uInt>(chunk.size() - 4));
  for (int k = 3; k >= 0; --k) chunk.push_back(static_cast<uint8_t>(crc >> (8 * k)));
  png.insert(png.end() - 12, chunk.begin(), chunk.end());  // IEND is the last 12 bytes
  return png;
}

void ImageSeeds(const fs::path& corpus, const fs::path& scratch) {
  cv::Mat color(12, 16, CV_8UC3), gray(9, 7, CV_8UC1);
  cv::randu(color, 0, 255);
  cv::randu(gray, 0, 255);
  auto encode = [&](const cv::Mat& image, const char* name) {
    varsfm::WriteImage(scratch / name, image, {.jpeg_quality = 75});
    const std::string s = Slurp(scratch / name);
    return Bytes(s.begin(), s.end());
  };
  const Bytes exif_35mm = Tiff(true, {{0x0112, 3, 6}}, {{0xA405, 3, 28}});
  const Bytes exif_plane = Tiff(false, {{0x0112, 3, 8}},
                                {{0xA002, 4, 4000},
                                 {0xA003, 4, 3000},
                                 {0x920A, 5, 43, 10},
                                 {0xA20E, 5, 4000000, 245},
                                 {0xA210, 3, 2}});
  Put(corpus / "image" / "color.jpg", encode(color, "c.jpg"));
  Put(corpus / "image" / "gray.jpg", encode(gray, "g.jpg"));
  Put(corpus / "image" / "exif.jpg", WithExif(encode(color, "c.jpg"), exif_35mm));
  Put(corpus / "image" / "color.png", encode(color, "c.png"));
  Put(corpus / "image" / "gray.png", encode(gray, "g.png"));
  Put(corpus / "image" / "exif.png", WithExifChunk(encode(gray, "g.png"), exif_plane));
  // The exif harness takes two bytes of image size (x 40 px) before the EXIF data.
  for (const auto& [name, exif] :
       {std::pair{"35mm", exif_35mm}, std::pair{"focal_plane", exif_plane}}) {
    Bytes input = {100, 75};
    input.insert(input.end(), exif.begin(), exif.end());
    Put(corpus / "exif" / name, input);
  }
}

void GroundTruthSeeds(const fs::path& corpus) {
  Put(corpus / "ground_truth" / "0000.jpg.camera",
      std::string("2759.48 0 1520.69\n0 2764.16 1006.81\n0 0 1\n0 0 0\n"
                  "0.450927 -0.0945642 -0.887537\n-0.892535 -0.0401974 -0.449183\n"
                  "0.00679074 0.994707 -0.102528\n-7.28137 -7.57667 0.204446\n3072 2048\n"));
}

// ---- The workspace database: one tiny workspace file, and rows for the blob harness.

void DatabaseSeeds(const fs::path& corpus, const fs::path& scratch) {
  const fs::path file = scratch / "seed.db";
  {
    varsfm::Database db(file);
    const varsfm::camera_t camera = db.WriteCamera({0, 2, 64, 48, {50, 50, 32, 24}, false});
    const varsfm::image_t a = db.WriteImage({0, "a.jpg", camera});
    const varsfm::image_t b = db.WriteImage({0, "b.jpg", camera});
    for (const varsfm::image_t id : {a, b}) {
      db.WriteKeypoints(id, {{1, 2}, {3, 4, 2.0f, 0.5f}});
      varsfm::FeatureDescriptors descriptors(2, 128);
      descriptors.setConstant(static_cast<uint8_t>(id));
      db.WriteDescriptors(id, descriptors);
    }
    db.WriteMatches(a, b, {{0, 1}, {1, 0}});
    varsfm::TwoViewGeometry geometry;
    geometry.config = varsfm::TwoViewGeometry::kUncalibrated;
    geometry.F << 0, -1, 2, 1, 0, -3, -2, 3, 0;
    geometry.inlier_matches = {{0, 1}};
    db.WriteTwoViewGeometry(b, a, geometry);
  }
  // Smallest pages, out of WAL mode, so the whole workspace is a few KB.
  sqlite3* raw = nullptr;
  sqlite3_open(file.c_str(), &raw);
  sqlite3_exec(raw, "PRAGMA journal_mode = DELETE; PRAGMA page_size = 512; VACUUM;", nullptr,
               nullptr, nullptr);
  sqlite3_close(raw);
  Put(corpus / "database_file" / "workspace.db", Slurp(file));

  // Blob harness: table byte, rows, cols, config, then the blobs (see database_blob_fuzzer.cc).
  auto row = [](uint8_t table, int64_t rows, int64_t cols, int32_t config,
                std::vector<std::string> blobs) {
    std::string header(21, '\0');
    header[0] = static_cast<char>(table);
    std::memcpy(header.data() + 1, &rows, 8);
    std::memcpy(header.data() + 9, &cols, 8);
    std::memcpy(header.data() + 17, &config, 4);
    return header + JoinParts(blobs);
  };
  auto floats = [](std::vector<float> v) {
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(float));
  };
  auto doubles = [](std::vector<double> v) {
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double));
  };
  const fs::path dir = corpus / "database_blob";
  Put(dir / "keypoints6", row(0, 2, 6, 0, {floats({1, 2, 1, 0, 0, 1, 3, 4, 2, 0, 0, 2})}));
  Put(dir / "keypoints4", row(0, 1, 4, 0, {floats({1, 2, 3, 0.5})}));
  Put(dir / "descriptors", row(1, 2, 128, 0, {std::string(256, '\x07')}));
  Put(dir / "matches", row(2, 2, 2, 0, {std::string("\0\0\0\0\1\0\0\0\1\0\0\0\0\0\0\0", 16)}));
  Put(dir / "two_view_geometry",
      row(3, 1, 2, 2,
          {std::string("\0\0\0\0\1\0\0\0", 8), doubles({0, -1, 2, 1, 0, -3, -2, 3, 0}),
           doubles({0, -1, 0, 1, 0, 0, 0, 0, 0}), doubles({1, 0, 0, 0, 1, 0, 0, 0, 1}),
           doubles({1, 0, 0, 0}), doubles({1, 0, 0})}));
  Put(dir / "camera", row(4, 64, 48, 2, {doubles({50, 50, 32, 24})}));
}

// Two small trees (branching 2: a root with two leaves; branching 3 over two levels) from
// clustered descriptors.
void VocabularySeeds(const fs::path& corpus, const fs::path& scratch) {
  for (const int depth : {1, 2}) {
    varsfm::TrainingDescriptors descriptors(24, varsfm::VocabularyTree::kDimension);
    for (int r = 0; r < descriptors.rows(); ++r)
      for (int c = 0; c < descriptors.cols(); ++c)
        descriptors(r, c) = static_cast<float>((r * 7 + c * 3) % 11 + (c == r % 6 ? 100 : 0));
    varsfm::VocabularyTreeOptions options;
    options.branching = depth == 1 ? 2 : 3;
    options.depth = depth;
    varsfm::WriteVocabularyTree(varsfm::VocabularyTree::Train(descriptors, options),
                                scratch / "tree.voc");
    Put(corpus / "vocabulary" / (depth == 1 ? "two_leaves.voc" : "two_levels.voc"),
        Slurp(scratch / "tree.voc"));
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR\n", argv[0]);
    return 2;
  }
  const fs::path corpus = argv[1];
  const fs::path scratch = varsfm::fuzz::ScratchDir();
  ColmapSeeds(corpus, scratch);
  PlySeeds(corpus, scratch);
  ObjSeeds(corpus, scratch);
  ImageSeeds(corpus, scratch);
  GroundTruthSeeds(corpus);
  DatabaseSeeds(corpus, scratch);
  VocabularySeeds(corpus, scratch);
  return 0;
}

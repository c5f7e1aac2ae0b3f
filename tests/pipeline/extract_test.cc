// End to end through the command-line tool: `varsfm extract` on photos, on a video, and on bad
// input, checked in the workspace database.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "support/test_data.h"
#include "varsfm/camera/colmap_models.h"
#include "varsfm/image/image_file.h"
#include "varsfm/image/jpeg_codec.h"
#include "varsfm/io/database.h"
#include "varsfm/pipeline/extract.h"
#include "varsfm/util/file_fingerprint.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;
using testing::CopyFileHead;
using testing::RunCommand;
using testing::ShellQuote;
using testing::TempDir;
using testing::VarsfmBinary;

std::string Extract(const fs::path& workspace, const std::string& input_args) {
  return fmt::format("{} extract --workspace {} {}", ShellQuote(VarsfmBinary()),
                     ShellQuote(workspace), input_args);
}

// `varsfm run INPUT OUT` and further arguments, as a command line.
std::string RunLine(const fs::path& input, const fs::path& out, const std::string& args = "") {
  return fmt::format("{} run {} {} {}", ShellQuote(VarsfmBinary()), ShellQuote(input),
                     ShellQuote(out), args);
}

std::string FileBytes(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

void CopyKermit(const fs::path& kermit, const fs::path& to, int first, int last) {
  fs::create_directories(to);
  for (int i = first; i <= last; ++i) {
    const std::string name = fmt::format("kermit{:03d}.jpg", i);
    fs::copy_file(kermit / name, to / name, fs::copy_options::overwrite_existing);
  }
}

TEST(ExtractCommand, KermitEveryImageGetsCameraAndRootSiftFeatures) {
  VARSFM_REQUIRE_SHARED_DATA(kermit, "bundler/kermit");
  TempDir dir("extract_kermit");
  const fs::path workspace = dir.path() / "ws.db";
  std::string out;
  ASSERT_EQ(RunCommand(Extract(workspace, "--images " + ShellQuote(kermit)), &out), 0) << out;

  Database db(workspace);
  const std::vector<DbImage> images = db.ReadAllImages();
  ASSERT_EQ(images.size(), 11u);
  EXPECT_EQ(db.NumCameras(), 11u);  // one camera per image: intrinsics vary
  std::set<camera_t> cameras;
  for (size_t i = 0; i < images.size(); ++i) {
    const DbImage& image = images[i];
    SCOPED_TRACE(image.name);
    // Ids follow the names, as COLMAP numbers them.
    EXPECT_EQ(image.image_id, i + 1);
    EXPECT_EQ(image.name, fmt::format("kermit{:03d}.jpg", i));
    cameras.insert(image.camera_id);
    const auto camera = db.ReadCamera(image.camera_id);
    ASSERT_TRUE(camera.has_value());
    EXPECT_EQ(camera->model_id, kColmapSimpleRadial);
    EXPECT_EQ(camera->width, 640);
    EXPECT_EQ(camera->height, 480);
    // The EXIF focal length is a prior (COLMAP 3.8 writes 660.50 px for these photos), the
    // principal point at the centre and k = 0.
    EXPECT_TRUE(camera->has_prior_focal_length);
    ASSERT_EQ(camera->params.size(), 4u);
    EXPECT_NEAR(camera->params[0], 660.5, 0.01 * 660.5);
    EXPECT_EQ(camera->params[1], 320.0);
    EXPECT_EQ(camera->params[2], 240.0);
    EXPECT_EQ(camera->params[3], 0.0);

    const FeatureKeypoints keypoints = db.ReadKeypoints(image.image_id);
    const FeatureDescriptors descriptors = db.ReadDescriptors(image.image_id);
    EXPECT_GT(keypoints.size(), 1000u);
    EXPECT_LE(keypoints.size(), 8192u);
    ASSERT_EQ(descriptors.rows(), static_cast<int>(keypoints.size()));
    ASSERT_EQ(descriptors.cols(), 128);
    for (const FeatureKeypoint& kp : keypoints) {
      ASSERT_TRUE(kp.x >= 0 && kp.x <= 640 && kp.y >= 0 && kp.y <= 480) << kp.x << " " << kp.y;
    }
    // RootSIFT: each row is a unit vector quantised as 512 x (saturating at 255).
    for (int r = 0; r < descriptors.rows(); ++r) {
      double sum = 0;
      for (int c = 0; c < 128; ++c) sum += std::pow(descriptors(r, c) / 512.0, 2);
      ASSERT_GT(sum, 0.9) << "row " << r;
      ASSERT_LT(sum, 1.02) << "row " << r;
    }
  }
  EXPECT_EQ(cameras.size(), 11u);
}

TEST(ExtractCommand, RerunSkipsExtractedImagesAndAddsNewOnes) {
  VARSFM_REQUIRE_SHARED_DATA(kermit, "bundler/kermit");
  TempDir dir("extract_rerun");
  const fs::path images = dir.path() / "images";
  const fs::path workspace = dir.path() / "ws.db";
  CopyKermit(kermit, images, 0, 2);
  std::string out;
  ASSERT_EQ(RunCommand(Extract(workspace, "--images " + ShellQuote(images)), &out), 0) << out;
  FeatureKeypoints first;
  {
    Database db(workspace);
    ASSERT_EQ(db.NumImages(), 3u);
    first = db.ReadKeypoints(1);
  }
  // Nothing new: nothing written.
  ASSERT_EQ(RunCommand(Extract(workspace, "--images " + ShellQuote(images)), &out), 0) << out;
  EXPECT_NE(out.find("3 of 3 images already extracted"), std::string::npos) << out;

  CopyKermit(kermit, images, 3, 4);
  ASSERT_EQ(RunCommand(Extract(workspace, "--images " + ShellQuote(images) + " --threads 1"), &out),
            0)
      << out;
  EXPECT_NE(out.find("3 of 5 images already extracted"), std::string::npos) << out;
  Database db(workspace);
  EXPECT_EQ(db.NumImages(), 5u);
  EXPECT_EQ(db.NumCameras(), 5u);
  EXPECT_EQ(db.ReadImageWithName("kermit000.jpg")->image_id, 1u);
  EXPECT_EQ(db.ReadImageWithName("kermit004.jpg")->image_id, 5u);
  const FeatureKeypoints again = db.ReadKeypoints(1);
  ASSERT_EQ(again.size(), first.size());
  for (size_t i = 0; i < first.size(); ++i) EXPECT_EQ(again[i].x, first[i].x);
}

TEST(ExtractCommand, UnreadableImagesAreSkippedWithAWarning) {
  VARSFM_REQUIRE_SHARED_DATA(kermit, "bundler/kermit");
  TempDir dir("extract_mixed");
  const fs::path images = dir.path() / "images";
  CopyKermit(kermit, images, 0, 1);
  std::ofstream(images / "text.jpg") << "not an image\n";
  const std::string jpeg = FileBytes(kermit / "kermit002.jpg");
  std::ofstream(images / "truncated.jpg", std::ios::binary) << jpeg.substr(0, jpeg.size() / 2);
  WriteImage(images / "tiny.png", cv::Mat(20, 20, CV_8UC1, cv::Scalar(3)));
  std::string out;
  ASSERT_EQ(RunCommand(Extract(dir.path() / "ws.db", "--images " + ShellQuote(images)), &out), 0)
      << out;
  for (const char* name : {"text.jpg", "truncated.jpg", "tiny.png"}) {
    EXPECT_NE(out.find(name), std::string::npos) << name << " not named in:\n" << out;
  }
  Database db(dir.path() / "ws.db");
  EXPECT_EQ(db.NumImages(), 2u);
}

// A textured grey image with features (blurred noise), different for each seed.
void WriteTexturedImage(const fs::path& path, int seed, int width = 320, int height = 240) {
  cv::Mat image(height, width, CV_8UC1);
  cv::RNG(seed).fill(image, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(image, image, cv::Size(), 2.0);
  WriteImage(path, image);
}

// `images` with three textured PNGs, 0.png to 2.png; returns `images`.
fs::path WriteThreeImages(const fs::path& images) {
  fs::create_directories(images);
  for (int i = 0; i < 3; ++i) WriteTexturedImage(images / fmt::format("{}.png", i), i + 1);
  return images;
}

// A photo copied under another name is extracted (an image like any other) and named in a
// warning; two files alike at both ends (the same fingerprint) but not in the middle are not.
TEST(ExtractCommand, ACopyOfAPhotoIsNamedInAWarning) {
  TempDir dir("extract_copies");
  const fs::path images = WriteThreeImages(dir.path() / "images");
  fs::copy_file(images / "1.png", images / "copy_of_1.png");
  // Two 400 x 400 binary PGMs (160 kB) that differ in rows 170-230 only: same size, same first
  // and last 64 KiB (rows 0-163 and 236-399).
  cv::Mat a(400, 400, CV_8UC1);
  cv::RNG(5).fill(a, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(a, a, cv::Size(), 2.0);
  cv::Mat b = a.clone();
  cv::flip(a.rowRange(170, 230), b.rowRange(170, 230), 1);
  for (const auto& [name, image] : {std::pair{"a.pgm", a}, std::pair{"b.pgm", b}}) {
    std::ofstream file(images / name, std::ios::binary);
    file << "P5\n400 400\n255\n";
    file.write(reinterpret_cast<const char*>(image.data),
               static_cast<std::streamsize>(image.total()));
  }
  ASSERT_EQ(FileFingerprint(images / "a.pgm"), FileFingerprint(images / "b.pgm"));
  const fs::path workspace = dir.path() / "ws.db";
  std::string out;
  ASSERT_EQ(RunCommand(Extract(workspace, "--images " + ShellQuote(images)), &out), 0) << out;
  EXPECT_NE(out.find("copy_of_1.png is the same file as 1.png (a copy?)"), std::string::npos)
      << out;
  EXPECT_EQ(out.find("b.pgm is the same file"), std::string::npos) << out;
  EXPECT_EQ(Database(workspace).NumImages(), 6u);
}

// A link to a photo of the folder is that photo (skipped with a warning naming both); broken
// links, link loops and a folder linked into itself are skipped with a warning, never an error.
TEST(ExtractCommand, LinksAreOnePhotoAndBrokenLinksAndLoopsAreSkipped) {
  TempDir dir("extract_links");
  const fs::path images = WriteThreeImages(dir.path() / "images");
  fs::create_symlink("1.png", images / "link.png");
  fs::create_symlink("absent.png", images / "broken.png");
  fs::create_symlink("loop2.png", images / "loop1.png");
  fs::create_symlink("loop1.png", images / "loop2.png");
  fs::create_symlink(".", images / "self");
  const fs::path workspace = dir.path() / "ws.db";
  std::string out;
  ASSERT_EQ(RunCommand(Extract(workspace, "--images " + ShellQuote(images)), &out), 0) << out;
  EXPECT_NE(out.find("skipping link.png: a link to 1.png"), std::string::npos) << out;
  for (const char* name : {"broken.png", "loop1.png", "loop2.png", "self"}) {
    EXPECT_NE(out.find(std::string("skipping ") + name), std::string::npos) << name << "\n" << out;
  }
  Database db(workspace);
  std::vector<std::string> names;
  for (const DbImage& image : db.ReadAllImages()) names.push_back(image.name);
  EXPECT_EQ(names, (std::vector<std::string>{"0.png", "1.png", "2.png"}));
}

// An extraction that fails half-way removes the images it added, so the workspace holds what
// it held before (a failure injected by a trigger on the third image's row).
TEST(ExtractCommand, AFailedRunLeavesTheWorkspaceAsItWas) {
  TempDir dir("extract_failure");
  const fs::path images = dir.path() / "images";
  fs::create_directories(images);
  WriteTexturedImage(images / "a.png", 1);
  const fs::path workspace = dir.path() / "ws.db";
  std::string out;
  ASSERT_EQ(RunCommand(Extract(workspace, "--images " + ShellQuote(images)), &out), 0) << out;
  WriteTexturedImage(images / "b.png", 2);
  WriteTexturedImage(images / "c.png", 3);
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(workspace.c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db,
                           "CREATE TRIGGER fail BEFORE INSERT ON images WHEN NEW.name = 'c.png' "
                           "BEGIN SELECT RAISE(ABORT, 'injected failure'); END",
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(db);
  }
  EXPECT_EQ(RunCommand(Extract(workspace, "--images " + ShellQuote(images) + " --threads 1"), &out),
            1)
      << out;
  EXPECT_NE(out.find("injected failure"), std::string::npos) << out;
  Database db(workspace);
  ASSERT_EQ(db.NumImages(), 1u) << out;
  EXPECT_EQ(db.ReadAllImages()[0].name, "a.png");
  EXPECT_EQ(db.NumCameras(), 1u);
}

// Features are recorded with the settings they were extracted with: a re-run with other
// settings extracts again (and drops the matches the old keypoints numbered), one with only
// another thread count skips every image.
TEST(ExtractCommand, OtherSettingsExtractAgainAndThreadsChangeNothing) {
  TempDir dir("extract_settings");
  const fs::path images = WriteThreeImages(dir.path() / "images");
  const fs::path workspace = dir.path() / "ws.db";
  const std::string input = "--images " + ShellQuote(images);
  std::string out;
  ASSERT_EQ(RunCommand(Extract(workspace, input + " --max-features 40"), &out), 0) << out;
  const std::string match =
      fmt::format("{} match --workspace {}", ShellQuote(VarsfmBinary()), ShellQuote(workspace));
  ASSERT_EQ(RunCommand(match, &out), 0) << out;
  size_t few = 0;
  {
    Database db(workspace);
    few = db.ReadKeypoints(1).size();
    ASSERT_EQ(db.NumMatchedPairs(), 3u);
  }

  ASSERT_EQ(RunCommand(Extract(workspace, input), &out), 0) << out;
  EXPECT_NE(out.find("3 images were extracted with other settings"), std::string::npos) << out;
  {
    Database db(workspace);
    EXPECT_EQ(db.NumImages(), 3u);
    EXPECT_EQ(db.NumCameras(), 3u);
    EXPECT_GT(db.ReadKeypoints(1).size(), few);
    EXPECT_EQ(db.NumMatchedPairs(), 0u);
    EXPECT_TRUE(db.ReadAllTwoViewGeometries().empty());
  }

  ASSERT_EQ(RunCommand(Extract(workspace, input + " --threads 1"), &out), 0) << out;
  EXPECT_NE(out.find("3 of 3 images already extracted"), std::string::npos) << out;
  EXPECT_EQ(out.find("other settings"), std::string::npos) << out;
}

// The two workspaces hold the same `n` images with the same features, bit for bit.
void ExpectSameFeatures(const fs::path& workspace_a, const fs::path& workspace_b, size_t n) {
  Database a(workspace_a), b(workspace_b);
  ASSERT_EQ(a.NumImages(), n);
  ASSERT_EQ(b.NumImages(), n);
  for (image_t id = 1; id <= n; ++id) {
    const FeatureKeypoints ka = a.ReadKeypoints(id), kb = b.ReadKeypoints(id);
    ASSERT_EQ(ka.size(), kb.size());
    ASSERT_GT(ka.size(), 0u);
    for (size_t k = 0; k < ka.size(); ++k) {
      EXPECT_EQ(ka[k].x, kb[k].x);
      EXPECT_EQ(ka[k].y, kb[k].y);
    }
    EXPECT_EQ(a.ReadDescriptors(id), b.ReadDescriptors(id));
  }
}

// A memory budget below one photo's scale space: one photo at a time, said so, and the features
// of a run without the budget, bit for bit.
TEST(ExtractCommand, AMemoryBudgetExtractsFewerPhotosAtOnceWithTheSameFeatures) {
  TempDir dir("extract_memory");
  const fs::path images = WriteThreeImages(dir.path() / "images");
  const std::string input = "--images " + ShellQuote(images);
  std::string out;
  ASSERT_EQ(RunCommand(Extract(dir.path() / "free.db", input), &out), 0) << out;
  EXPECT_EQ(out.find("at a time"), std::string::npos) << out;
  ASSERT_EQ(
      RunCommand(Extract(dir.path() / "bounded.db", input + " --memory-mb 1 --threads 2"), &out), 0)
      << out;
  EXPECT_NE(out.find("1 photo(s) at a time"), std::string::npos) << out;
  ExpectSameFeatures(dir.path() / "free.db", dir.path() / "bounded.db", 3);
}

// A small photo first and larger ones after (two cameras): the photos in flight follow the
// small one, but the larger ones' scale spaces (44 MB each) do not fit two at once in 60 MB, so
// they wait for the budget (whether one waits depends on the threads' timing; the waiting itself
// is ByteBudget's test). The run ends, without a deadlock, with the features of an unbounded one.
TEST(ExtractCommand, PhotosLargerThanTheFirstUnderATightBudgetGiveTheSameFeatures) {
  TempDir dir("extract_memory_sizes");
  const fs::path images = dir.path() / "images";
  fs::create_directories(images);
  WriteTexturedImage(images / "0.png", 1, 64, 48);
  for (int i = 1; i <= 4; ++i)
    WriteTexturedImage(images / fmt::format("{}.png", i), i + 1, 480, 360);
  const std::string input = "--images " + ShellQuote(images) + " --threads 2";
  std::string out;
  ASSERT_EQ(RunCommand(Extract(dir.path() / "free.db", input), &out), 0) << out;
  ASSERT_EQ(RunCommand(Extract(dir.path() / "bounded.db", input + " --memory-mb 60"), &out), 0)
      << out;
  EXPECT_EQ(out.find("at a time"), std::string::npos) << out;  // the small photo's count
  ExpectSameFeatures(dir.path() / "free.db", dir.path() / "bounded.db", 5);
}

// A photo replaced under its name (here by a half-size copy of another) is another file: it is
// extracted again, its camera takes the new size and its matches go; the others are skipped.
TEST(ExtractCommand, APhotoReplacedUnderItsNameIsExtractedAgain) {
  TempDir dir("extract_replaced");
  const fs::path images = WriteThreeImages(dir.path() / "images");
  const fs::path workspace = dir.path() / "ws.db";
  const std::string input = "--images " + ShellQuote(images);
  std::string out;
  ASSERT_EQ(RunCommand(Extract(workspace, input), &out), 0) << out;
  ASSERT_EQ(RunCommand(fmt::format("{} match --workspace {}", ShellQuote(VarsfmBinary()),
                                   ShellQuote(workspace)),
                       &out),
            0)
      << out;
  cv::Mat replacement(120, 160, CV_8UC1);
  cv::RNG(9).fill(replacement, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(replacement, replacement, cv::Size(), 1.0);
  WriteImage(images / "1.png", replacement);

  ASSERT_EQ(RunCommand(Extract(workspace, input), &out), 0) << out;
  EXPECT_NE(out.find("2 of 3 images already extracted"), std::string::npos) << out;
  EXPECT_NE(out.find("1 images are other files than the ones extracted"), std::string::npos) << out;
  {
    Database db(workspace);
    const std::optional<DbImage> image = db.ReadImageWithName("1.png");
    ASSERT_TRUE(image);
    const std::optional<DbCamera> camera = db.ReadCamera(image->camera_id);
    ASSERT_TRUE(camera);
    EXPECT_EQ(camera->width, 160);
    EXPECT_EQ(camera->height, 120);
    EXPECT_EQ(db.NumMatchedPairs(), 1u) << "only the pair without 1.png keeps its matches";
  }
  ASSERT_EQ(RunCommand(Extract(workspace, input), &out), 0) << out;
  EXPECT_NE(out.find("3 of 3 images already extracted"), std::string::npos) << out;
}

// The extractor's version is part of the recorded settings: features recorded with another
// version, or with none (an extractor from before versions were recorded), are extracted again,
// and the next run finds them current.
TEST(ExtractCommand, FeaturesOfAnotherExtractorVersionAreExtractedAgain) {
  TempDir dir("extract_version");
  const fs::path images = WriteThreeImages(dir.path() / "images");
  const fs::path workspace = dir.path() / "ws.db";
  const std::string extract = Extract(workspace, "--images " + ShellQuote(images));
  std::string out;
  ASSERT_EQ(RunCommand(extract, &out), 0) << out;
  const FeatureKeypoints first = Database(workspace).ReadKeypoints(1);
  const std::string older_records[] = {
      "json_remove(settings, '$.extractor_version')",
      fmt::format("json_set(settings, '$.extractor_version', {})", kSiftExtractorVersion - 1)};
  for (const std::string& older : older_records) {
    {
      sqlite3* db = nullptr;
      ASSERT_EQ(sqlite3_open(workspace.c_str(), &db), SQLITE_OK);
      // The record of the current extractor (an earlier pass of this loop left its own).
      const std::string sql = fmt::format(
          "UPDATE varsfm_settings SET settings = {} WHERE stage = 'extract' AND "
          "json_extract(settings, '$.extractor_version') = {}",
          older, kSiftExtractorVersion);
      EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sql;
      EXPECT_EQ(sqlite3_changes(db), 1) << sql;
      sqlite3_close(db);
    }
    ASSERT_EQ(RunCommand(extract, &out), 0) << out;
    EXPECT_NE(out.find("3 images were extracted with other settings"), std::string::npos)
        << older << "\n"
        << out;
    // These images are below max_image_size, so both versions extract the same features.
    const FeatureKeypoints again = Database(workspace).ReadKeypoints(1);
    EXPECT_TRUE(std::equal(again.begin(), again.end(), first.begin(), first.end(),
                           [](const FeatureKeypoint& a, const FeatureKeypoint& b) {
                             return a.x == b.x && a.y == b.y && a.a11 == b.a11 && a.a21 == b.a21;
                           }))
        << older;
    ASSERT_EQ(RunCommand(extract, &out), 0) << out;
    EXPECT_NE(out.find("3 of 3 images already extracted"), std::string::npos) << older << out;
  }
}

// A video panning across a textured scene by `step` pixels a frame, with blurred frames at
// `blurred`.
void WritePanVideo(const fs::path& path, int frames, const std::set<int>& blurred, int seed = 5,
                   int step = 10) {
  cv::Mat scene(360, 480 + step * frames, CV_8UC3, cv::Scalar(120, 120, 120));
  cv::RNG rng(seed);
  for (int i = 0; i < 500; ++i) {
    const cv::Point center(rng.uniform(0, scene.cols), rng.uniform(0, scene.rows));
    cv::circle(scene, center, rng.uniform(3, 25),
               cv::Scalar(rng.uniform(0, 256), rng.uniform(0, 256), rng.uniform(0, 256)),
               cv::FILLED);
  }
  cv::VideoWriter writer(path.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 25,
                         cv::Size(480, 360));
  ASSERT_TRUE(writer.isOpened());
  for (int i = 0; i < frames; ++i) {
    cv::Mat frame = scene(cv::Rect(step * i, 0, 480, 360)).clone();
    if (blurred.count(i)) cv::GaussianBlur(frame, frame, cv::Size(), 5.0);
    writer.write(frame);
  }
}

TEST(ExtractCommand, VideoKeyframesAreExtractedAndBlurredFramesDropped) {
  TempDir dir("extract_video");
  const fs::path video = dir.path() / "pan.avi";
  const std::set<int> blurred = {6, 7, 8, 20, 21};
  WritePanVideo(video, 40, blurred);
  const fs::path workspace = dir.path() / "scan.db";
  std::string out;
  ASSERT_EQ(
      RunCommand(Extract(workspace, "--video " + ShellQuote(video) + " --max-frames 8"), &out), 0)
      << out;
  const fs::path frames = VideoFramesDir(workspace);
  EXPECT_EQ(frames, dir.path() / "scan_frames");
  Database db(workspace);
  const std::vector<DbImage> images = db.ReadAllImages();
  ASSERT_GE(images.size(), 4u);
  EXPECT_LE(images.size(), 8u);
  for (const DbImage& image : images) {
    SCOPED_TRACE(image.name);
    ASSERT_EQ(image.name.rfind("pan/frame_", 0), 0u);  // a folder per video
    EXPECT_EQ(blurred.count(std::stoi(image.name.substr(10, 6))), 0u);
    EXPECT_TRUE(fs::is_regular_file(frames / image.name));
    EXPECT_GT(db.ReadKeypoints(image.image_id).size(), 100u);
    // Keyframes carry no EXIF: COLMAP's default focal 1.2 * max(w, h).
    const auto camera = db.ReadCamera(image.camera_id);
    EXPECT_FALSE(camera->has_prior_focal_length);
    EXPECT_EQ(camera->params, (std::vector<double>{576.0, 240.0, 180.0, 0.0}));
  }
}

// Two videos in one workspace keep their own frames (both number theirs frame_NNNNNN.jpg), also
// when their files have the same name; extracting one of them again is a resume.
TEST(ExtractCommand, SecondVideoKeepsTheFirstOnesFrames) {
  TempDir dir("extract_two_videos");
  fs::create_directories(dir.path() / "other");
  WritePanVideo(dir.path() / "pan.avi", 20, {});
  WritePanVideo(dir.path() / "walk.avi", 20, {}, 9);
  WritePanVideo(dir.path() / "other" / "pan.avi", 20, {}, 13);
  const fs::path workspace = dir.path() / "ws.db";
  const fs::path frames = VideoFramesDir(workspace);
  std::string out;
  ASSERT_EQ(RunCommand(Extract(workspace, "--video " + ShellQuote(dir.path() / "pan.avi")), &out),
            0)
      << out;
  std::map<std::string, std::string> first_files;
  for (const DbImage& image : Database(workspace).ReadAllImages()) {
    first_files[image.name] = FileBytes(frames / image.name);
  }
  ASSERT_GE(first_files.size(), 2u);

  for (const fs::path video : {dir.path() / "walk.avi", dir.path() / "other" / "pan.avi"}) {
    ASSERT_EQ(RunCommand(Extract(workspace, "--video " + ShellQuote(video)), &out), 0) << out;
  }
  std::map<std::string, size_t> per_video;
  {
    Database db(workspace);
    for (const DbImage& image : db.ReadAllImages()) {
      ++per_video[image.name.substr(0, image.name.find('/'))];
      EXPECT_TRUE(fs::is_regular_file(frames / image.name)) << image.name;
    }
  }
  EXPECT_EQ(per_video.size(), 3u);
  EXPECT_EQ(per_video["pan"], first_files.size());
  EXPECT_GE(per_video["walk"], 2u);
  EXPECT_GE(per_video["pan_2"], 2u);  // the other pan.avi
  for (const auto& [name, bytes] : first_files) {
    EXPECT_TRUE(FileBytes(frames / name) == bytes) << name << " overwritten";
  }

  const size_t total = per_video["pan"] + per_video["walk"] + per_video["pan_2"];
  ASSERT_EQ(RunCommand(Extract(workspace, "--video " + ShellQuote(dir.path() / "pan.avi")), &out),
            0)
      << out;
  EXPECT_NE(out.find(fmt::format("{0} of {0} images already extracted", first_files.size())),
            std::string::npos)
      << out;
  EXPECT_EQ(Database(workspace).NumImages(), total);
}

// Keyframes an earlier extraction chose with other keyframe settings and this one does not
// leave the workspace (the cap removed their files).
// `run` of a video into an output folder whose workspace holds other images (photos here) is
// refused before anything is written; a workspace holding this video's keyframes is its own.
TEST(RunCommand, AVideoIntoAnotherSetsFolderIsRefused) {
  TempDir dir("run_video_other_set");
  const fs::path video = dir.path() / "pan.avi";
  WritePanVideo(video, 20, {});
  const fs::path photos = WriteThreeImages(dir.path() / "images");
  const fs::path out = dir.path() / "out";
  std::string log;
  ASSERT_EQ(RunCommand(Extract(out / "workspace.db", "--images " + ShellQuote(photos)), &log), 0)
      << log;
  const std::string workspace = FileBytes(out / "workspace.db");
  EXPECT_EQ(RunCommand(RunLine(video, out, "--until sparse"), &log), 1) << log;
  EXPECT_NE(log.find("holds 3 image(s) that are not keyframes of"), std::string::npos) << log;
  EXPECT_TRUE(FileBytes(out / "workspace.db") == workspace) << "the workspace was changed";
  EXPECT_FALSE(fs::exists(VideoFramesDir(out / "workspace.db"))) << "keyframes were written";

  const fs::path own = dir.path() / "own";
  ASSERT_EQ(RunCommand(Extract(own / "workspace.db", "--video " + ShellQuote(video)), &log), 0)
      << log;
  RunCommand(RunLine(video, own, "--until sparse"), &log);
  EXPECT_EQ(log.find("not keyframes of"), std::string::npos) << log;
}

// A video from a camera that does not move gives one keyframe: `run` says so in the video's
// terms, on one line, before matching.
TEST(RunCommand, AVideoThatHardlyMovesIsAOneLineError) {
  TempDir dir("run_static_video");
  const fs::path video = dir.path() / "tripod.avi";
  WritePanVideo(video, 30, {}, /*seed=*/5, /*step=*/0);
  std::string log;
  EXPECT_EQ(RunCommand(RunLine(video, dir.path() / "out"), &log), 1) << log;
  EXPECT_NE(log.find("error: video " + video.string() + " gave 1 keyframe of 30 frames"),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("the camera hardly moves"), std::string::npos) << log;
  EXPECT_EQ(log.find("matching needs"), std::string::npos) << log;
}

// A video cut after its first frame or two also gives one keyframe: the error names the cut,
// not the camera's motion.
TEST(RunCommand, AVideoCutAfterItsFirstFrameIsAOneLineErrorNamingTheCut) {
  TempDir dir("run_cut_video");
  const fs::path whole = dir.path() / "pan.avi";
  WritePanVideo(whole, 30, {});
  const fs::path video = CopyFileHead(whole, dir.path() / "cut.avi", 0.05);
  std::string log;
  EXPECT_EQ(RunCommand(RunLine(video, dir.path() / "out"), &log), 1) << log;
  EXPECT_NE(log.find("error: video " + video.string() + " gave 1 keyframe: decoding stopped at"),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("of the 30 its container announces; the file is damaged or cut short"),
            std::string::npos)
      << log;
  EXPECT_EQ(log.find("hardly moves"), std::string::npos) << log;
}

TEST(ExtractCommand, OtherKeyframeSettingsReplaceTheEarlierKeyframes) {
  TempDir dir("extract_video_settings");
  const fs::path video = dir.path() / "pan.avi";
  WritePanVideo(video, 30, {});
  const fs::path workspace = dir.path() / "ws.db";
  std::string out;
  ASSERT_EQ(
      RunCommand(Extract(workspace, "--video " + ShellQuote(video) + " --max-frames 6"), &out), 0)
      << out;
  ASSERT_EQ(Database(workspace).NumImages(), 6u);
  ASSERT_EQ(
      RunCommand(Extract(workspace, "--video " + ShellQuote(video) + " --max-frames 3"), &out), 0)
      << out;
  Database db(workspace);
  EXPECT_EQ(db.NumImages(), 3u);
  EXPECT_EQ(db.NumCameras(), 3u);
  for (const DbImage& image : db.ReadAllImages()) {
    EXPECT_TRUE(fs::is_regular_file(VideoFramesDir(workspace) / image.name)) << image.name;
  }
}

// Bad input: a one-line error, a non-zero exit, and the workspace untouched (or not created).
class ExtractBadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    good_ = dir_.path() / "good";
    fs::create_directories(good_);
    cv::Mat image(240, 320, CV_8UC1);
    cv::RNG(1).fill(image, cv::RNG::UNIFORM, 0, 256);
    cv::GaussianBlur(image, image, cv::Size(), 2.0);
    WriteImage(good_ / "a.png", image);
    ASSERT_EQ(RunCommand(Extract(workspace_, "--images " + ShellQuote(good_)), &out_), 0) << out_;
    before_ = FileBytes(workspace_);
    ASSERT_FALSE(before_.empty());
  }

  // Runs extract with `args` on the existing workspace and on a new one.
  void ExpectFailure(const std::string& args, const std::string& named) {
    const int rc = RunCommand(Extract(workspace_, args), &out_);
    EXPECT_NE(rc, 0) << out_;
    EXPECT_NE(out_.find("error: "), std::string::npos) << out_;
    EXPECT_NE(out_.find(named), std::string::npos) << out_;
    EXPECT_EQ(FileBytes(workspace_), before_) << "workspace modified";
    const fs::path fresh = dir_.path() / "fresh.db";
    EXPECT_NE(RunCommand(Extract(fresh, args), &out_), 0) << out_;
    EXPECT_FALSE(fs::exists(fresh)) << "workspace created";
  }

  TempDir dir_{"extract_bad"};
  fs::path good_;
  fs::path workspace_ = dir_.path() / "ws.db";
  std::string before_;
  std::string out_;
};

TEST_F(ExtractBadInput, MissingFolder) {
  ExpectFailure("--images " + ShellQuote(dir_.path() / "absent"), "absent");
}

TEST_F(ExtractBadInput, EmptyFolder) {
  fs::create_directories(dir_.path() / "empty");
  std::ofstream(dir_.path() / "empty" / "readme.txt") << "no images here\n";
  ExpectFailure("--images " + ShellQuote(dir_.path() / "empty"), "empty");
}

// Pictures in formats varsfm does not decode (GIF, 1-bit PBM) and videos are named in a
// warning, not dropped in silence.
TEST_F(ExtractBadInput, PhotosOfUnreadFormatsAreNamed) {
  const fs::path phone = dir_.path() / "phone";
  fs::create_directories(phone);
  std::ofstream(phone / "a.pbm") << "P1";
  std::ofstream(phone / "b.gif") << "gif";
  std::ofstream(phone / "IMG_0002.MOV") << "video";  // a phone's camera roll has videos too
  ExpectFailure("--images " + ShellQuote(phone), "no image files");
  EXPECT_NE(out_.find("skipping 2 photo(s) in a format varsfm does not read"), std::string::npos)
      << out_;
  EXPECT_NE(out_.find("skipping 1 video(s) among the photos (e.g. IMG_0002.MOV)"),
            std::string::npos)
      << out_;
}

TEST_F(ExtractBadInput, OnlyTextAndTruncatedJpegs) {
  const fs::path bad = dir_.path() / "bad";
  fs::create_directories(bad);
  std::ofstream(bad / "text.jpg") << "this is text\n";
  std::vector<uint8_t> jpeg;
  cv::Mat image(240, 320, CV_8UC3);
  cv::RNG(2).fill(image, cv::RNG::UNIFORM, 0, 256);
  ASSERT_TRUE(EncodeJpeg(image, 95, &jpeg));
  std::ofstream(bad / "truncated.jpg", std::ios::binary)
      .write(reinterpret_cast<const char*>(jpeg.data()),
             static_cast<std::streamsize>(jpeg.size() / 2));
  ExpectFailure("--images " + ShellQuote(bad), "no readable image");
  EXPECT_NE(out_.find("text.jpg"), std::string::npos) << out_;
  EXPECT_NE(out_.find("truncated.jpg"), std::string::npos) << out_;
}

// Photos that decode but hold no feature (blank, lens cap on) made a workspace that every later
// stage failed on with another reason; a new workspace is refused, and an existing one, whose
// photos have features, only gains the blank ones with a warning.
TEST_F(ExtractBadInput, BlankPhotosAloneAreRefused) {
  const fs::path blank = dir_.path() / "blank";
  fs::create_directories(blank);
  for (const char* name : {"a.png", "b.png", "c.png"})
    WriteImage(blank / name, cv::Mat(240, 320, CV_8UC3, cv::Scalar(128, 128, 128)));
  const fs::path fresh = dir_.path() / "fresh.db";
  EXPECT_NE(RunCommand(Extract(fresh, "--images " + ShellQuote(blank)), &out_), 0) << out_;
  EXPECT_NE(out_.find("error: no feature in any of the 3 images"), std::string::npos) << out_;
  EXPECT_FALSE(fs::exists(fresh)) << "workspace created";

  EXPECT_EQ(RunCommand(Extract(workspace_, "--images " + ShellQuote(blank)), &out_), 0) << out_;
  EXPECT_NE(out_.find("has only 0 features"), std::string::npos) << out_;
}

TEST_F(ExtractBadInput, UndecodableAndMissingVideo) {
  std::ofstream(dir_.path() / "bad.avi") << "not a video\n";
  ExpectFailure("--video " + ShellQuote(dir_.path() / "bad.avi"), "bad.avi");
  ExpectFailure("--video " + ShellQuote(dir_.path() / "absent.mp4"), "absent.mp4");
}

// A usage error exits with CLI11's own code (neither 0 nor 1, varsfm's runtime error).
TEST_F(ExtractBadInput, BothOrNeitherInputIsAUsageError) {
  for (const std::string& args :
       {"--images " + ShellQuote(good_) + " --video x.avi", std::string()}) {
    const int rc = RunCommand(Extract(workspace_, args), &out_);
    EXPECT_NE(rc, 0) << out_;
    EXPECT_NE(rc, 1) << out_;
    EXPECT_NE(out_.find("--images"), std::string::npos) << out_;
  }
  EXPECT_EQ(FileBytes(workspace_), before_);
}

}  // namespace
}  // namespace varsfm
